"""Reference for `PendulumCart` (docs/mechanisms/PendulumCart.md, docs/derivations.md):

    (M+m) x'' + c1 x' + k x + m l (th'' cos th - th'^2 sin th) = F
    m l x'' cos th + 7/3 m l^2 th'' + c2 th' + m g l sin th    = 3 F l cos th
    F_N = (M+m) g + m l (th'' sin th + th'^2 cos th)       (ground on cart, up)
    E   = 1/2 (M+m) x'^2 + m l x' th' cos th + 7/6 m l^2 th'^2 + 1/2 k x^2 - m g l cos th
    dE/dt = F (x' + 3 l th' cos th) - c1 x'^2 - c2 th'^2
"""

from __future__ import annotations

import math

import numpy as np
from scipy.linalg import eigh

from ._common import case_settings, merge, run, with_constants

PARAMS = {"M": 1.0, "m": 0.5, "l": 0.25, "k": 10.0, "c1": 0.0, "c2": 0.0, "g": 9.81}
INPUTS = {"F": 0.0}
STATES = ("x", "x_dot", "theta", "theta_dot")
START = {"x": 0.0, "x_dot": 0.0, "theta": 0.3, "theta_dot": 0.0}
OUTPUTS = ("F_N", "E")
CALCULATED = ("omega_n1", "omega_n2")
EXTRA = ("x_ddot", "theta_ddot", "E_dot", "W_nc")
EXPERIMENT = {"start": 0.0, "stop": 10.0, "step": 0.01}


def params(**overrides) -> dict:
    return merge(PARAMS, overrides, "parameter")


def accelerations(y, p, F):
    """(x'', th'') from the two equations of motion (2x2 solve by Cramer's rule)."""
    x, v, th, w = y[:4]
    M, m, l, g = p["M"], p["m"], p["l"], p["g"]
    s, c = math.sin(th), math.cos(th)
    a11, a12, a22 = M + m, m * l * c, 7.0 / 3.0 * m * l * l
    b1 = F - p["c1"] * v - p["k"] * x + m * l * w * w * s
    b2 = 3.0 * F * l * c - p["c2"] * w - m * g * l * s
    det = a11 * a22 - a12 * a12  # = m l^2 (7/3 M + m (7/3 - cos^2)) > 0
    return (a22 * b1 - a12 * b2) / det, (a11 * b2 - a12 * b1) / det


def rhs(t, y, p, u):
    xa, tha = accelerations(y, p, u["F"])
    out = [y[1], xa, y[3], tha]
    if len(y) > 4:  # work of the non-conservative forces, integrated alongside
        out.append(power(y, p, u["F"]))
    return out


def normal_force(y, p, theta_ddot):
    """F_N = (M+m) g + m l (th'' sin th + th'^2 cos th): vertical Newton on rod + cart."""
    th, w = y[2], y[3]
    return (p["M"] + p["m"]) * p["g"] + p["m"] * p["l"] * (theta_ddot * math.sin(th) + w * w * math.cos(th))


def energy(y, p):
    x, v, th, w = y[:4]
    M, m, l = p["M"], p["m"], p["l"]
    return (0.5 * (M + m) * v * v + m * l * v * w * math.cos(th) + 7.0 / 6.0 * m * l * l * w * w
            + 0.5 * p["k"] * x * x - m * p["g"] * l * math.cos(th))


def power(y, p, F):
    """dE/dt = F (x' + 3 l th' cos th) - c1 x'^2 - c2 th'^2 (work of F at D, dissipation)."""
    v, th, w = y[1], y[2], y[3]
    return F * (v + 3.0 * p["l"] * w * math.cos(th)) - p["c1"] * v * v - p["c2"] * w * w


def _outputs(t, y, p, u):
    xa, tha = accelerations(y, p, u["F"])
    return {"F_N": normal_force(y, p, tha), "E": energy(y, p), "x_ddot": xa, "theta_ddot": tha,
            "E_dot": power(y, p, u["F"])}


def linear_matrices(p=None):
    """Linearized about x = 0, th = 0: M = [[M+m, m l], [m l, 7/3 m l^2]], K = diag(k, m g l),
    C = diag(c1, c2), input vector for F: [1, 3 l]."""
    p = merge(PARAMS, p, "parameter")
    M, m, l = p["M"], p["m"], p["l"]
    Mm = np.array([[M + m, m * l], [m * l, 7.0 / 3.0 * m * l * l]])
    K = np.diag([p["k"], m * p["g"] * l])
    C = np.diag([p["c1"], p["c2"]])
    return Mm, C, K


def linear_modes(p=None):
    """(omega ascending [2], shapes [2x2] columns (x, theta), each scaled so its largest
    |component| is +1) of the generalized problem K a = w^2 M a."""
    Mm, _, K = linear_matrices(p)
    w2, V = eigh(K, Mm)
    shapes = np.empty_like(V)
    for j in range(2):
        a = V[:, j]
        shapes[:, j] = a / a[np.argmax(np.abs(a))]
    return np.sqrt(w2), shapes


def calculated(p=None) -> dict:
    w, _ = linear_modes(p)
    return {"omega_n1": float(w[0]), "omega_n2": float(w[1])}


def calculated_closed_form(p=None) -> dict:
    """The same from det(K - w^2 M) = 0 written out:
    a w^4 - b w^2 + c = 0 with a = (M+m) 7/3 m l^2 - m^2 l^2, b = k 7/3 m l^2 + (M+m) m g l,
    c = k m g l."""
    p = merge(PARAMS, p, "parameter")
    M, m, l, g, k = p["M"], p["m"], p["l"], p["g"], p["k"]
    a = (M + m) * 7.0 / 3.0 * m * l * l - (m * l) ** 2
    b = k * 7.0 / 3.0 * m * l * l + (M + m) * m * g * l
    c = k * m * g * l
    sD = math.sqrt(b * b - 4 * a * c)
    hi = (b + sD) / (2 * a)
    lo = 2 * c / (b + sD)
    return {"omega_n1": math.sqrt(lo), "omega_n2": math.sqrt(hi)}


def simulate(p=None, y0=None, t_out=None, inputs=None, rtol=1e-12, atol=1e-12, switch_outputs="after"):
    """DOP853 solution; returns states, F_N, E, x_ddot, theta_ddot, E_dot, W_nc (work of F and
    of the dampers since t_out[0], integrated with the states), F, omega_n1/2."""
    p, s, t_out = case_settings(PARAMS, START, EXPERIMENT, p, y0, t_out)
    res = run(rhs, _outputs, STATES + ("W_nc",), [s[n] for n in STATES] + [0.0], t_out, p, INPUTS,
              inputs, rtol, atol, switch_outputs)
    return with_constants(res, calculated(p))
