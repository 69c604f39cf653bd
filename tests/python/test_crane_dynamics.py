"""The CraneDynamics FMU against its contract (docs/mechanisms/CraneDynamics.md) under FMPy.

The crane of `Crane` driven by the trolley drive's force F and the boom drive's torque tau,
with a boom inertia J_boom about O and a trolley mass m_trolley; x, theta and phi all follow
from the equations of motion M(q) q'' = f (Lagrange). The references do not reuse the FMU's
code or its equations as written:

* accelerations from the Lagrangian and T, N from the free-body diagrams of payload,
  trolley and boom, both derived with sympy in refs/derive/crane_dynamics.py; the trajectory reference
  integrates the Lagrangian with scipy DOP853 (rtol 1e-12) under the same zero-order hold
  of the inputs as fmpy;
* the total mechanical energy written here from the bodies' velocities in ground
  coordinates; its rate against the power of F and tau;
* the notes' formula (a) for T written here, applied to the simulated motion (with the
  accelerations differentiated numerically from the FMU's velocities as well);
* the static loads F = (m + m_trolley) g sin(theta), tau = x (m + m_trolley) g cos(theta).

Achieved errors are written to target/test-figures/crane_dynamics.{json,md}.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from fmpy.fmi2 import fmi2Discard, fmi2OK, fmi2Warning

import fmutest
from fmutest import LogMark, compare_to_reference, record_figures, simulate, status_name
from refs import crane_dynamics as ref_cd
from refs import derive, step_input
from refs._common import run as run_reference

NAME = "CraneDynamics"
FIG = "crane_dynamics"
REL_LIMIT = 1e-6
RTOL = 1e-8
P = {"m": 1000.0, "l": 5.0, "g": 9.81, "J_boom": 5000.0, "m_trolley": 200.0}
START = {"x": 10.0, "x_dot": 0.0, "theta": 0.5, "theta_dot": 0.0, "phi": 0.0, "phi_dot": 0.0}
STATES = ("x", "x_dot", "theta", "theta_dot", "phi", "phi_dot")


# =======================================================================================
# References written in this file


def static_loads(x: float, theta: float, p=P):
    mu = p["m"] + p["m_trolley"]
    return mu * p["g"] * math.sin(theta), x * mu * p["g"] * math.cos(theta)


def energy(r, p=P):
    """Kinetic + gravitational energy of boom, trolley and payload (heights from O)."""
    x, v, th, w, ph, phd = (np.asarray(r[n], float) for n in STATES)
    m, mt, l, g = p["m"], p["m_trolley"], p["l"], p["g"]
    # trolley at x (cos th, sin th); payload 'l' below it along (sin ph, -cos ph)
    tvx, tvy = v * np.cos(th) - x * w * np.sin(th), v * np.sin(th) + x * w * np.cos(th)
    pvx, pvy = tvx + l * phd * np.cos(ph), tvy + l * phd * np.sin(ph)
    kin = 0.5 * p["J_boom"] * w ** 2 + 0.5 * mt * (tvx ** 2 + tvy ** 2) + 0.5 * m * (pvx ** 2 + pvy ** 2)
    pot = mt * g * x * np.sin(th) + m * g * (x * np.sin(th) - l * np.cos(ph))
    return kin + pot


def tension_formula_a(r, xdd, thdd, p=P):
    """The notes' formula (a): T = m [(x'' - th'^2 x) sin s + (2 th' x' + th'' x) cos s
    + l phi'^2 + g cos phi], s = theta - phi."""
    x, v, th, w, ph, phd = (np.asarray(r[n], float) for n in STATES)
    s = th - ph
    return p["m"] * ((xdd - w * w * x) * np.sin(s) + (2 * w * v + thdd * x) * np.cos(s)
                     + p["l"] * phd ** 2 + p["g"] * np.cos(ph))


_LAG = None
_NE = None


def _lagrange_rhs(t, y, p, u):
    a = _LAG(y, p, u)
    return [y[1], a[0], y[3], a[1], y[5], a[2]]


