"""Reference for `CraneDynamics` (docs/mechanisms/CraneDynamics.md, docs/derivations.md).

q = (x, theta, phi); boom inertia J_boom about O, trolley mass m_trolley at x on the boom,
payload m on a massless cable of length l; inputs F (boom drive on trolley, along i_A) and
tau (torque on the boom about O, +K). With s = theta - phi, mt = m_trolley, mu = m + mt:

    M(q) = [[ mu,          0,               m l cos s   ],
            [ 0,           J_boom + mu x^2, -m x l sin s ],
            [ m l cos s,   -m x l sin s,    m l^2       ]]

    f = [ F   + mu x th'^2 - m l phi'^2 sin s - mu g sin th,
          tau - 2 mu x x' th' - m x l phi'^2 cos s - mu g x cos th,
          2 m l x' th' sin s + m x l th'^2 cos s - m g l sin phi ]

    M(q) q'' = f.   T = m [(x'' - th'^2 x) sin s + (2 th' x' + th'' x) cos s + l phi'^2 + g cos phi]
"""

from __future__ import annotations

import math

import numpy as np

from ._common import case_settings, merge, run, trolley_at_pivot

PARAMS = {"m": 1000.0, "l": 5.0, "g": 9.81, "J_boom": 5000.0, "m_trolley": 200.0}
INPUTS = {"F": 0.0, "tau": 0.0}
STATES = ("x", "x_dot", "theta", "theta_dot", "phi", "phi_dot")
START = {"x": 10.0, "x_dot": 0.0, "theta": 0.5, "theta_dot": 0.0, "phi": 0.0, "phi_dot": 0.0}
OUTPUTS = ("T", "payload_x", "payload_y", "x_ddot", "theta_ddot")
EXTRA = ("phi_ddot", "N", "E", "P_drives", "W_drives")
EXPERIMENT = {"start": 0.0, "stop": 20.0, "step": 0.01}


def params(**overrides) -> dict:
    return merge(PARAMS, overrides, "parameter")


def mass_matrix(y, p) -> np.ndarray:
    x, th, ph = y[0], y[2], y[4]
    m, l, mu = p["m"], p["l"], p["m"] + p["m_trolley"]
    s = th - ph
    return np.array([[mu, 0.0, m * l * math.cos(s)],
                     [0.0, p["J_boom"] + mu * x * x, -m * x * l * math.sin(s)],
                     [m * l * math.cos(s), -m * x * l * math.sin(s), m * l * l]])


def forcing(y, p, F, tau) -> np.ndarray:
    x, v, th, w, ph, phd = y[:6]
    m, l, g, mu = p["m"], p["l"], p["g"], p["m"] + p["m_trolley"]
    s = th - ph
    return np.array([F + mu * x * w * w - m * l * phd * phd * math.sin(s) - mu * g * math.sin(th),
                     tau - 2 * mu * x * v * w - m * x * l * phd * phd * math.cos(s) - mu * g * x * math.cos(th),
                     2 * m * l * v * w * math.sin(s) + m * x * l * w * w * math.cos(s) - m * g * l * math.sin(ph)])


def accelerations(y, p, F, tau):
    """(x'', th'', phi'') = M^-1 f, by Cramer's rule on the symmetric 3x3 (fast, exact form)."""
    x, v, th, w, ph, phd = y[:6]
    m, l, g, mu = p["m"], p["l"], p["g"], p["m"] + p["m_trolley"]
    s = th - ph
    ss, cs = math.sin(s), math.cos(s)
    a, c = mu, m * l * cs
    d, e = p["J_boom"] + mu * x * x, -m * x * l * ss
    f_ = m * l * l
    b1 = F + mu * x * w * w - m * l * phd * phd * ss - mu * g * math.sin(th)
    b2 = tau - 2 * mu * x * v * w - m * x * l * phd * phd * cs - mu * g * x * math.cos(th)
    b3 = 2 * m * l * v * w * ss + m * x * l * w * w * cs - m * g * l * math.sin(ph)
    # M = [[a, 0, c], [0, d, e], [c, e, f_]]
    A11, A12, A13 = d * f_ - e * e, c * e, -c * d
    A22, A23 = a * f_ - c * c, -a * e
    A33 = a * d
    det = a * A11 + c * A13
    return ((A11 * b1 + A12 * b2 + A13 * b3) / det,
            (A12 * b1 + A22 * b2 + A23 * b3) / det,
            (A13 * b1 + A23 * b2 + A33 * b3) / det)


