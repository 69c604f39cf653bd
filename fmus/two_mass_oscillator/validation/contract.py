"""The interface contract of `TwoMassOscillator` (docs/mechanisms/TwoMassOscillator.md) as data:
what its modelDescription.xml must declare, in the rows tests/python/test_contract.py reads."""

MODEL = "TwoMassOscillator"

#: <DefaultExperiment>: startTime, stopTime, stepSize
DEFAULT_EXPERIMENT = (0.0, 30.0, 0.01)

CALCULATED = ("fixed", "tunable")  # the variabilities a calculatedParameter may have

VARIABLES = {
    "m1": ("parameter", "fixed", "exact", 1.0, "kg"),
    "m2": ("parameter", "fixed", "exact", 1.0, "kg"),
    "k1": ("parameter", "tunable", "exact", 1.0, "N/m"),
    "k2": ("parameter", "tunable", "exact", 1.0, "N/m"),
    "k3": ("parameter", "tunable", "exact", 1.0, "N/m"),
    "c1": ("parameter", "tunable", "exact", 0.0, "N.s/m"),
    "c2": ("parameter", "tunable", "exact", 0.0, "N.s/m"),
    "c3": ("parameter", "tunable", "exact", 0.0, "N.s/m"),
    "F1": ("input", "continuous", None, 0.0, "N"),
    "F2": ("input", "continuous", None, 0.0, "N"),
    "x1": ("output", "continuous", "exact", 1.0, "m"),
    "x2": ("output", "continuous", "exact", 0.0, "m"),
    "x1_dot": ("output", "continuous", "exact", 0.0, "m/s"),
    "x2_dot": ("output", "continuous", "exact", 0.0, "m/s"),
    "x1_ddot": ("output", "continuous", "calculated", None, "m/s2"),
    "x2_ddot": ("output", "continuous", "calculated", None, "m/s2"),
    "E": ("output", "continuous", "calculated", None, "J"),
    "omega_n1": ("calculatedParameter", CALCULATED, "calculated", None, "rad/s"),
    "omega_n2": ("calculatedParameter", CALCULATED, "calculated", None, "rad/s"),
    "mode1_x1": ("calculatedParameter", CALCULATED, "calculated", None, "1"),
    "mode1_x2": ("calculatedParameter", CALCULATED, "calculated", None, "1"),
    "mode2_x1": ("calculatedParameter", CALCULATED, "calculated", None, "1"),
    "mode2_x2": ("calculatedParameter", CALCULATED, "calculated", None, "1"),
}

#: declared with min="0": the masses must be > 0 (the FMU rejects 0), the springs and
#: dampers >= 0 (k1 = k2 = 0 allowed)
MIN_ZERO = ["m1", "m2", "k1", "k2", "k3", "c1", "c2", "c3"]

#: the FMI 3.0 arrays (docs/mechanisms/README.md, "FMI 3.0, arrays"): the FMI 2.0 scalar at each
#: element, row-major (tests/python/test_fmi3.py; a mechanism without arrays leaves this out)
ARRAYS = {
    "M": "M_11 M_12 M_12 M_22",
    "K": "K_11 K_12 K_12 K_22",
    "C": "C_11 C_12 C_12 C_22",
    "modes": "mode1_x1 mode2_x1 mode1_x2 mode2_x2",
}
