"""Self-checks of tests/python/refs/pendulum_cart.py, the independent reference of PendulumCart:
two routes that share no code or equations (test_refs.py).
"""

from __future__ import annotations

import math

import numpy as np

from refs import derive, pendulum_cart, step_input
from test_refs import energy_rate_check, rel_err

RNG = np.random.default_rng(20240611)


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


def test_pendulum_cart_energy_rate_pointwise():
    p = pendulum_cart.params(c1=0.7, c2=0.05)
    energy_rate_check(derive.pendulum_cart_symbolic(), random_cart_states, pendulum_cart.rhs, p,
                       ["M", "m", "l", "k", "c1", "c2", "g"], ["F"],
                       lambda y, p, u: pendulum_cart.power(y, p, u["F"]))
