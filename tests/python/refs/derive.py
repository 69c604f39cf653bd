"""Symbolic derivations (sympy) of the equations of motion by two independent routes.

* Lagrange: T and V from the positions of the bodies, generalized forces from the virtual
  work of the non-conservative forces and couples, d/dt(dL/dq') - dL/dq = Xi.
* Newton-Euler: free-body diagrams of every body with the reaction forces as unknowns,
  accelerations from differentiating the position vectors twice (not from the notes'
  rotating-frame formulas), solved as one linear system.

Nothing here reuses the equations written in the other reference modules; the functions
return lambdified callables so a test can evaluate both routes at random states and
compare them with each other, with the reference modules and with the FMUs' outputs.

Callables take a state tuple/array (the contract's state order), a parameter dict and an
input dict (contract names) and return numpy arrays / dicts. Derivations are cached.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import sympy as sp

t = sp.Symbol("t", real=True)

__all__ = [
    "pendulum_cart_lagrange", "pendulum_cart_newton_euler", "pendulum_cart_symbolic",
    "crane_lagrange", "crane_newton_euler",
    "crane_dynamics_lagrange", "crane_dynamics_newton_euler", "crane_dynamics_symbolic",
    "rigid_body_lagrange", "rigid_body_quaternion_rate",
    "double_pendulum_cart_symbolic", "double_pendulum_cart_lagrange", "double_pendulum_cart_newton_euler",
]


# ----------------------------------------------------------------------------- helpers

def _coords(names):
    """Coordinates as functions of t and plain symbols for q, q', q''."""
    qf = [sp.Function(n, real=True)(t) for n in names]
    q0 = sp.symbols(" ".join(names), real=True)
    q1 = sp.symbols(" ".join(n + "_dot" for n in names), real=True)
    q2 = sp.symbols(" ".join(n + "_ddot" for n in names), real=True)
    if len(names) == 1:
        q0, q1, q2 = (q0,), (q1,), (q2,)
    return qf, list(q0), list(q1), list(q2)


def _plain(expr, qf, q0, q1, q2):
    expr = expr.subs({f.diff(t, 2): s for f, s in zip(qf, q2)})
    expr = expr.subs({f.diff(t): s for f, s in zip(qf, q1)})
    return expr.subs({f: s for f, s in zip(qf, q0)})


def _cross2(a, b):
    """z component of a x b for planar vectors (sympy Matrix 2x1)."""
    return a[0] * b[1] - a[1] * b[0]


def _lagrange_equations(T, V, qf, Xi):
    L = T - V
    return [sp.diff(sp.diff(L, q.diff(t)), t) - sp.diff(L, q) - X for q, X in zip(qf, Xi)]


def _linear_system(eqs, unknowns):
    """A u = b from equations linear in the unknowns (A = d eqs / d unknowns, b = -eqs|u=0)."""
    E = sp.Matrix(eqs)
    A = E.jacobian(unknowns)
    b = -E.xreplace({u: sp.S.Zero for u in unknowns})
    # linearity check: nothing of the unknowns may remain in A
    assert not (A.free_symbols & set(unknowns)), "equations are not linear in the unknowns"
    return A, b


def _wrap(fun, state_syms, param_names, input_names):
    """Adapter (y, p, u) -> fun(*y, *p[...], *u[...])."""
    def call(y, p, u=None):
        u = u or {}
        args = list(np.asarray(y, dtype=float)[: len(state_syms)])
        args += [float(p[n]) for n in param_names]
        args += [float(u.get(n, 0.0)) for n in input_names]
        return fun(*args)
    return call


# ----------------------------------------------------------------------------- PendulumCart

