"""The interface contract of `RigidBody` (docs/mechanisms/RigidBody.md) as data: what its
modelDescription.xml must declare, in the rows tests/python/test_contract.py reads."""

MODEL = "RigidBody"

#: <DefaultExperiment>: startTime, stopTime, stepSize
DEFAULT_EXPERIMENT = (0.0, 20.0, 0.01)

CALCULATED = ("fixed", "tunable")  # the variabilities a calculatedParameter may have

# The default body: a 0.3 x 0.2 x 0.1 m box of 2 kg, its principal moments about its centre.
M_BOX, A, B, C = 2.0, 0.3, 0.2, 0.1
BOX = (M_BOX * (B * B + C * C) / 12.0, M_BOX * (A * A + C * C) / 12.0, M_BOX * (A * A + B * B) / 12.0)

VARIABLES = {
    "M": ("parameter", "fixed", "exact", 2.0, "kg"),
    "I_xx": ("parameter", "fixed", "exact", BOX[0], "kg.m2"),
    "I_yy": ("parameter", "fixed", "exact", BOX[1], "kg.m2"),
    "I_zz": ("parameter", "fixed", "exact", BOX[2], "kg.m2"),
    "I_xy": ("parameter", "fixed", "exact", 0.0, "kg.m2"),
    "I_xz": ("parameter", "fixed", "exact", 0.0, "kg.m2"),
    "I_yz": ("parameter", "fixed", "exact", 0.0, "kg.m2"),
    "r_Cx": ("parameter", "fixed", "exact", 0.0, "m"),
    "r_Cy": ("parameter", "fixed", "exact", 0.0, "m"),
    "r_Cz": ("parameter", "fixed", "exact", 0.0, "m"),
    "g": ("parameter", "fixed", "exact", 9.81, "m/s2"),
    "tau_x": ("input", "continuous", None, 0.0, "N.m"),
    "tau_y": ("input", "continuous", None, 0.0, "N.m"),
    "tau_z": ("input", "continuous", None, 0.0, "N.m"),
    "w_x": ("output", "continuous", "exact", 0.01, "rad/s"),
    "w_y": ("output", "continuous", "exact", 5.0, "rad/s"),
    "w_z": ("output", "continuous", "exact", 0.01, "rad/s"),
    "q_w": ("output", "continuous", "exact", 1.0, "1"),
    "q_x": ("output", "continuous", "exact", 0.0, "1"),
    "q_y": ("output", "continuous", "exact", 0.0, "1"),
    "q_z": ("output", "continuous", "exact", 0.0, "1"),
    "H_X": ("output", "continuous", "calculated", None, "kg.m2/s"),
    "H_Y": ("output", "continuous", "calculated", None, "kg.m2/s"),
    "H_Z": ("output", "continuous", "calculated", None, "kg.m2/s"),
    "E_kin": ("output", "continuous", "calculated", None, "J"),
    "E_pot": ("output", "continuous", "calculated", None, "J"),
    "I_1": ("calculatedParameter", CALCULATED, "calculated", None, "kg.m2"),
    "I_2": ("calculatedParameter", CALCULATED, "calculated", None, "kg.m2"),
    "I_3": ("calculatedParameter", CALCULATED, "calculated", None, "kg.m2"),
}

#: declared with min="0" (the mass and the principal moments of the box must be > 0)
MIN_ZERO = ["M", "I_xx", "I_yy", "I_zz"]

#: the FMI 3.0 arrays (docs/mechanisms/README.md, "FMI 3.0, arrays"): the FMI 2.0 scalar at each
#: element, row-major (tests/python/test_fmi3.py; a mechanism without arrays leaves this out)
ARRAYS = {
    "I_C": "I_xx I_xy I_xz I_xy I_yy I_yz I_xz I_yz I_zz",
    "r_C": "r_Cx r_Cy r_Cz",
    "tau": "tau_x tau_y tau_z",
    "w": "w_x w_y w_z",
    "q": "q_w q_x q_y q_z",
    "H": "H_X H_Y H_Z",
    "w_dot": "w_x_dot w_y_dot w_z_dot",
    "q_dot": "q_w_dot q_x_dot q_y_dot q_z_dot",
    "I_principal": "I_1 I_2 I_3",
}
