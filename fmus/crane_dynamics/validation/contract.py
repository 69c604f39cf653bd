"""The interface contract of `CraneDynamics` (docs/mechanisms/CraneDynamics.md) as data: what its
modelDescription.xml must declare, in the rows tests/python/test_contract.py reads."""

import math

MODEL = "CraneDynamics"

#: <DefaultExperiment>: startTime, stopTime, stepSize
DEFAULT_EXPERIMENT = (0.0, 20.0, 0.01)

# The inputs start at the static drive loads of the default configuration (x = 10,
# theta = 0.5): F = (m + m_trolley) g sin(theta), tau = x (m + m_trolley) g cos(theta).
MU = 1000.0 + 200.0
F0 = MU * 9.81 * math.sin(0.5)
TAU0 = 10.0 * MU * 9.81 * math.cos(0.5)

VARIABLES = {
    "m": ("parameter", "fixed", "exact", 1000.0, "kg"),
    "l": ("parameter", "fixed", "exact", 5.0, "m"),
    "g": ("parameter", "fixed", "exact", 9.81, "m/s2"),
    "J_boom": ("parameter", "fixed", "exact", 5000.0, "kg.m2"),
    "m_trolley": ("parameter", "fixed", "exact", 200.0, "kg"),
    "F": ("input", "continuous", None, F0, "N"),
    "tau": ("input", "continuous", None, TAU0, "N.m"),
    "x": ("output", "continuous", "exact", 10.0, "m"),
    "x_dot": ("output", "continuous", "exact", 0.0, "m/s"),
    "theta": ("output", "continuous", "exact", 0.5, "rad"),
    "theta_dot": ("output", "continuous", "exact", 0.0, "rad/s"),
    "phi": ("output", "continuous", "exact", 0.0, "rad"),
    "phi_dot": ("output", "continuous", "exact", 0.0, "rad/s"),
    "T": ("output", "continuous", "calculated", None, "N"),
    "payload_x": ("output", "continuous", "calculated", None, "m"),
    "payload_y": ("output", "continuous", "calculated", None, "m"),
    "x_ddot": ("output", "continuous", "calculated", None, "m/s2"),
    "theta_ddot": ("output", "continuous", "calculated", None, "rad/s2"),
}

#: declared with min="0" (masses, length and inertia must be > 0: the FMU rejects 0)
MIN_ZERO = ["m", "l", "J_boom", "m_trolley"]

#: <Derivatives>: state -> its derivative
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