def _outputs(t, y, p, u):
    o = _NE(y, p, u)
    r = {n: y[i] for i, n in enumerate(STATES)}
    return {"T": o["T"], "N": o["N"], "x_ddot": o["x_ddot"], "theta_ddot": o["theta_ddot"],
            "phi_ddot": o["phi_ddot"], "E": float(energy(r, p)),
            "payload_x": y[0] * math.cos(y[2]) + p["l"] * math.sin(y[4]),
            "payload_y": y[0] * math.sin(y[2]) - p["l"] * math.cos(y[4]),
            "P_drives": u["F"] * y[1] + u["tau"] * y[3]}


def reference(t_out, inputs, y0=None, p=P):
    """DOP853 (rtol = atol = 1e-12) of the Lagrangian M q'' = f (refs/derive/crane_dynamics.py, sympy),
    restarted at every input switch (zero-order hold); outputs at a switch time use the
    input held over the step that ends there, as fmpy records a co-simulation FMU."""
    global _LAG, _NE
    _LAG, _NE = derive.crane_dynamics_lagrange(), derive.crane_dynamics_newton_euler()
    s = dict(START)
    s.update(y0 or {})
    return run_reference(_lagrange_rhs, _outputs, STATES, [s[n] for n in STATES], np.asarray(t_out, float),
                         dict(p), {"F": 0.0, "tau": 0.0}, inputs, 1e-12, 1e-12, "before")


@pytest.fixture(scope="module")
def slave_module():
    made = []

    def make(name, **kwargs):
        made.append(fmutest.Slave(fmutest.fmu_path(name), **kwargs))
        return made[-1]

    yield make
    for s in made:
        s.free()


def compare(res, ref, names, interval, case, limit=REL_LIMIT):
    return compare_to_reference(FIG, res, ref, names, interval, case, limit)


def row(variable, value, limit, interval=None, scale=None):
    d = dict(variable=variable, relative=float(value), limit=limit, **{"pass": bool(value <= limit)})
    if interval is not None:
        d["output_interval"] = interval
    if scale is not None:
        d.update(max_error=float(value * scale), range=float(scale))
    return d


# Open loop: drive loads switched around the static ones, as an fmpy input (switch times on
# the 0.01 grid). Constant loads make the rest position a saddle (a boom raised by d(theta)
# needs less torque), so open-loop runs diverge: this case is kept to 4 s (x goes from 10 to
# 40 m, theta from 0.5 to -0.5 rad).
F0, TAU0 = static_loads(10.0, 0.5)
OPEN_STOP = 4.0
OPEN_TIMES = [0.0, 0.8, 1.6, 2.4, 3.2]
OPEN_FACTORS = [(1.3, 1.0), (1.0, 1.05), (0.7, 0.97), (1.0, 1.0), (1.1, 0.98)]
OPEN_INPUT = step_input(["F", "tau"], OPEN_TIMES, [[kf * F0, kt * TAU0] for kf, kt in OPEN_FACTORS],
                        t_end=OPEN_STOP)
OPEN_START = {"phi_dot": 0.2}

# Closed loop, 20 s: a PD controller written here, sampled every 0.01 s (zero-order hold),
# luffs the boom from 0.5 to 0.8 rad and moves the trolley from 10 to 15 m and back to 12 m
# along smooth set-point ramps, with the static loads fed forward.
MU = P["m"] + P["m_trolley"]
KX, DX, KT, DT = 1200.0, 1700.0, 1.25e5, 1.75e5
H_CTRL, N_CTRL, H_FINE = 0.01, 2000, 0.001


def _smooth(t, a, b):
    s = min(max((t - a) / (b - a), 0.0), 1.0)
    return s * s * (3 - 2 * s)


def controller(t, y):
    x_ref = 10.0 + 5.0 * _smooth(t, 7.0, 11.0) - 3.0 * _smooth(t, 14.0, 16.0)
    th_ref = 0.5 + 0.3 * _smooth(t, 2.0, 5.0)
    x, xd, th, thd = y[0], y[1], y[2], y[3]
    return {"F": MU * P["g"] * math.sin(th) + KX * (x_ref - x) - DX * xd,
            "tau": x * MU * P["g"] * math.cos(th) + KT * (th_ref - th) - DT * thd}


