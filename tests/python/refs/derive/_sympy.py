"""What the derivations share: the time symbol, coordinates as functions of it, the plain
symbols they are replaced by, Lagrange's equations and the linear systems both routes end in."""

from __future__ import annotations

import numpy as np
import sympy as sp

t = sp.Symbol("t", real=True)


def coords(names):
    """Coordinates as functions of t and plain symbols for q, q', q''."""
    qf = [sp.Function(n, real=True)(t) for n in names]
    q0 = sp.symbols(" ".join(names), real=True)
    q1 = sp.symbols(" ".join(n + "_dot" for n in names), real=True)
    q2 = sp.symbols(" ".join(n + "_ddot" for n in names), real=True)
    if len(names) == 1:
        q0, q1, q2 = (q0,), (q1,), (q2,)
    return qf, list(q0), list(q1), list(q2)


def plain(expr, qf, q0, q1, q2):
    expr = expr.subs({f.diff(t, 2): s for f, s in zip(qf, q2)})
    expr = expr.subs({f.diff(t): s for f, s in zip(qf, q1)})
    return expr.subs({f: s for f, s in zip(qf, q0)})


def cross2(a, b):
    """z component of a x b for planar vectors (sympy Matrix 2x1)."""
    return a[0] * b[1] - a[1] * b[0]


def lagrange_equations(T, V, qf, Xi):
    L = T - V
    return [sp.diff(sp.diff(L, q.diff(t)), t) - sp.diff(L, q) - X for q, X in zip(qf, Xi)]


def linear_system(eqs, unknowns):
    """A u = b from equations linear in the unknowns (A = d eqs / d unknowns, b = -eqs|u=0)."""
    E = sp.Matrix(eqs)
    A = E.jacobian(unknowns)
    b = -E.xreplace({u: sp.S.Zero for u in unknowns})
    # linearity check: nothing of the unknowns may remain in A
    assert not (A.free_symbols & set(unknowns)), "equations are not linear in the unknowns"
    return A, b


def wrap(fun, state_syms, param_names, input_names):
    """Adapter (y, p, u) -> fun(*y, *p[...], *u[...])."""
    def call(y, p, u=None):
        u = u or {}
        args = list(np.asarray(y, dtype=float)[: len(state_syms)])
        args += [float(p[n]) for n in param_names]
        args += [float(u.get(n, 0.0)) for n in input_names]
        return fun(*args)
    return call
