"""The Oscillator FMU against its contract (docs/mechanisms/Oscillator.md) under FMPy.

    m x'' + c x' + k x = F + F0 sin(omega t)

The references below are closed forms written from the mathematics of the linear
second-order equation (homogeneous solution in each damping regime + particular solution),
not from mechfmu's Rust code. They are checked on their own first (ODE residual, initial
conditions, an independent scipy DOP853 solution), so a failure of an FMU test points at
the FMU.

Achieved errors are written to target/test-figures/oscillator.{json,md}.
"""

from __future__ import annotations

import math
import re
import subprocess
import sys
from ctypes import byref
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from fmpy.fmi2 import fmi2Error, fmi2Fatal, fmi2OK, fmi2Warning

import fmutest
from fmutest import LogMark, Slave, make_input, max_error, record_figures, simulate, simulate_refused, status_name

NAME = "Oscillator"
REL_LIMIT = 1e-6  # max |FMU - reference| / range of the reference
STOP = 20.0
DEFAULTS = dict(m=1.0, c=0.4, k=4.0, F0=0.0, omega=1.0, F=0.0, x=1.0, x_dot=0.0)


# =======================================================================================
# Closed-form reference


@dataclass(frozen=True)
class Params:
    m: float = 1.0
    c: float = 0.4
    k: float = 4.0
    F0: float = 0.0
    omega: float = 1.0

    @property
    def omega_n(self) -> float:
        return math.sqrt(self.k / self.m)

    @property
    def zeta(self) -> float:
        return self.c / (2.0 * math.sqrt(self.m * self.k))


def homogeneous(tau: np.ndarray, p: Params, y0: float, w0: float):
    """Solution of m y'' + c y' + k y = 0 with y(0) = y0, y'(0) = w0: (y, y', y'')."""
    tau = np.asarray(tau, dtype=float)
    m, c, k = p.m, p.c, p.k
    wn = math.sqrt(k / m)
    disc = c * c - 4.0 * m * k  # sign decides the regime; exact for the cases used here
    if c == 0.0:  # zeta = 0: undamped
        s, co = np.sin(wn * tau), np.cos(wn * tau)
        y = y0 * co + (w0 / wn) * s
        yd = -y0 * wn * s + w0 * co
        ydd = -wn * wn * y
        return y, yd, ydd
    sigma = c / (2.0 * m)  # = zeta * omega_n
    if disc < 0.0:  # 0 < zeta < 1: y = e^{-sigma tau} u, u = A cos(wd tau) + B sin(wd tau)
        wd = math.sqrt(k / m - sigma * sigma)
        A, B = y0, (w0 + sigma * y0) / wd
        s, co = np.sin(wd * tau), np.cos(wd * tau)
        u = A * co + B * s
        ud = -A * wd * s + B * wd * co
        e = np.exp(-sigma * tau)
        return e * u, e * (ud - sigma * u), e * ((sigma * sigma - wd * wd) * u - 2.0 * sigma * ud)
    if disc == 0.0:  # zeta = 1: y = e^{-wn tau} (A + B tau)
        A, B = y0, w0 + wn * y0
        u = A + B * tau
        e = np.exp(-wn * tau)
        return e * u, e * (B - wn * u), e * (-2.0 * wn * B + wn * wn * u)
    # zeta > 1: two real roots
    root = math.sqrt(sigma * sigma - k / m)
    r1, r2 = -sigma + root, -sigma - root
    A = (w0 - r2 * y0) / (r1 - r2)
    B = (r1 * y0 - w0) / (r1 - r2)
    e1, e2 = np.exp(r1 * tau), np.exp(r2 * tau)
    return A * e1 + B * e2, A * r1 * e1 + B * r2 * e2, A * r1 * r1 * e1 + B * r2 * r2 * e2