@pytest.fixture(scope="module")
def closed_loop_reference():
    """The closed loop with the Lagrangian plant (derive), DOP853 rtol = atol = 1e-12 over
    each 0.01 s control period, sampled every 1 ms; inputs recorded per sample as held over
    the step that ends there."""
    global _LAG, _NE
    _LAG, _NE = derive.crane_dynamics_lagrange(), derive.crane_dynamics_newton_euler()
    y = np.array([START[n] for n in STATES])
    n_fine = int(round(H_CTRL / H_FINE))
    rows, inputs = [y.copy()], [controller(0.0, y)]
    for k in range(N_CTRL):
        a = k * H_CTRL
        u = controller(a, y)
        te = a + H_FINE * np.arange(1, n_fine + 1)
        te[-1] = (k + 1) * H_CTRL
        sol = solve_ivp(_lagrange_rhs, (a, te[-1]), y, method="DOP853", t_eval=te, args=(P, u),
                        rtol=1e-12, atol=1e-12)
        assert sol.success
        rows.extend(sol.y.T)
        inputs.extend([u] * n_fine)
        y = sol.y[:, -1].copy()
    ref = _on_the_fine_grid(rows, STATES, inputs)
    Y = np.array(rows)
    outs = [_outputs(0.0, Y[j], P, inputs[j]) for j in range(Y.shape[0])]
    for k in outs[0]:
        ref[k] = np.array([o[k] for o in outs])
    return ref



def _on_the_fine_grid(rows, names, inputs):
    """A closed-loop run by name: ``rows`` of the values of ``names``, one every H_FINE from
    t = 0, and the drive loads ``inputs`` held at each."""
    data = np.array(rows)
    res = {"time": np.round(np.arange(data.shape[0]) * H_FINE, 12)}
    for i, n in enumerate(names):
        res[n] = data[:, i]
    res["F"] = np.array([u["F"] for u in inputs])
    res["tau"] = np.array([u["tau"] for u in inputs])
    return res

@pytest.fixture(scope="module")
def closed_loop_fmu(slave_module):
    """The same loop around the FMU: fmi2DoStep every 1 ms, the controller reads the FMU's
    states and sets F and tau every 10 steps (relative tolerance 1e-8)."""
    names = list(STATES) + ["T", "N", "x_ddot", "theta_ddot", "phi_ddot", "E", "W_drives", "P_drives",
                            "payload_x", "payload_y"]
    s = slave_module(NAME)
    s.initialize()
    n_fine = int(round(H_CTRL / H_FINE))
    y = s.get(*STATES)
    u = controller(0.0, y)
    s.set(**u)
    rows = [s.get(*names)]
    us = [u]
    for k in range(N_CTRL):
        u = controller(k * H_CTRL, s.get(*STATES))
        s.set(**u)
        for j in range(n_fine):
            t = k * H_CTRL + j * H_FINE
            h = (k + 1) * H_CTRL - t if j == n_fine - 1 else H_FINE
            s.step(t, h)
            rows.append(s.get(*names))
            us.append(u)
    res = _on_the_fine_grid(rows, names, us)
    assert not [r for r in s.log.records if r.status >= fmi2Warning], s.log.text()
    return res


class _Res(dict):
    """A dict that also answers .time, for compare()."""

    @property
    def time(self):
        return self["time"]


# =======================================================================================
# The references themselves (no FMU)


