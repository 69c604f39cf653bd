"""Both routes for the luffing crane driven by force and torque."""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import sympy as sp

from ._sympy import coords, cross2, lagrange_equations, linear_system, plain, t, wrap
from .crane import crane_geometry


@lru_cache(maxsize=None)
def crane_dynamics_symbolic():
    """Lagrangian mass matrix M(q), right-hand side f (M q'' = f) and the Newton-Euler system."""
    m, l, g, Jb, mt = sp.symbols("m l g J_boom m_trolley", real=True, positive=True)
    F, tau = sp.symbols("F tau", real=True)
    qf, q0, q1, q2 = coords(["x", "theta", "phi"])
    x, th, ph = qf
    iA, jA, iB, rt, rp = crane_geometry(x, th, ph, l)
    J = sp.Matrix([0, 1])
    vt, vp = rt.diff(t), rp.diff(t)
    w = th.diff(t)
    Tk = (sp.Rational(1, 2) * Jb * w ** 2 + sp.Rational(1, 2) * mt * vt.dot(vt)
          + sp.Rational(1, 2) * m * vp.dot(vp))
    V = mt * g * rt[1] + m * g * rp[1]
    # virtual work: F iA on the trolley, -F iA on the boom at the trolley's (material) point
    # x* iA(theta) with x* frozen, tau K on the boom.
    xs = sp.Symbol("x_star", real=True)
    r_boom_pt = xs * iA
    Xi = []
    for q in qf:
        dW = (F * iA).dot(rt.diff(q)) + (-F * iA).dot(r_boom_pt.diff(q)) + tau * sp.diff(w, q.diff(t))
        Xi.append(sp.trigsimp(dW.subs(xs, x)))
    eqs = [plain(e, qf, q0, q1, q2) for e in lagrange_equations(Tk, V, qf, Xi)]
    Mm, f = linear_system(eqs, q2)

    # Newton-Euler: payload, trolley (point mass on the boom, normal force N jA), boom (J about O)
    T, N = sp.symbols("T N", real=True)
    ap, at = rp.diff(t, 2), rt.diff(t, 2)
    payload = m * ap - (-T * iB - m * g * J)
    trolley = mt * at - (F * iA + N * jA + T * iB - mt * g * J)
    boom = Jb * th.diff(t, 2) - (tau + cross2(rt, -F * iA - N * jA))
    ne = [payload[0], payload[1], trolley[0], trolley[1], boom]
    ne = [plain(e, qf, q0, q1, q2) for e in ne]
    unknowns = [q2[0], q2[1], q2[2], T, N]
    A, b = linear_system(ne, unknowns)
    E = plain(Tk + V, qf, q0, q1, q2)
    return {"lagrange": eqs, "M": Mm, "f": f, "ne_A": A, "ne_b": b, "ne_unknowns": unknowns,
            "energy": E, "q": q0, "qd": q1, "qdd": q2, "params": [m, l, g, Jb, mt], "inputs": [F, tau]}


_CD_PARAMS = ["m", "l", "g", "J_boom", "m_trolley"]


def _cd_args(S):
    q, qd = S["q"], S["qd"]
    return [q[0], qd[0], q[1], qd[1], q[2], qd[2]] + S["params"] + S["inputs"]


@lru_cache(maxsize=None)
def crane_dynamics_lagrange():
    """acc(y, p, u) -> np.array([x_ddot, theta_ddot, phi_ddot]); acc.mass_matrix(y, p, u),
    acc.forcing(y, p, u) and acc.energy(y, p, u) are attached."""
    S = crane_dynamics_symbolic()
    args = _cd_args(S)
    cM = wrap(sp.lambdify(args, S["M"], "numpy", cse=True), args[:6], _CD_PARAMS, ["F", "tau"])
    cf = wrap(sp.lambdify(args, S["f"], "numpy", cse=True), args[:6], _CD_PARAMS, ["F", "tau"])
    cE = wrap(sp.lambdify(args, S["energy"], "numpy", cse=True), args[:6], _CD_PARAMS, ["F", "tau"])

    def acc(y, p, u=None):
        return np.linalg.solve(np.asarray(cM(y, p, u), float), np.asarray(cf(y, p, u), float).ravel())
    acc.mass_matrix = lambda y, p, u=None: np.asarray(cM(y, p, u), float)
    acc.forcing = lambda y, p, u=None: np.asarray(cf(y, p, u), float).ravel()
    acc.energy = lambda y, p, u=None: float(cE(y, p, u))
    return acc


@lru_cache(maxsize=None)
def crane_dynamics_newton_euler():
    """ne(y, p, u) -> dict x_ddot, theta_ddot, phi_ddot, T, N from the free-body diagrams."""
    S = crane_dynamics_symbolic()
    args = _cd_args(S)
    fA = wrap(sp.lambdify(args, S["ne_A"], "numpy", cse=True), args[:6], _CD_PARAMS, ["F", "tau"])
    fb = wrap(sp.lambdify(args, S["ne_b"], "numpy", cse=True), args[:6], _CD_PARAMS, ["F", "tau"])

    def ne(y, p, u=None):
        s = np.linalg.solve(np.asarray(fA(y, p, u), float), np.asarray(fb(y, p, u), float).ravel())
        return {"x_ddot": s[0], "theta_ddot": s[1], "phi_ddot": s[2], "T": s[3], "N": s[4]}
    return ne
