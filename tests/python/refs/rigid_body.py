"""Reference for `RigidBody` (docs/mechanisms/RigidBody.md): a body turning about a fixed pivot B.

    I_B = I_C + M [ (r_C . r_C) 1 - r_C (x) r_C ]
    I_B w' + w x (I_B w) = tau + r_C x (R^T (-M g Z))      (body axes)
    q' = 1/2 q (x) (0, w)                                  (q: body -> ground, Hamilton)

H = R I_B w (ground axes, about B); E_kin = 1/2 w . I_B w; E_pot = M g Z . (R r_C), zero at
the pivot's height.
"""

from __future__ import annotations

import math

import numpy as np

from ._common import case_settings, merge, run, with_constants


def box_inertia(M: float, a: float, b: float, c: float):
    """(I_xx, I_yy, I_zz) about the centre of a solid a x b x c box (edges along x, y, z)."""
    return M * (b * b + c * c) / 12.0, M * (a * a + c * c) / 12.0, M * (a * a + b * b) / 12.0


_BOX = box_inertia(2.0, 0.3, 0.2, 0.1)
PARAMS = {"M": 2.0, "I_xx": _BOX[0], "I_yy": _BOX[1], "I_zz": _BOX[2],
          "I_xy": 0.0, "I_xz": 0.0, "I_yz": 0.0, "r_Cx": 0.0, "r_Cy": 0.0, "r_Cz": 0.0, "g": 9.81}
INPUTS = {"tau_x": 0.0, "tau_y": 0.0, "tau_z": 0.0}
STATES = ("w_x", "w_y", "w_z", "q_w", "q_x", "q_y", "q_z")
START = {"w_x": 0.01, "w_y": 5.0, "w_z": 0.01, "q_w": 1.0, "q_x": 0.0, "q_y": 0.0, "q_z": 0.0}
OUTPUTS = ("H_X", "H_Y", "H_Z", "E_kin", "E_pot")
CALCULATED = ("I_1", "I_2", "I_3")
EXTRA = ("q_norm",)
EXPERIMENT = {"start": 0.0, "stop": 20.0, "step": 0.01}


def params(**overrides) -> dict:
    return merge(PARAMS, overrides, "parameter")


def inertia_about_centre(p=None) -> np.ndarray:
    """I_C as the matrix in body axes; entry xy is -int x y dm (the parameter I_xy as given)."""
    p = merge(PARAMS, p, "parameter")
    return np.array([[p["I_xx"], p["I_xy"], p["I_xz"]],
                     [p["I_xy"], p["I_yy"], p["I_yz"]],
                     [p["I_xz"], p["I_yz"], p["I_zz"]]])


def r_C(p=None) -> np.ndarray:
    p = merge(PARAMS, p, "parameter")
    return np.array([p["r_Cx"], p["r_Cy"], p["r_Cz"]])


def inertia_about_pivot(p=None) -> np.ndarray:
    """Parallel axis theorem: I_B = I_C + M [(r.r) 1 - r r^T]."""
    p = merge(PARAMS, p, "parameter")
    r = r_C(p)
    return inertia_about_centre(p) + p["M"] * (np.dot(r, r) * np.eye(3) - np.outer(r, r))


def principal(p=None):
    """(I_1 <= I_2 <= I_3, axes as columns) of I_B."""
    w, V = np.linalg.eigh(inertia_about_pivot(p))
    return w, V


def calculated(p=None) -> dict:
    w, _ = principal(p)
    return {"I_1": float(w[0]), "I_2": float(w[1]), "I_3": float(w[2])}


# ----------------------------------------------------------------------------- quaternions

def quat_mul(a, b):
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return np.array([aw * bw - ax * bx - ay * by - az * bz,
                     aw * bx + ax * bw + ay * bz - az * by,
                     aw * by - ax * bz + ay * bw + az * bx,
                     aw * bz + ax * by - ay * bx + az * bw])


def quat_axis(axis: str, angle: float):
    h = 0.5 * angle
    q = np.array([math.cos(h), 0.0, 0.0, 0.0])
    q["xyz".index(axis) + 1] = math.sin(h)
    return q


