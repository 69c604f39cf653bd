"""The TwoMassOscillator FMU against its contract (docs/mechanisms/TwoMassOscillator.md) under FMPy.

    m1 x1'' + (c1+c3) x1' - c3 x2' + (k1+k3) x1 - k3 x2 = F1
    m2 x2'' + (c2+c3) x2' - c3 x1' + (k2+k3) x2 - k3 x1 = F2

References written here from the mathematics, not from mechfmu's Rust code:

* the notes' closed form of det(K - w^2 M) = 0 for the frequencies and the null vector of
  K - w^2 M for the shapes (and scipy's generalized eigensolver as a second route);
* a start on a mode shape is a cos(w t), exactly;
* the damped, forced (piecewise-constant forces) response by the matrix exponential of the
  first-order system on each segment, and the independent DOP853 reference of
  tests/python/refs/two_mass.py as a second route;
* the work-energy balance dE/dt = F1 x1' + F2 x2' - c1 x1'^2 - c2 x2'^2 - c3 (x1' - x2')^2.

Achieved figures are written to target/test-figures/two_mass_oscillator.{json,md}.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from scipy.integrate import simpson
from scipy.linalg import eigh, expm, solve

from fmutest import figure_row as _row, max_error, record_figures, simulate, simulate_refused
from refs import step_input, two_mass

NAME = "TwoMassOscillator"
FIGURES = "two_mass_oscillator"
REL_LIMIT = 1e-6  # max |FMU - reference| / range (or amplitude) of the reference
STOP = 30.0

PARAMETERS = dict(m1=1.0, m2=1.0, k1=1.0, k2=1.0, k3=1.0, c1=0.0, c2=0.0, c3=0.0)
STARTS = dict(x1=1.0, x2=0.0, x1_dot=0.0, x2_dot=0.0)

CALCULATED = ["omega_n1", "omega_n2", "mode1_x1", "mode1_x2", "mode2_x1", "mode2_x2"]


# =======================================================================================
# References


def matrices(p: dict):
    """M, C, K of M x'' + C x' + K x = F, from the two equations of the contract."""
    M = np.diag([p["m1"], p["m2"]])
    C = np.array([[p["c1"] + p["c3"], -p["c3"]], [-p["c3"], p["c2"] + p["c3"]]])
    K = np.array([[p["k1"] + p["k3"], -p["k3"]], [-p["k3"], p["k2"] + p["k3"]]])
    return M, C, K


def notes_closed_form(p: dict) -> dict:
    """The notes' omega^2 = [B -+ sqrt(B^2 - 4 m1 m2 C)] / (2 m1 m2) and a1/a2 from the first
    row, k3 / (k1 + k3 - m1 w^2); shapes scaled so the larger |component| is +1 (x1 on a tie).
    The smaller root is computed as 2C / (B + sqrt(D)): the same number without cancellation."""
    m1, m2, k1, k2, k3 = (p[n] for n in ("m1", "m2", "k1", "k2", "k3"))
    B = m1 * k2 + m2 * k1 + (m1 + m2) * k3
    C = k1 * k2 + (k1 + k2) * k3
    sD = math.sqrt(B * B - 4.0 * m1 * m2 * C)
    w2 = [2.0 * C / (B + sD), (B + sD) / (2.0 * m1 * m2)]
    out = {"omega_n1": math.sqrt(w2[0]), "omega_n2": math.sqrt(w2[1])}
    for i, w2i in enumerate(w2, start=1):
        r = (k1 + k3 - m1 * w2i) / k3  # a2 / a1
        a = (1.0, r) if abs(r) <= 1.0 else (1.0 / r, 1.0)
        out[f"mode{i}_x1"], out[f"mode{i}_x2"] = a
    return out