def particular(t: np.ndarray, p: Params, F: float):
    """A particular solution for the constant force F plus F0 sin(omega t): (x, x', x'')."""
    t = np.asarray(t, dtype=float)
    if F != 0.0:
        if p.k == 0.0:
            raise ValueError("constant force with k = 0 has no bounded particular solution")
        x, xd, xdd = np.full_like(t, F / p.k), np.zeros_like(t), np.zeros_like(t)
    else:
        x, xd, xdd = np.zeros_like(t), np.zeros_like(t), np.zeros_like(t)
    if p.F0 != 0.0:
        w = p.omega
        detune = p.k - p.m * w * w
        if p.c == 0.0 and detune == 0.0:
            # undamped, exactly at resonance: x_p = -(F0 / (2 m w)) t cos(w t)  (secular growth)
            a = -p.F0 / (2.0 * p.m * w)
            s, co = np.sin(w * t), np.cos(w * t)
            x = x + a * t * co
            xd = xd + a * (co - w * t * s)
            xdd = xdd + a * (-2.0 * w * s - w * w * t * co)
        else:
            X = p.F0 / math.hypot(detune, p.c * w)
            psi = -math.atan2(p.c * w, detune)
            ph = w * t + psi
            x = x + X * np.sin(ph)
            xd = xd + X * w * np.cos(ph)
            xdd = xdd - X * w * w * np.sin(ph)
    return x, xd, xdd


def response(t: np.ndarray, p: Params, x0: float, v0: float, F: float = 0.0, t0: float = 0.0):
    """Complete response for t >= t0 from x(t0) = x0, x'(t0) = v0 with constant F."""
    t = np.asarray(t, dtype=float)
    xp, xpd, xpdd = particular(t, p, F)
    xp0, xpd0, _ = particular(np.array([t0]), p, F)
    y, yd, ydd = homogeneous(t - t0, p, x0 - xp0[0], v0 - xpd0[0])
    return xp + y, xpd + yd, xpdd + ydd


@dataclass(frozen=True)
class Segment:
    """From time t_start on: parameters p and a constant input F."""

    t_start: float
    p: Params
    F: float = 0.0


def piecewise(t: np.ndarray, segments: list[Segment], x0: float, v0: float):
    """Response through parameter/input changes. At a change time the sample takes the
    left value (the FMU's output at a communication point reflects the input and parameters
    that were held over the step ending there; the new values apply to the next step)."""
    t = np.asarray(t, dtype=float)
    x, v, a = np.empty_like(t), np.empty_like(t), np.empty_like(t)
    xs, vs = x0, v0
    for i, seg in enumerate(segments):
        t_end = segments[i + 1].t_start if i + 1 < len(segments) else math.inf
        lo = t > seg.t_start if i > 0 else np.ones_like(t, dtype=bool)
        if i > 0:
            lo &= ~np.isclose(t, seg.t_start, rtol=0, atol=1e-9)
        hi = (t <= t_end) | np.isclose(t, t_end, rtol=0, atol=1e-9) if math.isfinite(t_end) else np.ones_like(lo)
        sel = lo & hi
        xx, vv, aa = response(t[sel], seg.p, xs, vs, seg.F, seg.t_start)
        x[sel], v[sel], a[sel] = xx, vv, aa
        if math.isfinite(t_end):
            xe, ve, _ = response(np.array([t_end]), seg.p, xs, vs, seg.F, seg.t_start)
            xs, vs = xe[0], ve[0]
    return x, v, a


# =======================================================================================
# Cases


@dataclass(frozen=True)
class Case:
    name: str
    p: Params = Params()
    x0: float = 1.0
    v0: float = 0.0
    F: float = 0.0  # constant force (from t_F on)
    t_F: float = 0.0  # time of the force step (0: applied from the start)
    set_states: bool = True  # pass x, x_dot as start values (False: rely on the defaults 1, 0)

    def segments(self) -> list[Segment]:
        if self.F != 0.0 and self.t_F > 0.0:
            return [Segment(0.0, self.p, 0.0), Segment(self.t_F, self.p, self.F)]
        return [Segment(0.0, self.p, self.F)]

    def reference(self, t):
        return piecewise(t, self.segments(), self.x0, self.v0)

    def start_values(self) -> dict[str, float]:
        sv = {}
        for key in ("m", "c", "k", "F0", "omega"):
            val = getattr(self.p, key)
            if val != DEFAULTS[key]:
                sv[key] = val
        if self.set_states:
            sv["x"], sv["x_dot"] = self.x0, self.v0
        return sv

    def input(self):
        if self.F == 0.0:
            return None
        if self.t_F > 0.0:
            return make_input([0.0, self.t_F, self.t_F, STOP], F=[0.0, 0.0, self.F, self.F])
        return make_input([0.0, STOP], F=[self.F, self.F])


