"""The Crane FMU against its contract (docs/mechanisms/Crane.md) under FMPy.

Boom and trolley massless, their motion prescribed by the inputs x_ddot and theta_ddot;
with s = theta - phi:

    l phi'' = -g sin phi - (x'' - th'^2 x) cos s + (2 th' x' + th'' x) sin s
    T       = m [(x'' - th'^2 x) sin s + (2 th' x' + th'' x) cos s + l phi'^2 + g cos phi]
    F = T sin s,   tau = x T cos s

The references do not reuse these lines or the Rust code:

* the exact pendulum (drives still): period 4 sqrt(l/g) K(sin(phi0/2)), phi(t) from Jacobi
  elliptic functions (refs.crane.pendulum), T = m g (3 cos phi - 2 cos phi0);
* the payload's Lagrangian with x(t), theta(t) prescribed and the free-body diagrams of
  payload, trolley and boom, both derived with sympy in refs/derive/crane.py, integrated here
  with scipy DOP853 (rtol 1e-12) under the same zero-order hold as fmpy's input;
* energy written here from the payload's velocity in ground coordinates.

Achieved errors are written to target/test-figures/crane.{json,md}.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from scipy.integrate import simpson
from scipy.special import ellipk

from fmpy.fmi2 import fmi2Discard, fmi2OK, fmi2Warning

from fmutest import LogMark, compare_to_reference, record_figures, simulate, status_name
from refs import crane as ref_crane
from refs import derive, step_input
from refs._common import run as run_reference

NAME = "Crane"
FIG = "crane"
REL_LIMIT = 1e-6  # max |FMU - reference| / range of the reference
RTOL = 1e-8  # FMPy relative_tolerance used throughout
P = {"m": 1000.0, "l": 5.0, "g": 9.81}
START = {"x": 10.0, "x_dot": 0.0, "theta": 0.5, "theta_dot": 0.0, "phi": 0.0, "phi_dot": 0.0}
STATES = ("x", "x_dot", "theta", "theta_dot", "phi", "phi_dot")


# =======================================================================================
# References written in this file


def pendulum_period(phi0: float, p=P) -> float:
    """4 sqrt(l/g) K(k), k = sin(phi0/2); scipy's ellipk takes the parameter k^2."""
    k = math.sin(phi0 / 2.0)
    return 4.0 * math.sqrt(p["l"] / p["g"]) * float(ellipk(k * k))


def payload_energy(r, p=P):
    """Payload kinetic + potential energy from the states, in ground coordinates."""
    x, v, th, w, ph, phd = (np.asarray(r[n]) for n in STATES)
    px = x * np.cos(th) + p["l"] * np.sin(ph)
    py = x * np.sin(th) - p["l"] * np.cos(ph)
    dpx = v * np.cos(th) - x * w * np.sin(th) + p["l"] * phd * np.cos(ph)
    dpy = v * np.sin(th) + x * w * np.cos(th) + p["l"] * phd * np.sin(ph)
    return 0.5 * p["m"] * (dpx ** 2 + dpy ** 2) + p["m"] * p["g"] * py, px, py


_LAG = None
_NE = None


def _lagrange_rhs(t, y, p, u):
    """State derivative with phi'' from the payload's Lagrangian (sympy, refs/derive/crane.py)."""
    xdd, thdd = u["x_ddot"], u["theta_ddot"]
    return [y[1], xdd, y[3], thdd, y[5], float(_LAG(y, p, u))]


def _newton_euler_outputs(t, y, p, u):
    """T, F, tau (and phi'') from the free-body diagrams of payload, trolley and boom."""
    o = _NE(y, p, u)
    e, px, py = payload_energy({n: y[i] for i, n in enumerate(STATES)}, p)
    return {"T": o["T"], "F": o["F"], "tau": o["tau"], "phi_ddot": o["phi_ddot"],
            "payload_x": px, "payload_y": py, "E_payload": e,
            "P_drives": o["F"] * y[1] + o["tau"] * y[3]}


