"""Self-checks of the independent references in tests/python/refs (no FMU needed).

Every test compares two routes that do not share code or equations: the DOP853 solution
against a closed form, Lagrange against Newton-Euler (sympy), a conservation law or a
work-energy balance integrated alongside, or a hand-computed value.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp

from refs import (crane, crane_dynamics, derive, double_pendulum_cart, oscillator, pendulum_cart, rigid_body,
                  step_input, two_mass)
from refs._common import zoh_value, _table

RNG = np.random.default_rng(20240611)


def rel_err(a, b):
    a, b = np.asarray(a, float), np.asarray(b, float)
    return float(np.max(np.abs(a - b)) / max(np.max(np.abs(b)), 1e-300))


# ============================================================================ inputs (ZOH)

def test_step_input_table_is_fmpy_style_and_switches_at_listed_time():
    tab = step_input(["F"], [0.0, 2.0, 5.0], [[0.0], [3.0], [-1.0]], t_end=10.0)
    assert tab.dtype.names == ("time", "F")
    assert list(tab["time"]) == [0.0, 2.0, 2.0, 5.0, 5.0, 10.0]
    tb = _table(tab, {"F": 0.0})
    assert zoh_value(tb, {"F": 9.0}, -1.0)["F"] == 0.0           # before the first row
    assert zoh_value(tb, {"F": 9.0}, 1.999999)["F"] == 0.0
    assert zoh_value(tb, {"F": 9.0}, 2.0)["F"] == 3.0             # switches AT t = 2
    assert zoh_value(tb, {"F": 9.0}, 2.0, before=True)["F"] == 0.0
    assert zoh_value(tb, {"F": 9.0}, 5.0)["F"] == -1.0
    assert zoh_value(tb, {"F": 9.0}, 50.0)["F"] == -1.0


def test_zoh_rows_without_duplicates_read_the_same():
    a = step_input(["F"], [0.0, 2.0], [[0.0], [3.0]], t_end=4.0)
    b = np.array([(0.0, 0.0), (2.0, 3.0)], dtype=[("time", float), ("F", float)])
    t = np.linspace(0, 4, 41)
    ra, rb = oscillator.simulate(None, None, t, a), oscillator.simulate(None, None, t, b)
    assert np.array_equal(ra["x"], rb["x"])


def test_unknown_names_are_rejected():
    with pytest.raises(KeyError):
        oscillator.simulate({"mass": 2.0}, None, [0.0, 1.0])
    with pytest.raises(KeyError):
        oscillator.simulate(None, {"y": 2.0}, [0.0, 1.0])
    with pytest.raises(KeyError):
        oscillator.simulate(None, None, [0.0, 1.0], step_input(["G"], [0.0], [[1.0]]))


# ============================================================================ Oscillator

@pytest.mark.parametrize("c, expected", [(5.0, "overdamped"), (4.0, "critical"), (0.4, "underdamped"),
                                         (0.0, "undamped")])
def test_oscillator_free_response_all_regimes(c, expected):
    p = oscillator.params(c=c)  # m = 1, k = 4: c = 4 is critical
    assert oscillator.regime(p) == expected
    t = np.linspace(0.0, 20.0, 2001)
    r = oscillator.simulate(p, {"x": 1.0, "x_dot": -0.7}, t)
    x, v = oscillator.free_response(p, 1.0, -0.7, t)
    assert np.max(np.abs(r["x"] - x)) < 1e-9
    assert np.max(np.abs(r["x_dot"] - v)) < 1e-9
    assert np.max(np.abs(r["x_ddot"] - (-(c * v + 4.0 * x)))) < 1e-8


def test_oscillator_overdamped_form_equals_notes_exponentials():
    p = oscillator.params(c=5.0)
    s1, s2 = oscillator.overdamped_roots(p)
    x0, v0 = 1.0, -0.7
    B = (v0 - s1 * x0) / (s2 - s1)
    A = x0 - B
    t = np.linspace(0, 10, 101)
    x, _ = oscillator.free_response(p, x0, v0, t)
    assert np.max(np.abs(x - (A * np.exp(s1 * t) + B * np.exp(s2 * t)))) < 1e-13


def test_oscillator_step_response_with_input_switch():
    """F = 0 until t = 2, then F = 3 (zero-order hold): closed form in two pieces."""
    p = oscillator.params()
    t = np.linspace(0.0, 20.0, 2001)
    inp = step_input(["F"], [0.0, 2.0], [[0.0], [3.0]], t_end=20.0)
    r = oscillator.simulate(p, {"x": 1.0, "x_dot": 0.0}, t, inp)
    x1, v1 = oscillator.free_response(p, 1.0, 0.0, t)
    x2s, v2s = oscillator.free_response(p, 1.0, 0.0, np.array([2.0]))
    x2, v2 = oscillator.step_response(p, 3.0, x2s[0], v2s[0], t - 2.0)
    xe = np.where(t < 2.0, x1, x2)
    assert np.max(np.abs(r["x"] - xe)) < 1e-9
    i2 = int(np.flatnonzero(t == 2.0)[0])
    assert r["F"][i2] == 3.0 and r["F"][i2 - 1] == 0.0
    assert abs(r["x"][-1] - 3.0 / 4.0) < 2e-3          # settles to F/k
    rb = oscillator.simulate(p, {"x": 1.0, "x_dot": 0.0}, t, inp, switch_outputs="before")
    assert rb["F"][i2] == 0.0 and np.array_equal(rb["x"], r["x"])


@pytest.mark.parametrize("c, omega", [(0.4, 1.7), (0.4, 2.0), (0.0, 1.3), (0.0, 2.0), (6.0, 0.5)])
def test_oscillator_complete_harmonic_response(c, omega):
    p = oscillator.params(c=c, F0=2.0, omega=omega)
    t = np.linspace(0.0, 20.0, 2001)
    r = oscillator.simulate(p, {"x": 0.3, "x_dot": 0.5}, t)
    x, v = oscillator.response(p, 0.3, 0.5, t)
    assert np.max(np.abs(r["x"] - x)) < 1e-9 * max(1.0, np.max(np.abs(x)))
    assert np.max(np.abs(r["x_dot"] - v)) < 1e-9 * max(1.0, np.max(np.abs(v)))


def test_oscillator_steady_amplitude_and_phase():
    p = oscillator.params(c=0.8, F0=2.0, omega=1.5)
    X, psi = oscillator.steady_amplitude_phase(p)
    w = 1.5
    # X e^{i psi} (k - m w^2 + i c w) = F0 (phasor of m x'' + c x' + k x = F0 sin w t)
    z = X * np.exp(1j * psi) * (4.0 - w * w + 1j * 0.8 * w)
    assert abs(z - 2.0) < 1e-12
    t = np.linspace(60.0, 80.0, 201)  # transient gone (e^{-0.4 * 60})
    r = oscillator.simulate(p, {"x": 0.0, "x_dot": 0.0}, np.concatenate([[0.0], t]))
    assert np.max(np.abs(r["x"][1:] - X * np.sin(w * t + psi))) < 1e-9


def test_oscillator_peak_of_amplitude_response():
    p = oscillator.params(c=0.4, F0=1.0)
    wp, Xp = oscillator.peak(p)
    ws = np.linspace(wp - 1e-3, wp + 1e-3, 2001)
    Xs = [oscillator.steady_amplitude_phase(p, w)[0] for w in ws]
    assert abs(ws[int(np.argmax(Xs))] - wp) < 2e-6
    assert abs(max(Xs) - Xp) < 1e-12 * Xp


# ============================================================================ TwoMassOscillator

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


# ============================================================================ PendulumCart

def random_cart_states(n):
    for _ in range(n):
        y = RNG.uniform(-1.0, 1.0, 4) * np.array([0.5, 2.0, math.pi, 6.0])
        yield y, {"F": float(RNG.normal(0.0, 3.0))}


def test_pendulum_cart_lagrange_equals_newton_euler_equals_reference():
    lag, ne = derive.pendulum_cart_lagrange(), derive.pendulum_cart_newton_euler()
    p = pendulum_cart.params(c1=0.7, c2=0.05, k=13.0)
    for y, u in random_cart_states(25):
        a = lag(y, p, u)
        b = ne(y, p, u)
        r = pendulum_cart.accelerations(y, p, u["F"])
        scale = max(1.0, np.max(np.abs(a)))
        assert np.max(np.abs(a - [b["x_ddot"], b["theta_ddot"]])) < 1e-12 * scale
        assert np.max(np.abs(a - r)) < 1e-12 * scale
        o = pendulum_cart._outputs(0.0, y, p, u)
        assert abs(o["F_N"] - b["F_N"]) < 1e-12 * max(1.0, abs(b["F_N"]))
        assert abs(o["E"] - b["E"]) < 1e-12 * max(1.0, abs(b["E"]))
        assert abs(o["E_dot"] - b["E_dot"]) < 1e-12 * max(1.0, abs(b["E_dot"]))


def test_pendulum_cart_lagrangian_mass_matrix_is_the_contracts():
    lag = derive.pendulum_cart_lagrange()
    p = pendulum_cart.params()
    for y, u in random_cart_states(5):
        Mm = np.asarray(lag.mass_matrix(y, p, u), float)
        c = math.cos(y[2])
        ml = p["m"] * p["l"]
        assert np.allclose(Mm, [[p["M"] + p["m"], ml * c], [ml * c, 7 / 3 * p["m"] * p["l"] ** 2]], rtol=1e-14, atol=0)


def test_pendulum_cart_notes_normal_force_has_the_wrong_sign():
    """F_N from the free-body diagrams vs the notes' printed (M+m)g - m l (...)."""
    ne = derive.pendulum_cart_newton_euler()
    p = pendulum_cart.params()
    y = (0.0, 0.0, 0.0, 3.0)        # rod through the bottom, swinging
    b = ne(y, p, {"F": 0.0})
    th, thd, thdd = y[2], y[3], b["theta_ddot"]
    notes = (p["M"] + p["m"]) * p["g"] - p["m"] * p["l"] * (thdd * math.sin(th) + thd ** 2 * math.cos(th))
    assert b["F_N"] > (p["M"] + p["m"]) * p["g"] > notes
    assert abs(b["F_N"] - ((p["M"] + p["m"]) * p["g"] + p["m"] * p["l"] * 9.0)) < 1e-12


