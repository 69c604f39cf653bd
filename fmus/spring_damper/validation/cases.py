"""Reference cases of `SpringDamper` (docs/mechanisms/SpringDamper.md), a massless spring and
damper between points a and b:

    F_a = k (x_b - x_a - l0) + c (v_b - v_a),   F_b = -F_a,   E = ½ k (x_b - x_a - l0)²

It has no state: the references are these formulas (tests/python/refs/spring_damper.py) at
random inputs, held over ten communication steps each, as an importer reads the outputs at the
end of a step (the inputs held over it).
"""

import numpy as np

from mechfmu_validate.case import Case, step_input
from refs import spring_damper as sd, solution

STOP, H = 1.0, 0.01
OUTPUTS = ["F_a", "F_b", "E"]


def random_inputs(seed):
    """x_a, x_b, v_a, v_b: new random values every 0.1 s (at the times np.arange gives, which
    are the communication points k h the importers reach)."""
    rng = np.random.default_rng(seed)
    times = np.arange(0.0, STOP, 0.1)
    values = np.column_stack([rng.uniform(-2.0, 2.0, times.size), rng.uniform(-1.0, 3.0, times.size),
                              rng.uniform(-5.0, 5.0, times.size), rng.uniform(-5.0, 5.0, times.size)])
    return step_input(["x_a", "x_b", "v_a", "v_b"], times, values, STOP)


def formula_case(name, description, parameters, seed, **kw):
    inputs = random_inputs(seed)
    return Case(name, description=description, start_values=parameters, input=inputs, stop_time=STOP,
                output_interval=H, outputs=OUTPUTS, reference=solution(sd, parameters, inputs),
                tolerance=1e-12, **kw)


CASES = [
    formula_case("default_experiment", "The DefaultExperiment (k = 1, no damping) at random inputs.", {}, 1,
                 relative_tolerance=None, default_experiment=True),
    formula_case("spring_and_damper", "k = 40 N/m, c = 3 N.s/m, l0 = 0.5 m at random inputs.",
                 {"k": 40.0, "c": 3.0, "l0": 0.5}, 2),
    formula_case("damper_alone", "k = 0, c = 12 N.s/m: the force from the velocities alone, no energy.",
                 {"k": 0.0, "c": 12.0}, 3),
]