def rotation(q) -> np.ndarray:
    """R (body -> ground) of a unit quaternion (w, x, y, z)."""
    w, x, y, z = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


# ----------------------------------------------------------------------------- model

def _prepare(p):
    if "_IB" not in p:
        pp = {k: v for k, v in p.items() if not k.startswith("_")}
        IB = inertia_about_pivot(pp)
        p = dict(p, _IB=IB, _IBinv=np.linalg.inv(IB), _r=r_C(pp),
                 _IBt=tuple(map(tuple, IB.tolist())), _IBit=tuple(map(tuple, np.linalg.inv(IB).tolist())),
                 _rt=tuple(r_C(pp).tolist()))
    return p


def _rhs_core(y, p, tau):
    """Plain-float arithmetic (this is called ~10^5 times per simulation)."""
    (a11, a12, a13), (a21, a22, a23), (a31, a32, a33) = p["_IBt"]
    (b11, b12, b13), (b21, b22, b23), (b31, b32, b33) = p["_IBit"]
    rx, ry, rz = p["_rt"]
    wx, wy, wz, qw, qx, qy, qz = y[:7]
    # body components of the ground vertical Z: third row of R
    Zx, Zy, Zz = 2 * (qx * qz - qw * qy), 2 * (qy * qz + qw * qx), 1 - 2 * (qx * qx + qy * qy)
    Mg = p["M"] * p["g"]
    Gx, Gy, Gz = -Mg * Zx, -Mg * Zy, -Mg * Zz            # weight in body axes
    hx = a11 * wx + a12 * wy + a13 * wz                  # I_B w
    hy = a21 * wx + a22 * wy + a23 * wz
    hz = a31 * wx + a32 * wy + a33 * wz
    mx = tau[0] + (ry * Gz - rz * Gy) - (wy * hz - wz * hy)
    my = tau[1] + (rz * Gx - rx * Gz) - (wz * hx - wx * hz)
    mz = tau[2] + (rx * Gy - ry * Gx) - (wx * hy - wy * hx)
    return [b11 * mx + b12 * my + b13 * mz,
            b21 * mx + b22 * my + b23 * mz,
            b31 * mx + b32 * my + b33 * mz,
            0.5 * (-qx * wx - qy * wy - qz * wz),
            0.5 * (qw * wx + qy * wz - qz * wy),
            0.5 * (qw * wy + qz * wx - qx * wz),
            0.5 * (qw * wz + qx * wy - qy * wx)]


def rhs(t, y, p, u):
    if "_IBt" not in p:
        p = _prepare(p)
    return _rhs_core(y, p, (u["tau_x"], u["tau_y"], u["tau_z"]))


def outputs_of(y, p) -> dict:
    p = _prepare(p)
    w = np.asarray(y[0:3])
    q = np.asarray(y[3:7])
    R = rotation(q / np.linalg.norm(q))
    Hb = p["_IB"] @ w
    H = R @ Hb
    return {"H_X": H[0], "H_Y": H[1], "H_Z": H[2], "E_kin": 0.5 * float(w @ Hb),
            "E_pot": p["M"] * p["g"] * float((R @ p["_r"])[2]), "q_norm": float(np.linalg.norm(q))}


def _outputs(t, y, p, u):
    return outputs_of(y, p)


def simulate(p=None, y0=None, t_out=None, inputs=None, rtol=1e-12, atol=1e-12, switch_outputs="after"):
    """DOP853 solution: w, q (integrated as is, not renormalized), H_X..H_Z, E_kin, E_pot,
    q_norm, the inputs and I_1..I_3."""
    p, s, t_out = case_settings(PARAMS, START, EXPERIMENT, p, y0, t_out)
    p = _prepare(p)
    res = run(rhs, _outputs, STATES, [s[n] for n in STATES], t_out, p, INPUTS, inputs, rtol, atol,
              switch_outputs)
    return with_constants(res, calculated({k: v for k, v in p.items() if not k.startswith("_")}))