CASES = [
    # free response, the four damping regimes (zeta printed in the name)
    Case("free_overdamped_z1.25", Params(c=5.0)),
    Case("free_overdamped_z2.5_x0v0", Params(m=0.5, c=5.0, k=2.0), x0=0.3, v0=-2.0),
    Case("free_critical_z1", Params(c=4.0), x0=-0.5, v0=3.0),
    Case("free_critical_z1_m2", Params(m=2.0, c=8.0, k=8.0), x0=0.8, v0=-4.0),
    Case("free_underdamped_z0.1_defaults", Params(), set_states=False),
    Case("free_underdamped_z0.034_x0v0", Params(m=2.5, c=0.3, k=7.0), x0=0.2, v0=1.5),
    Case("free_undamped_z0", Params(c=0.0), x0=0.7, v0=-1.1),
    # constant force
    Case("step_F2_underdamped", Params(), x0=0.0, v0=0.0, F=2.0),
    Case("step_F3_at_2.5_overdamped", Params(c=5.0), x0=0.5, v0=0.0, F=3.0, t_F=2.5),
    Case("step_F-1.5_at_7.3_undamped", Params(c=0.0, k=9.0), x0=0.0, v0=0.4, F=-1.5, t_F=7.3),
    # harmonic forcing near and at resonance (omega_n = 2)
    Case("harmonic_w1.9_z0.1", Params(F0=1.0, omega=1.9)),
    Case("harmonic_w2.0_z0.1_resonance", Params(F0=0.5, omega=2.0), x0=0.0, v0=0.0),
    Case("harmonic_w2.1_z0.05_x0v0", Params(c=0.2, F0=1.0, omega=2.1), x0=-0.3, v0=0.8),
    Case("harmonic_w1.8_z0_beats", Params(c=0.0, F0=1.0, omega=1.8), x0=0.0, v0=0.0),
    Case("harmonic_w2.0_z0_secular", Params(c=0.0, F0=0.5, omega=2.0), x0=0.0, v0=0.0),
    Case("harmonic_plus_F_overdamped", Params(c=5.0, F0=2.0, omega=1.95), x0=0.0, v0=1.0, F=1.0),
]

INTERVALS = [0.01, 0.0137]


# =======================================================================================
# The references themselves (no FMU involved)


@pytest.mark.parametrize("case", CASES, ids=lambda c: c.name)
def test_reference_satisfies_ode_and_initial_conditions(case: Case):
    t = np.linspace(0.0, STOP, 4001)
    if case.t_F > 0:
        t = np.union1d(t, [case.t_F])
    x, v, a = case.reference(t)
    assert x[0] == pytest.approx(case.x0, abs=1e-14) and v[0] == pytest.approx(case.v0, abs=1e-14)
    for seg_i, seg in enumerate(case.segments()):
        sel = t > seg.t_start if seg_i else t >= 0
        if seg_i == 0 and len(case.segments()) > 1:
            sel &= t <= case.segments()[1].t_start
        p = seg.p
        lhs = p.m * a[sel] + p.c * v[sel] + p.k * x[sel]
        rhs = seg.F + p.F0 * np.sin(p.omega * t[sel])
        scale = np.max(np.abs(p.m * a[sel])) + np.max(np.abs(p.k * x[sel])) + abs(seg.F) + p.F0 + 1e-300
        assert np.max(np.abs(lhs - rhs)) <= 1e-12 * scale
    # x' and x'' are the time derivatives of x (central differences, away from the jump)
    tt = np.linspace(0.05, STOP - 0.05, 397)
    if case.t_F > 0:
        tt = tt[np.abs(tt - case.t_F) > 0.01]
    h = 1e-5
    xp, vp, _ = case.reference(tt + h)
    xm, vm, _ = case.reference(tt - h)
    x1, v1, a1 = case.reference(tt)
    assert np.max(np.abs((xp - xm) / (2 * h) - v1)) <= 1e-7 * (np.ptp(v1) + 1e-300) + 1e-9
    assert np.max(np.abs((vp - vm) / (2 * h) - a1)) <= 1e-7 * (np.ptp(a1) + 1e-300) + 1e-9