def reference(t_out, inputs=None, y0=None, p=P):
    """DOP853 (rtol = atol = 1e-12) of the Lagrangian equation, restarted at every input
    switch (zero-order hold); outputs at a switch time use the input held over the step
    that ends there, as fmpy records a co-simulation FMU."""
    global _LAG, _NE
    _LAG, _NE = derive.crane_lagrange(), derive.crane_newton_euler()
    s = dict(START)
    s.update(y0 or {})
    return run_reference(_lagrange_rhs, _newton_euler_outputs, STATES, [s[n] for n in STATES],
                         np.asarray(t_out, float), dict(p), {"x_ddot": 0.0, "theta_ddot": 0.0}, inputs,
                         1e-12, 1e-12, "before")


def hermite_zero_crossings(t, y, dy, direction=-1):
    """Times where y crosses zero (direction -1: downwards), located on the cubic Hermite
    interpolant of the samples y and slopes dy (error O(h^4))."""
    out = []
    for i in range(len(t) - 1):
        y0, y1 = y[i], y[i + 1]
        if not ((direction < 0 and y0 > 0 >= y1) or (direction > 0 and y0 < 0 <= y1)):
            continue
        h = t[i + 1] - t[i]
        d0, d1 = dy[i] * h, dy[i + 1] * h

        def f(s):
            return ((2 * s ** 3 - 3 * s ** 2 + 1) * y0 + (s ** 3 - 2 * s ** 2 + s) * d0
                    + (-2 * s ** 3 + 3 * s ** 2) * y1 + (s ** 3 - s ** 2) * d1)

        lo, hi = 0.0, 1.0
        for _ in range(80):
            mid = 0.5 * (lo + hi)
            if (f(mid) > 0) == (y0 > 0):
                lo = mid
            else:
                hi = mid
        out.append(t[i] + 0.5 * (lo + hi) * h)
    return np.array(out)


def compare(res, ref, names, interval, case, limit=REL_LIMIT):
    return compare_to_reference(FIG, res, ref, names, interval, case, limit)


# Drives moving: piecewise-constant accelerations (switch times on the 0.01 grid).
MOVING_TIMES = [0.0, 1.0, 2.5, 4.0, 6.0, 7.5, 9.0, 11.0, 13.0, 14.5, 16.0]
MOVING_VALUES = [  # (x_ddot, theta_ddot)
    [0.5, 0.0], [0.5, 0.04], [0.0, 0.04], [-0.5, 0.0], [0.0, -0.04], [0.0, 0.0],
    [-0.3, -0.03], [0.3, 0.03], [0.4, 0.0], [0.0, 0.02], [-0.2, -0.02]]
MOVING_INPUT = step_input(["x_ddot", "theta_ddot"], MOVING_TIMES, MOVING_VALUES, t_end=20.0)
MOVING_START = {"x_dot": 0.2, "theta_dot": -0.02, "phi": 0.1}


@pytest.fixture(scope="module")
def moving_reference():
    """The moving-drives reference on a 0.001 s grid (every output interval used below
    divides into it or is interpolated on it by the same DOP853 run)."""
    cache = {}

    def get(t_out):
        key = (len(t_out), float(t_out[0]), float(t_out[-1]))
        if key not in cache:
            cache[key] = reference(t_out, MOVING_INPUT, MOVING_START)
        return cache[key]

    return get


# =======================================================================================
# The references themselves (no FMU)