def test_reference_agrees_with_the_other_engineers_reference():
    """derive's Lagrangian (this file's reference) against refs/crane_dynamics.py (the same
    equations by hand, Cramer's rule) on the open-loop case."""
    t = np.linspace(0.0, OPEN_STOP, 401)
    a = reference(t, OPEN_INPUT, OPEN_START)
    b = ref_cd.simulate(None, OPEN_START, t, OPEN_INPUT, switch_outputs="before")
    for name in STATES + ("T", "N", "x_ddot", "theta_ddot", "E", "payload_x", "payload_y"):
        assert np.max(np.abs(a[name] - b[name])) <= 1e-9 * np.ptp(b[name]), name
    # taut cable, trolley out on the boom (which runs away: x reaches 40 m by t = 4 s)
    assert np.min(a["T"]) > 0.4 * P["m"] * P["g"] and 5.0 < np.min(a["x"]) and np.max(a["x"]) < 50.0


def test_closed_loop_reference_is_a_crane_move(closed_loop_reference):
    """The controller does what it is meant to (so the case is meaningful), and the
    reference's plant agrees with refs/crane_dynamics.py along it."""
    r = closed_loop_reference
    i = {t: int(round(t / H_FINE)) for t in (1.9, 6.9, 13.9, 20.0)}
    assert abs(r["theta"][i[1.9]] - 0.5) < 1e-3 and abs(r["theta"][i[6.9]] - 0.8) < 0.05
    assert abs(r["x"][i[13.9]] - 15.0) < 0.5 and abs(r["x"][i[20.0]] - 12.0) < 0.5
    assert 0.02 < np.max(np.abs(r["phi"])) < 0.2 and np.min(r["T"]) > 0.8 * P["m"] * P["g"]
    for j in range(0, r["time"].size, 997):
        y = [r[n][j] for n in STATES]
        acc = ref_cd.accelerations(y, P, r["F"][j], r["tau"][j])
        assert np.allclose(acc, [r["x_ddot"][j], r["theta_ddot"][j], r["phi_ddot"][j]], rtol=1e-10, atol=1e-12)


def test_energy_and_formula_a_references_agree_with_derive():
    rng = np.random.default_rng(11)
    lag, ne = derive.crane_dynamics_lagrange(), derive.crane_dynamics_newton_euler()
    for _ in range(20):
        y = [rng.uniform(1.0, 20.0), rng.normal(0, 2), rng.uniform(-1.5, 1.5), rng.normal(0, 0.5),
             rng.uniform(-2.5, 2.5), rng.normal(0, 1.5)]
        u = {"F": float(rng.normal(0, 5e3)), "tau": float(rng.normal(0, 5e4))}
        r = {n: y[i] for i, n in enumerate(STATES)}
        assert float(energy(r)) == pytest.approx(lag.energy(y, P, u), rel=1e-12, abs=1e-9)
        a = lag(y, P, u)
        assert float(tension_formula_a(r, a[0], a[1])) == pytest.approx(ne(y, P, u)["T"], rel=1e-9, abs=1e-6)


# =======================================================================================
# modelDescription: checked against fmus/crane_dynamics/validation/contract.toml by test_contract.py


# =======================================================================================
# Equations at scattered states (outputs at initialization: no integration involved)


