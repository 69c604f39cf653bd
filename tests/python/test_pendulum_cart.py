"""The PendulumCart FMU against its contract (docs/mechanisms/PendulumCart.md) under FMPy.

    (M+m) x'' + c1 x' + k x + m l (th'' cos th - th'^2 sin th) = F
    m l x'' cos th + 7/3 m l^2 th'' + c2 th' + m g l sin th    = 3 F l cos th
    F_N = (M+m) g + m l (th'' sin th + th'^2 cos th)
    E   = 1/2 (M+m) x'^2 + m l x' th' cos th + 7/6 m l^2 th'^2 + 1/2 k x^2 - m g l cos th

References, none taken from mechfmu's Rust code:

* the equations of motion derived twice with sympy (Lagrange, and Newton-Euler body by body
  with the reaction forces as unknowns) in tests/python/refs/derive/pendulum_cart.py, evaluated at random
  states against the FMU's x_ddot, theta_ddot, F_N and E;
* the right-hand side written below from the contract's equations, integrated by scipy's
  DOP853 at rtol 1e-12 for the large swings;
* the work-energy balance dE/dt = F (x' + 3 l th' cos th) - c1 x'^2 - c2 th'^2, both at every
  sample (chain rule with the FMU's accelerations) and integrated along a run;
* the linearized modes from the contract's mass and stiffness matrices (closed form and
  scipy's generalized eigensolver).

Achieved figures are written to target/test-figures/pendulum_cart.{json,md}.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from scipy.integrate import simpson, solve_ivp
from scipy.linalg import eigh
from scipy.optimize import least_squares

from fmpy.fmi2 import FMU2Model

import fmutest
from fmutest import Slave, figure_row as _row, fmu_path, max_error, record_figures, simulate, simulate_refused
from refs import derive, step_input

NAME = "PendulumCart"
FIGURES = "pendulum_cart"
REL_LIMIT = 1e-6
STOP = 10.0

PARAMETERS = dict(M=1.0, m=0.5, l=0.25, k=10.0, c1=0.0, c2=0.0, g=9.81)
STARTS = dict(x=0.0, x_dot=0.0, theta=0.3, theta_dot=0.0)
STATES = ["x", "x_dot", "theta", "theta_dot"]
OUTPUTS = STATES + ["x_ddot", "theta_ddot", "F_N", "E"]


def params(**kw) -> dict:
    p = dict(PARAMETERS)
    p.update({k: float(v) for k, v in kw.items()})
    return p


# =======================================================================================
# The equations, written from the contract (vectorized over numpy arrays)


def accelerations(p, x, v, th, w, F):
    """(x'', th'') from the two equations of motion, solved by Cramer's rule."""
    M, m, l, g = p["M"], p["m"], p["l"], p["g"]
    s, c = np.sin(th), np.cos(th)
    a11, a12, a22 = M + m, m * l * c, 7.0 / 3.0 * m * l * l
    b1 = F - p["c1"] * v - p["k"] * x + m * l * w * w * s
    b2 = 3.0 * F * l * c - p["c2"] * w - m * g * l * s
    det = a11 * a22 - a12 * a12
    return (a22 * b1 - a12 * b2) / det, (a11 * b2 - a12 * b1) / det


def normal_force(p, th, w, th_dd):
    return (p["M"] + p["m"]) * p["g"] + p["m"] * p["l"] * (th_dd * np.sin(th) + w * w * np.cos(th))


def energy(p, x, v, th, w):
    M, m, l = p["M"], p["m"], p["l"]
    return (0.5 * (M + m) * v * v + m * l * v * w * np.cos(th) + 7.0 / 6.0 * m * l * l * w * w
            + 0.5 * p["k"] * x * x - m * p["g"] * l * np.cos(th))


def power(p, v, th, w, F):
    return F * (v + 3.0 * p["l"] * w * np.cos(th)) - p["c1"] * v * v - p["c2"] * w * w


