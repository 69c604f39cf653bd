"""The interface contract of `DoublePendulumCart` (docs/mechanisms/DoublePendulumCart.md) as data:
what its modelDescription.xml must declare, in the rows tests/python/test_contract.py reads."""

MODEL = "DoublePendulumCart"

#: <DefaultExperiment>: startTime, stopTime, stepSize
DEFAULT_EXPERIMENT = (0.0, 10.0, 0.01)

VARIABLES = {
    "M": ("parameter", "fixed", "exact", 1.0, "kg"),
    "m1": ("parameter", "fixed", "exact", 0.5, "kg"),
    "m2": ("parameter", "fixed", "exact", 0.5, "kg"),
    "l1": ("parameter", "fixed", "exact", 0.5, "m"),
    "l2": ("parameter", "fixed", "exact", 0.5, "m"),
    "g": ("parameter", "fixed", "exact", 9.81, "m/s2"),
    "c": ("parameter", "tunable", "exact", 0.0, "N.s/m"),
    "F": ("input", "continuous", None, 0.0, "N"),
    "x": ("output", "continuous", "exact", 0.0, "m"),
    "x_dot": ("output", "continuous", "exact", 0.0, "m/s"),
    "phi1": ("output", "continuous", "exact", 1.0, "rad"),
    "phi1_dot": ("output", "continuous", "exact", 0.0, "rad/s"),
    "phi2": ("output", "continuous", "exact", 0.5, "rad"),
    "phi2_dot": ("output", "continuous", "exact", 0.0, "rad/s"),
    "x_ddot": ("output", "continuous", "calculated", None, "m/s2"),
    "phi1_ddot": ("output", "continuous", "calculated", None, "rad/s2"),
    "phi2_ddot": ("output", "continuous", "calculated", None, "rad/s2"),
    "tip_x": ("output", "continuous", "calculated", None, "m"),
    "tip_y": ("output", "continuous", "calculated", None, "m"),
    "E": ("output", "continuous", "calculated", None, "J"),
    "p_x": ("output", "continuous", "calculated", None, "N.s"),
}

#: declared with min="0" (masses and lengths must be > 0: the FMU rejects 0)
MIN_ZERO = ["M", "m1", "m2", "l1", "l2"]

#: <Derivatives>: state -> its derivative
DERIVATIVES = {
    "x": "x_dot",
    "x_dot": "x_ddot",
    "phi1": "phi1_dot",
    "phi1_dot": "phi1_ddot",
    "phi2": "phi2_dot",
    "phi2_dot": "phi2_ddot",
}
