"""Self-checks of tests/python/refs/two_mass.py, the independent reference of TwoMassOscillator:
two routes that share no code or equations (test_refs.py).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from refs import step_input, two_mass


TWO_MASS_CASES = [
    {},                                                         # m1 = m2, k1 = k2 = k3
    {"m1": 1.0, "m2": 2.0, "k1": 0.0, "k2": 0.0, "k3": 1.0},     # 2 m1 = m2, free pair
    {"m1": 1.3, "m2": 0.7, "k1": 2.0, "k2": 0.5, "k3": 0.3},
    {"m1": 2.0, "m2": 0.5, "k1": 0.1, "k2": 7.0, "k3": 2.5},
    {"m1": 1.0, "m2": 1.0, "k1": 2.0, "k2": 1.0, "k3": 0.0},     # uncoupled
]


@pytest.mark.parametrize("p", TWO_MASS_CASES)
def test_two_mass_closed_form_equals_eigensolver(p):
    a, b = two_mass.modes(p), two_mass.modes_eig(p)
    for k in a:
        assert abs(a[k] - b[k]) < 1e-12, k
    M, _, K = two_mass.matrices(p)
    for j in (1, 2):
        w2 = a[f"omega_n{j}"] ** 2
        assert abs(np.linalg.det(K - w2 * M)) < 1e-12 * max(1.0, np.abs(K).max() ** 2)
        v = np.array([a[f"mode{j}_x1"], a[f"mode{j}_x2"]])
        assert np.max(np.abs((K - w2 * M) @ v)) < 1e-12 * max(1.0, np.abs(K).max())
        assert 1.0 in v and np.max(np.abs(v)) < 1.0 + 1e-14
    assert a["omega_n1"] <= a["omega_n2"]


def test_two_mass_notes_special_cases():
    k, m = 1.7, 0.9
    a = two_mass.modes({"m1": m, "m2": m, "k1": k, "k2": k, "k3": k})
    assert abs(a["omega_n1"] - math.sqrt(k / m)) < 1e-14 and abs(a["omega_n2"] - math.sqrt(3 * k / m)) < 1e-14
    got = (a["mode1_x1"], a["mode1_x2"], a["mode2_x1"], a["mode2_x2"])
    assert got[0] == 1.0 and got[2] == 1.0    # tie: x1 is +1
    assert np.max(np.abs(np.array(got) - [1.0, 1.0, 1.0, -1.0])) < 1e-14
    b = two_mass.modes({"m1": m, "m2": 2 * m, "k1": 0.0, "k2": 0.0, "k3": k})
    assert b["omega_n1"] == 0.0 and abs(b["omega_n2"] - math.sqrt(3 * k / (2 * m))) < 1e-14
    # a1/a2 = -2, scaled so the largest component is +1: (1, -1/2)
    assert (b["mode1_x1"], b["mode1_x2"]) == (1.0, 1.0)
    assert b["mode2_x1"] == 1.0 and abs(b["mode2_x2"] + 0.5) < 1e-15


def test_two_mass_tie_rule():
    s = two_mass.scale_shape([-1.0, 1.0 + 1e-15])   # a tie up to rounding: x1 = +1
    assert s[0] == 1.0 and abs(s[1] + 1.0) < 1e-14
    assert list(two_mass.scale_shape([0.5, -1.0])) == [-0.5, 1.0]


@pytest.mark.parametrize("p", TWO_MASS_CASES[:4])
@pytest.mark.parametrize("mode", [1, 2])
def test_two_mass_start_on_a_mode_stays_a_pure_sinusoid(p, mode):
    md = two_mass.modes(p)
    A = 0.8
    t = np.linspace(0.0, 30.0, 3001)
    y0 = {"x1": A * md[f"mode{mode}_x1"], "x2": A * md[f"mode{mode}_x2"], "x1_dot": 0.0, "x2_dot": 0.0}
    r = two_mass.simulate(p, y0, t)
    x1, x2 = two_mass.modal_response(p, mode, A, t)
    assert max(np.max(np.abs(r["x1"] - x1)), np.max(np.abs(r["x2"] - x2))) < 1e-9 * A


def test_two_mass_damped_forced_against_matrix_exponential():
    """Piecewise-constant forces: exact discrete solution of the linear system (expm)."""
    from scipy.linalg import expm
    p = two_mass.params(m1=1.2, m2=0.8, k1=1.0, k2=2.0, k3=0.5, c1=0.1, c2=0.05, c3=0.2)
    M, C, K = two_mass.matrices(p)
    Mi = np.linalg.inv(M)
    A = np.block([[np.zeros((2, 2)), np.eye(2)], [-Mi @ K, -Mi @ C]])
    Bm = np.vstack([np.zeros((2, 2)), Mi])
    times, F = [0.0, 3.0, 7.5], [[1.0, 0.0], [0.0, -2.0], [0.5, 0.5]]
    inp = step_input(["F1", "F2"], times, F, t_end=30.0)
    t = np.linspace(0.0, 30.0, 301)
    r = two_mass.simulate(p, None, t, inp)
    z = np.array([1.0, 0.0, 0.0, 0.0])
    Aug = np.zeros((6, 6))
    Aug[:4, :4], Aug[:4, 4:] = A, Bm
    out = [z]
    for i in range(1, t.size):
        u = np.array(F[int(np.searchsorted(times, t[i - 1], side="right")) - 1])
        z = (expm(Aug * (t[i] - t[i - 1])) @ np.concatenate([z, u]))[:4]
        out.append(z)
    Z = np.array(out).T
    for j, n in enumerate(two_mass.STATES):
        assert np.max(np.abs(r[n] - Z[j])) < 1e-9, n