def test_reference_agrees_with_the_other_engineers_reference():
    """derive's Lagrangian + Newton-Euler (this file) against refs/crane.py (contract
    formulas) on the moving-drives case: two formulations, same DOP853."""
    t = np.linspace(0.0, 20.0, 401)
    a = reference(t, MOVING_INPUT, MOVING_START)
    b = ref_crane.simulate(None, MOVING_START, t, MOVING_INPUT, switch_outputs="before")
    for name in STATES + ("T", "F", "tau", "payload_x", "payload_y", "E_payload"):
        assert np.max(np.abs(a[name] - b[name])) <= 1e-9 * np.ptp(b[name]), name
    assert np.min(a["T"]) > 0.2 * P["m"] * P["g"], "the moving case keeps the cable taut"
    assert np.min(a["x"]) > 5.0, "the moving case keeps the trolley away from the pivot"


def test_exact_pendulum_reference_is_the_elliptic_solution():
    """The Jacobi-elliptic swing satisfies l phi'' = -g sin phi (finite differences) and
    has the period 4 sqrt(l/g) K."""
    phi0 = math.radians(100.0)
    period = pendulum_period(phi0)
    t = np.linspace(0.0, period, 20001)
    ph, phd = ref_crane.pendulum(P, phi0, t)
    assert abs(ph[0] - phi0) < 1e-13 and abs(ph[-1] - phi0) < 1e-9 and abs(ph[10000] + phi0) < 1e-9
    h = t[1] - t[0]
    phdd = (ph[2:] - 2 * ph[1:-1] + ph[:-2]) / h ** 2
    assert np.max(np.abs(phdd + P["g"] / P["l"] * np.sin(ph[1:-1]))) < 1e-5


# =======================================================================================
# modelDescription: checked against fmus/crane/validation/contract.toml by test_contract.py


# =======================================================================================
# Equations at scattered states (evaluated at initialization: no integration involved)


def _outputs_at(slave, y, u):
    s = slave(NAME)
    s.initialize({**{n: y[i] for i, n in enumerate(STATES)}, **u})
    return dict(zip(("phi_ddot", "T", "F", "tau", "E_payload", "P_drives", "payload_x", "payload_y"),
                    s.get("phi_ddot", "T", "F", "tau", "E_payload", "P_drives", "payload_x", "payload_y")))


def test_equations_match_lagrange_and_newton_euler_at_scattered_states(slave):
    rng = np.random.default_rng(4)
    lag, ne = derive.crane_lagrange(), derive.crane_newton_euler()
    worst = {k: 0.0 for k in ("phi_ddot", "T", "F", "tau", "E_payload", "payload_x", "payload_y", "identity")}
    for _ in range(40):
        y = [rng.uniform(0.5, 20.0), rng.normal(0, 2), rng.uniform(-1.5, 1.5), rng.normal(0, 0.5),
             rng.uniform(-2.5, 2.5), rng.normal(0, 1.5)]
        u = {"x_ddot": float(rng.normal(0, 2)), "theta_ddot": float(rng.normal(0, 0.3))}
        o = _outputs_at(slave, y, u)
        b = ne(y, P, u)
        want = {"phi_ddot": float(lag(y, P, u)), "T": b["T"], "F": b["F"], "tau": b["tau"]}
        e, px, py = payload_energy({n: y[i] for i, n in enumerate(STATES)})
        want.update(E_payload=e, payload_x=px, payload_y=py)
        for k, w in want.items():
            scale = {"phi_ddot": 1.0, "T": P["m"] * P["g"], "F": P["m"] * P["g"], "tau": 20 * P["m"] * P["g"],
                     "E_payload": P["m"] * P["g"] * 20, "payload_x": 20.0, "payload_y": 20.0}[k]
            worst[k] = max(worst[k], abs(o[k] - w) / max(abs(w), scale))
        worst["identity"] = max(worst["identity"],
                                abs(math.hypot(o["F"], o["tau"] / y[0]) - abs(o["T"])) / abs(o["T"]))
    record_figures(FIG, "scattered_states_vs_lagrange_newton_euler",
                   {"case": "40 random states and inputs, outputs at initialization",
                    "variables": [dict(variable=k, relative=v, limit=1e-12, **{"pass": bool(v <= 1e-12)})
                                  for k, v in worst.items()]})
    assert all(v <= 1e-12 for v in worst.values()), worst


