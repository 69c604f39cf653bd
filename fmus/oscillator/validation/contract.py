"""The interface contract of `Oscillator` (docs/mechanisms/Oscillator.md) as data: what its
modelDescription.xml must declare, in the rows tests/python/test_contract.py reads."""

MODEL = "Oscillator"

#: <DefaultExperiment>: startTime, stopTime, stepSize
DEFAULT_EXPERIMENT = (0.0, 20.0, 0.01)

CALCULATED = ("fixed", "tunable")  # the variabilities a calculatedParameter may have

VARIABLES = {
    "m": ("parameter", "fixed", "exact", 1.0, "kg"),
    "c": ("parameter", "tunable", "exact", 0.4, "N.s/m"),
    "k": ("parameter", "tunable", "exact", 4.0, "N/m"),
    "F0": ("parameter", "tunable", "exact", 0.0, "N"),
    "omega": ("parameter", "tunable", "exact", 1.0, "rad/s"),
    "F": ("input", "continuous", None, 0.0, "N"),
    "x": ("output", "continuous", "exact", 1.0, "m"),
    "x_dot": ("output", "continuous", "exact", 0.0, "m/s"),
    "x_ddot": ("output", "continuous", "calculated", None, "m/s2"),
    "omega_n": ("calculatedParameter", CALCULATED, "calculated", None, "rad/s"),
    "zeta": ("calculatedParameter", CALCULATED, "calculated", None, "1"),
}

#: declared with min="0" (a mass must be > 0: the FMU rejects 0 at initialization)
MIN_ZERO = ["m"]