# ----------------------------------------------------------------------------- closed forms

def axisymmetric_rate(p=None, w_z: float = 1.0) -> float:
    """Torque-free body with I_B[0,0] = I_B[1,1] = I_1, I_B[2,2] = I_3 (no products):
    (w_x, w_y) turns about body z at Omega = (I_3 - I_1)/I_1 w_z, counter-clockwise seen
    from +z when Omega > 0 (w_x' = -Omega w_y, w_y' = Omega w_x)."""
    IB = inertia_about_pivot(p)
    return (IB[2, 2] - IB[0, 0]) / IB[0, 0] * w_z


def torque_free_axisymmetric(p, w0, t):
    """Closed form (w_x + i w_y)(t) = (w_x0 + i w_y0) e^{i Omega t}, w_z constant."""
    t = np.asarray(t, dtype=float)
    Om = axisymmetric_rate(p, w0[2])
    z = (w0[0] + 1j * w0[1]) * np.exp(1j * Om * t)
    return z.real, z.imag, np.full_like(t, w0[2])


def precession_rates(p, theta: float, w3: float):
    """Steady precession of a heavy symmetric top (r_C = (0, 0, d), I_B symmetric about z).

    theta: nutation (angle between ground Z and body z), w3 = w . e3 (total spin component),
    Omega: precession rate about +Z. Steady precession needs
        M g d = Omega (I_3 w3 - I_1 Omega cos theta)
    i.e. I_1 cos(theta) Omega^2 - I_3 w3 Omega + M g d = 0, I_1, I_3 about the pivot.
    Returns (slow, fast) roots (slow ~ M g d / (I_3 w3)); real only if
    I_3^2 w3^2 >= 4 I_1 M g d cos theta. At cos theta = 0 only the slow root exists (fast = inf).
    """
    p = merge(PARAMS, {k: v for k, v in p.items() if not k.startswith("_")}, "parameter")
    IB = inertia_about_pivot(p)
    I1, I3 = IB[0, 0], IB[2, 2]
    d = p["r_Cz"]
    a, b, c = I1 * math.cos(theta), -I3 * w3, p["M"] * p["g"] * d
    D = b * b - 4 * a * c
    if D < 0:
        raise ValueError("no steady precession: spin too slow (I_3^2 w3^2 < 4 I_1 M g d cos theta)")
    qq = -0.5 * (b + math.copysign(math.sqrt(D), b))
    slow = c / qq if qq != 0 else 0.0
    fast = qq / a if a != 0 else math.inf
    return slow, fast


def precession_state(p, theta: float, w3: float, Omega: float) -> dict:
    """Start of a steady precession: q0 = rotation by theta about x (e3 tilted towards -Y),
    w0 = R^T (Omega Z) + psi' e3 = (0, Omega sin theta, w3), psi' = w3 - Omega cos theta."""
    q = quat_axis("x", theta)
    return {"w_x": 0.0, "w_y": Omega * math.sin(theta), "w_z": w3,
            "q_w": q[0], "q_x": q[1], "q_y": q[2], "q_z": q[3]}


def precession_motion(theta: float, w3: float, Omega: float, t):
    """Closed-form steady precession (z-x-z Euler angles Omega t, theta, psi' t):
    q(t) = qz(Omega t) qx(theta) qz(psi' t), w(t) = (Omega sin th sin psi, Omega sin th cos psi, w3).
    Returns (w [3 x n], q [4 x n])."""
    t = np.asarray(t, dtype=float)
    psid = w3 - Omega * math.cos(theta)
    qx = quat_axis("x", theta)
    Q = np.empty((4, t.size))
    for i, ti in enumerate(t):
        Q[:, i] = quat_mul(quat_mul(quat_axis("z", Omega * ti), qx), quat_axis("z", psid * ti))
    psi = psid * t
    W = np.vstack([Omega * math.sin(theta) * np.sin(psi), Omega * math.sin(theta) * np.cos(psi),
                   np.full_like(t, w3)])
    return W, Q