def test_pendulum_cart_energy_conserved():
    p = pendulum_cart.params()
    t = np.linspace(0.0, 20.0, 2001)
    r = pendulum_cart.simulate(p, {"theta": 2.5, "x": 0.1}, t)
    assert rel_err(r["E"], np.full_like(t, r["E"][0])) < 1e-10


def test_pendulum_cart_energy_balance_with_damping_and_forcing():
    p = pendulum_cart.params(c1=0.4, c2=0.02)
    t = np.linspace(0.0, 10.0, 1001)
    inp = step_input(["F"], [0.0, 1.0, 2.5, 4.0, 6.0], [[0.0], [2.0], [-1.5], [0.7], [0.0]], t_end=10.0)
    r = pendulum_cart.simulate(p, None, t, inp)
    dE, W = r["E"] - r["E"][0], r["W_nc"]
    assert np.max(np.abs(dE - W)) < 1e-9 * max(1.0, np.max(np.abs(W)))
    assert np.max(np.abs(W)) > 0.1  # the forcing did work


def test_pendulum_cart_normal_force_at_bottom_of_swing():
    p = pendulum_cart.params()
    t = np.linspace(0.0, 10.0, 10001)
    r = pendulum_cart.simulate(p, None, t)
    idx = np.flatnonzero(np.sign(r["theta"][:-1]) != np.sign(r["theta"][1:]))
    assert idx.size >= 4
    W = (p["M"] + p["m"]) * p["g"]
    for i in idx:
        j = i if abs(r["theta"][i]) < abs(r["theta"][i + 1]) else i + 1
        assert r["F_N"][j] > W + 0.5 * p["m"] * p["l"] * r["theta_dot"][j] ** 2
    # at rest, hanging: F_N = (M+m) g exactly
    r0 = pendulum_cart.simulate(p, {"theta": 0.0}, [0.0, 1.0])
    assert np.max(np.abs(r0["F_N"] - W)) < 1e-12


