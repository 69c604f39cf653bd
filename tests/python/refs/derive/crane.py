"""Both routes for the luffing crane with its motion prescribed by the drives (the payload's swing alone)."""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import sympy as sp

from ._sympy import coords, linear_system, plain, t, wrap


def crane_geometry(x, th, ph, l):
    iA = sp.Matrix([sp.cos(th), sp.sin(th)])
    jA = sp.Matrix([-sp.sin(th), sp.cos(th)])
    iB = sp.Matrix([sp.sin(ph), -sp.cos(ph)])       # from trolley to payload
    rt = x * iA
    rp = rt + l * iB
    return iA, jA, iB, rt, rp


@lru_cache(maxsize=None)
def _crane_symbolic():
    m, l, g = sp.symbols("m l g", real=True, positive=True)
    qf, q0, q1, q2 = coords(["x", "theta", "phi"])
    x, th, ph = qf
    iA, jA, iB, rt, rp = crane_geometry(x, th, ph, l)
    J = sp.Matrix([0, 1])
    # Lagrange for phi alone, x(t) and theta(t) prescribed (rheonomic constraint)
    vp = rp.diff(t)
    L = sp.Rational(1, 2) * m * vp.dot(vp) - m * g * rp[1]
    eq_phi = sp.diff(sp.diff(L, ph.diff(t)), t) - sp.diff(L, ph)
    eq_phi = plain(eq_phi, qf, q0, q1, q2)
    A1, b1 = linear_system([eq_phi], [q2[2]])
    phdd_lag = b1[0] / A1[0, 0]
    # Newton-Euler: payload m a_p = -T iB - m g J; massless trolley 0 = F iA + N jA + T iB;
    # massless boom 0 = tau - x N.
    T, N, F, tau = sp.symbols("T N F tau", real=True)
    ap = rp.diff(t, 2)
    eqs = list(m * ap - (-T * iB - m * g * J)) + list(F * iA + N * jA + T * iB) + [tau - x * N]
    eqs = [plain(e, qf, q0, q1, q2) for e in eqs]
    unknowns = [q2[2], T, F, N, tau]
    A, b = linear_system(eqs, unknowns)
    return {"phi_ddot": phdd_lag, "ne_A": A, "ne_b": b, "q": q0, "qd": q1, "qdd": q2,
            "params": [m, l, g]}


def _crane_args(S):
    q, qd, qdd = S["q"], S["qd"], S["qdd"]
    return [q[0], qd[0], q[1], qd[1], q[2], qd[2]] + S["params"] + [qdd[0], qdd[1]]


@lru_cache(maxsize=None)
def crane_lagrange():
    """phi_ddot(y, p, u) from the payload's Lagrangian with x(t), theta(t) prescribed
    (u: x_ddot, theta_ddot)."""
    S = _crane_symbolic()
    args = _crane_args(S)
    return wrap(sp.lambdify(args, S["phi_ddot"], "numpy"), args[:6], ["m", "l", "g"], ["x_ddot", "theta_ddot"])


@lru_cache(maxsize=None)
def crane_newton_euler():
    """ne(y, p, u) -> dict phi_ddot, T, F, tau, N by Newton on payload, trolley and boom."""
    S = _crane_symbolic()
    args = _crane_args(S)
    fA = wrap(sp.lambdify(args, S["ne_A"], "numpy", cse=True), args[:6], ["m", "l", "g"], ["x_ddot", "theta_ddot"])
    fb = wrap(sp.lambdify(args, S["ne_b"], "numpy", cse=True), args[:6], ["m", "l", "g"], ["x_ddot", "theta_ddot"])

    def ne(y, p, u=None):
        s = np.linalg.solve(np.asarray(fA(y, p, u), float), np.asarray(fb(y, p, u), float).ravel())
        return {"phi_ddot": s[0], "T": s[1], "F": s[2], "N": s[3], "tau": s[4]}
    return ne