def test_hanging_payload_is_stable(slave):
    """Linearized about the hanging payload with the drives still: phi'' = -(g/l) phi
    (the notes' printed equation would give +g/l: a payload that falls over)."""
    for x, th in [(10.0, 0.5), (3.0, -0.2), (15.0, 1.2)]:
        h = 1e-6
        k = []
        for ph in (h, -h):
            s = slave(NAME)
            s.initialize({"x": x, "theta": th, "phi": ph})
            k.append(s.get("phi_ddot")[0])
        slope = (k[0] - k[1]) / (2 * h)
        assert slope == pytest.approx(-P["g"] / P["l"], rel=1e-8)


# =======================================================================================
# Drives still: the pendulum


PERIOD_ANGLES = [5, 10, 20, 30, 45, 60, 75, 90, 105, 120]


@pytest.mark.parametrize("h", [0.005, 0.1])
@pytest.mark.parametrize("deg", PERIOD_ANGLES)
def test_still_drives_period_is_the_elliptic_period(fmu, deg, h):
    """Period from the zero crossings of phi (where phi_dot is largest), located on the cubic
    Hermite interpolant of phi and phi_dot at the output points, fitted over the crossings of
    about four periods; relative_tolerance 1e-8 (no tighter tolerance needed). At h = 0.1 s
    the solver chooses its own steps (the interpolation adds O(h^4), ~1e-9 relative); at
    0.005 s the communication points bound the solver's steps."""
    phi0 = math.radians(deg)
    exact = pendulum_period(phi0)
    stop = round(4.3 * exact / h) * h
    res = simulate(fmu(NAME), relative_tolerance=RTOL, output_interval=h, stop_time=stop,
                   start_values={"phi": phi0}, output=["phi", "phi_dot"])
    down = hermite_zero_crossings(res.time, res["phi"], res["phi_dot"], -1)
    up = hermite_zero_crossings(res.time, res["phi"], res["phi_dot"], +1)
    assert len(down) >= 4 and len(up) >= 4, (down, up)
    # crossings at (2j+1) P/4: a least-squares line through all eight gives P
    times = np.sort(np.concatenate([down, up]))
    n = np.arange(times.size)
    slope, intercept = np.polyfit(n, times, 1)
    period = 2.0 * slope
    rel = abs(period - exact) / exact
    # and each full period on its own
    each = np.concatenate([np.diff(down), np.diff(up)])
    rel_each = float(np.max(np.abs(each - exact)) / exact)
    rel_quarter = abs(intercept - exact / 4) / exact
    record_figures(FIG, f"period_phi0_{deg:03d}deg_h{h}", {
        "case": f"drives still, released from rest at {deg} deg: period vs 4 sqrt(l/g) K(sin(phi0/2))",
        "variables": [
            dict(variable="period", output_interval=h, max_error=abs(period - exact), range=exact,
                 relative=rel, limit=REL_LIMIT, **{"pass": bool(rel <= REL_LIMIT)}),
            dict(variable="period_each", output_interval=h, max_error=rel_each * exact, range=exact,
                 relative=rel_each, limit=REL_LIMIT, **{"pass": bool(rel_each <= REL_LIMIT)}),
            dict(variable="first_crossing", output_interval=h, max_error=abs(intercept - exact / 4),
                 range=exact, relative=rel_quarter, limit=REL_LIMIT, **{"pass": bool(rel_quarter <= REL_LIMIT)}),
        ]})
    assert rel <= REL_LIMIT, f"period {period!r} vs {exact!r}: {rel:.2e}"
    assert rel_each <= REL_LIMIT, f"single periods {each} vs {exact!r}"
    assert rel_quarter <= REL_LIMIT


