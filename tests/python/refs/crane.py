"""Reference for `Crane` (docs/mechanisms/Crane.md): boom and trolley massless, their motion
prescribed by the inputs x_ddot and theta_ddot; the payload swings. With s = theta - phi:

    l phi'' = -g sin phi - (x'' - th'^2 x) cos s + (2 th' x' + th'' x) sin s
    T   = m [(x'' - th'^2 x) sin s + (2 th' x' + th'' x) cos s + l phi'^2 + g cos phi]
    F   = T sin s,   tau = x T cos s

(the notes print the first line with the signs of the g and (x'' - th'^2 x) terms flipped,
which makes the hanging payload unstable; see docs/derivations.md).
"""

from __future__ import annotations

import math

import numpy as np
from scipy.special import ellipj, ellipk

from ._common import case_settings, merge, run, trolley_at_pivot

PARAMS = {"m": 1000.0, "l": 5.0, "g": 9.81}
INPUTS = {"x_ddot": 0.0, "theta_ddot": 0.0}
STATES = ("x", "x_dot", "theta", "theta_dot", "phi", "phi_dot")
START = {"x": 10.0, "x_dot": 0.0, "theta": 0.5, "theta_dot": 0.0, "phi": 0.0, "phi_dot": 0.0}
OUTPUTS = ("T", "F", "tau", "payload_x", "payload_y")
EXTRA = ("phi_ddot", "E_payload", "P_drives", "W_drives")
EXPERIMENT = {"start": 0.0, "stop": 20.0, "step": 0.01}


def params(**overrides) -> dict:
    return merge(PARAMS, overrides, "parameter")


def phi_ddot(y, p, xdd, thdd):
    x, v, th, w, ph, phd = y[:6]
    s = th - ph
    return (-p["g"] * math.sin(ph) - (xdd - w * w * x) * math.cos(s) + (2 * w * v + thdd * x) * math.sin(s)) / p["l"]


def tension(y, p, xdd, thdd):
    x, v, th, w, ph, phd = y[:6]
    s = th - ph
    return p["m"] * ((xdd - w * w * x) * math.sin(s) + (2 * w * v + thdd * x) * math.cos(s)
                     + p["l"] * phd * phd + p["g"] * math.cos(ph))


def drive_loads(y, p, xdd, thdd):
    """(T, F, tau): cable tension, trolley drive force along i_A, boom torque about O (K)."""
    T = tension(y, p, xdd, thdd)
    s = y[2] - y[4]
    return T, T * math.sin(s), y[0] * T * math.cos(s)


def payload_position(y, p):
    x, th, ph = y[0], y[2], y[4]
    return x * math.cos(th) + p["l"] * math.sin(ph), x * math.sin(th) - p["l"] * math.cos(ph)


def payload_velocity(y, p):
    x, v, th, w, ph, phd = y[:6]
    l = p["l"]
    return (v * math.cos(th) - x * w * math.sin(th) + l * phd * math.cos(ph),
            v * math.sin(th) + x * w * math.cos(th) + l * phd * math.sin(ph))


def payload_energy(y, p):
    vx, vy = payload_velocity(y, p)
    return 0.5 * p["m"] * (vx * vx + vy * vy) + p["m"] * p["g"] * payload_position(y, p)[1]


def rhs(t, y, p, u):
    xdd, thdd = u["x_ddot"], u["theta_ddot"]
    out = [y[1], xdd, y[3], thdd, y[5], phi_ddot(y, p, xdd, thdd)]
    if len(y) > 6:  # work done by the drives, integrated alongside
        T, F, tau = drive_loads(y, p, xdd, thdd)
        out.append(F * y[1] + tau * y[3])
    return out


def _outputs(t, y, p, u):
    xdd, thdd = u["x_ddot"], u["theta_ddot"]
    T, F, tau = drive_loads(y, p, xdd, thdd)
    px, py = payload_position(y, p)
    return {"T": T, "F": F, "tau": tau, "payload_x": px, "payload_y": py,
            "phi_ddot": phi_ddot(y, p, xdd, thdd), "E_payload": payload_energy(y, p),
            "P_drives": F * y[1] + tau * y[3]}


def simulate(p=None, y0=None, t_out=None, inputs=None, rtol=1e-12, atol=1e-12, switch_outputs="after"):
    """DOP853 solution: states, T, F, tau, payload_x/y, phi_ddot, E_payload, P_drives,
    W_drives (work of F and tau since t_out[0]), and the inputs."""
    p, s, t_out = case_settings(PARAMS, START, EXPERIMENT, p, y0, t_out)
    return run(rhs, _outputs, STATES + ("W_drives",), [s[n] for n in STATES] + [0.0], t_out, p,
               INPUTS, inputs, rtol, atol, switch_outputs, events=[trolley_at_pivot])


# ----------------------------------------------------------------------------- closed forms

def small_amplitude_omega(p=None) -> float:
    """Drives still, linearized about phi = 0: l phi'' = -g phi, a stable oscillation."""
    p = merge(PARAMS, p, "parameter")
    return math.sqrt(p["g"] / p["l"])


def period(p=None, phi0: float = 0.1) -> float:
    """Large-amplitude period from rest at phi0: 4 sqrt(l/g) K(k), k = sin(phi0/2).
    scipy's ellipk takes the PARAMETER m = k^2."""
    p = merge(PARAMS, p, "parameter")
    k = math.sin(phi0 / 2.0)
    return 4.0 * math.sqrt(p["l"] / p["g"]) * float(ellipk(k * k))


def pendulum(p=None, phi0: float = 0.1, t=None):
    """Exact swing from rest at phi0 with the drives still (Jacobi elliptic functions):
    sin(phi/2) = k cd(w0 t | m), phi' = -2 k k' w0 sd(w0 t | m), k = sin(phi0/2), m = k^2,
    k' = sqrt(1 - m), w0 = sqrt(g/l). Returns (phi, phi_dot)."""
    p = merge(PARAMS, p, "parameter")
    t = np.asarray(t, dtype=float)
    w0 = math.sqrt(p["g"] / p["l"])
    k = math.sin(phi0 / 2.0)
    mm = k * k
    sn, cn, dn, _ = ellipj(w0 * t, mm)
    phi = 2.0 * np.arcsin(k * cn / dn)
    phid = -2.0 * k * math.sqrt(1.0 - mm) * w0 * sn / dn
    return phi, phid


def still_loads(p=None, x: float = 10.0, theta: float = 0.5, phi: float = 0.0, phi_dot: float = 0.0):
    """(T, F, tau) with the drives still: T = m (g cos phi + l phi'^2), F = T sin(theta - phi),
    tau = x T cos(theta - phi); at rest (phi = 0): T = m g, F = m g sin theta, tau = x m g cos theta."""
    p = merge(PARAMS, p, "parameter")
    return drive_loads((x, 0.0, theta, 0.0, phi, phi_dot), p, 0.0, 0.0)


def phi_ddot_notes(y, p, xdd, thdd):
    """The tangential equation AS PRINTED in the notes (wrong; kept to show it):
    0 = -(x'' - th'^2 x) cos s - (2 th' x' + th'' x) sin s + l phi'' - g sin phi."""
    x, v, th, w, ph, phd = y[:6]
    s = th - ph
    return (p["g"] * math.sin(ph) + (xdd - w * w * x) * math.cos(s) + (2 * w * v + thdd * x) * math.sin(s)) / p["l"]