def test_equations_match_lagrange_and_newton_euler_at_scattered_states(slave):
    rng = np.random.default_rng(5)
    lag, ne = derive.crane_dynamics_lagrange(), derive.crane_dynamics_newton_euler()
    names = ("x_ddot", "theta_ddot", "phi_ddot", "T", "N", "E", "payload_x", "payload_y")
    worst = dict.fromkeys(names, 0.0)
    for i in range(40):
        p = dict(P) if i % 2 == 0 else dict(P, J_boom=float(rng.uniform(500, 2e4)),
                                               m_trolley=float(rng.uniform(20, 2000)),
                                               m=float(rng.uniform(100, 5000)), l=float(rng.uniform(1, 20)))
        y = [rng.uniform(0.5, 20.0), rng.normal(0, 2), rng.uniform(-1.5, 1.5), rng.normal(0, 0.5),
             rng.uniform(-2.5, 2.5), rng.normal(0, 1.5)]
        u = {"F": float(rng.normal(0, 5e3)), "tau": float(rng.normal(0, 5e4))}
        s = slave(NAME)
        s.initialize({**{k: v for k, v in p.items() if v != P[k]}, **{n: y[j] for j, n in enumerate(STATES)}, **u})
        got = dict(zip(names, s.get(*names)))
        s.free()
        a, b = lag(y, p, u), ne(y, p, u)
        want = {"x_ddot": a[0], "theta_ddot": a[1], "phi_ddot": a[2], "T": b["T"], "N": b["N"],
                "E": lag.energy(y, p, u), "payload_x": y[0] * math.cos(y[2]) + p["l"] * math.sin(y[4]),
                "payload_y": y[0] * math.sin(y[2]) - p["l"] * math.cos(y[4])}
        # scales: the size of the terms that make each value up
        mg = p["m"] * p["g"]
        scale = {"x_ddot": p["g"], "theta_ddot": p["g"] / y[0], "phi_ddot": p["g"] / p["l"], "T": mg, "N": mg,
                 "E": mg * 20, "payload_x": 20.0, "payload_y": 20.0}
        for k in names:
            worst[k] = max(worst[k], abs(got[k] - want[k]) / max(abs(want[k]), scale[k]))
    record_figures(FIG, "scattered_states_vs_lagrange_newton_euler", {
        "case": "40 random states, inputs and parameters; outputs at initialization",
        "variables": [row(k, v, 1e-11) for k, v in worst.items()]})
    assert all(v <= 1e-11 for v in worst.values()), worst


# =======================================================================================
# At rest under the static loads


@pytest.mark.parametrize("x,theta", [(10.0, 0.5), (4.0, -0.3), (17.0, 1.1)])
def test_static_loads_hold_the_crane_at_rest(fmu, x, theta):
    F, tau = static_loads(x, theta)
    inp = step_input(["F", "tau"], [0.0], [[F, tau]], t_end=20.0)
    res = simulate(fmu(NAME), relative_tolerance=RTOL, output_interval=0.01, stop_time=20.0,
                   start_values={"x": x, "theta": theta}, input=inp)
    assert res.time[-1] == pytest.approx(20.0)
    moved = max(float(np.max(np.abs(res["x"] - x))), float(np.max(np.abs(res["theta"] - theta))),
                float(np.max(np.abs(res["phi"]))))
    speed = max(float(np.max(np.abs(res[n]))) for n in ("x_dot", "theta_dot", "phi_dot"))
    mg = P["m"] * P["g"]
    t_err = float(np.max(np.abs(res["T"] - mg)) / mg)
    record_figures(FIG, f"static_x{x}_theta{theta}", {
        "case": f"static loads at x = {x}, theta = {theta} for 20 s",
        "variables": [row("displacement", moved, 1e-9, 0.01), row("speed", speed, 1e-9, 0.01),
                      row("T_vs_mg", t_err, 1e-9, 0.01)]})
    assert moved <= 1e-9 and speed <= 1e-9 and t_err <= 1e-9, (moved, speed, t_err)


def test_default_experiment_holds_the_crane_at_rest(fmu):
    """The inputs start at the static loads of the default configuration."""
    res = simulate(fmu(NAME), relative_tolerance=None)
    assert res.time[-1] == pytest.approx(20.0)
    assert np.max(np.abs(res["x"] - 10.0)) <= 1e-9 and np.max(np.abs(res["theta"] - 0.5)) <= 1e-9
    assert np.max(np.abs(res["T"] - P["m"] * P["g"])) <= 1e-9 * P["m"] * P["g"]


# =======================================================================================
# Moving: trajectory, energy, tension


@pytest.mark.parametrize("interval", [0.01, 0.0137])
def test_open_loop_trajectory_matches_the_lagrangian_reference(fmu, interval):
    """Piecewise-constant F and tau as an fmpy input, 4 s."""
    res = simulate(fmu(NAME), relative_tolerance=RTOL, output_interval=interval, stop_time=OPEN_STOP,
                   start_values=OPEN_START, input=OPEN_INPUT)
    ref = reference(res.time, OPEN_INPUT, OPEN_START)
    names = list(STATES) + ["T", "N", "x_ddot", "theta_ddot", "phi_ddot", "payload_x", "payload_y", "E"]
    failures = compare(res, ref, names, interval, f"open_loop_h{interval}")
    assert not failures, "\n".join(failures)
    assert not [r for r in res.log if r.status >= fmi2Warning], [str(r) for r in res.log]