@pytest.mark.parametrize("deg", [5, 45, 90, 120])
def test_still_drives_swing_loads_and_energy(fmu, deg):
    """phi against the Jacobi-elliptic solution; T = m g (3 cos phi - 2 cos phi0) with the
    exact phi(t); F = T sin(theta - phi), tau = x T cos(theta - phi); energy constant."""
    phi0 = math.radians(deg)
    x0, th0 = 12.0, 0.8
    res = simulate(fmu(NAME), relative_tolerance=RTOL, output_interval=0.01, stop_time=20.0,
                   start_values={"phi": phi0, "x": x0, "theta": th0})
    t = res.time
    ph, phd = ref_crane.pendulum(P, phi0, t)
    T = P["m"] * P["g"] * (3 * np.cos(ph) - 2 * math.cos(phi0))
    ref = {"phi": ph, "phi_dot": phd, "T": T, "F": T * np.sin(th0 - ph), "tau": x0 * T * np.cos(th0 - ph),
           "payload_x": x0 * math.cos(th0) + P["l"] * np.sin(ph),
           "payload_y": x0 * math.sin(th0) - P["l"] * np.cos(ph)}
    failures = compare(res, ref, list(ref), 0.01, f"still_drives_{deg:03d}deg")
    # energy: from the states (this file's formula) and the FMU's own output
    e, _, _ = payload_energy(res)
    e0 = P["m"] * P["g"] * (x0 * math.sin(th0) - P["l"] * math.cos(phi0))
    swing = P["m"] * P["g"] * P["l"] * (1 - math.cos(phi0))  # energy scale of the swing
    drift = float(np.max(np.abs(e - e0)) / swing)
    out = float(np.max(np.abs(res["E_payload"] - e)) / swing)
    record_figures(FIG, f"still_drives_{deg:03d}deg_energy", {
        "case": f"drives still from {deg} deg: energy drift / (m g l (1 - cos phi0))",
        "variables": [dict(variable="E_drift", output_interval=0.01, max_error=drift * swing, range=swing,
                           relative=drift, limit=REL_LIMIT, **{"pass": bool(drift <= REL_LIMIT)}),
                      dict(variable="E_payload", output_interval=0.01, max_error=out * swing, range=swing,
                           relative=out, limit=1e-9, **{"pass": bool(out <= 1e-9)})]})
    assert np.all(res["x"] == x0) and np.all(res["theta"] == th0) and np.all(res["W_drives"] == 0.0)
    assert not failures, "\n".join(failures)
    assert drift <= REL_LIMIT and out <= 1e-9, (drift, out)


def test_slack_cable_is_warned_once_per_episode(slave):
    """Released at 120 deg: T = m g (3 cos phi + 1) < 0 while cos phi < -1/3, i.e. around
    every turning point; one warning per such episode, through fmi2Warning steps."""
    phi0 = math.radians(120.0)
    period = pendulum_period(phi0)
    s = slave(NAME, logging_on=True)
    s.initialize({"phi": phi0})
    h, t = 0.01, 0.0
    statuses, T = [], []
    n = int(2.2 * period / h)
    for i in range(n):
        st = s.call("fmi2DoStep", i * h, h, 1)
        assert st in (fmi2OK, fmi2Warning), status_name(st)
        statuses.append(st)
        T.append(s.get("T")[0])
    t = h * np.arange(1, n + 1)
    # episodes from the exact solution: T < 0 at the release (t = 0) and around k P / 2
    ph, _ = ref_crane.pendulum(P, phi0, np.concatenate([[0.0], t]))
    slack = 3 * np.cos(ph) + 1 < 0
    episodes = int(slack[0]) + int(np.sum(slack[1:] & ~slack[:-1]))
    warnings = [r for r in s.log.records if r.status == fmi2Warning and re.search("slack", r.message)]
    record_figures(FIG, "slack_cable_120deg", {"case": "released at 120 deg, 2.2 periods", "variables": [
        dict(variable="slack_episodes", max_error=float(abs(len(warnings) - episodes)), range=float(episodes),
             relative=float(abs(len(warnings) - episodes)), limit=0.0, **{"pass": bool(len(warnings) == episodes)})]})
    assert episodes == 5
    assert len(warnings) == episodes, [r.message for r in warnings]
    assert statuses.count(fmi2Warning) == episodes
    assert all("T = -" in r.message for r in warnings)
    # the swing itself goes on (a rigid rod): outputs stay finite
    assert np.all(np.isfinite(T)) and min(T) < 0 < max(T)