def exact_linear_response(p: dict, y0, t: np.ndarray, switch_times, forces):
    """Exact solution of M x'' + C x' + K x = F(t) for piecewise-constant F (forces[i] holds
    from switch_times[i]): y = y_eq + expm(A (t - t_i)) (y(t_i) - y_eq) on each segment, with
    A = [[0, I], [-M^-1 K, -M^-1 C]] and y_eq = (K^-1 F, 0). Returns states [4, n] and the
    accelerations [2, n] with the force held over the step that ends at each sample (what a
    co-simulation FMU reports), and the force on each sample's step [2, n]."""
    M, C, K = matrices(p)
    Minv = np.linalg.inv(M)
    A = np.block([[np.zeros((2, 2)), np.eye(2)], [-Minv @ K, -Minv @ C]])
    Y = np.empty((4, t.size))
    y = np.asarray(y0, dtype=float)
    edges = list(switch_times) + [math.inf]
    for i in range(len(switch_times)):
        a, b = edges[i], edges[i + 1]
        F = np.asarray(forces[i], dtype=float)
        y_eq = np.concatenate([solve(K, F), np.zeros(2)])
        sel = (t >= a) & (t <= b) if i == 0 else (t > a) & (t <= b)
        Y[:, sel] = y_eq[:, None] + np.stack([expm(A * (tt - a)) @ (y - y_eq) for tt in t[sel]], axis=1)
        if b < math.inf:
            y = y_eq + expm(A * (b - a)) @ (y - y_eq)
    # force on the step that ends at each sample (at t = 0: the force applied at t = 0)
    idx = np.searchsorted(np.asarray(switch_times), t, side="left") - 1
    idx[0] = 0
    Fs = np.asarray(forces, dtype=float)[np.clip(idx, 0, None)].T
    acc = Minv @ (Fs - C @ Y[2:] - K @ Y[:2])
    return Y, acc, Fs


def energy(p: dict, x1, x2, v1, v2):
    return 0.5 * (p["m1"] * v1 ** 2 + p["m2"] * v2 ** 2 + p["k1"] * x1 ** 2 + p["k2"] * x2 ** 2
                  + p["k3"] * (x1 - x2) ** 2)


def params(**kw) -> dict:
    p = dict(PARAMETERS)
    p.update({k: float(v) for k, v in kw.items()})
    return p


# =======================================================================================
# The FMU file (its modelDescription: fmus/two_mass_oscillator/validation/contract.toml, test_contract.py)


def test_start_values_read_back_after_initialization(slave):
    s = slave(NAME)
    s.initialize()
    names = list(PARAMETERS) + ["F1", "F2"] + list(STARTS)
    got = dict(zip(names, s.get(*names)))
    assert got == {**PARAMETERS, "F1": 0.0, "F2": 0.0, **STARTS}
    # x1 = 1 at rest, k1 = k3 = 1: x1'' = -(k1 + k3) / m1 = -2, x2'' = k3 / m2 = 1, E = 1
    assert s.get("x1_ddot", "x2_ddot", "E") == [-2.0, 1.0, 1.0]


# =======================================================================================
# Frequencies and mode shapes

MODE_SETS = [
    dict(),                                               # notes: m1 = m2, k1 = k2 = k3
    dict(m1=1.0, m2=2.0, k1=0.0, k2=0.0, k3=1.0),         # notes: 2 m1 = m2, k1 = k2 = 0
    dict(m1=2.0, m2=1.0, k1=3.0, k2=0.5, k3=2.0),
    dict(m1=0.3, m2=7.0, k1=12.0, k2=0.1, k3=0.4),
    dict(m1=5.0, m2=0.2, k1=0.0, k2=3.0, k3=9.0),
    dict(m1=1.0, m2=1.0, k1=1.0, k2=4.0, k3=0.01),        # weak coupling
    dict(m1=4e-3, m2=2.5, k1=3e4, k2=2.0, k3=50.0),       # widely spread scales
]


def _calculated(slave, p: dict) -> dict:
    s = slave(NAME)
    s.initialize({k: v for k, v in p.items()})
    return dict(zip(CALCULATED, s.get(*CALCULATED)))


