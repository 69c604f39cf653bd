"""Reference for `TwoMassOscillator` (docs/mechanisms/TwoMassOscillator.md):

    m1 x1'' + (c1+c3) x1' - c3 x2' + (k1+k3) x1 - k3 x2 = F1
    m2 x2'' + (c2+c3) x2' - c3 x1' + (k2+k3) x2 - k3 x1 = F2
"""

from __future__ import annotations

import math

import numpy as np
from scipy.linalg import eigh

from ._common import case_settings, merge, run, with_constants

PARAMS = {"m1": 1.0, "m2": 1.0, "k1": 1.0, "k2": 1.0, "k3": 1.0, "c1": 0.0, "c2": 0.0, "c3": 0.0}
INPUTS = {"F1": 0.0, "F2": 0.0}
STATES = ("x1", "x2", "x1_dot", "x2_dot")
START = {"x1": 1.0, "x2": 0.0, "x1_dot": 0.0, "x2_dot": 0.0}
CALCULATED = ("omega_n1", "omega_n2", "mode1_x1", "mode1_x2", "mode2_x1", "mode2_x2")
EXPERIMENT = {"start": 0.0, "stop": 30.0, "step": 0.01}

#: relative tolerance under which |x1| and |x2| count as a tie in the mode-shape scaling
TIE_RTOL = 1e-9


def params(**overrides) -> dict:
    return merge(PARAMS, overrides, "parameter")


def matrices(p=None):
    """M, C, K of  M x'' + C x' + K x = F."""
    p = merge(PARAMS, p, "parameter")
    M = np.diag([p["m1"], p["m2"]])
    C = np.array([[p["c1"] + p["c3"], -p["c3"]], [-p["c3"], p["c2"] + p["c3"]]])
    K = np.array([[p["k1"] + p["k3"], -p["k3"]], [-p["k3"], p["k2"] + p["k3"]]])
    return M, C, K


def rhs(t, y, p, u):
    x1, x2, v1, v2 = y
    a1 = (u["F1"] - (p["c1"] + p["c3"]) * v1 + p["c3"] * v2 - (p["k1"] + p["k3"]) * x1 + p["k3"] * x2) / p["m1"]
    a2 = (u["F2"] - (p["c2"] + p["c3"]) * v2 + p["c3"] * v1 - (p["k2"] + p["k3"]) * x2 + p["k3"] * x1) / p["m2"]
    return [v1, v2, a1, a2]


def _outputs(t, y, p, u):
    d = rhs(t, y, p, u)
    return {"x1_ddot": d[2], "x2_ddot": d[3]}


def scale_shape(a) -> np.ndarray:
    """Scale so that the component of largest magnitude is +1 (tie, within TIE_RTOL: x1 = +1)."""
    a1, a2 = float(a[0]), float(a[1])
    if abs(a1) >= abs(a2) * (1.0 - TIE_RTOL):
        return np.array([1.0, a2 / a1 + 0.0])  # + 0.0 turns -0.0 into 0.0
    return np.array([a1 / a2 + 0.0, 1.0])


def omega_squared(p=None):
    """The notes' closed form of det(K - w^2 M) = 0 (checked in docs/derivations.md):

        m1 m2 w^4 - B w^2 + C = 0,  B = m1 k2 + m2 k1 + (m1+m2) k3,  C = k1 k2 + (k1+k2) k3
        w^2 = [B -+ sqrt(B^2 - 4 m1 m2 C)] / (2 m1 m2)

    The smaller root is evaluated as 2C / (B + sqrt(D)) (same value, no cancellation).
    """
    p = merge(PARAMS, p, "parameter")
    m1, m2, k1, k2, k3 = p["m1"], p["m2"], p["k1"], p["k2"], p["k3"]
    B = m1 * k2 + m2 * k1 + (m1 + m2) * k3
    C = k1 * k2 + (k1 + k2) * k3
    D = max(B * B - 4.0 * m1 * m2 * C, 0.0)  # D = (m1(k2+k3) - m2(k1+k3))^2 + 4 m1 m2 k3^2 >= 0
    sD = math.sqrt(D)
    w2_hi = (B + sD) / (2.0 * m1 * m2)
    w2_lo = 2.0 * C / (B + sD) if B + sD > 0 else 0.0
    return max(w2_lo, 0.0), max(w2_hi, 0.0)


def _shape(p, w2):
    """Null vector of K - w^2 M, from the better-conditioned row:
    row 1 gives a1/a2 = k3 / (k1+k3 - m1 w^2), row 2 gives a1/a2 = (k2+k3 - m2 w^2) / k3."""
    r1 = np.array([p["k3"], p["k1"] + p["k3"] - p["m1"] * w2])
    r2 = np.array([p["k2"] + p["k3"] - p["m2"] * w2, p["k3"]])
    return r1 if np.hypot(*r1) >= np.hypot(*r2) else r2


def modes(p=None) -> dict:
    """Closed-form undamped frequencies (ascending) and mode shapes, contract names.

    With k3 = 0 and k1/m1 = k2/m2 the frequencies coincide and any vector is a mode;
    this reference then returns (1, 0) and (0, 1).
    """
    p = merge(PARAMS, p, "parameter")
    w2a, w2b = omega_squared(p)
    s1, s2 = _shape(p, w2a), _shape(p, w2b)
    if np.hypot(*s1) == 0.0 or w2a == w2b:
        s1, s2 = np.array([1.0, 0.0]), np.array([0.0, 1.0])
    s1, s2 = scale_shape(s1), scale_shape(s2)
    return {"omega_n1": math.sqrt(w2a), "omega_n2": math.sqrt(w2b),
            "mode1_x1": float(s1[0]), "mode1_x2": float(s1[1]),
            "mode2_x1": float(s2[0]), "mode2_x2": float(s2[1])}


def modes_eig(p=None) -> dict:
    """Same quantities by scipy's generalized symmetric eigensolver (independent route)."""
    M, _, K = matrices(p)
    w2, V = eigh(K, M)
    w = np.sqrt(np.clip(w2, 0.0, None))
    s1, s2 = scale_shape(V[:, 0]), scale_shape(V[:, 1])
    return {"omega_n1": float(w[0]), "omega_n2": float(w[1]),
            "mode1_x1": float(s1[0]), "mode1_x2": float(s1[1]),
            "mode2_x1": float(s2[0]), "mode2_x2": float(s2[1])}


def modal_response(p, mode: int, amplitude: float, t):
    """Undamped, unforced start on a mode shape (zero velocity): x = a A cos(w t)."""
    md = modes(p)
    w = md[f"omega_n{mode}"]
    a = np.array([md[f"mode{mode}_x1"], md[f"mode{mode}_x2"]]) * amplitude
    t = np.asarray(t, dtype=float)
    return a[0] * np.cos(w * t), a[1] * np.cos(w * t)


def simulate(p=None, y0=None, t_out=None, inputs=None, rtol=1e-12, atol=1e-12, switch_outputs="after"):
    p, s, t_out = case_settings(PARAMS, START, EXPERIMENT, p, y0, t_out)
    res = run(rhs, _outputs, STATES, [s[n] for n in STATES], t_out, p, INPUTS, inputs, rtol, atol,
              switch_outputs)
    return with_constants(res, modes(p))
