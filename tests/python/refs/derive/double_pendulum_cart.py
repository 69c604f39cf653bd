"""Both routes for the double pendulum on a driven cart."""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import sympy as sp

from ._sympy import coords, lagrange_equations, linear_system, plain, t, wrap


@lru_cache(maxsize=None)
def double_pendulum_cart_symbolic():
    """Both routes symbolically. Lagrange: T and V from the positions of the cart, m1 and m2,
    the virtual work of F and the drag on the cart. Newton: the cart, m1 and m2 each, the rod
    tensions T1, T2 and the track's normal force N as unknowns. Returns 'M', 'f' (M q'' = f),
    'ne_A', 'ne_b' (unknowns x'', phi1'', phi2'', T1, T2, N), 'energy', 'momentum', 'power',
    'force' (dp_x/dt) and the plain symbols."""
    M, m1, m2, l1, l2, g, c, F = sp.symbols("M m1 m2 l1 l2 g c F", real=True)
    qf, q0, q1, q2 = coords(["x", "phi1", "phi2"])
    x, p1, p2 = qf
    I, J = sp.Matrix([1, 0]), sp.Matrix([0, 1])
    e1 = sp.Matrix([sp.sin(p1), -sp.cos(p1)])      # along rod 1, from the pin to m1
    e2 = sp.Matrix([sp.sin(p2), -sp.cos(p2)])      # along rod 2, from m1 to m2
    r0 = x * I
    r1 = r0 + l1 * e1
    r2 = r1 + l2 * e2
    v0, v1, v2 = r0.diff(t), r1.diff(t), r2.diff(t)
    half = sp.Rational(1, 2)
    Tk = half * M * v0.dot(v0) + half * m1 * v1.dot(v1) + half * m2 * v2.dot(v2)
    V = g * (m1 * r1[1] + m2 * r2[1])
    Xi = [((F - c * x.diff(t)) * I).dot(r0.diff(q)) for q in qf]
    eqs = [plain(e, qf, q0, q1, q2) for e in lagrange_equations(Tk, V, qf, Xi)]
    Mm, f = linear_system(eqs, q2)

    # Newton: a rod in tension T_i pulls its mass by -T_i e_i and its upper end by +T_i e_i.
    T1, T2, N = sp.symbols("T1 T2 N", real=True)
    cart = M * r0.diff(t, 2) - ((F - c * x.diff(t)) * I + T1 * e1 + (N - M * g) * J)
    mass1 = m1 * r1.diff(t, 2) - (-T1 * e1 + T2 * e2 - m1 * g * J)
    mass2 = m2 * r2.diff(t, 2) - (-T2 * e2 - m2 * g * J)
    ne = [plain(e, qf, q0, q1, q2) for e in [*cart, *mass1, *mass2]]
    unknowns = [q2[0], q2[1], q2[2], T1, T2, N]
    A, b = linear_system(ne, unknowns)

    E = plain(Tk + V, qf, q0, q1, q2)
    px = plain(M * v0[0] + m1 * v1[0] + m2 * v2[0], qf, q0, q1, q2)
    xd = q1[0]
    return {"M": Mm, "f": f, "ne_A": A, "ne_b": b, "ne_unknowns": unknowns, "energy": E, "momentum": px,
            "power": (F - c * xd) * xd, "force": F - c * xd, "T": plain(Tk, qf, q0, q1, q2),
            "V": plain(V, qf, q0, q1, q2), "q": q0, "qd": q1, "qdd": q2,
            "params": [M, m1, m2, l1, l2, g, c], "inputs": [F]}


_DPC_PARAMS = ["M", "m1", "m2", "l1", "l2", "g", "c"]


def _dpc_args(S):
    q, qd = S["q"], S["qd"]
    return [q[0], qd[0], q[1], qd[1], q[2], qd[2]] + S["params"] + S["inputs"]


@lru_cache(maxsize=None)
def double_pendulum_cart_lagrange():
    """acc(y, p, u) -> np.array([x_ddot, phi1_ddot, phi2_ddot]) from the Lagrangian (numeric
    solve of M q'' = f); acc.mass_matrix, acc.forcing, acc.energy and acc.momentum attached."""
    S = double_pendulum_cart_symbolic()
    args = _dpc_args(S)
    fn = {k: wrap(sp.lambdify(args, S[k], "numpy", cse=True), args[:6], _DPC_PARAMS, ["F"])
          for k in ("M", "f", "energy", "momentum")}

    def acc(y, p, u=None):
        return np.linalg.solve(np.asarray(fn["M"](y, p, u), float), np.asarray(fn["f"](y, p, u), float).ravel())
    acc.mass_matrix = lambda y, p, u=None: np.asarray(fn["M"](y, p, u), float)
    acc.forcing = lambda y, p, u=None: np.asarray(fn["f"](y, p, u), float).ravel()
    acc.energy = lambda y, p, u=None: float(fn["energy"](y, p, u))
    acc.momentum = lambda y, p, u=None: float(fn["momentum"](y, p, u))
    return acc


@lru_cache(maxsize=None)
def double_pendulum_cart_newton_euler():
    """ne(y, p, u) -> dict x_ddot, phi1_ddot, phi2_ddot, T1, T2, N from the free-body diagrams."""
    S = double_pendulum_cart_symbolic()
    args = _dpc_args(S)
    fA = wrap(sp.lambdify(args, S["ne_A"], "numpy", cse=True), args[:6], _DPC_PARAMS, ["F"])
    fb = wrap(sp.lambdify(args, S["ne_b"], "numpy", cse=True), args[:6], _DPC_PARAMS, ["F"])

    def ne(y, p, u=None):
        s = np.linalg.solve(np.asarray(fA(y, p, u), float), np.asarray(fb(y, p, u), float).ravel())
        return dict(zip(("x_ddot", "phi1_ddot", "phi2_ddot", "T1", "T2", "N"), s))
    return ne
