"""Reference cases of `CraneController` (docs/mechanisms/CraneController.md), the control law of
`CraneDynamics`' drives:

    F   = (m + m_trolley) g sin(theta)   + kp_x (x_ref - x) - kd_x x_dot + k_sway phi_dot
    tau = (m + m_trolley) g x cos(theta) + kp_theta (theta_ref - theta) - kd_theta theta_dot

It has no state: the references are these formulas (tests/python/refs/crane_controller.py) at
random measurements, held over ten communication steps each, as an importer reads the outputs
at the end of a step (the inputs held over it).
"""

import numpy as np

from mechfmu_validate.case import Case, step_input
from refs import crane_controller as cc, solution

STOP, H = 1.0, 0.01
INPUTS = ["x", "x_dot", "theta", "theta_dot", "phi_dot"]


def random_inputs(seed):
    """The crane's measurements: new random values every 0.1 s (at the times np.arange gives, which
    are the communication points k h the importers reach)."""
    rng = np.random.default_rng(seed)
    times = np.arange(0.0, STOP, 0.1)
    values = np.column_stack([rng.uniform(2.0, 18.0, times.size), rng.uniform(-1.0, 1.0, times.size),
                              rng.uniform(0.0, 1.2, times.size), rng.uniform(-0.2, 0.2, times.size),
                              rng.uniform(-0.5, 0.5, times.size)])
    return step_input(INPUTS, times, values, STOP)


def formula_case(name, description, parameters, seed, **kw):
    inputs = random_inputs(seed)
    return Case(name, description=description, start_values=parameters, input=inputs, stop_time=STOP,
                output_interval=H, outputs=["F", "tau"], reference=solution(cc, parameters, inputs),
                tolerance=1e-12, **kw)


CASES = [
    formula_case("default_experiment", "The DefaultExperiment (the default gains) at random measurements.",
                 {}, 11, relative_tolerance=None, default_experiment=True),
    formula_case("reach", "Other references: x_ref = 15 m, theta_ref = 0.3 rad.",
                 {"x_ref": 15.0, "theta_ref": 0.3}, 12),
    formula_case("other_gains", "Other gains and a lighter crane: kp_x = 400, kd_x = 900, kp_theta = 6e4, "
                 "kd_theta = 9e4, k_sway = -1500, m = 300 kg, m_trolley = 80 kg.",
                 {"kp_x": 400.0, "kd_x": 900.0, "kp_theta": 6e4, "kd_theta": 9e4, "k_sway": -1500.0, "m": 300.0,
                  "m_trolley": 80.0}, 13),
]