@pytest.mark.parametrize("overrides", MODE_SETS, ids=lambda d: ",".join(f"{k}={v}" for k, v in d.items()) or "defaults")
def test_modes_equal_the_notes_closed_form(slave, overrides):
    p = params(**overrides)
    got = _calculated(slave, p)
    want = notes_closed_form(p)
    eig = two_mass.modes_eig(p)  # scipy's generalized eigensolver (second route)
    w_scale = want["omega_n2"]
    rows, failures = [], []
    for n in CALCULATED:
        scale = w_scale if n.startswith("omega") else 1.0
        err = abs(got[n] - want[n])
        rows.append(_row(n, err, scale, err / scale, 1e-13, None))
        if err > 1e-13 * scale:
            failures.append(f"{n}: FMU {got[n]!r}, closed form {want[n]!r}")
        assert abs(eig[n] - want[n]) <= 1e-12 * scale, f"the two references disagree on {n}"
    # residual of the eigenproblem with the FMU's own values
    M, _, K = matrices(p)
    for i in (1, 2):
        a = np.array([got[f"mode{i}_x1"], got[f"mode{i}_x2"]])
        assert max(abs(a)) == 1.0 and 1.0 in a, f"mode {i} {a} is not scaled to a largest component of +1"
        r = (K - got[f"omega_n{i}"] ** 2 * M) @ a
        assert np.max(np.abs(r)) <= 1e-12 * np.max(np.abs(K)), f"mode {i}: (K - w^2 M) a = {r}"
    record_figures(FIGURES, "modes " + (",".join(f"{k}={v}" for k, v in overrides.items()) or "defaults"),
                   {"params": p, "variables": rows})
    assert not failures, "\n".join(failures)


def test_the_notes_two_examples(slave):
    m, k = 1.7, 2.3
    got = _calculated(slave, params(m1=m, m2=m, k1=k, k2=k, k3=k))
    assert got["omega_n1"] == pytest.approx(math.sqrt(k / m), rel=1e-15)
    assert got["omega_n2"] == pytest.approx(math.sqrt(3 * k / m), rel=1e-15)
    assert [got[n] for n in CALCULATED[2:]] == [1.0, 1.0, 1.0, -1.0]  # 1 : 1 and 1 : -1, exact ties

    got = _calculated(slave, params(m1=m, m2=2 * m, k1=0.0, k2=0.0, k3=k))
    assert got["omega_n1"] == 0.0
    assert got["omega_n2"] == pytest.approx(math.sqrt(3 * k / (2 * m)), rel=1e-15)
    assert (got["mode1_x1"], got["mode1_x2"]) == (1.0, 1.0)
    # The notes: a1/a2 = -2, so with the larger component +1 the shape is (1, -1/2)
    # (momentum m1 a1 + m2 a2 = 0 for a free pair).
    assert got["mode2_x1"] == 1.0
    assert got["mode2_x2"] == pytest.approx(-0.5, abs=2e-16)


def test_frequencies_follow_a_tunable_stiffness(slave):
    s = slave(NAME)
    s.initialize()
    s.step(0.0, 0.01)
    s.set(k3=4.0, k1=0.0, k2=0.0)
    got = dict(zip(CALCULATED, s.get(*CALCULATED)))
    want = notes_closed_form(params(k1=0.0, k2=0.0, k3=4.0))
    assert got["omega_n1"] == 0.0
    for n in CALCULATED:
        assert got[n] == pytest.approx(want[n], rel=1e-14, abs=1e-15), n


# =======================================================================================
# Responses

SINE_SETS = [dict(), dict(m1=1.0, m2=2.0, k1=0.0, k2=0.0, k3=1.0), dict(m1=1.3, m2=0.7, k1=2.0, k2=0.5, k3=1.1),
             dict(m1=0.3, m2=7.0, k1=12.0, k2=0.1, k3=0.4)]