@pytest.mark.parametrize("case", CASES, ids=lambda c: c.name)
def test_reference_matches_independent_numerical_solution(case: Case):
    """The closed forms against scipy DOP853 at rtol 1e-12 (same ODE, integrated)."""
    t_eval = np.linspace(0.0, STOP, 2001)
    x_ref, v_ref, _ = case.reference(t_eval)
    xs, vs = case.x0, case.v0
    got_x, got_v = [], []
    segs = case.segments()
    for i, seg in enumerate(segs):
        t_end = segs[i + 1].t_start if i + 1 < len(segs) else STOP
        p, F = seg.p, seg.F

        def rhs(t, y, p=p, F=F):
            return [y[1], (F + p.F0 * math.sin(p.omega * t) - p.c * y[1] - p.k * y[0]) / p.m]

        sel = (t_eval >= seg.t_start) & (t_eval < t_end) if i + 1 < len(segs) else (t_eval >= seg.t_start)
        sol = solve_ivp(rhs, (seg.t_start, t_end), [xs, vs], method="DOP853", rtol=1e-12, atol=1e-14,
                        t_eval=t_eval[sel], dense_output=True)
        assert sol.success
        got_x.append(sol.y[0])
        got_v.append(sol.y[1])
        xs, vs = sol.sol(t_end)
    got_x, got_v = np.concatenate(got_x), np.concatenate(got_v)
    assert np.max(np.abs(got_x - x_ref)) <= 1e-9 * np.ptp(x_ref)
    assert np.max(np.abs(got_v - v_ref)) <= 1e-9 * np.ptp(v_ref)


def test_reference_regimes_are_the_named_ones():
    zetas = {c.name: c.p.zeta for c in CASES}
    assert zetas["free_overdamped_z1.25"] == pytest.approx(1.25)
    assert zetas["free_overdamped_z2.5_x0v0"] == pytest.approx(2.5)
    assert zetas["free_critical_z1"] == 1.0 and zetas["free_critical_z1_m2"] == 1.0
    assert zetas["free_underdamped_z0.1_defaults"] == pytest.approx(0.1)
    assert zetas["free_undamped_z0"] == 0.0


# =======================================================================================
# modelDescription (checked against fmus/oscillator/validation/contract.toml by test_contract.py)


def test_fmpy_validate_cli_exits_zero(fmu):
    path = fmu(NAME)
    proc = subprocess.run([sys.executable, "-m", "fmpy", "validate", str(path)],
                          capture_output=True, text=True, timeout=120)
    assert proc.returncode == 0, f"`fmpy validate` exited {proc.returncode}:\n{proc.stdout}\n{proc.stderr}"
    assert "No problems found" in proc.stdout


# =======================================================================================
# Accuracy under simulate_fmu


def _check_against_reference(case: Case, interval: float, res, x_ref, v_ref, a_ref, record_as: str):
    rows, failures = [], []
    for var, ref in (("x", x_ref), ("x_dot", v_ref), ("x_ddot", a_ref)):
        err, rng, i = max_error(res[var], ref)
        rel = err / rng if rng > 0 else math.inf
        ok = rel <= REL_LIMIT
        rows.append(dict(variable=var, output_interval=interval, max_error=err, range=rng, relative=rel,
                         limit=REL_LIMIT, at_t=float(res.time[i]), got=float(res[var][i]),
                         want=float(ref[i]), samples=int(len(ref)), **{"pass": ok}))
        print(f"{record_as}: {var}: max error {err:.3e} = {rel:.3e} of range {rng:.4g} at t = {res.time[i]:.4f}")
        if not ok:
            failures.append(f"{var}: max |FMU - reference| = {err:.3e} = {rel:.3e} x range {rng:.4g} "
                            f"(limit {REL_LIMIT:g}) at t = {res.time[i]:.6g}: FMU {res[var][i]!r}, "
                            f"reference {ref[i]!r}")
    record_figures("oscillator", record_as, {"case": case.name, "params": case.p.__dict__, "x0": case.x0,
                                             "v0": case.v0, "F": case.F, "t_F": case.t_F,
                                             "variables": rows})
    assert not failures, f"{case.name} at output_interval {interval}:\n" + "\n".join(failures)


@pytest.mark.parametrize("interval", INTERVALS)
@pytest.mark.parametrize("case", CASES, ids=lambda c: c.name)
def test_simulate_matches_closed_form(fmu, case: Case, interval: float):
    res = simulate(fmu(NAME), relative_tolerance=1e-8, output_interval=interval,
                   start_values=case.start_values(), input=case.input(), stop_time=STOP,
                   output=["x", "x_dot", "x_ddot"])
    t = res.time
    bad = [r for r in res.log if r.status >= fmi2Error]
    assert not bad, "errors logged during the run:\n" + "\n".join(map(str, bad))
    assert t[0] == 0.0
    assert t[-1] == pytest.approx(STOP, abs=1e-9), f"the run ended at t = {t[-1]!r}, not {STOP}"
    n_regular = math.floor(STOP / interval + 1e-9)
    assert len(t) >= n_regular + 1, f"{len(t)} samples, expected at least {n_regular + 1}"
    x_ref, v_ref, a_ref = case.reference(t)
    _check_against_reference(case, interval, res, x_ref, v_ref, a_ref, f"{case.name}@{interval}")