def test_pendulum_cart_linear_frequencies():
    p = pendulum_cart.params()
    a = pendulum_cart.calculated(p)
    b = pendulum_cart.calculated_closed_form(p)
    for k in a:
        assert abs(a[k] - b[k]) < 1e-12 * b[k]


def test_pendulum_cart_small_oscillations_follow_linear_modes():
    """theta0 = 1e-6: the nonlinear reference equals the modal superposition of the
    linearized system (nonlinear terms ~ theta0^2 relative)."""
    p = pendulum_cart.params()
    w, Phi = pendulum_cart.linear_modes(p)
    Mm, _, _ = pendulum_cart.linear_matrices(p)
    th0 = 1e-6
    q0 = np.array([0.3 * th0, th0])
    t = np.linspace(0.0, 10.0, 1001)
    r = pendulum_cart.simulate(p, {"x": q0[0], "theta": q0[1]}, t, atol=1e-20)
    lin = np.zeros((2, t.size))
    for i in range(2):
        ph = Phi[:, i]
        lin += np.outer(ph * (ph @ Mm @ q0) / (ph @ Mm @ ph), np.cos(w[i] * t))
    assert np.max(np.abs(r["x"] - lin[0])) < 1e-9 * th0
    assert np.max(np.abs(r["theta"] - lin[1])) < 1e-9 * th0


# ============================================================================ Crane

def random_crane_state():
    """Either crane's state (x, x_dot, theta, theta_dot, phi, phi_dot) at random."""
    return np.array([RNG.uniform(1.0, 20.0), RNG.normal(0, 2), RNG.uniform(-1.5, 1.5), RNG.normal(0, 0.5),
                     RNG.uniform(-2.5, 2.5), RNG.normal(0, 1.5)])


def random_crane_states(n):
    for _ in range(n):
        y = random_crane_state()
        yield y, {"x_ddot": float(RNG.normal(0, 2)), "theta_ddot": float(RNG.normal(0, 0.3))}


def test_crane_lagrange_equals_newton_euler_equals_reference():
    lag, ne = derive.crane_lagrange(), derive.crane_newton_euler()
    p = crane.params()
    for y, u in random_crane_states(25):
        o = crane._outputs(0.0, y, p, u)
        b = ne(y, p, u)
        assert abs(lag(y, p, u) - o["phi_ddot"]) < 1e-12 * max(1.0, abs(o["phi_ddot"]))
        assert abs(b["phi_ddot"] - o["phi_ddot"]) < 1e-12 * max(1.0, abs(o["phi_ddot"]))
        for k in ("T", "F", "tau"):
            assert abs(b[k] - o[k]) < 1e-12 * max(1.0, abs(o[k])), k
        if o["T"] > 0:
            assert abs(math.hypot(o["F"], o["tau"] / y[0]) - o["T"]) < 1e-12 * o["T"]
        else:
            assert abs(math.hypot(o["F"], o["tau"] / y[0]) + o["T"]) < 1e-12 * abs(o["T"])


def test_crane_hanging_payload_is_stable_and_the_notes_equation_is_not():
    p = crane.params()
    h = 1e-6
    for x, th in [(10.0, 0.5), (3.0, -0.2), (15.0, 1.2)]:
        y = lambda ph: (x, 0.0, th, 0.0, ph, 0.0)
        k_ok = (crane.phi_ddot(y(h), p, 0, 0) - crane.phi_ddot(y(-h), p, 0, 0)) / (2 * h)
        k_notes = (crane.phi_ddot_notes(y(h), p, 0, 0) - crane.phi_ddot_notes(y(-h), p, 0, 0)) / (2 * h)
        assert abs(k_ok + p["g"] / p["l"]) < 1e-8        # phi'' = -(g/l) phi: oscillates
        assert abs(k_notes - p["g"] / p["l"]) < 1e-8     # phi'' = +(g/l) phi: diverges