@lru_cache(maxsize=None)
def pendulum_cart_symbolic():
    """Both routes symbolically. Returns a dict of sympy objects:
    'lagrange': [eq_x, eq_theta] (= 0), 'M', 'f' (M q'' = f), 'ne_unknowns', 'ne_A', 'ne_b',
    'energy', 'power', and the plain symbols."""
    M, m, l, k, c1, c2, g, F = sp.symbols("M m l k c1 c2 g F", real=True)
    qf, q0, q1, q2 = _coords(["x", "theta"])
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
    eqs = [_plain(e, qf, q0, q1, q2) for e in _lagrange_equations(Tk, V, qf, Xi)]
    Mm, f = _linear_system(eqs, q2)

    # Newton-Euler. Unknowns: x'', th'', F1, F2 (force of the ROD ON THE CART at A, I and J
    # components), F_N (ground on cart, up). Cart: translation only. Rod: Newton at C and
    # Euler about C (not about A: the moment equation does not reuse the notes' form).
    F1, F2, FN = sp.symbols("F1 F2 F_N", real=True)
    aA, aC = rA.diff(t, 2), rC.diff(t, 2)
    cart = M * aA - (F1 * I + F2 * J - M * g * J + FN * J - k * x * I - c1 * x.diff(t) * I)
    rod_force = m * aC - (-F1 * I - F2 * J - m * g * J + F * I)
    rod_moment = (I_C * th.diff(t, 2)
                  - (_cross2(rD - rC, F * I) + _cross2(rA - rC, -F1 * I - F2 * J) - c2 * w))
    ne = [cart[0], cart[1], rod_force[0], rod_force[1], rod_moment]
    ne = [_plain(e, qf, q0, q1, q2) for e in ne]
    unknowns = [q2[0], q2[1], F1, F2, FN]
    A, b = _linear_system(ne, unknowns)

    E = _plain(Tk + V, qf, q0, q1, q2)
    vD = rD.diff(t)
    P = _plain((F * I).dot(vD) - c1 * x.diff(t) ** 2 - c2 * w ** 2, qf, q0, q1, q2)
    return {"lagrange": eqs, "M": Mm, "f": f, "ne_unknowns": unknowns, "ne_A": A, "ne_b": b,
            "energy": E, "power": P, "T": _plain(Tk, qf, q0, q1, q2), "V": _plain(V, qf, q0, q1, q2),
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
    cM, cf = _wrap(fM, args[:4], _PC_PARAMS, ["F"]), _wrap(ff, args[:4], _PC_PARAMS, ["F"])

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
    fA = _wrap(sp.lambdify(args, S["ne_A"], "numpy", cse=True), args[:4], _PC_PARAMS, ["F"])
    fb = _wrap(sp.lambdify(args, S["ne_b"], "numpy", cse=True), args[:4], _PC_PARAMS, ["F"])
    fE = _wrap(sp.lambdify(args, S["energy"], "numpy"), args[:4], _PC_PARAMS, ["F"])
    fP = _wrap(sp.lambdify(args, S["power"], "numpy"), args[:4], _PC_PARAMS, ["F"])

    def ne(y, p, u=None):
        sol = np.linalg.solve(np.asarray(fA(y, p, u), float), np.asarray(fb(y, p, u), float).ravel())
        return {"x_ddot": sol[0], "theta_ddot": sol[1], "F1": sol[2], "F2": sol[3], "F_N": sol[4],
                "E": float(fE(y, p, u)), "E_dot": float(fP(y, p, u))}
    return ne


# ----------------------------------------------------------------------------- Crane (prescribed)

def _crane_geometry(x, th, ph, l):
    iA = sp.Matrix([sp.cos(th), sp.sin(th)])
    jA = sp.Matrix([-sp.sin(th), sp.cos(th)])
    iB = sp.Matrix([sp.sin(ph), -sp.cos(ph)])       # from trolley to payload
    rt = x * iA
    rp = rt + l * iB
    return iA, jA, iB, rt, rp


@lru_cache(maxsize=None)
def _crane_symbolic():
    m, l, g = sp.symbols("m l g", real=True, positive=True)
    qf, q0, q1, q2 = _coords(["x", "theta", "phi"])
    x, th, ph = qf
    iA, jA, iB, rt, rp = _crane_geometry(x, th, ph, l)
    J = sp.Matrix([0, 1])
    # Lagrange for phi alone, x(t) and theta(t) prescribed (rheonomic constraint)
    vp = rp.diff(t)
    L = sp.Rational(1, 2) * m * vp.dot(vp) - m * g * rp[1]
    eq_phi = sp.diff(sp.diff(L, ph.diff(t)), t) - sp.diff(L, ph)
    eq_phi = _plain(eq_phi, qf, q0, q1, q2)
    A1, b1 = _linear_system([eq_phi], [q2[2]])
    phdd_lag = b1[0] / A1[0, 0]
    # Newton-Euler: payload m a_p = -T iB - m g J; massless trolley 0 = F iA + N jA + T iB;
    # massless boom 0 = tau - x N.
    T, N, F, tau = sp.symbols("T N F tau", real=True)
    ap = rp.diff(t, 2)
    eqs = list(m * ap - (-T * iB - m * g * J)) + list(F * iA + N * jA + T * iB) + [tau - x * N]
    eqs = [_plain(e, qf, q0, q1, q2) for e in eqs]
    unknowns = [q2[2], T, F, N, tau]
    A, b = _linear_system(eqs, unknowns)
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
    return _wrap(sp.lambdify(args, S["phi_ddot"], "numpy"), args[:6], ["m", "l", "g"], ["x_ddot", "theta_ddot"])


@lru_cache(maxsize=None)
def crane_newton_euler():
    """ne(y, p, u) -> dict phi_ddot, T, F, tau, N by Newton on payload, trolley and boom."""
    S = _crane_symbolic()
    args = _crane_args(S)
    fA = _wrap(sp.lambdify(args, S["ne_A"], "numpy", cse=True), args[:6], ["m", "l", "g"], ["x_ddot", "theta_ddot"])
    fb = _wrap(sp.lambdify(args, S["ne_b"], "numpy", cse=True), args[:6], ["m", "l", "g"], ["x_ddot", "theta_ddot"])

    def ne(y, p, u=None):
        s = np.linalg.solve(np.asarray(fA(y, p, u), float), np.asarray(fb(y, p, u), float).ravel())
        return {"phi_ddot": s[0], "T": s[1], "F": s[2], "N": s[3], "tau": s[4]}
    return ne


# ----------------------------------------------------------------------------- CraneDynamics

@lru_cache(maxsize=None)
def crane_dynamics_symbolic():
    """Lagrangian mass matrix M(q), right-hand side f (M q'' = f) and the Newton-Euler system."""
    m, l, g, Jb, mt = sp.symbols("m l g J_boom m_trolley", real=True, positive=True)
    F, tau = sp.symbols("F tau", real=True)
    qf, q0, q1, q2 = _coords(["x", "theta", "phi"])
    x, th, ph = qf
    iA, jA, iB, rt, rp = _crane_geometry(x, th, ph, l)
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
    eqs = [_plain(e, qf, q0, q1, q2) for e in _lagrange_equations(Tk, V, qf, Xi)]
    Mm, f = _linear_system(eqs, q2)

    # Newton-Euler: payload, trolley (point mass on the boom, normal force N jA), boom (J about O)
    T, N = sp.symbols("T N", real=True)
    ap, at = rp.diff(t, 2), rt.diff(t, 2)
    payload = m * ap - (-T * iB - m * g * J)
    trolley = mt * at - (F * iA + N * jA + T * iB - mt * g * J)
    boom = Jb * th.diff(t, 2) - (tau + _cross2(rt, -F * iA - N * jA))
    ne = [payload[0], payload[1], trolley[0], trolley[1], boom]
    ne = [_plain(e, qf, q0, q1, q2) for e in ne]
    unknowns = [q2[0], q2[1], q2[2], T, N]
    A, b = _linear_system(ne, unknowns)
    E = _plain(Tk + V, qf, q0, q1, q2)
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
    cM = _wrap(sp.lambdify(args, S["M"], "numpy", cse=True), args[:6], _CD_PARAMS, ["F", "tau"])
    cf = _wrap(sp.lambdify(args, S["f"], "numpy", cse=True), args[:6], _CD_PARAMS, ["F", "tau"])
    cE = _wrap(sp.lambdify(args, S["energy"], "numpy", cse=True), args[:6], _CD_PARAMS, ["F", "tau"])

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
    fA = _wrap(sp.lambdify(args, S["ne_A"], "numpy", cse=True), args[:6], _CD_PARAMS, ["F", "tau"])
    fb = _wrap(sp.lambdify(args, S["ne_b"], "numpy", cse=True), args[:6], _CD_PARAMS, ["F", "tau"])

    def ne(y, p, u=None):
        s = np.linalg.solve(np.asarray(fA(y, p, u), float), np.asarray(fb(y, p, u), float).ravel())
        return {"x_ddot": s[0], "theta_ddot": s[1], "phi_ddot": s[2], "T": s[3], "N": s[4]}
    return ne


# ----------------------------------------------------------------------------- RigidBody

def _rot(axis, a):
    c, s = sp.cos(a), sp.sin(a)
    if axis == "x":
        return sp.Matrix([[1, 0, 0], [0, c, -s], [0, s, c]])
    return sp.Matrix([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def _dt(expr, q0, q1, q2):
    """Total time derivative of an expression in plain symbols q, q', (q'') by the chain rule."""
    return sum(sp.diff(expr, a) * b for a, b in zip(q0 + q1, q1 + q2))


@lru_cache(maxsize=None)
def _rigid_symbolic():
    # plain symbols and an explicit chain-rule d/dt here: the rotation matrices make the
    # Function(t) route of the planar mechanisms slow
    Mm, g = sp.symbols("M g", real=True)
    Ixx, Iyy, Izz, Ixy, Ixz, Iyz = sp.symbols("I_xx I_yy I_zz I_xy I_xz I_yz", real=True)
    rx, ry, rz = sp.symbols("r_Cx r_Cy r_Cz", real=True)
    tx, ty, tz = sp.symbols("tau_x tau_y tau_z", real=True)
    q0 = list(sp.symbols("phi theta psi", real=True))
    q1 = list(sp.symbols("phi_dot theta_dot psi_dot", real=True))
    q2 = list(sp.symbols("phi_ddot theta_ddot psi_ddot", real=True))
    ph, th, ps = q0
    R = _rot("z", ph) * _rot("x", th) * _rot("z", ps)          # body -> ground, z-x-z
    Rdot = R.applyfunc(lambda e: _dt(e, q0, q1, q2))
    W = R.T * Rdot                                               # skew(w_body)
    wb = sp.Matrix([W[2, 1], W[0, 2], W[1, 0]])
    IC = sp.Matrix([[Ixx, Ixy, Ixz], [Ixy, Iyy, Iyz], [Ixz, Iyz, Izz]])
    r = sp.Matrix([rx, ry, rz])
    IB = IC + Mm * (r.dot(r) * sp.eye(3) - r * r.T)
    Tk = sp.Rational(1, 2) * (wb.T * IB * wb)[0, 0]
    V = Mm * g * (R * r)[2]
    taub = sp.Matrix([tx, ty, tz])
    L = Tk - V
    eqs = [_dt(sp.diff(L, qd), q0, q1, q2) - sp.diff(L, q) - taub.dot(wb.diff(qd))
           for q, qd in zip(q0, q1)]
    A, b = _linear_system(eqs, q2)
    Jw = wb.jacobian(q1)                       # d w / d q'
    dw_rest = wb.jacobian(q0) * sp.Matrix(q1)  # (d w / d q) q'
    # quaternion of R = qz(phi) qx(theta) qz(psi) and its time derivative

    def qa(axis, a):
        h = a / 2
        return sp.Quaternion(sp.cos(h), sp.sin(h) if axis == "x" else 0, 0, sp.sin(h) if axis == "z" else 0)
    Q = qa("z", ph) * qa("x", th) * qa("z", ps)
    qv = sp.Matrix([Q.a, Q.b, Q.c, Q.d])
    qdot = qv.applyfunc(lambda e: _dt(e, q0, q1, q2))
    params = [Mm, Ixx, Iyy, Izz, Ixy, Ixz, Iyz, rx, ry, rz, g]
    return {"A": A, "b": b, "Jw": Jw, "dw_rest": dw_rest, "wb": wb, "q": q0, "qd": q1,
            "params": params, "inputs": [tx, ty, tz], "quat": qv, "quat_dot": qdot,
            "energy": Tk + V}


_RB_PARAMS = ["M", "I_xx", "I_yy", "I_zz", "I_xy", "I_xz", "I_yz", "r_Cx", "r_Cy", "r_Cz", "g"]


@lru_cache(maxsize=None)
def rigid_body_lagrange():
    """lag(angles, rates, p, u) -> dict w (body), w_dot (body), q (quaternion), q_dot, from the
    Lagrangian in z-x-z Euler angles (phi, theta, psi) with generalized forces tau_b . dw/dq'.
    Singular at sin(theta) = 0: use states away from it."""
    S = _rigid_symbolic()
    args = list(S["q"]) + list(S["qd"]) + S["params"] + S["inputs"]
    fns = {k: sp.lambdify(args, S[k], "numpy", cse=True) for k in ("A", "b", "Jw", "dw_rest", "wb", "quat", "quat_dot", "energy")}

    def lag(angles, rates, p, u=None):
        u = u or {}
        a = [float(v) for v in angles] + [float(v) for v in rates]
        a += [float(p[n]) for n in _RB_PARAMS] + [float(u.get(n, 0.0)) for n in ("tau_x", "tau_y", "tau_z")]
        A = np.asarray(fns["A"](*a), float)
        b = np.asarray(fns["b"](*a), float).ravel()
        qdd = np.linalg.solve(A, b)
        wdot = np.asarray(fns["Jw"](*a), float) @ qdd + np.asarray(fns["dw_rest"](*a), float).ravel()
        return {"w": np.asarray(fns["wb"](*a), float).ravel(), "w_dot": wdot,
                "q": np.asarray(fns["quat"](*a), float).ravel(),
                "q_dot": np.asarray(fns["quat_dot"](*a), float).ravel(),
                "E": float(fns["energy"](*a)), "angles_ddot": qdd}
    return lag


def rigid_body_quaternion_rate(q, w):
    """q' = 1/2 q (x) (0, w) with sympy's Quaternion product (an independent implementation)."""
    Q = sp.Quaternion(*[sp.Float(v, 30) for v in q]) * sp.Quaternion(0, *[sp.Float(v, 30) for v in w])
    return np.array([float(Q.a), float(Q.b), float(Q.c), float(Q.d)]) * 0.5


# ----------------------------------------------------------------------------- DoublePendulumCart

@lru_cache(maxsize=None)
def double_pendulum_cart_symbolic():
    """Both routes symbolically. Lagrange: T and V from the positions of the cart, m1 and m2,
    the virtual work of F and the drag on the cart. Newton: the cart, m1 and m2 each, the rod
    tensions T1, T2 and the track's normal force N as unknowns. Returns 'M', 'f' (M q'' = f),
    'ne_A', 'ne_b' (unknowns x'', phi1'', phi2'', T1, T2, N), 'energy', 'momentum', 'power',
    'force' (dp_x/dt) and the plain symbols."""
    M, m1, m2, l1, l2, g, c, F = sp.symbols("M m1 m2 l1 l2 g c F", real=True)
    qf, q0, q1, q2 = _coords(["x", "phi1", "phi2"])
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
    eqs = [_plain(e, qf, q0, q1, q2) for e in _lagrange_equations(Tk, V, qf, Xi)]
    Mm, f = _linear_system(eqs, q2)

    # Newton: a rod in tension T_i pulls its mass by -T_i e_i and its upper end by +T_i e_i.
    T1, T2, N = sp.symbols("T1 T2 N", real=True)
    cart = M * r0.diff(t, 2) - ((F - c * x.diff(t)) * I + T1 * e1 + (N - M * g) * J)
    mass1 = m1 * r1.diff(t, 2) - (-T1 * e1 + T2 * e2 - m1 * g * J)
    mass2 = m2 * r2.diff(t, 2) - (-T2 * e2 - m2 * g * J)
    ne = [_plain(e, qf, q0, q1, q2) for e in [*cart, *mass1, *mass2]]
    unknowns = [q2[0], q2[1], q2[2], T1, T2, N]
    A, b = _linear_system(ne, unknowns)

    E = _plain(Tk + V, qf, q0, q1, q2)
    px = _plain(M * v0[0] + m1 * v1[0] + m2 * v2[0], qf, q0, q1, q2)
    xd = q1[0]
    return {"M": Mm, "f": f, "ne_A": A, "ne_b": b, "ne_unknowns": unknowns, "energy": E, "momentum": px,
            "power": (F - c * xd) * xd, "force": F - c * xd, "T": _plain(Tk, qf, q0, q1, q2),
            "V": _plain(V, qf, q0, q1, q2), "q": q0, "qd": q1, "qdd": q2,
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
    fn = {k: _wrap(sp.lambdify(args, S[k], "numpy", cse=True), args[:6], _DPC_PARAMS, ["F"])
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
    fA = _wrap(sp.lambdify(args, S["ne_A"], "numpy", cse=True), args[:6], _DPC_PARAMS, ["F"])
    fb = _wrap(sp.lambdify(args, S["ne_b"], "numpy", cse=True), args[:6], _DPC_PARAMS, ["F"])

    def ne(y, p, u=None):
        s = np.linalg.solve(np.asarray(fA(y, p, u), float), np.asarray(fb(y, p, u), float).ravel())
        return dict(zip(("x_ddot", "phi1_ddot", "phi2_ddot", "T1", "T2", "N"), s))
    return ne