def reference(p, y0, t, switches=(0.0,), forces=(0.0,)):
    """DOP853 (rtol = atol = 1e-12) of the equations above, restarted at every switch of the
    piecewise-constant F; outputs at each sample with the F held over the step that ends
    there (what a co-simulation FMU reports)."""
    def rhs(_, y, F):
        xa, tha = accelerations(p, y[0], y[1], y[2], y[3], F)
        return [y[1], xa, y[3], tha]

    Y = np.empty((4, t.size))
    y = np.asarray(y0, dtype=float)
    edges = list(switches) + [t[-1]]
    for i, F in enumerate(forces):
        a, b = edges[i], edges[i + 1]
        sel = (t >= a) & (t <= b) if i == 0 else (t > a) & (t <= b)
        if b <= a:
            continue
        sol = solve_ivp(rhs, (a, b), y, method="DOP853", rtol=1e-12, atol=1e-12,
                        t_eval=np.concatenate([t[sel], [b]]) if not np.any(t[sel] == b) else t[sel], args=(F,))
        assert sol.success, sol.message
        Y[:, sel] = sol.y[:, : int(sel.sum())]
        y = sol.y[:, -1]
    idx = np.searchsorted(np.asarray(switches), t, side="left") - 1
    idx[0] = 0
    Fs = np.asarray(forces, dtype=float)[np.clip(idx, 0, None)]
    xa, tha = accelerations(p, *Y, Fs)
    out = dict(zip(STATES, Y))
    out.update(x_ddot=xa, theta_ddot=tha, F_N=normal_force(p, Y[2], Y[3], tha), E=energy(p, *Y), F=Fs)
    return out


def linear_matrices(p):
    M, m, l = p["M"], p["m"], p["l"]
    return (np.array([[M + m, m * l], [m * l, 7.0 / 3.0 * m * l * l]]),
            np.diag([p["k"], m * p["g"] * l]))


def closed_form_frequencies(p):
    """det(K - w^2 M) = 0: a w^4 - b w^2 + c = 0, smaller root as 2c / (b + sqrt(D))."""
    M, m, l, g, k = p["M"], p["m"], p["l"], p["g"], p["k"]
    a = (M + m) * 7.0 / 3.0 * m * l * l - (m * l) ** 2
    b = k * 7.0 / 3.0 * m * l * l + (M + m) * m * g * l
    c = k * m * g * l
    sD = math.sqrt(b * b - 4.0 * a * c)
    return math.sqrt(2.0 * c / (b + sD)), math.sqrt((b + sD) / (2.0 * a))


# =======================================================================================
# The FMU file (its modelDescription: fmus/pendulum_cart/validation/contract.toml, test_contract.py)


def test_outputs_at_start_follow_the_equations(slave):
    s = slave(NAME)
    s.initialize()
    p = params()
    got = dict(zip(OUTPUTS, s.get(*OUTPUTS)))
    xa, tha = accelerations(p, 0.0, 0.0, 0.3, 0.0, 0.0)
    want = dict(STARTS, x_ddot=xa, theta_ddot=tha, F_N=normal_force(p, 0.3, 0.0, tha),
                E=energy(p, 0.0, 0.0, 0.3, 0.0))
    for n in OUTPUTS:
        assert got[n] == pytest.approx(want[n], rel=1e-14, abs=1e-15), n


# =======================================================================================
# Linearized frequencies

FREQ_SETS = [dict(), dict(M=3.0, m=0.2, l=1.0, k=1.0), dict(M=0.4, m=2.0, l=0.1, k=100.0, g=1.6),
             dict(k=0.0), dict(M=50.0, m=1e-3, l=2.0, k=0.3), dict(g=0.0, k=4.0)]


