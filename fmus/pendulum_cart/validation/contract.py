"""The interface contract of `PendulumCart` (docs/mechanisms/PendulumCart.md) as data: what its
modelDescription.xml must declare, in the rows tests/python/test_contract.py reads."""

MODEL = "PendulumCart"

#: <DefaultExperiment>: startTime, stopTime, stepSize
DEFAULT_EXPERIMENT = (0.0, 10.0, 0.01)

CALCULATED = ("fixed", "tunable")  # the variabilities a calculatedParameter may have

VARIABLES = {
    "M": ("parameter", "fixed", "exact", 1.0, "kg"),
    "m": ("parameter", "fixed", "exact", 0.5, "kg"),
    "l": ("parameter", "fixed", "exact", 0.25, "m"),
    "k": ("parameter", "tunable", "exact", 10.0, "N/m"),
    "c1": ("parameter", "tunable", "exact", 0.0, "N.s/m"),
    "c2": ("parameter", "tunable", "exact", 0.0, "N.m.s/rad"),
    "g": ("parameter", "fixed", "exact", 9.81, "m/s2"),
    "F": ("input", "continuous", None, 0.0, "N"),
    "x": ("output", "continuous", "exact", 0.0, "m"),
    "x_dot": ("output", "continuous", "exact", 0.0, "m/s"),
    "theta": ("output", "continuous", "exact", 0.3, "rad"),
    "theta_dot": ("output", "continuous", "exact", 0.0, "rad/s"),
    "x_ddot": ("output", "continuous", "calculated", None, "m/s2"),
    "theta_ddot": ("output", "continuous", "calculated", None, "rad/s2"),
    "F_N": ("output", "continuous", "calculated", None, "N"),
    "E": ("output", "continuous", "calculated", None, "J"),
    "omega_n1": ("calculatedParameter", CALCULATED, "calculated", None, "rad/s"),
    "omega_n2": ("calculatedParameter", CALCULATED, "calculated", None, "rad/s"),
}

#: declared with min="0" (masses and lengths must be > 0: the FMU rejects 0)
MIN_ZERO = ["M", "m", "l"]