# =======================================================================================
# Drives moving


@pytest.mark.parametrize("interval", [0.01, 0.0137])
def test_moving_drives_trajectory_matches_reference(fmu, moving_reference, interval):
    res = simulate(fmu(NAME), relative_tolerance=RTOL, output_interval=interval, stop_time=20.0,
                   start_values=MOVING_START, input=MOVING_INPUT)
    ref = moving_reference(res.time)
    names = list(STATES) + ["T", "F", "tau", "payload_x", "payload_y", "phi_ddot", "E_payload"]
    failures = compare(res, ref, names, interval, f"moving_drives_h{interval}")
    assert not failures, "\n".join(failures)
    assert not [r for r in res.log if r.status >= fmi2Warning], [str(r) for r in res.log]


def test_moving_drives_tension_is_the_resultant_of_drive_loads(fmu):
    res = simulate(fmu(NAME), relative_tolerance=RTOL, output_interval=0.01, stop_time=20.0,
                   start_values=MOVING_START, input=MOVING_INPUT)
    assert np.min(res["T"]) > 0
    resultant = np.hypot(res["F"], res["tau"] / res["x"])
    rel = float(np.max(np.abs(resultant - res["T"]) / res["T"]))
    record_figures(FIG, "moving_drives_T_identity", {"case": "T = sqrt(F^2 + (tau/x)^2) on the moving run",
                   "variables": [dict(variable="T_identity", output_interval=0.01, relative=rel, limit=1e-9,
                                      **{"pass": bool(rel <= 1e-9)})]})
    assert rel <= 1e-9


def test_moving_drives_work_equals_payload_energy_gain(fmu):
    """Three routes: the FMU's W_drives (P integrated by the FMU's solver), Simpson's rule on
    F x_dot + tau theta_dot sampled every 1 ms, and the gain of the payload's energy
    computed here from the states."""
    h = 0.001
    res = simulate(fmu(NAME), relative_tolerance=RTOL, output_interval=h, stop_time=20.0,
                   start_values=MOVING_START, input=MOVING_INPUT,
                   output=list(STATES) + ["F", "tau", "W_drives", "E_payload"])
    t = res.time
    e, _, _ = payload_energy(res)
    gain = e - e[0]
    scale = float(np.max(np.abs(gain)))
    assert scale > 1e5, "the case must move the payload"
    # quadrature, segment by segment between input switches: a sample AT a switch carries
    # the power of the segment that ends there; the first point of a segment is
    # extrapolated (cubic) from the next four samples.
    power = res["F"] * res["x_dot"] + res["tau"] * res["theta_dot"]
    cuts = [0.0] + [c for c in MOVING_TIMES[1:] if c < 20.0] + [20.0]
    work = np.zeros_like(t)
    acc = 0.0
    for a, b in zip(cuts[:-1], cuts[1:]):
        i0, i1 = int(round(a / h)), int(round(b / h))
        seg = power[i0:i1 + 1].copy()
        if a > 0:
            seg[0] = 4 * seg[1] - 6 * seg[2] + 4 * seg[3] - seg[4]
        tt = t[i0:i1 + 1]
        cum = np.concatenate([[0.0], np.cumsum(0.5 * (seg[1:] + seg[:-1]) * np.diff(tt))])
        work[i0:i1 + 1] = acc + cum
        acc += float(simpson(seg, x=tt))
    w_simpson_end = acc
    err_w = float(np.max(np.abs(res["W_drives"] - gain)) / scale)
    err_q = abs(w_simpson_end - gain[-1]) / scale
    err_trap = float(np.max(np.abs(work - gain)) / scale)  # trapezoid: O(h^2), a sanity bound
    err_e = float(np.max(np.abs(res["E_payload"] - e)) / scale)
    record_figures(FIG, "moving_drives_work_energy", {
        "case": "work of F and tau vs the payload's energy gain (scale: max |gain|)",
        "variables": [
            dict(variable="W_drives", output_interval=h, max_error=err_w * scale, range=scale, relative=err_w,
                 limit=REL_LIMIT, **{"pass": bool(err_w <= REL_LIMIT)}),
            dict(variable="W_simpson_end", output_interval=h, max_error=err_q * scale, range=scale,
                 relative=err_q, limit=REL_LIMIT, **{"pass": bool(err_q <= REL_LIMIT)}),
            dict(variable="W_trapezoid", output_interval=h, max_error=err_trap * scale, range=scale,
                 relative=err_trap, limit=1e-5, **{"pass": bool(err_trap <= 1e-5)}),
            dict(variable="E_payload", output_interval=h, max_error=err_e * scale, range=scale, relative=err_e,
                 limit=1e-12, **{"pass": bool(err_e <= 1e-12)}),
        ]})
    assert err_w <= REL_LIMIT and err_q <= REL_LIMIT and err_trap <= 1e-5 and err_e <= 1e-12, \
        (err_w, err_q, err_trap, err_e)


