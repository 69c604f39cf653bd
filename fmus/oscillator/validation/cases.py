"""Reference cases of `Oscillator` (docs/mechanisms/Oscillator.md):

    m x'' + c x' + k x = F + F0 sin(omega t)

Closed forms of the linear equation (tests/python/refs/oscillator.py): the free response in
each damping regime, the step response to a constant F and the complete response to
F0 sin(omega t). Run by `mechfmu validate` (FMPy and libcosim) and tests/python/test_cases.py.
"""

import numpy as np

from mechfmu_validate.case import Case, step_input
from refs import oscillator as osc

STOP = 20.0
H = 0.01
XV = ["x", "x_dot"]


def _with_acceleration(p, x, v, t, F=0.0):
    """x, x_dot and x_ddot = (F + F0 sin(omega t) - c x_dot - k x) / m."""
    q = osc.params(**p)
    a = (F + q["F0"] * np.sin(q["omega"] * t) - q["c"] * v - q["k"] * x) / q["m"]
    return {"x": x, "x_dot": v, "x_ddot": a}


def free(p, x0, v0):
    def reference(t):
        x, v = osc.free_response(p, x0, v0, t)
        return _with_acceleration(p, x, v, t)
    return reference


def complete(p, x0, v0, F=0.0):
    def reference(t):
        x, v = osc.response(osc.params(**p), x0, v0, t, F)
        return _with_acceleration(p, x, v, t, F)
    return reference


def _free_case(name, description, p, x0=1.0, v0=0.0, **kw):
    return Case(name, description=description, start_values={**p, "x": x0, "x_dot": v0}, stop_time=STOP,
                output_interval=H, relative_tolerance=1e-8, outputs=["x", "x_dot", "x_ddot"],
                reference=free(p, x0, v0), tolerance=1e-6, **kw)


CASES = [
    Case("default_experiment",
         description="The DefaultExperiment (zeta = 0.1, released from x0 = 1 m) against the closed-form "
                     "underdamped free response.",
         stop_time=STOP, output_interval=H, relative_tolerance=None,
         outputs=["x", "x_dot", "x_ddot"], reference=free({}, 1.0, 0.0), tolerance=1e-6,
         default_experiment=True),
    _free_case("free_overdamped", "Free response, zeta = 1.25 (c = 5): two real roots.", {"c": 5.0}, 1.0, 0.0),
    _free_case("free_critical", "Free response, zeta = 1 (c = 4), from x0 = -0.5, v0 = 3.", {"c": 4.0}, -0.5, 3.0),
    _free_case("free_underdamped", "Free response, zeta = 0.034 (m = 2.5, c = 0.3, k = 7).",
               {"m": 2.5, "c": 0.3, "k": 7.0}, 0.2, 1.5),
    _free_case("free_undamped", "Free response, zeta = 0 (c = 0): x0 cos(wn t) + v0/wn sin(wn t).",
               {"c": 0.0}, 0.7, -1.1),
    Case("step_force",
         description="Step response: F = 2 N from t = 0, from rest (x -> F/k = 0.5).",
         start_values={"x": 0.0, "x_dot": 0.0}, input=step_input(["F"], [0.0], [[2.0]], STOP),
         stop_time=STOP, output_interval=H, relative_tolerance=1e-8, outputs=["x", "x_dot", "x_ddot"],
         reference=complete({}, 0.0, 0.0, F=2.0), tolerance=1e-6),
    Case("harmonic_near_resonance",
         description="Complete (transient + steady) response to F0 sin(omega t), F0 = 1 N, omega = 1.9 rad/s "
                     "(wn = 2): steady amplitude F0 / sqrt((k - m w^2)^2 + (c w)^2), phase -atan2(c w, k - m w^2).",
         start_values={"F0": 1.0, "omega": 1.9, "x": 1.0, "x_dot": 0.0},
         stop_time=STOP, output_interval=H, relative_tolerance=1e-8, outputs=["x", "x_dot", "x_ddot"],
         reference=complete({"F0": 1.0, "omega": 1.9}, 1.0, 0.0), tolerance=1e-6),
]