@pytest.mark.parametrize("overrides", FREQ_SETS, ids=lambda d: ",".join(f"{k}={v}" for k, v in d.items()) or "defaults")
def test_linearized_frequencies(slave, overrides):
    p = params(**overrides)
    s = slave(NAME)
    s.initialize(overrides)
    got = s.get("omega_n1", "omega_n2")
    want = closed_form_frequencies(p)
    Mm, K = linear_matrices(p)
    w2 = eigh(K, Mm, eigvals_only=True)
    assert np.allclose(np.sqrt(np.clip(w2, 0, None)), want, rtol=1e-12, atol=1e-12 * want[1])
    rows = []
    for i in range(2):
        err = abs(got[i] - want[i])
        rows.append(_row(f"omega_n{i + 1}", err, want[1], err / want[1], 1e-13, None))
        assert err <= 1e-13 * want[1], f"omega_n{i + 1}: FMU {got[i]!r}, closed form {want[i]!r}"
    if p["k"] == 0.0 or p["g"] == 0.0:
        assert got[0] == 0.0, "a free cart (k = 0) or a rod without gravity has a zero frequency"
    record_figures(FIGURES, "frequencies " + (",".join(f"{k}={v}" for k, v in overrides.items()) or "defaults"),
                   {"params": p, "variables": rows})


def test_frequencies_follow_a_tunable_stiffness(slave):
    s = slave(NAME)
    s.initialize()
    s.step(0.0, 0.01)
    s.set(k=0.0)
    assert s.get("omega_n1")[0] == 0.0
    s.set(k=40.0)
    want = closed_form_frequencies(params(k=40.0))
    got = s.get("omega_n1", "omega_n2")
    assert got == pytest.approx(list(want), rel=1e-13)


# =======================================================================================
# The right-hand side against Lagrange and Newton-Euler (sympy, refs/derive/pendulum_cart.py)

def _random_cases(n: int):
    rng = np.random.default_rng(31415)
    for _ in range(n):
        p = dict(M=rng.uniform(0.1, 5), m=rng.uniform(0.05, 3), l=rng.uniform(0.05, 1.5), k=rng.uniform(0, 50),
                 c1=rng.uniform(0, 2), c2=rng.uniform(0, 0.5), g=rng.uniform(0, 20))
        y = dict(x=rng.uniform(-1, 1), x_dot=rng.uniform(-3, 3), theta=rng.uniform(-7, 7),
                 theta_dot=rng.uniform(-10, 10))
        yield p, y, float(rng.uniform(-10, 10))