# =======================================================================================
# Limits of the model and invalid values


def _run_into_the_pivot(fmu):
    mark = LogMark()
    res = simulate(fmu(NAME), relative_tolerance=RTOL, output_interval=0.1, stop_time=5.0,
                   start_values={"x": 1.0, "x_dot": -1.05})
    return res, mark


def test_trolley_reaching_the_pivot_ends_with_discard(fmu):
    """x = 1 - 1.05 t reaches the pivot at t = 0.952, inside the step [0.9, 1.0]: fmpy gets
    fmi2Discard, asks for the last successful time and stops there; the message says why;
    no NaN anywhere."""
    res, mark = _run_into_the_pivot(fmu)
    hits = mark.find(r"trolley reached the pivot", status=fmi2Discard)
    assert hits, mark.text()
    # The step [0.9, 1.0] crosses the pivot: it ends at the last valid point, in [0.9, 0.952).
    assert 0.9 <= res.time[-1] < 1.0 / 1.05, res.time[-3:]
    assert res.time[-2] == pytest.approx(0.9)
    for name in res.result.dtype.names:
        assert np.all(np.isfinite(res[name])), name
    assert np.all(res["x"] > 0)
    # the recorded end point lies on the trolley's path (x = 1 - 1.05 t)
    assert res["x"][-1] == pytest.approx(1.0 - 1.05 * res.time[-1], abs=1e-12)


def test_trolley_reaching_the_pivot_stops_at_the_last_valid_time(fmu):
    res, _ = _run_into_the_pivot(fmu)
    assert res["x"][-1] > 0.0 and res.time[-1] <= 1.0 / 1.05


@pytest.mark.parametrize("name,value", [("m", 0.0), ("m", -1.0), ("l", 0.0), ("l", -5.0), ("x", 0.0),
                                        ("x", -2.0), ("g", -9.81)])
def test_invalid_values_fail_initialization_with_a_message(slave, name, value):
    slave(NAME).expect_refused_on_leaving_initialization(name, value)


def test_default_experiment_runs_without_arguments(fmu):
    res = simulate(fmu(NAME), relative_tolerance=None)
    assert res.time[-1] == pytest.approx(20.0)
    # defaults: drives still, payload hanging at rest: nothing moves, T = m g
    assert np.all(res["phi"] == 0.0)
    assert np.max(np.abs(res["T"] - P["m"] * P["g"])) <= 1e-12 * P["m"] * P["g"]