def test_crane_static_loads():
    p = crane.params()
    T, F, tau = crane.still_loads(p, 10.0, 0.5)
    mg = p["m"] * p["g"]
    assert abs(T - mg) < 1e-12 * mg
    assert abs(F - mg * math.sin(0.5)) < 1e-12 * mg
    assert abs(tau - 10.0 * mg * math.cos(0.5)) < 1e-12 * 10 * mg
    r = crane.simulate(p, None, np.linspace(0, 20, 201))
    assert np.max(np.abs(r["phi"])) == 0.0 and np.max(np.abs(r["T"] - mg)) < 1e-9 * mg


def test_crane_elliptic_period_convention():
    """4 sqrt(l/g) K(k) with K from scipy (parameter m = k^2) vs the period integral."""
    p = crane.params()
    for phi0 in np.radians([5.0, 30.0, 90.0, 120.0, 170.0]):
        k = math.sin(phi0 / 2)
        Kq = quad(lambda s: 1.0 / math.sqrt(1.0 - (k * math.sin(s)) ** 2), 0.0, math.pi / 2, epsabs=0, epsrel=1e-13)[0]
        assert abs(crane.period(p, phi0) - 4 * math.sqrt(p["l"] / p["g"]) * Kq) < 1e-12 * crane.period(p, phi0)
    assert abs(crane.period(p, 1e-8) - 2 * math.pi * math.sqrt(p["l"] / p["g"])) < 1e-12


@pytest.mark.parametrize("deg", [5.0, 45.0, 90.0, 120.0])
def test_crane_large_amplitude_swing(deg):
    p = crane.params()
    phi0 = math.radians(deg)
    t = np.linspace(0.0, 20.0, 2001)
    r = crane.simulate(p, {"phi": phi0}, t)
    ph, phd = crane.pendulum(p, phi0, t)
    assert np.max(np.abs(r["phi"] - ph)) < 1e-9 * phi0
    assert np.max(np.abs(r["phi_dot"] - phd)) < 1e-9 * max(1.0, np.max(np.abs(phd)))
    assert np.max(np.abs(r["E_payload"] - r["E_payload"][0])) < 1e-10 * p["m"] * p["g"] * p["l"]
    # half period by event location on phi' = 0
    ev = lambda tt, y, pp, uu: y[5]
    ev.direction = 1
    y0 = [10.0, 0.0, 0.5, 0.0, phi0, 0.0]
    sol = solve_ivp(crane.rhs, (0, 20), y0, method="DOP853", args=(p, crane.INPUTS), events=ev, rtol=1e-12, atol=1e-12)
    half = sol.t_events[0][0]
    assert abs(2 * half - crane.period(p, phi0)) < 1e-9 * crane.period(p, phi0)


def test_crane_moving_drives_work_energy_and_tension_identity():
    p = crane.params()
    t = np.linspace(0.0, 20.0, 2001)
    inp = step_input(["x_ddot", "theta_ddot"], [0.0, 2.0, 5.0, 9.0, 12.0],
                     [[0.5, 0.0], [0.0, 0.02], [-0.6, -0.03], [0.2, 0.01], [0.0, 0.0]], t_end=20.0)
    r = crane.simulate(p, None, t, inp)
    assert np.min(r["T"]) > 0
    assert rel_err(r["T"], np.hypot(r["F"], r["tau"] / r["x"])) < 1e-12
    dE = r["E_payload"] - r["E_payload"][0]
    assert np.max(np.abs(dE - r["W_drives"])) < 1e-9 * np.max(np.abs(r["W_drives"]))
    # the prescribed motion is integrated exactly (piecewise quadratics)
    xe, ve = 10.0, 0.0
    segs = [(0.0, 2.0, 0.5), (2.0, 5.0, 0.0), (5.0, 9.0, -0.6), (9.0, 12.0, 0.2), (12.0, 20.0, 0.0)]
    for a, b, acc in segs:
        m = (t >= a) & (t <= b)
        assert np.max(np.abs(r["x"][m] - (xe + ve * (t[m] - a) + 0.5 * acc * (t[m] - a) ** 2))) < 1e-9
        xe, ve = xe + ve * (b - a) + 0.5 * acc * (b - a) ** 2, ve + acc * (b - a)
    # payload position is consistent with the states
    assert np.max(np.abs(r["payload_x"] - (r["x"] * np.cos(r["theta"]) + 5 * np.sin(r["phi"])))) < 1e-12 * 20


def test_crane_trolley_reaching_pivot_stops_the_reference():
    inp = step_input(["x_ddot", "theta_ddot"], [0.0], [[-2.0, 0.0]], t_end=10.0)
    with pytest.raises(RuntimeError, match="pivot"):
        crane.simulate(None, None, np.linspace(0, 10, 11), inp)


# ============================================================================ CraneDynamics

def random_cd_states(n):
    for _ in range(n):
        y = random_crane_state()
        yield y, {"F": float(RNG.normal(0, 5e3)), "tau": float(RNG.normal(0, 5e4))}


def test_crane_dynamics_lagrange_equals_newton_euler_equals_reference():
    lag, ne = derive.crane_dynamics_lagrange(), derive.crane_dynamics_newton_euler()
    p = crane_dynamics.params(J_boom=3000.0, m_trolley=350.0)
    for y, u in random_cd_states(25):
        a = lag(y, p, u)
        b = ne(y, p, u)
        o = crane_dynamics._outputs(0.0, y, p, u)
        scale = max(1.0, np.max(np.abs(a)))
        assert np.max(np.abs(a - [b["x_ddot"], b["theta_ddot"], b["phi_ddot"]])) < 1e-12 * scale
        assert np.max(np.abs(a - [o["x_ddot"], o["theta_ddot"], o["phi_ddot"]])) < 1e-12 * scale
        assert abs(b["T"] - o["T"]) < 1e-12 * max(1.0, abs(o["T"]))
        assert abs(b["N"] - o["N"]) < 1e-12 * max(1.0, abs(o["N"]))
        Mm, f = lag.mass_matrix(y, p, u), lag.forcing(y, p, u)
        assert np.max(np.abs(Mm - crane_dynamics.mass_matrix(y, p))) < 1e-12 * np.max(np.abs(Mm))
        assert np.max(np.abs(f - crane_dynamics.forcing(y, p, u["F"], u["tau"]))) < 1e-12 * np.max(np.abs(f))
        assert abs(lag.energy(y, p, u) - o["E"]) < 1e-12 * max(1.0, abs(o["E"]))


