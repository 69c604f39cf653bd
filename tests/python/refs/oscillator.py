"""Reference for `Oscillator`:  m x'' + c x' + k x = F + F0 sin(omega t).

Written from the equation of docs/mechanisms/Oscillator.md (and docs/derivations.md), not from
the Rust code.
"""

from __future__ import annotations

import math

import numpy as np

from ._common import case_settings, merge, run, with_constants

PARAMS = {"m": 1.0, "c": 0.4, "k": 4.0, "F0": 0.0, "omega": 1.0}
INPUTS = {"F": 0.0}
STATES = ("x", "x_dot")
START = {"x": 1.0, "x_dot": 0.0}
OUTPUTS = ("x_ddot",)
CALCULATED = ("omega_n", "zeta")
EXPERIMENT = {"start": 0.0, "stop": 20.0, "step": 0.01}


def params(**overrides) -> dict:
    return merge(PARAMS, overrides, "parameter")


def calculated(p: dict | None = None) -> dict:
    p = merge(PARAMS, p, "parameter")
    return {"omega_n": math.sqrt(p["k"] / p["m"]), "zeta": p["c"] / (2.0 * math.sqrt(p["m"] * p["k"]))}


def x_ddot(t, x, v, p, F):
    return (F + p["F0"] * math.sin(p["omega"] * t) - p["c"] * v - p["k"] * x) / p["m"]


def rhs(t, y, p, u):
    x, v = y
    return [v, (u["F"] + p["F0"] * math.sin(p["omega"] * t) - p["c"] * v - p["k"] * x) / p["m"]]


def _outputs(t, y, p, u):
    return {"x_ddot": x_ddot(t, y[0], y[1], p, u["F"])}


def simulate(p=None, y0=None, t_out=None, inputs=None, rtol=1e-12, atol=1e-12, switch_outputs="after"):
    """DOP853 solution at t_out; returns time, x, x_dot, x_ddot, F, omega_n, zeta."""
    p, s, t_out = case_settings(PARAMS, START, EXPERIMENT, p, y0, t_out)
    res = run(rhs, _outputs, STATES, [s[n] for n in STATES], t_out, p, INPUTS, inputs, rtol, atol,
              switch_outputs)
    return with_constants(res, calculated(p))


# ----------------------------------------------------------------------------- closed forms

def steady_amplitude_phase(p: dict | None = None, omega: float | None = None, F0: float | None = None):
    """X = F0 / sqrt((k - m w^2)^2 + (c w)^2), psi = -atan2(c w, k - m w^2); x_p = X sin(w t + psi)."""
    p = merge(PARAMS, p, "parameter")
    w = p["omega"] if omega is None else omega
    F0 = p["F0"] if F0 is None else F0
    d_re, d_im = p["k"] - p["m"] * w * w, p["c"] * w
    return F0 / math.hypot(d_re, d_im), -math.atan2(d_im, d_re)


def regime(p: dict | None = None) -> str:
    z = calculated(p)["zeta"]
    if z == 0.0:
        return "undamped"
    if z < 1.0:
        return "underdamped"
    if z == 1.0:
        return "critical"
    return "overdamped"


def homogeneous(p, x0, v0, t):
    """Free response x_h(t) with x_h(0) = x0, x_h'(0) = v0, and its derivative.

    With sigma = zeta wn:
      0 <= zeta < 1: x = e^{-sigma t} [x0 cos(wd t) + (v0 + sigma x0) sin(wd t)/wd], wd = wn sqrt(1-zeta^2)
      zeta = 1:      x = e^{-wn t} [x0 + (v0 + wn x0) t]
      zeta > 1:      x = e^{-sigma t} [x0 cosh(b t) + (v0 + sigma x0) sinh(b t)/b], b = wn sqrt(zeta^2-1)
                       (= A e^{s1 t} + B e^{s2 t}, s1,2 = -sigma +- b, written without cancellation)
    zeta = 0 is the first line with sigma = 0 (x0 cos wn t + v0/wn sin wn t).
    """
    p = merge(PARAMS, p, "parameter")
    t = np.asarray(t, dtype=float)
    wn = math.sqrt(p["k"] / p["m"])
    z = p["c"] / (2.0 * math.sqrt(p["m"] * p["k"]))
    sig = z * wn
    B = v0 + sig * x0
    if z < 1.0:
        wd = wn * math.sqrt(1.0 - z * z)
        e = np.exp(-sig * t)
        E1, E2 = e * np.cos(wd * t), e * np.sin(wd * t) / wd
        dE1, dE2 = -wd * e * np.sin(wd * t) - sig * E1, e * np.cos(wd * t) - sig * E2
    elif z == 1.0:
        e = np.exp(-sig * t)
        E1, E2 = e, e * t
        dE1, dE2 = -sig * e, e - sig * e * t
    else:
        # e^{-sig t} cosh(b t) and e^{-sig t} sinh(b t)/b from decaying exponentials
        # (no overflow for large t, no cancellation for b -> 0)
        b = wn * math.sqrt(z * z - 1.0)
        g, em = np.exp((b - sig) * t), np.expm1(-2.0 * b * t)
        E1, E2 = g * (2.0 + em) / 2.0, -g * em / (2.0 * b)
        dE1 = g * (-b * em - sig * (2.0 + em)) / 2.0
        dE2 = g * ((2.0 + em) / 2.0 + sig * em / (2.0 * b))
    x = x0 * E1 + B * E2
    v = x0 * dE1 + B * dE2
    return x, v