def test_closed_loop_trajectory_matches_the_lagrangian_reference(closed_loop_fmu, closed_loop_reference):
    """20 s under the PD controller (FMU and reference each closing their own loop)."""
    res, ref = _Res(closed_loop_fmu), closed_loop_reference
    assert np.array_equal(res["time"], ref["time"])
    names = list(STATES) + ["F", "tau", "T", "N", "x_ddot", "theta_ddot", "phi_ddot", "payload_x",
                            "payload_y", "E"]
    failures = compare(res, ref, names, H_FINE, "closed_loop_20s")
    assert not failures, "\n".join(failures)


def test_energy_balance_over_20_s(closed_loop_fmu):
    """Power of F and tau = rate of change of the total mechanical energy (E computed here
    from the states), three ways over the 20 s closed-loop run:
    * E(t) - E(0) against the FMU's W_drives;
    * against the work summed period by period: F and tau are constant over each 0.01 s
      control period, so their work there is exactly F dx + tau dtheta;
    * dE/dt by 4th-order central differences of E (1 ms samples, inside each control
      period) against F x_dot + tau theta_dot at the same instants."""
    r = closed_loop_fmu
    e = energy(r)
    gain = e - e[0]
    scale = float(np.max(np.abs(gain)))
    assert scale > 1e4, "the case must exchange energy"
    err_w = float(np.max(np.abs(r["W_drives"] - gain)) / scale)
    n_fine = int(round(H_CTRL / H_FINE))
    k = np.arange(0, r["time"].size, n_fine)  # control instants
    f, tau = r["F"][k[1:]], r["tau"][k[1:]]  # held over the period ending at k[1:]
    work = np.concatenate([[0.0], np.cumsum(f * np.diff(r["x"][k]) + tau * np.diff(r["theta"][k]))])
    err_sum = float(np.max(np.abs(work - gain[k])) / scale)
    # rates at the middle sample of each period (5-point stencil inside the period)
    power = r["F"] * r["x_dot"] + r["tau"] * r["theta_dot"]
    mid = k[:-1] + n_fine // 2
    dEdt = (-e[mid + 2] + 8 * e[mid + 1] - 8 * e[mid - 1] + e[mid - 2]) / (12 * H_FINE)
    p_scale = float(np.max(np.abs(power)))
    err_rate = float(np.max(np.abs(dEdt - power[mid])) / p_scale)
    err_p = float(np.max(np.abs(r["P_drives"] - power)) / p_scale)
    err_e = float(np.max(np.abs(r["E"] - e)) / scale)
    record_figures(FIG, "energy_balance_closed_loop_20s", {
        "case": "E(t) - E(0) vs work of F and tau (scale max |gain|); dE/dt vs power (scale max |P|)",
        "variables": [row("W_drives", err_w, REL_LIMIT, H_FINE, scale), row("W_sum_F_dx", err_sum, REL_LIMIT, H_FINE, scale),
                      row("dE_dt", err_rate, REL_LIMIT, H_FINE, p_scale), row("P_drives", err_p, 1e-12, H_FINE, p_scale),
                      row("E_output", err_e, 1e-12, H_FINE, scale)]})
    assert err_w <= REL_LIMIT and err_sum <= REL_LIMIT and err_rate <= REL_LIMIT, (err_w, err_sum, err_rate)
    assert err_p <= 1e-12 and err_e <= 1e-12, (err_p, err_e)


