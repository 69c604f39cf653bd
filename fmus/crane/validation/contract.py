"""The interface contract of `Crane` (docs/mechanisms/Crane.md) as data: what its
modelDescription.xml must declare, in the rows tests/python/test_contract.py reads."""

MODEL = "Crane"

#: <DefaultExperiment>: startTime, stopTime, stepSize
DEFAULT_EXPERIMENT = (0.0, 20.0, 0.01)

VARIABLES = {
    "m": ("parameter", "fixed", "exact", 1000.0, "kg"),
    "l": ("parameter", "fixed", "exact", 5.0, "m"),
    "g": ("parameter", "fixed", "exact", 9.81, "m/s2"),
    "x_ddot": ("input", "continuous", None, 0.0, "m/s2"),
    "theta_ddot": ("input", "continuous", None, 0.0, "rad/s2"),
    "x": ("output", "continuous", "exact", 10.0, "m"),
    "x_dot": ("output", "continuous", "exact", 0.0, "m/s"),
    "theta": ("output", "continuous", "exact", 0.5, "rad"),
    "theta_dot": ("output", "continuous", "exact", 0.0, "rad/s"),
    "phi": ("output", "continuous", "exact", 0.0, "rad"),
    "phi_dot": ("output", "continuous", "exact", 0.0, "rad/s"),
    "T": ("output", "continuous", "calculated", None, "N"),
    "F": ("output", "continuous", "calculated", None, "N"),
    "tau": ("output", "continuous", "calculated", None, "N.m"),
    "payload_x": ("output", "continuous", "calculated", None, "m"),
    "payload_y": ("output", "continuous", "calculated", None, "m"),
}

#: declared with min="0" (the payload's mass and the cable's length must be > 0)
MIN_ZERO = ["m", "l"]

#: <Derivatives>: state -> its derivative. The inputs are the derivatives of x_dot and
#: theta_dot (the drives' motion is prescribed).
DERIVATIVES = {
    "x": "x_dot",
    "x_dot": "x_ddot",
    "theta": "theta_dot",
    "theta_dot": "theta_ddot",
    "phi": "phi_dot",
    "phi_dot": "phi_ddot",
    "W_drives": "P_drives",
}

#: the event indicators of Model Exchange: the trolley's distance x from the pivot and the cable
#: tension T (tests/python/test_model_exchange.py; a mechanism without events leaves this out)
EVENT_INDICATORS = 2