def test_right_hand_side_satisfies_lagrange_and_newton_euler(slave):
    lagrange, newton_euler = derive.pendulum_cart_lagrange(), derive.pendulum_cart_newton_euler()
    worst = {n: 0.0 for n in ("x_ddot", "theta_ddot", "F_N", "E", "residual_x", "residual_theta")}
    for p, y, F in _random_cases(40):
        s = slave(NAME)
        s.initialize({**p, **y, "F": F})
        got = dict(zip(OUTPUTS, s.get(*OUTPUTS)))
        s.free()
        state = [y[n] for n in STATES]
        lag = lagrange(state, p, {"F": F})
        ne = newton_euler(state, p, {"F": F})
        acc_scale = {"x_ddot": max(abs(lag[0]), abs(ne["x_ddot"]), 1.0),
                     "theta_ddot": max(abs(lag[1]), abs(ne["theta_ddot"]), 1.0)}
        for n, i in (("x_ddot", 0), ("theta_ddot", 1)):
            for route, want in (("Lagrange", lag[i]), ("Newton-Euler", ne[n])):
                rel = abs(got[n] - want) / acc_scale[n]
                worst[n] = max(worst[n], rel)
                assert rel <= 1e-11, f"{n}: FMU {got[n]!r}, {route} {want!r} at {p}, {y}, F = {F}"
        f_scale = (p["M"] + p["m"]) * p["g"] + p["m"] * p["l"] * (abs(ne["theta_ddot"]) + y["theta_dot"] ** 2) + 1.0
        rel = abs(got["F_N"] - ne["F_N"]) / f_scale
        worst["F_N"] = max(worst["F_N"], rel)
        assert rel <= 1e-11, f"F_N: FMU {got['F_N']!r}, Newton-Euler {ne['F_N']!r}"
        e_scale = abs(ne["E"]) + p["m"] * p["g"] * p["l"] + 1.0
        rel = abs(got["E"] - ne["E"]) / e_scale
        worst["E"] = max(worst["E"], rel)
        assert rel <= 1e-13, f"E: FMU {got['E']!r}, from T + V {ne['E']!r}"
        # the contract's two equations, with the FMU's accelerations
        M, m, l, g, k, c1, c2 = (p[n] for n in ("M", "m", "l", "g", "k", "c1", "c2"))
        x, v, th, w = state
        xa, tha = got["x_ddot"], got["theta_ddot"]
        r1 = (M + m) * xa + c1 * v + k * x + m * l * (tha * math.cos(th) - w * w * math.sin(th)) - F
        r2 = m * l * xa * math.cos(th) + 7 / 3 * m * l * l * tha + c2 * w + m * g * l * math.sin(th) - 3 * F * l * math.cos(th)
        worst["residual_x"] = max(worst["residual_x"], abs(r1) / f_scale)
        worst["residual_theta"] = max(worst["residual_theta"], abs(r2) / (f_scale * l))
        assert abs(r1) <= 1e-12 * f_scale and abs(r2) <= 1e-12 * f_scale * l, (r1, r2)
    record_figures(FIGURES, "right-hand side vs Lagrange and Newton-Euler (40 random states)",
                   {"case": "max |FMU - route| / scale over random states",
                    "variables": [_row(n, v, 1.0, v, 1e-11, None) for n, v in worst.items()]})


# =======================================================================================
# Energy

ENERGY_STARTS = [dict(), dict(theta=2.5, x=0.1), dict(theta=0.0, theta_dot=9.0, x_dot=-0.4)]


@pytest.mark.parametrize("start", ENERGY_STARTS, ids=["default", "large_swing", "looping"])
def test_energy_is_constant_without_damping_and_force(fmu, start):
    p = params()
    res = simulate(fmu(NAME), relative_tolerance=1e-8, output_interval=0.01, stop_time=20.0,
                   start_values=start, output=OUTPUTS)
    assert res.time[-1] == pytest.approx(20.0)
    E = res["E"]
    drift = float(np.max(np.abs(E - E[0])))
    rel = drift / abs(E[0])
    # the same drift against the energy above the equilibrium (E_min = -m g l): the motion's scale
    rel_motion = drift / (E[0] + p["m"] * p["g"] * p["l"])
    record_figures(FIGURES, f"energy constant {start or 'default'}",
                   {"case": "max |E - E(0)| over 20 s, c1 = c2 = 0, F = 0", "variables": [
                       _row("E / |E(0)|", drift, abs(E[0]), rel, 1e-7, float(res.time[np.argmax(np.abs(E - E[0]))]), 0.01),
                       _row("E / (E(0) - E_min)", drift, E[0] + p["m"] * p["g"] * p["l"], rel_motion, 1e-7, None, 0.01)]})
    assert rel <= 1e-7, f"E drifts by {drift:.3e} = {rel:.3e} of |E(0)|"
    assert rel_motion <= 1e-7, f"E drifts by {drift:.3e} = {rel_motion:.3e} of the energy above equilibrium"


BAL_P = dict(c1=0.4, c2=0.03, k=10.0)
BAL_SWITCHES = [0.0, 1.0, 4.0, 7.0]
BAL_FORCES = [0.8, -1.2, 2.0, 0.0]
BAL_START = dict(theta=0.8, x_dot=0.3)