def test_tension_obeys_formula_a_on_the_simulated_motion(closed_loop_fmu):
    """T against the notes' formula (a) evaluated (i) with the FMU's accelerations, (ii) with
    accelerations differentiated from the FMU's velocities (inside each control period),
    (iii) against the tension from Newton-Euler (derive) at the FMU's states and inputs."""
    r = closed_loop_fmu
    T = r["T"]
    t_rng = float(np.ptp(T))
    a = float(np.max(np.abs(tension_formula_a(r, r["x_ddot"], r["theta_ddot"]) - T)) / t_rng)
    n_fine = int(round(H_CTRL / H_FINE))
    mid = np.arange(0, r["time"].size - 1, n_fine)[:-1] + n_fine // 2

    def d(v):
        return (-v[mid + 2] + 8 * v[mid + 1] - 8 * v[mid - 1] + v[mid - 2]) / (12 * H_FINE)

    at_mid = {n: r[n][mid] for n in STATES}
    b = float(np.max(np.abs(tension_formula_a(at_mid, d(r["x_dot"]), d(r["theta_dot"])) - T[mid])) / t_rng)
    ne = derive.crane_dynamics_newton_euler()
    idx = np.arange(0, r["time"].size, 97)
    c = max(abs(ne([r[n][j] for n in STATES], P, {"F": r["F"][j], "tau": r["tau"][j]})["T"] - T[j])
            for j in idx) / t_rng
    record_figures(FIG, "tension_formula_a", {
        "case": "T vs formula (a) on the closed-loop motion (scale: range of T)",
        "variables": [row("T_formula_a", a, 1e-12, H_FINE, t_rng), row("T_formula_a_fd", b, REL_LIMIT, H_FINE, t_rng),
                      row("T_newton_euler", c, 1e-10, H_FINE, t_rng)]})
    assert a <= 1e-12 and b <= REL_LIMIT and c <= 1e-10, (a, b, c)


# =======================================================================================
# Limits of the model and invalid values


def test_slack_cable_is_warned_once_per_episode(slave):
    """The boom driven down hard drops the trolley faster than the payload can follow."""
    s = slave(NAME, logging_on=True)
    s.initialize({"tau": -3.0 * TAU0})
    statuses, T = [], []
    for i in range(30):
        st = s.call("fmi2DoStep", i * 0.01, 0.01, 1)
        assert st in (fmi2OK, fmi2Warning), status_name(st)
        statuses.append(st)
        T.append(s.get("T")[0])
    T = np.array(T)
    episodes = int(T[0] < 0) + int(np.sum((T[1:] < 0) & (T[:-1] >= 0)))
    warnings = [r for r in s.log.records if r.status == fmi2Warning and re.search("slack", r.message)]
    assert episodes >= 1
    assert len(warnings) == episodes == statuses.count(fmi2Warning), (episodes, [r.message for r in warnings])


def test_trolley_reaching_the_pivot_ends_with_discard(fmu):
    """The trolley drive pulls inwards: the trolley reaches O at t = 0.946 s (reference);
    fmpy gets fmi2Discard and stops at the last successful time, with a message, no NaN."""
    inp = step_input(["F", "tau"], [0.0], [[-1e4, 0.5 * TAU0]], t_end=5.0)
    with pytest.raises(RuntimeError, match=r"t = 0\.946"):
        ref_cd.simulate(None, None, np.linspace(0.0, 5.0, 11), inp)
    mark = LogMark()
    res = simulate(fmu(NAME), relative_tolerance=RTOL, output_interval=0.01, stop_time=5.0, input=inp)
    assert mark.find(r"trolley reached the pivot", status=fmi2Discard), mark.text()
    assert 0.94 < res.time[-1] <= 0.95 + 1e-12, res.time[-3:]
    for name in res.result.dtype.names:
        assert np.all(np.isfinite(res[name])), name
    assert np.all(res["x"][:-1] > 0)


@pytest.mark.parametrize("name,value", [("m", 0.0), ("l", -1.0), ("J_boom", 0.0), ("J_boom", -5000.0),
                                        ("m_trolley", 0.0), ("m_trolley", -200.0), ("x", 0.0), ("x", -3.0)])
def test_invalid_values_fail_initialization_with_a_message(slave, name, value):
    slave(NAME).expect_refused_on_leaving_initialization(name, value)