@pytest.mark.parametrize("mode", [1, 2])
@pytest.mark.parametrize("overrides", SINE_SETS, ids=["notes1", "notes2", "set3", "set4"])
def test_a_start_on_a_mode_stays_a_pure_sinusoid(fmu, overrides, mode):
    """x(0) = A a, x'(0) = 0 gives x(t) = A a cos(w t) for 30 s (closed-form w and a)."""
    p = params(**overrides)
    md = notes_closed_form(p)
    w, a = md[f"omega_n{mode}"], np.array([md[f"mode{mode}_x1"], md[f"mode{mode}_x2"]])
    A = 0.3
    res = simulate(fmu(NAME), relative_tolerance=1e-8, output_interval=0.01, stop_time=STOP,
                   start_values={**overrides, "x1": A * a[0], "x2": A * a[1]},
                   output=["x1", "x2", "x1_dot", "x2_dot", "x1_ddot", "x2_ddot"])
    t = res.time
    assert t[-1] == pytest.approx(STOP)
    c, s = np.cos(w * t), np.sin(w * t)
    ref = {"x1": A * a[0] * c, "x2": A * a[1] * c, "x1_dot": -A * a[0] * w * s, "x2_dot": -A * a[1] * w * s,
           "x1_ddot": -A * a[0] * w * w * c, "x2_ddot": -A * a[1] * w * w * c}
    amp = {"x1": A, "x2": A, "x1_dot": A * w, "x2_dot": A * w, "x1_ddot": A * w * w, "x2_ddot": A * w * w}
    rows, failures = [], []
    for n, r in ref.items():
        err = float(np.max(np.abs(res[n] - r)))
        if amp[n] == 0.0:  # the zero mode at rest: the masses must not move at all
            assert err <= 1e-12, f"{n}: {err:.3e} for a start at rest on the zero mode"
            continue
        rel = err / amp[n]
        i = int(np.argmax(np.abs(res[n] - r)))
        rows.append(_row(n, err, amp[n], rel, REL_LIMIT, float(t[i]), 0.01))
        if rel > REL_LIMIT:
            failures.append(f"{n}: max error {err:.3e} = {rel:.3e} of amplitude at t = {t[i]:.4g}")
    record_figures(FIGURES, f"pure mode {mode} {overrides or 'defaults'}",
                   {"case": "start on a mode shape, |error| / amplitude", "params": p, "variables": rows})
    assert not failures, "\n".join(failures)


def test_free_pair_translates_rigidly(fmu):
    """k1 = k2 = 0 and a start on the zero-frequency mode with a velocity: x = x0 + v t."""
    p = params(m1=1.0, m2=2.0, k1=0.0, k2=0.0, k3=1.0, c3=0.3)
    res = simulate(fmu(NAME), relative_tolerance=1e-8, output_interval=0.1, stop_time=STOP,
                   start_values={**{k: p[k] for k in ("m2", "k1", "k2", "c3")}, "x1": 0.2, "x2": 0.2,
                                 "x1_dot": -0.5, "x2_dot": -0.5},
                   output=["x1", "x2", "x1_dot", "x2_dot"])
    ref = 0.2 - 0.5 * res.time
    for n in ("x1", "x2"):
        err, rng, _ = max_error(res[n], ref)
        assert err <= REL_LIMIT * rng, f"{n}: {err:.3e} of {rng}"


DAMPED = dict(m1=1.2, m2=0.8, k1=1.0, k2=2.0, k3=0.5, c1=0.1, c2=0.05, c3=0.2)
SWITCHES = [0.0, 3.0, 7.5, 12.0, 20.0]
FORCES = [(0.0, 0.0), (1.0, 0.0), (1.0, -2.0), (-0.5, 0.7), (0.0, 0.0)]
Y0 = dict(x1=0.3, x2=-0.1, x1_dot=0.0, x2_dot=0.4)


def _damped_forced_run(fmu, interval: float):
    p = params(**DAMPED)
    inp = step_input(["F1", "F2"], SWITCHES, FORCES, t_end=STOP)
    res = simulate(fmu(NAME), relative_tolerance=1e-8, output_interval=interval, stop_time=STOP,
                   start_values={**DAMPED, **Y0}, input=inp,
                   output=["x1", "x2", "x1_dot", "x2_dot", "x1_ddot", "x2_ddot", "E"])
    return p, inp, res


