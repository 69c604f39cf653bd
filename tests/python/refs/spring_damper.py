"""Reference for `SpringDamper`, a massless spring and damper between points a and b on a line:

    F_a = k (x_b - x_a - l0) + c (v_b - v_a),   F_b = -F_a,   E = ½ k (x_b - x_a - l0)²

Written from the formulas of docs/mechanisms/README.md, not from the Rust code. It has no
state: ``simulate`` evaluates the outputs at the output times from the inputs.
"""

from __future__ import annotations

from ._common import case_settings, run

PARAMS = {"k": 1.0, "c": 0.0, "l0": 0.0}
INPUTS = {"x_a": 0.0, "x_b": 0.0, "v_a": 0.0, "v_b": 0.0}
STATES = ()
START: dict[str, float] = {}
OUTPUTS = ("F_a", "F_b", "E")
EXPERIMENT = {"start": 0.0, "stop": 1.0, "step": 0.01}


def forces(p, u) -> dict:
    stretch = u["x_b"] - u["x_a"] - p["l0"]
    F_a = p["k"] * stretch + p["c"] * (u["v_b"] - u["v_a"])
    return {"F_a": F_a, "F_b": -F_a, "E": 0.5 * p["k"] * stretch ** 2}


def simulate(p=None, y0=None, t_out=None, inputs=None, rtol=1e-12, atol=1e-12, switch_outputs="after"):
    """The outputs at t_out, from the inputs held (zero-order) as ``run`` reads them."""
    p, _, t_out = case_settings(PARAMS, START, EXPERIMENT, p, y0, t_out)
    return run(lambda t, y, p, u: [], lambda t, y, p, u: forces(p, u), STATES, [], t_out, p, INPUTS, inputs,
               rtol, atol, switch_outputs)