def tension(y, p, xdd, thdd):
    """Payload Newton along the cable (the notes' formula (a))."""
    x, v, th, w, ph, phd = y[:6]
    s = th - ph
    return p["m"] * ((xdd - w * w * x) * math.sin(s) + (2 * w * v + thdd * x) * math.cos(s)
                     + p["l"] * phd * phd + p["g"] * math.cos(ph))


def boom_normal_force(y, p, xdd, thdd, T):
    """N: force of the boom on the trolley along j_A (trolley Newton along j_A)."""
    x, v, th, w, ph = y[:5]
    s = th - ph
    mt = p["m_trolley"]
    return mt * (2 * v * w + x * thdd) + T * math.cos(s) + mt * p["g"] * math.cos(th)


def energy(y, p):
    """T + V of boom, trolley and payload (heights from O)."""
    x, v, th, w, ph, phd = y[:6]
    m, l, g, mt = p["m"], p["l"], p["g"], p["m_trolley"]
    vx = v * math.cos(th) - x * w * math.sin(th) + l * phd * math.cos(ph)
    vy = v * math.sin(th) + x * w * math.cos(th) + l * phd * math.sin(ph)
    kin = 0.5 * p["J_boom"] * w * w + 0.5 * mt * (v * v + x * x * w * w) + 0.5 * m * (vx * vx + vy * vy)
    pot = mt * g * x * math.sin(th) + m * g * (x * math.sin(th) - l * math.cos(ph))
    return kin + pot


def static_loads(p=None, x: float = 10.0, theta: float = 0.5):
    """Drive loads that hold the crane at rest with the payload hanging still:
    F = (m + m_trolley) g sin theta, tau = x (m + m_trolley) g cos theta (then T = m g)."""
    p = merge(PARAMS, p, "parameter")
    mu = p["m"] + p["m_trolley"]
    return mu * p["g"] * math.sin(theta), x * mu * p["g"] * math.cos(theta)


def rhs(t, y, p, u):
    xdd, thdd, phdd = accelerations(y, p, u["F"], u["tau"])
    out = [y[1], xdd, y[3], thdd, y[5], phdd]
    if len(y) > 6:  # work of the drives, integrated alongside
        out.append(u["F"] * y[1] + u["tau"] * y[3])
    return out


def _outputs(t, y, p, u):
    xdd, thdd, phdd = accelerations(y, p, u["F"], u["tau"])
    T = tension(y, p, xdd, thdd)
    x, th, ph = y[0], y[2], y[4]
    return {"T": T, "payload_x": x * math.cos(th) + p["l"] * math.sin(ph),
            "payload_y": x * math.sin(th) - p["l"] * math.cos(ph),
            "x_ddot": xdd, "theta_ddot": thdd, "phi_ddot": phdd,
            "N": boom_normal_force(y, p, xdd, thdd, T), "E": energy(y, p),
            "P_drives": u["F"] * y[1] + u["tau"] * y[3]}


def simulate(p=None, y0=None, t_out=None, inputs=None, rtol=1e-12, atol=1e-12, switch_outputs="after"):
    """DOP853 solution: states, T, payload_x/y, x_ddot, theta_ddot, phi_ddot, N, E, P_drives,
    W_drives (work of F and tau since t_out[0]) and the inputs F, tau. Raises RuntimeError if
    the trolley reaches the pivot."""
    p, s, t_out = case_settings(PARAMS, START, EXPERIMENT, p, y0, t_out)
    return run(rhs, _outputs, STATES + ("W_drives",), [s[n] for n in STATES] + [0.0], t_out, p,
               INPUTS, inputs, rtol, atol, switch_outputs, events=[trolley_at_pivot])
