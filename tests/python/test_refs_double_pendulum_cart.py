"""Self-checks of tests/python/refs/double_pendulum_cart.py, the independent reference of DoublePendulumCart:
two routes that share no code or equations (test_refs.py).
"""

from __future__ import annotations

import math

import numpy as np

from refs import derive, double_pendulum_cart, step_input
from test_refs import energy_rate_check, rel_err

RNG = np.random.default_rng(20240611)


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


def test_double_pendulum_cart_energy_rate_pointwise():
    p = double_pendulum_cart.params(c=0.7)
    energy_rate_check(derive.double_pendulum_cart_symbolic(), random_dpc_states, double_pendulum_cart.rhs, p,
                       list(double_pendulum_cart.PARAMS), ["F"],
                       lambda y, p, u: double_pendulum_cart.power(y, p, u["F"]))