def test_crane_dynamics_tension_obeys_formula_a_on_the_motion():
    """T from the payload's free-body diagram (Newton-Euler unknown) equals formula (a)
    evaluated with the accelerations of the simulated motion."""
    ne = derive.crane_dynamics_newton_euler()
    p = crane_dynamics.params()
    F, tau = crane_dynamics.static_loads(p, 10.0, 0.5)
    inp = step_input(["F", "tau"], [0.0, 1.0, 3.0], [[F, tau], [F * 1.1, tau * 0.98], [F, tau]], t_end=8.0)
    t = np.linspace(0, 8, 81)
    r = crane_dynamics.simulate(p, None, t, inp)
    for j in range(0, t.size, 7):
        y = [r[n][j] for n in crane_dynamics.STATES]
        u = {"F": r["F"][j], "tau": r["tau"][j]}
        assert abs(ne(y, p, u)["T"] - r["T"][j]) < 1e-12 * abs(r["T"][j])
        assert abs(crane.tension(y, crane.params(m=p["m"], l=p["l"], g=p["g"]), r["x_ddot"][j], r["theta_ddot"][j])
                   - r["T"][j]) < 1e-12 * abs(r["T"][j])


def test_crane_dynamics_static_loads_hold_it_at_rest():
    p = crane_dynamics.params()
    for x, th in [(10.0, 0.5), (4.0, -0.3), (17.0, 1.1)]:
        F, tau = crane_dynamics.static_loads(p, x, th)
        mu = p["m"] + p["m_trolley"]
        assert abs(F - mu * p["g"] * math.sin(th)) < 1e-9 and abs(tau - x * mu * p["g"] * math.cos(th)) < 1e-9
        t = np.linspace(0.0, 20.0, 201)
        r = crane_dynamics.simulate(p, {"x": x, "theta": th}, t, step_input(["F", "tau"], [0.0], [[F, tau]], t_end=20))
        drift = max(np.max(np.abs(r["x"] - x)), np.max(np.abs(r["theta"] - th)), np.max(np.abs(r["phi"])))
        assert drift < 1e-9
        assert np.max(np.abs(r["T"] - p["m"] * p["g"])) < 1e-9 * p["m"] * p["g"]
        # the accelerations vanish (to rounding)
        acc = crane_dynamics.accelerations((x, 0, th, 0, 0, 0), p, F, tau)
        assert max(abs(a) for a in acc) < 1e-12


def test_crane_dynamics_energy_balance():
    p = crane_dynamics.params()
    F, tau = crane_dynamics.static_loads(p, 10.0, 0.5)
    inp = step_input(["F", "tau"], [0.0, 1.0, 4.0, 6.0, 11.0],
                     [[F, tau], [F + 800, tau + 4000], [F - 600, tau - 6000], [F, tau + 1500], [F, tau]], t_end=20)
    t = np.linspace(0.0, 20.0, 2001)
    r = crane_dynamics.simulate(p, None, t, inp)
    dE = r["E"] - r["E"][0]
    assert np.max(np.abs(r["W_drives"])) > 1e3
    assert np.max(np.abs(dE - r["W_drives"])) < 1e-9 * max(np.max(np.abs(r["W_drives"])), abs(r["E"][0]))
    # constant static loads but a swinging payload: the crane leaves its (unstable) rest
    # position and the constant F and tau do work on it
    r2 = crane_dynamics.simulate(p, {"phi": 0.3}, t, step_input(["F", "tau"], [0.0], [[F, tau]], t_end=20))
    W2 = r2["W_drives"]
    assert np.max(np.abs(W2)) > 1e3
    assert np.max(np.abs(r2["E"] - r2["E"][0] - W2)) < 1e-9 * max(np.max(np.abs(W2)), abs(r2["E"][0]))
    # no drive power at all (F = tau = 0 and the crane at x > 0 moving): energy constant
    r3 = crane_dynamics.simulate(p, {"phi": 0.3}, np.linspace(0, 3, 301))
    assert np.max(np.abs(r3["W_drives"])) == 0.0
    assert np.max(np.abs(r3["E"] - r3["E"][0])) < 1e-10 * np.max(np.abs(r3["E"]))


# ============================================================================ RigidBody

def test_rigid_body_box_and_rod_inertia():
    c = rigid_body.calculated()
    box = sorted(rigid_body.box_inertia(2.0, 0.3, 0.2, 0.1))
    assert np.allclose([c["I_1"], c["I_2"], c["I_3"]], box, rtol=1e-15, atol=0)
    assert abs(box[0] - 2.0 * 0.05 / 12) < 1e-16 and abs(box[2] - 2.0 * 0.13 / 12) < 1e-16
    # slender rod (radius a) of length L along x, pivot at one end
    M, L, a = 3.0, 1.2, 0.01
    p = rigid_body.params(M=M, I_xx=M * a * a / 2, I_yy=M * L * L / 12 + M * a * a / 4,
                          I_zz=M * L * L / 12 + M * a * a / 4, r_Cx=L / 2)
    IB = rigid_body.inertia_about_pivot(p)
    assert abs(IB[1, 1] - (M * L * L / 3 + M * a * a / 4)) < 1e-15 and IB[0, 0] == M * a * a / 2


