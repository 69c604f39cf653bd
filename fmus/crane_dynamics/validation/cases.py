"""Reference cases of `CraneDynamics` (docs/mechanisms/CraneDynamics.md): the crane driven by
the trolley force F and the boom torque tau, with the boom's inertia J_boom and the trolley's
mass m_trolley (tests/python/refs/crane_dynamics.py gives M(q) q'' = f).

References: the static drive loads F = (m + m_trolley) g sin(theta),
tau = x (m + m_trolley) g cos(theta) hold the crane at rest with T = m g (closed form);
DOP853 (rtol = atol = 1e-12) otherwise; the power of F and tau equals the rate of change of
the total mechanical energy (E - E(0) = W_drives).
"""

import math

import numpy as np

from mechfmu_validate.case import Case, step_input
from refs import crane_dynamics as cd, split, solution

STATES = ["x", "x_dot", "theta", "theta_dot", "phi", "phi_dot"]
CONTRACT = [*STATES, "T", "payload_x", "payload_y", "x_ddot", "theta_ddot"]


def static_input(start_values, stop):
    p, y0 = split(cd, start_values)
    s = {**cd.START, **y0}
    F, tau = cd.static_loads(p, s["x"], s["theta"])
    return step_input(["F", "tau"], [0.0], [[F, tau]], stop)


def numerical(start_values, inputs):
    return solution(cd, start_values, inputs)


def at_rest(start_values):
    """The static loads hold everything still: states constant, T = m g, no acceleration."""
    p, y0 = split(cd, start_values)
    q = cd.params(**p)
    s = {**cd.START, **y0}

    def reference(t):
        c = lambda v: np.full_like(t, v)  # noqa: E731
        return {**{n: c(s[n]) for n in STATES}, "T": c(q["m"] * q["g"]),
                "payload_x": c(s["x"] * math.cos(s["theta"])),
                "payload_y": c(s["x"] * math.sin(s["theta"]) - q["l"]),
                "x_ddot": c(0.0), "theta_ddot": c(0.0)}
    return reference


def energy_balance(r):
    """E - E(0) = W_drives (the work of F and tau), relative to max |W_drives|."""
    E, W = r["E"], r["W_drives"]
    return {"E - E(0) = W_drives": np.abs(E - E[0] - W) / max(np.max(np.abs(W)), np.ptp(E))}


P = cd.params()
F0, TAU0 = cd.static_loads(P, 10.0, 0.5)
DEFAULT_INPUT = step_input(["F", "tau"], [0.0], [[F0, TAU0]], 20.0)
HOLD = {"x": 8.0, "theta": 0.8}
DRIVEN_INPUT = step_input(["F", "tau"], [0.0, 1.0, 4.0, 6.0, 11.0],
                          [[F0, TAU0], [F0 + 800, TAU0 + 4000], [F0 - 600, TAU0 - 6000], [F0, TAU0 + 1500],
                           [F0, TAU0]], 20.0)

CASES = [
    Case("default_experiment",
         description="The DefaultExperiment: the inputs' start values are the static loads of the default "
                     "configuration, so the crane stays at rest; against DOP853.",
         stop_time=20.0, output_interval=0.01, relative_tolerance=None, outputs=CONTRACT,
         reference=numerical({}, DEFAULT_INPUT), tolerance=1e-6, default_experiment=True),
    Case("static_loads_hold",
         description="Trolley at x = 8 m, boom at 0.8 rad, the static loads F = (m + m_trolley) g sin(theta), "
                     "tau = x (m + m_trolley) g cos(theta) applied: nothing moves and T = m g (closed form; "
                     "accelerations compared in absolute terms).",
         start_values=HOLD, input=static_input(HOLD, 20.0), stop_time=20.0, output_interval=0.01,
         relative_tolerance=1e-8, outputs=CONTRACT, reference=at_rest(HOLD),
         scale={"x_ddot": 1.0, "theta_ddot": 1.0, "x_dot": 1.0, "theta_dot": 1.0, "phi": 1.0, "phi_dot": 1.0},
         tolerance=1e-9),
    Case("driven_energy_balance",
         description="F and tau stepping around the static loads (at 1, 4, 6, 11 s): DOP853 restarted at every "
                     "switch, and the work of the drives equal to the gain of mechanical energy.",
         input=DRIVEN_INPUT, stop_time=20.0, output_interval=0.01, relative_tolerance=1e-8,
         outputs=[*CONTRACT, "E", "W_drives"], reference=numerical({}, DRIVEN_INPUT), metric=energy_balance,
         tolerance=1e-6, reference_files=[*STATES, "T", "payload_x", "x_ddot", "theta_ddot"]),
]