def test_energy_balance_with_damping_and_input(fmu):
    """dE/dt = F (x' + 3 l th' cos th) - c1 x'^2 - c2 th'^2, with F an fmpy input table."""
    p = params(**BAL_P)
    h = 0.002
    inp = step_input(["F"], BAL_SWITCHES, [[f] for f in BAL_FORCES], t_end=STOP)
    res = simulate(fmu(NAME), relative_tolerance=1e-8, output_interval=h, stop_time=STOP,
                   start_values={**BAL_P, **BAL_START}, input=inp, output=OUTPUTS)
    t = res.time
    x, v, th, w, xa, tha, E = (res[n] for n in ("x", "x_dot", "theta", "theta_dot", "x_ddot", "theta_ddot", "E"))
    idx = np.clip(np.searchsorted(BAL_SWITCHES, t, side="left") - 1, 0, None)
    F_held = np.asarray(BAL_FORCES)[idx]  # the force over the step that ends at each sample

    # 1. At every sample: dE/dt by the chain rule on the contract's E with the FMU's
    #    accelerations equals the power of F and the dampers.
    M, m, l, g, k = p["M"], p["m"], p["l"], p["g"], p["k"]
    s, c = np.sin(th), np.cos(th)
    dE = ((M + m) * v * xa + m * l * (xa * w * c + v * tha * c - v * w * w * s) + 7 / 3 * m * l * l * w * tha
          + k * x * v + m * g * l * s * w)
    P = power(p, v, th, w, F_held)
    p_scale = float(np.max(np.abs(P)))
    pointwise = float(np.max(np.abs(dE - P)))
    assert pointwise <= 1e-12 * p_scale, f"dE/dt - P = {pointwise:.3e} (power scale {p_scale:.3g})"

    # 2. Along the run: E(t) - E(0) = integral of P, Simpson on each constant-force segment.
    edges = BAL_SWITCHES[1:] + [STOP]
    W, t_at = [0.0], [0.0]
    for (a, b), F in zip(zip(BAL_SWITCHES, edges), BAL_FORCES):
        sel = (t >= a - 1e-9) & (t <= b + 1e-9)
        assert sel.sum() % 2 == 1, "Simpson's rule wants an even number of intervals per segment"
        W.append(W[-1] + simpson(power(p, v[sel], th[sel], w[sel], F), x=t[sel]))
        t_at.append(b)
    E_at = np.interp(t_at, t, E)
    err = np.abs(E_at - E_at[0] - np.asarray(W))
    work_scale = float(np.sum(np.abs(np.diff(W))))  # total work exchanged, all segments
    worst = float(np.max(err))
    assert work_scale > 0.5, "the case must exchange a meaningful amount of work"
    record_figures(FIGURES, "energy balance c1, c2 > 0, input F",
                   {"case": "E(t) - E(0) against the integrated power", "params": p, "variables": [
                       _row("dE/dt - P (pointwise)", pointwise, p_scale, pointwise / p_scale, 1e-12, None, h),
                       _row("E - E(0) - W (integrated)", worst, work_scale, worst / work_scale, 1e-7,
                            float(t_at[int(np.argmax(err))]), h)]})
    assert worst <= 1e-7 * work_scale, f"E(t) - E(0) - W(t) = {worst:.3e} (work exchanged {work_scale:.3g} J)"


# =======================================================================================
# Normal force