@pytest.mark.parametrize("interval", [0.01, 0.05])
def test_damped_forced_matches_exact_solution(fmu, interval):
    p, inp, res = _damped_forced_run(fmu, interval)
    t = res.time
    assert t[-1] == pytest.approx(STOP)
    Y, acc, _ = exact_linear_response(p, [Y0[n] for n in ("x1", "x2", "x1_dot", "x2_dot")], t, SWITCHES, FORCES)
    ref = {"x1": Y[0], "x2": Y[1], "x1_dot": Y[2], "x2_dot": Y[3], "x1_ddot": acc[0], "x2_ddot": acc[1],
           "E": energy(p, *Y)}
    # second, independent route: DOP853 at rtol 1e-12 (tests/python/refs/two_mass.py)
    dop = two_mass.simulate(p, Y0, t, inp, switch_outputs="before")
    rows, failures = [], []
    for n, r in ref.items():
        err, rng, i = max_error(res[n], r)
        rel = err / rng
        rows.append(_row(n, err, rng, rel, REL_LIMIT, float(t[i]), interval))
        if rel > REL_LIMIT:
            failures.append(f"{n}: max error {err:.3e} = {rel:.3e} of range at t = {t[i]:.4g}")
        if n in dop:
            assert np.max(np.abs(dop[n] - r)) <= 1e-9 * rng, f"the two references disagree on {n}"
    record_figures(FIGURES, f"damped+forced@{interval}", {"case": "c1, c2, c3 > 0, step forces F1, F2",
                                                         "params": p, "variables": rows})
    assert not failures, "\n".join(failures)


def test_energy_balance_damped_forced(fmu):
    """E(t) - E(0) = integral of F1 x1' + F2 x2' - c1 x1'^2 - c2 x2'^2 - c3 (x1' - x2')^2, the
    power integrated by Simpson's rule on each constant-force segment (fine output grid)."""
    h = 0.005
    p, _, res = _damped_forced_run(fmu, h)
    t = res.time
    x1, x2, v1, v2, E = (res[n] for n in ("x1", "x2", "x1_dot", "x2_dot", "E"))
    # E is the energy of the states it is reported with
    assert np.max(np.abs(E - energy(p, x1, x2, v1, v2))) <= 1e-14 * np.max(np.abs(E))
    edges = SWITCHES[1:] + [STOP]
    W = [0.0]
    t_at = [0.0]
    for (a, b), F in zip(zip(SWITCHES, edges), FORCES):
        sel = (t >= a - 1e-9) & (t <= b + 1e-9)
        tt = t[sel]
        P = (F[0] * v1[sel] + F[1] * v2[sel] - p["c1"] * v1[sel] ** 2 - p["c2"] * v2[sel] ** 2
             - p["c3"] * (v1[sel] - v2[sel]) ** 2)
        assert len(tt) % 2 == 1, "Simpson's rule wants an even number of intervals per segment"
        W.append(W[-1] + simpson(P, x=tt))
        t_at.append(b)
    E_at = np.interp(t_at, t, E)
    err = np.abs(E_at - E_at[0] - np.asarray(W))
    scale = float(np.max(E) - np.min(E))
    worst = float(np.max(err))
    record_figures(FIGURES, "energy balance damped+forced",
                   {"case": "|E(t) - E(0) - W(t)| at the force switches / range of E", "params": p,
                    "variables": [_row("E - W", worst, scale, worst / scale, 1e-7, float(t_at[int(np.argmax(err))]), h)]})
    assert worst <= 1e-7 * scale, f"work-energy balance off by {worst:.3e} (E range {scale:.3g})"


def test_default_experiment_runs_without_arguments(fmu):
    res = simulate(fmu(NAME), relative_tolerance=None, output=["x1", "x2"])
    assert res.time[-1] == pytest.approx(STOP)
    # defaults: x(0) = (1, 0) = 1/2 (1, 1) + 1/2 (1, -1): modes at 1 and sqrt(3)
    ref = 0.5 * np.cos(res.time) + 0.5 * np.cos(math.sqrt(3.0) * res.time)
    err, rng, _ = max_error(res["x1"], ref)
    assert err <= 1e-3 * rng  # the DefaultExperiment's own tolerance (1e-6): a loose sanity bound


# =======================================================================================
# Invalid parameters


@pytest.mark.parametrize("name,value", [("m1", 0.0), ("m2", -1.0), ("k1", -0.5), ("k3", -2.0), ("c2", -0.1)])
def test_invalid_parameter_fails_initialization(slave, name, value):
    slave(NAME).expect_refused_at_initialization(name, value)


def test_zero_mass_makes_simulate_fmu_raise(fmu):
    mark = simulate_refused(fmu(NAME), {"m2": 0.0})
    assert any("m2" in r.message for r in mark.records), mark.text()


def test_legal_sequence_logs_no_error(slave):
    slave(NAME).expect_steps_without_error({"k1": 0.0, "k2": 0.0})