@pytest.mark.parametrize("interval", [0.5, 2.5])
def test_tolerance_is_honoured_over_long_communication_steps(fmu, interval):
    """With communication steps far longer than the solver's steps, the accuracy must come
    from the tolerance given to fmi2SetupExperiment: 1e-8 still meets the 1e-6 criterion,
    and a tighter tolerance gives a smaller error than a looser one."""
    case = next(c for c in CASES if c.name == "harmonic_w1.9_z0.1")
    errs = {}
    for rtol in (1e-4, 1e-8, 1e-11):
        res = simulate(fmu(NAME), relative_tolerance=rtol, output_interval=interval,
                       start_values=case.start_values(), stop_time=STOP, output=["x"])
        assert res.time[-1] == pytest.approx(STOP)
        x_ref, _, _ = case.reference(res.time)
        err, rng, _ = max_error(res["x"], x_ref)
        errs[rtol] = err / rng
    print(f"long steps {interval}: relative error by tolerance {errs}")
    assert errs[1e-8] <= REL_LIMIT, f"rtol 1e-8, communication step {interval}: {errs[1e-8]:.3e} of range"
    assert errs[1e-11] < errs[1e-4], f"a tighter tolerance did not reduce the error: {errs}"
    assert errs[1e-11] <= 1e-8, f"rtol 1e-11 gives only {errs[1e-11]:.3e} of range"


def test_default_experiment_runs_without_arguments(fmu):
    """simulate_fmu with nothing but the file: DefaultExperiment, defaults, free response."""
    res = simulate(fmu(NAME), relative_tolerance=None, output=["x", "x_dot", "x_ddot"])
    assert res.time[-1] == pytest.approx(STOP)
    x_ref, _, _ = response(res.time, Params(), 1.0, 0.0)
    err, rng, _ = max_error(res["x"], x_ref)
    # The DefaultExperiment's own tolerance applies here: only a loose sanity bound.
    assert err <= 1e-3 * rng


# =======================================================================================
# Calculated parameters


@pytest.mark.parametrize("m,c,k", [(None, None, None), (1.0, 0.4, 4.0), (2.5, 0.3, 7.0), (0.5, 5.0, 2.0),
                                   (1.0, 4.0, 4.0), (1.0, 0.0, 9.0), (3e-3, 1e2, 7e5)])
def test_calculated_parameters(slave, m, c, k):
    s = slave(NAME)
    sv = {n: v for n, v in (("m", m), ("c", c), ("k", k)) if v is not None}
    s.initialize(sv)
    m_, c_, k_ = (m or 1.0, 0.4 if c is None else c, k or 4.0)
    omega_n, zeta = s.get("omega_n", "zeta")
    assert omega_n == pytest.approx(math.sqrt(k_ / m_), rel=1e-14, abs=0)
    assert zeta == pytest.approx(c_ / (2.0 * math.sqrt(m_ * k_)), rel=1e-14, abs=0)


def test_start_values_read_back_after_initialization(slave):
    s = slave(NAME)
    s.initialize()
    got = dict(zip(["m", "c", "k", "F0", "omega", "F", "x", "x_dot"],
                   s.get("m", "c", "k", "F0", "omega", "F", "x", "x_dot")))
    assert got == DEFAULTS
    # x_ddot at t = 0 from the equation with the defaults: (0 - 0.4*0 - 4*1) / 1
    assert s.get("x_ddot")[0] == pytest.approx(-4.0, rel=1e-15)


# =======================================================================================
# Invalid parameters


