"""The interface contract of `Oscillator` (docs/mechanisms/Oscillator.md): what its
modelDescription.xml must declare. Data only: tests/python/test_contract.py checks every FMU
against its crate's file (mechfmu's Rust side does not read it).

VARIABLES: name -> (causality, variability, initial, start, unit). A variability is a value
or a tuple of the values allowed; initial is None for an input (no `initial` attribute),
"exact" with the start value given, or "calculated" (no start value); unit is the name of a
<UnitDefinitions> unit ("1": dimensionless).
"""

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
