"""Both routes for the cart on a spring with a pendulum rod."""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import sympy as sp

from ._sympy import coords, cross2, lagrange_equations, linear_system, plain, t, wrap


@lru_cache(maxsize=None)
def pendulum_cart_symbolic():
    """Both routes symbolically. Returns a dict of sympy objects:
    'lagrange': [eq_x, eq_theta] (= 0), 'M', 'f' (M q'' = f), 'ne_unknowns', 'ne_A', 'ne_b',
    'energy', 'power', and the plain symbols."""
    M, m, l, k, c1, c2, g, F = sp.symbols("M m l k c1 c2 g F", real=True)
    qf, q0, q1, q2 = coords(["x", "theta"])
    x, th = qf
    I, J = sp.Matrix([1, 0]), sp.Matrix([0, 1])
    down = sp.Matrix([sp.sin(th), -sp.cos(th)])       # unit vector from A along the rod
    rA = x * I
    rC = rA + l * down
    rD = rA + 3 * l * down
    vA, vC = rA.diff(t), rC.diff(t)
    I_C = sp.Rational(1, 12) * m * (4 * l) ** 2       # thin rod of length 4l about C
    w = th.diff(t)
    Tk = sp.Rational(1, 2) * M * vA.dot(vA) + sp.Rational(1, 2) * m * vC.dot(vC) + sp.Rational(1, 2) * I_C * w ** 2
    V = sp.Rational(1, 2) * k * x ** 2 + m * g * rC[1]
    # virtual work: F I at D, dashpot -c1 x' I at A, couple -c2 th' K on the rod (+ on the cart,
    # which does not rotate)
    Xi = [(F * I).dot(rD.diff(q)) + (-c1 * x.diff(t) * I).dot(rA.diff(q))
          + (-c2 * w) * sp.diff(w, q.diff(t)) for q in qf]
    eqs = [plain(e, qf, q0, q1, q2) for e in lagrange_equations(Tk, V, qf, Xi)]
    Mm, f = linear_system(eqs, q2)

    # Newton-Euler. Unknowns: x'', th'', F1, F2 (force of the ROD ON THE CART at A, I and J
    # components), F_N (ground on cart, up). Cart: translation only. Rod: Newton at C and
    # Euler about C (not about A: the moment equation does not reuse the notes' form).
    F1, F2, FN = sp.symbols("F1 F2 F_N", real=True)
    aA, aC = rA.diff(t, 2), rC.diff(t, 2)
    cart = M * aA - (F1 * I + F2 * J - M * g * J + FN * J - k * x * I - c1 * x.diff(t) * I)
    rod_force = m * aC - (-F1 * I - F2 * J - m * g * J + F * I)
    rod_moment = (I_C * th.diff(t, 2)
                  - (cross2(rD - rC, F * I) + cross2(rA - rC, -F1 * I - F2 * J) - c2 * w))
    ne = [cart[0], cart[1], rod_force[0], rod_force[1], rod_moment]
    ne = [plain(e, qf, q0, q1, q2) for e in ne]
    unknowns = [q2[0], q2[1], F1, F2, FN]
    A, b = linear_system(ne, unknowns)

    E = plain(Tk + V, qf, q0, q1, q2)
    vD = rD.diff(t)
    P = plain((F * I).dot(vD) - c1 * x.diff(t) ** 2 - c2 * w ** 2, qf, q0, q1, q2)
    return {"lagrange": eqs, "M": Mm, "f": f, "ne_unknowns": unknowns, "ne_A": A, "ne_b": b,
            "energy": E, "power": P, "T": plain(Tk, qf, q0, q1, q2), "V": plain(V, qf, q0, q1, q2),
            "q": q0, "qd": q1, "qdd": q2, "params": [M, m, l, k, c1, c2, g], "inputs": [F]}


_PC_PARAMS = ["M", "m", "l", "k", "c1", "c2", "g"]


def _pc_state_syms(S):
    # contract state order: x, x_dot, theta, theta_dot
    return [S["q"][0], S["qd"][0], S["q"][1], S["qd"][1]]


@lru_cache(maxsize=None)
def pendulum_cart_lagrange():
    """acc(y, p, u) -> np.array([x_ddot, theta_ddot]) from the Lagrangian (numeric solve of M q'' = f)."""
    S = pendulum_cart_symbolic()
    args = _pc_state_syms(S) + S["params"] + S["inputs"]
    fM = sp.lambdify(args, S["M"], "numpy", cse=True)
    ff = sp.lambdify(args, S["f"], "numpy", cse=True)
    cM, cf = wrap(fM, args[:4], _PC_PARAMS, ["F"]), wrap(ff, args[:4], _PC_PARAMS, ["F"])

    def acc(y, p, u=None):
        return np.linalg.solve(np.asarray(cM(y, p, u), float), np.asarray(cf(y, p, u), float).ravel())
    acc.mass_matrix = cM
    acc.forcing = cf
    return acc


@lru_cache(maxsize=None)
def pendulum_cart_newton_euler():
    """ne(y, p, u) -> dict x_ddot, theta_ddot, F1, F2, F_N from the free-body diagrams."""
    S = pendulum_cart_symbolic()
    args = _pc_state_syms(S) + S["params"] + S["inputs"]
    fA = wrap(sp.lambdify(args, S["ne_A"], "numpy", cse=True), args[:4], _PC_PARAMS, ["F"])
    fb = wrap(sp.lambdify(args, S["ne_b"], "numpy", cse=True), args[:4], _PC_PARAMS, ["F"])
    fE = wrap(sp.lambdify(args, S["energy"], "numpy"), args[:4], _PC_PARAMS, ["F"])
    fP = wrap(sp.lambdify(args, S["power"], "numpy"), args[:4], _PC_PARAMS, ["F"])

    def ne(y, p, u=None):
        sol = np.linalg.solve(np.asarray(fA(y, p, u), float), np.asarray(fb(y, p, u), float).ravel())
        return {"x_ddot": sol[0], "theta_ddot": sol[1], "F1": sol[2], "F2": sol[3], "F_N": sol[4],
                "E": float(fE(y, p, u)), "E_dot": float(fP(y, p, u))}
    return ne