@pytest.mark.parametrize("logging_on", [False, True], ids=["loggingOff", "loggingOn"])
@pytest.mark.parametrize("m", [0.0, -1.0])
def test_nonpositive_mass_fails_initialization(slave, m, logging_on):
    s = slave(NAME, logging_on=logging_on)
    s.setup()
    statuses = {"fmi2SetReal(m)": s.set_real_status({"m": m})}
    if statuses["fmi2SetReal(m)"] < fmi2Error:
        statuses["fmi2EnterInitializationMode"] = s.call("fmi2EnterInitializationMode")
    if max(statuses.values()) < fmi2Error:
        statuses["fmi2ExitInitializationMode"] = s.call("fmi2ExitInitializationMode")
    worst = max(statuses.values())
    assert worst in (fmi2Error, fmi2Fatal), (
        f"m = {m}: initialization did not fail: "
        + ", ".join(f"{k} -> {status_name(v)}" for k, v in statuses.items()))
    assert worst == fmi2Error, f"m = {m}: {status_name(worst)} where fmi2Error is expected"
    named = [r for r in s.log.records if r.status >= fmi2Error and re.search(r"(?<![\w.])m(?![\w(])", r.message)]
    assert named, f"m = {m}: no error message naming `m` was logged; log:\n{s.log.text()}"


@pytest.mark.parametrize("m", [0.0, -1.0])
def test_nonpositive_mass_makes_simulate_fmu_raise(fmu, m):
    mark = simulate_refused(fmu(NAME), {"m": m})
    assert any(re.search(r"(?<![\w.])m(?![\w(])", r.message) for r in mark.records), \
        f"no message naming `m`; log:\n{mark.text()}"


# =======================================================================================
# Call sequences


def _instantiated(s: Slave):
    pass


def _setup_done(s: Slave):
    s.setup()


def _in_init(s: Slave):
    s.setup()
    s.enter()


def _step_complete(s: Slave):
    s.initialize()


def _stepped(s: Slave):
    s.initialize()
    s.step(0.0, 0.01)


def _terminated(s: Slave):
    s.initialize()
    s.step(0.0, 0.01)
    assert s.call("fmi2Terminate") == fmi2OK, f"first fmi2Terminate failed; log:\n{s.log.text()}"


def _do_step(s: Slave):
    return s.call("fmi2DoStep", 0.0, 0.01, 1)


def _do_step_at_0_01(s: Slave):
    return s.call("fmi2DoStep", 0.01, 0.01, 1)


ILLEGAL = [
    # (id, prepare, function, call)
    ("doStep_after_instantiate", _instantiated, "fmi2DoStep", _do_step),
    ("doStep_after_setupExperiment", _setup_done, "fmi2DoStep", _do_step),
    ("doStep_in_initialization_mode", _in_init, "fmi2DoStep", _do_step),
    ("exitInitializationMode_without_enter", _setup_done, "fmi2ExitInitializationMode",
     lambda s: s.call("fmi2ExitInitializationMode")),
    ("exitInitializationMode_after_instantiate", _instantiated, "fmi2ExitInitializationMode",
     lambda s: s.call("fmi2ExitInitializationMode")),
    ("enterInitializationMode_twice", _in_init, "fmi2EnterInitializationMode",
     lambda s: s.call("fmi2EnterInitializationMode")),
    ("enterInitializationMode_after_init", _step_complete, "fmi2EnterInitializationMode",
     lambda s: s.call("fmi2EnterInitializationMode")),
    ("setupExperiment_in_initialization_mode", _in_init, "fmi2SetupExperiment",
     lambda s: s.call("fmi2SetupExperiment", 0, 0.0, 0.0, 0, 0.0)),
    ("setupExperiment_after_init", _step_complete, "fmi2SetupExperiment",
     lambda s: s.call("fmi2SetupExperiment", 0, 0.0, 0.0, 0, 0.0)),
    ("terminate_before_init", _instantiated, "fmi2Terminate", lambda s: s.call("fmi2Terminate")),
    ("terminate_in_initialization_mode", _in_init, "fmi2Terminate", lambda s: s.call("fmi2Terminate")),
    ("terminate_twice", _terminated, "fmi2Terminate", lambda s: s.call("fmi2Terminate")),
    ("doStep_after_terminate", _terminated, "fmi2DoStep", _do_step_at_0_01),
    ("setReal_input_after_terminate", _terminated, "fmi2SetReal", lambda s: s.set_real_status({"F": 1.0})),
]


@pytest.mark.parametrize("prepare,function,call", [i[1:] for i in ILLEGAL], ids=[i[0] for i in ILLEGAL])
def test_illegal_call_sequence_is_an_error(slave, prepare, function, call):
    s = slave(NAME)
    prepare(s)
    mark = LogMark()
    status = call(s)
    assert status == fmi2Error, f"{function} returned {status_name(status)}, expected fmi2Error; log:\n{mark.text()}"
    hits = mark.find(r"illegal call sequence")
    assert hits, f"{function}: no message containing 'illegal call sequence' was logged; log:\n{mark.text()}"
    assert any(function in r.message for r in hits), \
        f"the message does not name {function}: {[r.message for r in hits]}"
    assert all(r.status >= fmi2Error for r in hits), f"logged with status {[status_name(r.status) for r in hits]}"