def test_normal_force_at_the_bottom_of_a_swing_exceeds_the_weight(fmu):
    p = params()
    res = simulate(fmu(NAME), relative_tolerance=1e-8, output_interval=0.001, stop_time=5.0,
                   start_values={"theta": 1.2}, output=OUTPUTS)
    th, w, F_N, tha = res["theta"], res["theta_dot"], res["F_N"], res["theta_ddot"]
    weight = (p["M"] + p["m"]) * p["g"]
    crossings = np.flatnonzero(np.sign(th[:-1]) != np.sign(th[1:]))
    assert len(crossings) >= 3, "the rod must swing through the bottom several times"
    ne = derive.pendulum_cart_newton_euler()
    for i in crossings:
        j = i if abs(th[i]) < abs(th[i + 1]) else i + 1
        state = [res[n][j] for n in STATES]
        # at the bottom F_N - (M+m) g is about m l th'^2 > 0: the rod presses the cart down
        assert F_N[j] > weight + 0.9 * p["m"] * p["l"] * w[j] ** 2, f"F_N = {F_N[j]} at t = {res.time[j]}"
        assert F_N[j] == pytest.approx(ne(state, p, {"F": 0.0})["F_N"], rel=1e-12)
        notes = weight - p["m"] * p["l"] * (tha[j] * math.sin(th[j]) + w[j] ** 2 * math.cos(th[j]))
        assert notes < weight, "the notes' printed sign would put F_N below the weight here"
    margin = float(np.min(F_N[crossings] / weight)) - 1.0
    record_figures(FIGURES, "normal force at the bottom", {
        "case": "F_N / ((M+m) g) - 1 at the samples nearest theta = 0 (smallest); must be > 0",
        "min_excess_over_weight": margin, "crossings": int(len(crossings))})


# =======================================================================================
# Small oscillations


def _modal(p):
    Mm, K = linear_matrices(p)
    w2, Phi = eigh(K, Mm)
    return np.sqrt(w2), Phi


@pytest.mark.parametrize("start", ["theta0", "mode1", "mode2"])
def test_small_oscillations_at_the_linearized_frequencies(fmu, slave, start):
    """theta0 = 1e-3 (or a start on one linear mode): the modal coordinates of the FMU's
    (x, theta) are sinusoids at omega_n1 and omega_n2 (frequencies fitted by least squares)."""
    p = params()
    w_lin, Phi = _modal(p)
    w_closed = closed_form_frequencies(p)
    assert np.allclose(w_lin, w_closed, rtol=1e-12)
    eps = 1e-3
    if start == "theta0":
        q0 = np.array([0.0, eps])
    else:
        q0 = Phi[:, int(start[-1]) - 1] * eps / np.max(np.abs(Phi[:, int(start[-1]) - 1]))
    stop = 20.0
    res = simulate(fmu(NAME), relative_tolerance=1e-8, output_interval=0.01, stop_time=stop,
                   start_values={"x": q0[0], "theta": q0[1]}, output=["x", "theta", "omega_n1", "omega_n2"])
    t = res.time
    fmu_w = [float(res["omega_n1"][0]), float(res["omega_n2"][0])]
    assert fmu_w == pytest.approx(list(w_closed), rel=1e-13)
    eta = np.linalg.solve(Phi, np.vstack([res["x"], res["theta"]]))
    eta0 = np.linalg.solve(Phi, q0)
    amp = float(np.max(np.abs(eta0)))
    rows = []
    for i in range(2):
        if abs(eta0[i]) < 1e-9 * amp:  # a mode not excited by this start must stay quiet
            quiet = float(np.max(np.abs(eta[i]))) / amp
            rows.append(_row(f"eta{i + 1} (not excited) / amplitude", quiet * amp, amp, quiet, 1e-4, None, 0.01))
            assert quiet <= 1e-4, f"mode {i + 1} grew to {quiet:.2e} of the amplitude"
            continue

        def resid(z, i=i):
            return z[0] * np.cos(z[2] * t) + z[1] * np.sin(z[2] * t) - eta[i]

        fit = least_squares(resid, [eta0[i], 0.0, w_closed[i]], xtol=1e-15, ftol=1e-15, gtol=1e-15)
        w_fit = fit.x[2]
        rel_w = abs(w_fit / w_closed[i] - 1.0)
        misfit = float(np.max(np.abs(fit.fun))) / abs(eta0[i])
        # the linear prediction itself, no fit: eta_i(0) cos(omega_n_i t)
        lin = float(np.max(np.abs(eta[i] - eta0[i] * np.cos(fmu_w[i] * t)))) / abs(eta0[i])
        rows += [_row(f"omega fitted to eta{i + 1} vs omega_n{i + 1}", abs(w_fit - w_closed[i]), w_closed[i], rel_w,
                      1e-6, None, 0.01),
                 _row(f"eta{i + 1} - fitted sinusoid", misfit * abs(eta0[i]), abs(eta0[i]), misfit, 1e-4, None, 0.01),
                 _row(f"eta{i + 1} - eta{i + 1}(0) cos(omega_n{i + 1} t)", lin * abs(eta0[i]), abs(eta0[i]), lin, 1e-4,
                      None, 0.01)]
        assert rel_w <= 1e-6, f"mode {i + 1}: fitted {w_fit!r}, omega_n{i + 1} = {w_closed[i]!r}"
        assert misfit <= 1e-4 and lin <= 1e-4, (misfit, lin)
    record_figures(FIGURES, f"small oscillations {start}", {"case": f"start {q0.tolist()}, 20 s", "variables": rows})


