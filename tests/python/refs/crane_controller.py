"""Reference for `CraneController`, the stateless control law that positions `CraneDynamics`:

    F   = (m + m_trolley) g sin(theta)   + kp_x (x_ref - x) - kd_x x_dot + k_sway phi_dot
    tau = (m + m_trolley) g x cos(theta) + kp_theta (theta_ref - theta) - kd_theta theta_dot

Written from the formulas of docs/mechanisms/README.md, not from the Rust code. It has no
state: ``simulate`` evaluates the outputs at the output times from the inputs.
"""

from __future__ import annotations

import math

from ._common import case_settings, run

PARAMS = {"x_ref": 12.0, "theta_ref": 0.6, "kp_x": 1200.0, "kd_x": 1700.0, "kp_theta": 125000.0,
          "kd_theta": 175000.0, "k_sway": 3000.0, "m": 1000.0, "m_trolley": 200.0, "g": 9.81}
INPUTS = {"x": 10.0, "x_dot": 0.0, "theta": 0.5, "theta_dot": 0.0, "phi_dot": 0.0}
STATES = ()
START: dict[str, float] = {}
OUTPUTS = ("F", "tau")
EXPERIMENT = {"start": 0.0, "stop": 1.0, "step": 0.01}


def drives(p, u) -> dict:
    weight = (p["m"] + p["m_trolley"]) * p["g"]
    F = (weight * math.sin(u["theta"]) + p["kp_x"] * (p["x_ref"] - u["x"]) - p["kd_x"] * u["x_dot"]
         + p["k_sway"] * u["phi_dot"])
    tau = (weight * u["x"] * math.cos(u["theta"]) + p["kp_theta"] * (p["theta_ref"] - u["theta"])
           - p["kd_theta"] * u["theta_dot"])
    return {"F": F, "tau": tau}


def simulate(p=None, y0=None, t_out=None, inputs=None, rtol=1e-12, atol=1e-12, switch_outputs="after"):
    """The outputs at t_out, from the inputs held (zero-order) as ``run`` reads them."""
    p, _, t_out = case_settings(PARAMS, START, EXPERIMENT, p, y0, t_out)
    return run(lambda t, y, p, u: [], lambda t, y, p, u: drives(p, u), STATES, [], t_out, p, INPUTS, inputs,
               rtol, atol, switch_outputs)