def test_setting_fixed_parameter_after_initialization_is_rejected(slave):
    s = slave(NAME)
    s.initialize()
    mark = LogMark()
    status = s.set_real_status({"m": 2.0})
    assert status == fmi2Error, f"fmi2SetReal(m) after initialization returned {status_name(status)}"
    msgs = [r for r in mark.records if r.status >= fmi2Error]
    assert msgs, f"no error message logged; log:\n{mark.text()}"
    assert any(re.search(r"illegal call sequence", r.message, re.I)
               or re.search(r"(?<![\w.])m(?![\w(])", r.message) for r in msgs), \
        f"the message neither says 'illegal call sequence' nor names `m`: {[r.message for r in msgs]}"


def test_rejected_set_of_fixed_parameter_changes_nothing(slave):
    s = slave(NAME)
    s.initialize()
    s.set_real_status({"m": 2.0})
    # fmi2Error leaves the instance usable for getters; whatever else it allows, m must be unchanged
    status, values = s.get_real_status(["m", "omega_n"])
    if status == fmi2OK:
        assert values == [1.0, 2.0]


# fmi2GetReal is not allowed in the instantiated state at all (FMI 2.0.5 table 4.2.4): skip that pair
@pytest.mark.parametrize("op,state", [("get", "initialization"), ("get", "stepComplete"), ("set", "instantiated"),
                                      ("set", "initialization"), ("set", "stepComplete")])
def test_unknown_value_reference_is_an_error(slave, state, op):
    s = slave(NAME)
    {"instantiated": _instantiated, "initialization": _in_init, "stepComplete": _step_complete}[state](s)
    bad_vr = max(s.vr.values()) + 1000
    mark = LogMark()
    if op == "get":
        status, _ = s.get_real_status([s.vr["x"], bad_vr])
    else:
        status = s.set_real_status({bad_vr: 1.0})
    assert status == fmi2Error, f"fmi2{op.title()}Real with value reference {bad_vr}: {status_name(status)}"
    assert mark.find(str(bad_vr), status=fmi2Error), \
        f"no error message naming value reference {bad_vr}; log:\n{mark.text()}"


def test_wrong_guid_fails_to_instantiate(fmu):
    path = fmu(NAME)
    s = Slave(path, instantiate=False)
    try:
        mark = LogMark()
        comp = s.fmu.fmi2Instantiate(NAME.encode(), 1, b"{00000000-0000-0000-0000-000000000000}",
                                     Path(s.unzipdir, "resources").as_uri().encode(),
                                     byref(fmutest.CALLBACKS), 0, 0)
        assert not comp, "fmi2Instantiate accepted a foreign GUID"
        assert mark.find(r"guid"), f"no message about the GUID; log:\n{mark.text()}"
    finally:
        s.fmu.freeLibrary()


def test_an_unknown_fmu_type_is_refused(fmu):
    """fmuType is fmi2ModelExchange (0) or fmi2CoSimulation (1); anything else is refused
    with a message."""
    path = fmu(NAME)
    s = Slave(path, instantiate=False)
    try:
        mark = LogMark()
        comp = s.fmu.fmi2Instantiate(NAME.encode(), 2, s.md.guid.encode(),
                                     Path(s.unzipdir, "resources").as_uri().encode(),
                                     byref(fmutest.CALLBACKS), 0, 0)
        if comp:
            s.fmu.fmi2FreeInstance(comp)
        assert not comp, "fmi2Instantiate(fmuType = 2) succeeded"
        assert mark.find(r"fmuType = 2"), f"refused without a message naming it; log:\n{mark.text()}"
    finally:
        s.fmu.freeLibrary()


def test_messages_are_passed_as_percent_s_argument(slave):
    """The logger's `message` argument is a printf format: the FMU must pass "%s" and the
    text as its argument, never the text itself (a '%' in a message would be misread)."""
    s = slave(NAME, raw_logger=True)
    s.call("fmi2DoStep", 0.0, 0.01, 1)  # illegal: provokes a message
    assert s.log.records, "nothing was logged for an illegal fmi2DoStep"
    assert all(r.message == "%s" for r in s.log.records), [r.message for r in s.log.records]


