"""Self-checks of tests/python/refs/crane_dynamics.py, the independent reference of CraneDynamics:
two routes that share no code or equations (test_refs.py).
"""

from __future__ import annotations

import math

import numpy as np

from refs import crane, crane_dynamics, derive, step_input
from test_refs import energy_rate_check
from test_refs_crane import random_crane_state

RNG = np.random.default_rng(20240611)


def random_cd_states(n):
    for _ in range(n):
        y = random_crane_state(RNG)
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


def test_crane_dynamics_energy_rate_pointwise():
    p = crane_dynamics.params()
    energy_rate_check(derive.crane_dynamics_symbolic(), random_cd_states, crane_dynamics.rhs, p,
                       ["m", "l", "g", "J_boom", "m_trolley"], ["F", "tau"],
                       lambda y, p, u: u["F"] * y[1] + u["tau"] * y[3])