def test_rigid_body_parallel_axis_against_point_masses():
    """I_C and I_B computed by definition sum m [(r.r)1 - r r^T] over a point cloud."""
    pts = RNG.normal(size=(40, 3)) * [0.3, 0.2, 0.1]
    ms = RNG.uniform(0.1, 1.0, 40)
    M = ms.sum()
    C = (ms[:, None] * pts).sum(0) / M
    B = np.array([0.05, -0.4, 0.2])

    def inertia(o):
        d = pts - o
        return sum(mi * (di @ di * np.eye(3) - np.outer(di, di)) for mi, di in zip(ms, d))
    IC, IBd = inertia(C), inertia(B)
    r = C - B
    p = rigid_body.params(M=M, I_xx=IC[0, 0], I_yy=IC[1, 1], I_zz=IC[2, 2], I_xy=IC[0, 1], I_xz=IC[0, 2],
                          I_yz=IC[1, 2], r_Cx=r[0], r_Cy=r[1], r_Cz=r[2])
    assert np.max(np.abs(rigid_body.inertia_about_pivot(p) - IBd)) < 1e-13
    assert IC[0, 1] < 0 or IC[0, 1] > 0  # products present; entry is -sum m x y
    d = pts - C
    assert abs(IC[0, 1] + (ms * d[:, 0] * d[:, 1]).sum()) < 1e-14


def test_rigid_body_principal_moments_with_products():
    p = rigid_body.params(I_xx=4.0, I_yy=4.0, I_zz=3.0, I_xy=-1.0)
    c = rigid_body.calculated(p)
    assert np.allclose([c["I_1"], c["I_2"], c["I_3"]], [3.0, 3.0, 5.0], rtol=1e-15, atol=1e-15)
    w, V = rigid_body.principal(p)
    assert abs(abs(V[:, 2] @ np.array([1, -1, 0]) / math.sqrt(2)) - 1) < 1e-14


def test_rigid_body_euler_equations_equal_lagrange_in_euler_angles():
    lag = derive.rigid_body_lagrange()
    p = rigid_body.params(I_xy=0.001, I_xz=-0.0005, I_yz=0.0008, r_Cx=0.03, r_Cy=-0.02, r_Cz=0.1)
    for _ in range(15):
        ang = [RNG.uniform(-3, 3), RNG.uniform(0.3, 2.8), RNG.uniform(-3, 3)]
        rates = RNG.normal(size=3) * 3
        u = {"tau_x": RNG.normal() * 0.1, "tau_y": RNG.normal() * 0.1, "tau_z": RNG.normal() * 0.1}
        d = lag(ang, rates, p, u)
        y = np.concatenate([d["w"], d["q"]])
        f = np.asarray(rigid_body.rhs(0.0, y, p, u))
        assert np.max(np.abs(f[:3] - d["w_dot"])) < 1e-12 * max(1.0, np.max(np.abs(d["w_dot"])))
        assert np.max(np.abs(f[3:] - d["q_dot"])) < 1e-13 * max(1.0, np.max(np.abs(d["q_dot"])))
        assert np.max(np.abs(f[3:] - derive.rigid_body_quaternion_rate(d["q"], d["w"]))) < 1e-14
        o = rigid_body.outputs_of(y, p)
        assert abs(o["E_kin"] + o["E_pot"] - d["E"]) < 1e-12 * max(1.0, abs(d["E"]))


def test_rigid_body_torque_free_conservation_and_intermediate_axis_flip():
    t = np.linspace(0.0, 20.0, 2001)
    r = rigid_body.simulate(None, None, t)
    H = np.vstack([r["H_X"], r["H_Y"], r["H_Z"]])
    assert np.max(np.abs(H - H[:, :1])) < 1e-10 * np.linalg.norm(H[:, 0])
    assert rel_err(r["E_kin"], np.full_like(t, r["E_kin"][0])) < 1e-10
    assert np.max(np.abs(r["q_norm"] - 1)) < 1e-10
    assert np.min(r["w_y"]) < -4.9 and np.max(r["w_y"]) > 4.9   # it flips (and back)


@pytest.mark.parametrize("axis", ["x", "z"])
def test_rigid_body_spin_about_extreme_axes_is_stable(axis):
    y0 = {"w_x": 0.01, "w_y": 0.01, "w_z": 0.01}
    y0["w_" + axis] = 5.0
    r = rigid_body.simulate(None, y0, np.linspace(0.0, 20.0, 2001))
    others = [a for a in "xyz" if a != axis]
    assert max(np.max(np.abs(r["w_" + a])) for a in others) < 0.05
    assert np.min(r["w_" + axis]) > 4.99