def test_log_carries_the_instance_name(slave):
    s = slave(NAME, instance_name="oscillator under test")
    s.call("fmi2DoStep", 0.0, 0.01, 1)
    assert s.log.records, "nothing was logged for an illegal fmi2DoStep"
    assert {r.instance for r in s.log.records} == {"oscillator under test"}


def test_legal_sequence_returns_ok_and_logs_no_error(slave):
    s = slave(NAME)
    s.initialize(stop=1.0)
    t = 0.0
    for _ in range(100):
        s.step(t, 0.01)
        t += 0.01
    assert s.call("fmi2Terminate") == fmi2OK
    assert not [r for r in s.log.records if r.status >= fmi2Warning], s.log.text()


# =======================================================================================
# Tunable parameters between steps


def _run_steps(s: Slave, t0: float, t1: float, h: float, names=("x", "x_dot", "x_ddot")):
    n = int(round((t1 - t0) / h))
    ts, rows = [], []
    for i in range(n):
        t = t0 + i * h
        s.step(t, h)
        ts.append(t0 + (i + 1) * h)
        rows.append(s.get(*names))
    return np.array(ts), np.array(rows)


TUNABLE = [
    ("c", 0.4, 2.5),
    ("k", 4.0, 9.0),
    ("F0", 0.0, 1.5),
    ("omega", 1.0, 2.6),
]


@pytest.mark.parametrize("name,before,after", TUNABLE, ids=[t[0] for t in TUNABLE])
def test_tunable_parameter_change_takes_effect(slave, name, before, after):
    s = slave(NAME)
    p0 = Params(F0=0.7) if name == "omega" else Params()
    s.initialize({"F0": p0.F0} if p0.F0 else None)
    assert s.get(name)[0] == before
    h, t_change, t_end = 0.01, 5.0, 12.0
    t1, r1 = _run_steps(s, 0.0, t_change, h)
    s.set(**{name: after})
    assert s.get(name)[0] == after, f"{name} reads back {s.get(name)[0]} after fmi2SetReal({after})"
    t2, r2 = _run_steps(s, t_change, t_end, h)
    t = np.concatenate([t1, t2])
    got = np.vstack([r1, r2])
    p1 = replace(p0, **{name: after})
    ref = piecewise(t, [Segment(0.0, p0), Segment(t_change, p1)], 1.0, 0.0)
    # the same run without the change, to prove the change made a difference
    unchanged = piecewise(t, [Segment(0.0, p0)], 1.0, 0.0)
    failures = []
    rows = []
    for j, var in enumerate(["x", "x_dot", "x_ddot"]):
        err, rng, i = max_error(got[:, j], ref[j])
        rel = err / rng
        rows.append(dict(variable=var, output_interval=h, max_error=err, range=rng, relative=rel,
                         limit=REL_LIMIT, at_t=float(t[i]), **{"pass": rel <= REL_LIMIT}))
        if rel > REL_LIMIT:
            failures.append(f"{var}: max error {err:.3e} = {rel:.3e} of range at t = {t[i]:.4g} "
                            f"(FMU {got[i, j]!r}, reference {ref[j][i]!r})")
        assert np.max(np.abs(unchanged[j] - ref[j])) > 1e3 * REL_LIMIT * rng  # the case is meaningful
    record_figures("oscillator", f"tunable_{name}_{before}->{after}_at_{t_change}",
                   {"case": f"set {name} from {before} to {after} at t = {t_change}", "variables": rows})
    assert not failures, f"after changing {name} at t = {t_change}:\n" + "\n".join(failures)


def test_input_change_between_low_level_steps(slave):
    s = slave(NAME)
    s.initialize()
    h = 0.01
    t1, r1 = _run_steps(s, 0.0, 3.0, h)
    s.set(F=2.0)
    t2, r2 = _run_steps(s, 3.0, 10.0, h)
    t = np.concatenate([t1, t2])
    got = np.vstack([r1, r2])
    ref = piecewise(t, [Segment(0.0, Params()), Segment(3.0, Params(), 2.0)], 1.0, 0.0)
    for j, var in enumerate(["x", "x_dot", "x_ddot"]):
        err, rng, i = max_error(got[:, j], ref[j])
        assert err <= REL_LIMIT * rng, f"{var}: {err:.3e} > {REL_LIMIT:g} x {rng:.4g} at t = {t[i]}"
