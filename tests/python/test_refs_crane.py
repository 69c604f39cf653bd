"""Self-checks of tests/python/refs/crane.py, the independent reference of Crane:
two routes that share no code or equations (test_refs.py).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad, solve_ivp

from refs import crane, derive, step_input
from test_refs import rel_err

RNG = np.random.default_rng(20240611)


def random_crane_state(rng: np.random.Generator) -> np.ndarray:
    """x, x_dot, theta, theta_dot, phi, phi_dot spread over the crane's range (CraneDynamics' too)."""
    return np.array([rng.uniform(1.0, 20.0), rng.normal(0, 2), rng.uniform(-1.5, 1.5), rng.normal(0, 0.5),
                     rng.uniform(-2.5, 2.5), rng.normal(0, 1.5)])


def random_crane_states(n):
    for _ in range(n):
        y = random_crane_state(RNG)
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