@pytest.mark.parametrize("Iz", [0.03, 0.005])   # oblate and prolate
def test_rigid_body_axisymmetric_torque_free_closed_form(Iz):
    p = rigid_body.params(I_xx=0.01, I_yy=0.01, I_zz=Iz)
    w0 = (0.3, -0.2, 4.0)
    t = np.linspace(0.0, 20.0, 2001)
    r = rigid_body.simulate(p, {"w_x": w0[0], "w_y": w0[1], "w_z": w0[2]}, t)
    wx, wy, wz = rigid_body.torque_free_axisymmetric(p, w0, t)
    assert np.max(np.abs(r["w_x"] - wx)) < 1e-9 and np.max(np.abs(r["w_y"] - wy)) < 1e-9
    assert np.max(np.abs(r["w_z"] - 4.0)) < 1e-12
    # direction: the angle of (w_x, w_y) advances at (I3 - I1)/I1 w_z (unwrapped phase slope)
    ang = np.unwrap(np.arctan2(r["w_y"], r["w_x"]))
    rate = (ang[-1] - ang[0]) / 20.0
    assert abs(rate - (Iz - 0.01) / 0.01 * 4.0) < 1e-8 * abs(rate)


def test_rigid_body_heavy_top_conserves_H_Z_and_energy():
    p = rigid_body.params(I_xy=0.001, r_Cx=0.02, r_Cy=0.01, r_Cz=0.15)
    q = rigid_body.quat_axis("x", 0.7)
    y0 = {"w_x": 1.0, "w_y": -2.0, "w_z": 30.0, "q_w": q[0], "q_x": q[1], "q_y": q[2], "q_z": q[3]}
    t = np.linspace(0.0, 10.0, 1001)
    r = rigid_body.simulate(p, y0, t)
    E = r["E_kin"] + r["E_pot"]
    assert np.ptp(r["E_pot"]) > 0.01                                   # gravity does work
    assert np.max(np.abs(E - E[0])) < 1e-10 * np.max(np.abs(r["E_kin"]))
    assert np.max(np.abs(r["H_Z"] - r["H_Z"][0])) < 1e-10 * np.max(np.abs(r["H_Z"]))
    assert np.ptp(r["H_X"]) > 1e-3                                     # H_X, H_Y are not conserved


@pytest.mark.parametrize("theta", [0.5, 2.0])
@pytest.mark.parametrize("root", [0, 1])
def test_rigid_body_steady_precession(theta, root):
    p = rigid_body.params(I_xx=0.01, I_yy=0.01, I_zz=0.02, r_Cz=0.1)
    w3 = 50.0
    Om = rigid_body.precession_rates(p, theta, w3)[root]
    IB = rigid_body.inertia_about_pivot(p)
    # the steady-precession condition M g d = Omega (I3 w3 - I1 Omega cos theta)
    assert abs(Om * (IB[2, 2] * w3 - IB[0, 0] * Om * math.cos(theta)) - p["M"] * p["g"] * 0.1) < 1e-12
    t = np.linspace(0.0, 5.0, 501)
    r = rigid_body.simulate(p, rigid_body.precession_state(p, theta, w3, Om), t)
    W, Q = rigid_body.precession_motion(theta, w3, Om, t)
    assert np.max(np.abs(np.vstack([r["w_x"], r["w_y"], r["w_z"]]) - W)) < 1e-9 * max(w3, abs(Om))
    assert np.max(np.abs(np.vstack([r["q_w"], r["q_x"], r["q_y"], r["q_z"]]) - Q)) < 1e-9
    # the nutation angle stays theta: body z in ground axes has Z-component cos theta
    zz = 1 - 2 * (r["q_x"] ** 2 + r["q_y"] ** 2)
    assert np.max(np.abs(zz - math.cos(theta))) < 1e-10


def test_rigid_body_slow_precession_approximation():
    p = rigid_body.params(I_xx=0.01, I_yy=0.01, I_zz=0.02, r_Cz=0.1)
    slow, fast = rigid_body.precession_rates(p, 0.5, 2000.0)
    approx = p["M"] * p["g"] * 0.1 / (0.02 * 2000.0)
    assert abs(slow - approx) < 1e-3 * approx and fast > 100 * slow


# ============================================================================ DoublePendulumCart

def random_dpc_states(n):
    for _ in range(n):
        y = RNG.uniform(-1.0, 1.0, 6) * np.array([1.0, 3.0, 7.0, 10.0, 7.0, 10.0])
        yield y, {"F": float(RNG.normal(0.0, 5.0))}


def test_double_pendulum_cart_lagrange_equals_newton_equals_reference():
    """sympy's Lagrange (T, V, the virtual work of F and the drag) and sympy's Newton (the
    three bodies, tensions and the track's normal force unknown) against the reference's
    numeric Newton solve: accelerations, tensions, E and p_x."""
    lag, ne = derive.double_pendulum_cart_lagrange(), derive.double_pendulum_cart_newton_euler()
    p = double_pendulum_cart.params(M=1.7, m1=0.4, m2=0.9, l1=0.7, l2=0.3, c=0.6)
    for y, u in random_dpc_states(25):
        a = lag(y, p, u)
        b = ne(y, p, u)
        r = double_pendulum_cart.newton(y, p, u["F"])
        scale = max(1.0, np.max(np.abs(a)))
        assert np.max(np.abs(a - [b["x_ddot"], b["phi1_ddot"], b["phi2_ddot"]])) < 1e-12 * scale
        assert np.max(np.abs(a - r[:3])) < 1e-12 * scale
        t_scale = max(1.0, abs(r[3]), abs(r[4]))
        assert abs(b["T1"] - r[3]) < 1e-12 * t_scale and abs(b["T2"] - r[4]) < 1e-12 * t_scale
        # the track holds the cart up: N = M g - (rod 1's pull on the cart, vertically)
        assert abs(b["N"] - (p["M"] * p["g"] + r[3] * math.cos(y[2]))) < 1e-12 * max(1.0, abs(b["N"]))
        assert abs(lag.energy(y, p, u) - double_pendulum_cart.energy(y, p)) < 1e-13 * max(1.0, abs(lag.energy(y, p, u)))
        assert abs(lag.momentum(y, p, u) - double_pendulum_cart.momentum(y, p)) < 1e-13 * max(1.0, abs(
            lag.momentum(y, p, u)))