# =======================================================================================
# Large swings against DOP853


SWINGS = {
    "large_swing": (dict(), dict(theta=2.5, x=0.1), [0.0], [0.0]),
    "looping_damped_forced": (dict(c1=0.2, c2=0.02, k=25.0), dict(theta=0.0, theta_dot=14.0),
                              [0.0, 2.0, 5.0], [0.0, 1.5, -1.0]),
}


@pytest.mark.parametrize("case", list(SWINGS))
def test_large_swing_matches_dop853(fmu, case):
    over, start, switches, forces = SWINGS[case]
    p = params(**over)
    inp = step_input(["F"], switches, [[f] for f in forces], t_end=STOP) if len(switches) > 1 else None
    res = simulate(fmu(NAME), relative_tolerance=1e-8, output_interval=0.01, stop_time=STOP,
                   start_values={**over, **start}, input=inp, output=OUTPUTS)
    t = res.time
    assert t[-1] == pytest.approx(STOP)
    y0 = [{**STARTS, **start}[n] for n in STATES]
    ref = reference(p, y0, t, switches, forces)
    if case == "looping_damped_forced":
        assert np.max(np.abs(ref["theta"])) > 2 * math.pi, "the case must go over the top"
    rows, failures = [], []
    for n in OUTPUTS:
        err, rng, i = max_error(res[n], ref[n])
        # relative to the range of the reference, or to its peak magnitude when that is larger
        # (E is constant in the undamped case: its range is only the reference's rounding)
        scale = max(rng, float(np.max(np.abs(ref[n]))))
        rel = err / scale
        rows.append(_row(n, err, scale, rel, REL_LIMIT, float(t[i]), 0.01))
        if rel > REL_LIMIT:
            failures.append(f"{n}: max error {err:.3e} = {rel:.3e} of {scale:.4g} at t = {t[i]:.4g}")
    record_figures(FIGURES, f"swing {case}", {"case": case, "params": p, "start": start, "variables": rows})
    assert not failures, "\n".join(failures)


def test_default_experiment_runs_without_arguments(fmu):
    res = simulate(fmu(NAME), relative_tolerance=None, output=["x", "theta"])
    assert res.time[-1] == pytest.approx(STOP)
    ref = reference(params(), [STARTS[n] for n in STATES], res.time)
    for n in ("x", "theta"):
        err, rng, _ = max_error(res[n], ref[n])
        assert err <= 1e-3 * rng  # the DefaultExperiment's own tolerance (1e-6): a loose sanity bound


# =======================================================================================
# Invalid parameters


@pytest.mark.parametrize("name,value", [("M", 0.0), ("m", -0.5), ("l", 0.0), ("k", -1.0), ("c1", -0.1), ("g", -9.81)])
def test_invalid_parameter_fails_initialization(slave, name, value):
    slave(NAME).expect_refused_at_initialization(name, value)


