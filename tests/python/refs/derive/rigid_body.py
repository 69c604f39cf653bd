"""Both routes for the rigid body about a fixed point (Lagrange in Euler angles) and the quaternion rate."""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import sympy as sp

from ._sympy import linear_system


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
    A, b = linear_system(eqs, q2)
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