def test_double_pendulum_cart_lagrange_is_the_written_out_equations():
    """Symbolically: the mass matrix and right-hand side sympy derives from T, V and Q are
    the equations written out in fmus/double_pendulum_cart/src/lib.rs and its NOTES."""
    import sympy as sp
    S = derive.double_pendulum_cart_symbolic()
    x, a, b = S["q"]
    xd, ad, bd = S["qd"]
    M, m1, m2, l1, l2, g, c = S["params"]
    (F,) = S["inputs"]
    m12, d = m1 + m2, a - b
    written_M = sp.Matrix([[M + m12, m12 * l1 * sp.cos(a), m2 * l2 * sp.cos(b)],
                           [m12 * l1 * sp.cos(a), m12 * l1 ** 2, m2 * l1 * l2 * sp.cos(d)],
                           [m2 * l2 * sp.cos(b), m2 * l1 * l2 * sp.cos(d), m2 * l2 ** 2]])
    written_f = sp.Matrix([F - c * xd + m12 * l1 * ad ** 2 * sp.sin(a) + m2 * l2 * bd ** 2 * sp.sin(b),
                           -m12 * g * l1 * sp.sin(a) - m2 * l1 * l2 * bd ** 2 * sp.sin(d),
                           -m2 * g * l2 * sp.sin(b) + m2 * l1 * l2 * ad ** 2 * sp.sin(d)])
    assert sp.simplify(S["M"] - written_M) == sp.zeros(3, 3)
    assert sp.simplify(sp.expand_trig(S["f"] - written_f)) == sp.zeros(3, 1)


def test_double_pendulum_cart_invariants_and_balances():
    """Free: E and p_x constant over 20 s of a chaotic swing. Forced and damped: E - E(0) and
    p_x - p_x(0) equal the work and the impulse of F and the drag integrated alongside."""
    t = np.linspace(0.0, 20.0, 2001)
    r = double_pendulum_cart.simulate(None, {"phi1": 2.0, "phi2": 1.0, "x_dot": 0.4}, t)
    assert rel_err(r["E"], np.full_like(t, r["E"][0])) < 1e-10
    assert rel_err(r["p_x"], np.full_like(t, r["p_x"][0])) < 1e-10
    p = double_pendulum_cart.params(c=0.5)
    t = np.linspace(0.0, 10.0, 1001)
    inp = step_input(["F"], [0.0, 1.0, 3.0, 5.0, 7.0], [[0.0], [2.0], [-3.0], [1.5], [0.0]], t_end=10.0)
    r = double_pendulum_cart.simulate(p, None, t, inp)
    assert np.max(np.abs(r["E"] - r["E"][0] - r["W_nc"])) < 1e-10 * np.max(np.abs(r["W_nc"]))
    assert np.max(np.abs(r["p_x"] - r["p_x"][0] - r["J_nc"])) < 1e-10 * np.max(np.abs(r["J_nc"]))
    assert np.max(np.abs(r["W_nc"])) > 1.0 and np.max(np.abs(r["J_nc"])) > 1.0  # the force and the drag acted


# ============================================================================ energy rate, pointwise

def _energy_rate_check(S, states, rhs, p, pnames, inputs, power, n=15):
    """dE/dt = grad(E) . y' at random states equals the power of the non-conservative forces."""
    import sympy as sp
    order = [S["q"][0], S["qd"][0], S["q"][1], S["qd"][1]] + ([S["q"][2], S["qd"][2]] if len(S["q"]) > 2 else [])
    grad = sp.lambdify(order + S["params"], [sp.diff(S["energy"], v) for v in order], "numpy")
    for y, u in states(n):
        g = np.array(grad(*y, *[p[k] for k in pnames]), float)
        yd = np.asarray(rhs(0.0, y, p, u), float)[: len(order)]
        P = power(y, p, u)
        assert abs(g @ yd - P) < 1e-10 * max(1.0, np.max(np.abs(g * yd))), (g @ yd, P)


def test_pendulum_cart_energy_rate_pointwise():
    p = pendulum_cart.params(c1=0.7, c2=0.05)
    _energy_rate_check(derive.pendulum_cart_symbolic(), random_cart_states, pendulum_cart.rhs, p,
                       ["M", "m", "l", "k", "c1", "c2", "g"], ["F"],
                       lambda y, p, u: pendulum_cart.power(y, p, u["F"]))


def test_crane_dynamics_energy_rate_pointwise():
    p = crane_dynamics.params()
    _energy_rate_check(derive.crane_dynamics_symbolic(), random_cd_states, crane_dynamics.rhs, p,
                       ["m", "l", "g", "J_boom", "m_trolley"], ["F", "tau"],
                       lambda y, p, u: u["F"] * y[1] + u["tau"] * y[3])


def test_double_pendulum_cart_energy_rate_pointwise():
    p = double_pendulum_cart.params(c=0.7)
    _energy_rate_check(derive.double_pendulum_cart_symbolic(), random_dpc_states, double_pendulum_cart.rhs, p,
                       list(double_pendulum_cart.PARAMS), ["F"],
                       lambda y, p, u: double_pendulum_cart.power(y, p, u["F"]))