def overdamped_roots(p=None):
    """s1,2 = -zeta wn +- wn sqrt(zeta^2 - 1) (the notes' form, for zeta > 1)."""
    p = merge(PARAMS, p, "parameter")
    wn = math.sqrt(p["k"] / p["m"])
    z = p["c"] / (2.0 * math.sqrt(p["m"] * p["k"]))
    r = wn * math.sqrt(z * z - 1.0)
    return -z * wn + r, -z * wn - r


def particular(p, t, F=0.0):
    """Particular solution for constant F plus F0 sin(omega t) and its derivative.

    Constant F: x_p = F/k. Harmonic: x_p = X sin(w t + psi); at undamped resonance
    (c = 0, w = wn) x_p = -F0 t cos(wn t) / (2 m wn).
    """
    p = merge(PARAMS, p, "parameter")
    t = np.asarray(t, dtype=float)
    xp = np.full_like(t, F / p["k"])
    vp = np.zeros_like(t)
    if p["F0"] != 0.0:
        w = p["omega"]
        wn = math.sqrt(p["k"] / p["m"])
        if p["c"] == 0.0 and w == wn:
            a = -p["F0"] / (2.0 * p["m"] * wn)
            xp = xp + a * t * np.cos(wn * t)
            vp = vp + a * (np.cos(wn * t) - wn * t * np.sin(wn * t))
        else:
            X, psi = steady_amplitude_phase(p)
            xp = xp + X * np.sin(w * t + psi)
            vp = vp + X * w * np.cos(w * t + psi)
    return xp, vp


def response(p=None, x0=1.0, v0=0.0, t=None, F=0.0):
    """Complete (transient + steady) response to a constant F plus F0 sin(omega t):
    x = x_h + x_p with x_h's constants fitted to x(0) = x0, x'(0) = v0. Returns (x, x_dot)."""
    p = merge(PARAMS, p, "parameter")
    t = np.asarray(t, dtype=float)
    xp0, vp0 = particular(p, np.array([0.0]), F)
    xh, vh = homogeneous(p, x0 - xp0[0], v0 - vp0[0], t)
    xp, vp = particular(p, t, F)
    return xh + xp, vh + vp


def free_response(p=None, x0=1.0, v0=0.0, t=None):
    q = dict(merge(PARAMS, p, "parameter"), F0=0.0)
    return homogeneous(q, x0, v0, t)


def step_response(p=None, F=1.0, x0=0.0, v0=0.0, t=None):
    q = dict(merge(PARAMS, p, "parameter"), F0=0.0)
    return response(q, x0, v0, t, F)


def harmonic_response(p=None, x0=0.0, v0=0.0, t=None):
    return response(p, x0, v0, t, 0.0)


def peak(p=None):
    """Peak of the amplitude response (zeta < 1/sqrt 2): w_peak = wn sqrt(1 - 2 zeta^2),
    X_peak = F0 / (2 k zeta sqrt(1 - zeta^2))."""
    p = merge(PARAMS, p, "parameter")
    c = calculated(p)
    z, wn = c["zeta"], c["omega_n"]
    return wn * math.sqrt(1 - 2 * z * z), p["F0"] / (2 * p["k"] * z * math.sqrt(1 - z * z))