def test_zero_length_makes_simulate_fmu_raise(fmu):
    mark = simulate_refused(fmu(NAME), {"l": 0.0})
    assert any(re.search(r"(?<![\w.])l(?![\w(])", r.message) for r in mark.records), mark.text()


def test_legal_sequence_logs_no_error(slave):
    slave(NAME).expect_steps_without_error({"k": 0.0})


# =======================================================================================
# Linearization: the directional derivatives, in Co-Simulation and in Model Exchange


def test_linearizing_the_pendulum_cart_at_rest_gives_its_natural_frequencies():
    """In Co-Simulation, at rest: A = dx'/dx from fmi2GetDirectionalDerivative; its eigenvalues
    are +-i w1, +-i w2, the FMU's omega_n1 and omega_n2."""
    with Slave(fmu_path("PendulumCart")) as s:
        s.initialize({"theta": 0.0, "x": 0.0})
        states = ["x", "theta", "x_dot", "theta_dot"]
        rates = ["x_dot", "theta_dot", "x_ddot", "theta_ddot"]
        known = [s.vr[n] for n in states]
        unknown = [s.vr[n] for n in rates]
        A = np.column_stack([s.fmu.getDirectionalDerivative(unknown, known, list(np.eye(4)[j])) for j in range(4)])
        omega = np.sort(np.abs(np.linalg.eigvals(A).imag))[::2]
        w1, w2 = s.get("omega_n1", "omega_n2")
        assert omega == pytest.approx([w1, w2], rel=1e-9)
        assert np.max(np.abs(np.linalg.eigvals(A).real)) < 1e-9 * w2  # undamped by default


def test_linearizing_the_pendulum_cart_in_model_exchange_gives_its_natural_frequencies():
    """As the test above does in Co-Simulation, in Model Exchange: at rest, in
    continuous-time mode, A = dx'/dx from fmi2GetDirectionalDerivative (the derivatives'
    value references as unknowns, the states' as knowns). Its eigenvalues are +-i w1, +-i w2:
    the FMU's omega_n1, omega_n2, and the same as the Co-Simulation instance's."""
    directory, md = fmutest.extracted(fmu_path("PendulumCart"))
    vr = {v.name: v.valueReference for v in md.modelVariables}
    rates = [d.variable for d in md.derivatives]
    unknown = [r.valueReference for r in rates]
    known = [r.derivative.valueReference for r in rates]
    model = FMU2Model(guid=md.guid, unzipDirectory=directory, modelIdentifier=md.modelExchange.modelIdentifier,
                      instanceName="linearize")
    model.instantiate(callbacks=fmutest.CALLBACKS)
    try:
        model.setupExperiment(startTime=0.0)
        model.setReal([vr["x"], vr["theta"]], [0.0, 0.0])
        model.enterInitializationMode()
        model.exitInitializationMode()
        assert not model.newDiscreteStates()[1], "terminateSimulation at the start"
        model.enterContinuousTimeMode()
        A = np.column_stack([model.getDirectionalDerivative(unknown, known, list(seed)) for seed in np.eye(len(known))])
        w1, w2 = model.getReal([vr["omega_n1"], vr["omega_n2"]])
        model.terminate()
    finally:
        model.freeInstance()
    eig = np.linalg.eigvals(A)
    assert np.sort(np.abs(eig.imag))[::2] == pytest.approx([w1, w2], rel=1e-9)
    assert np.max(np.abs(eig.real)) < 1e-9 * w2  # undamped by default
    with Slave(fmu_path("PendulumCart")) as s:
        s.initialize({"x": 0.0, "theta": 0.0})
        A_cs = np.column_stack([s.fmu.getDirectionalDerivative(unknown, known, list(seed))
                                for seed in np.eye(len(known))])
    assert np.allclose(A, A_cs, rtol=1e-13, atol=0.0)

