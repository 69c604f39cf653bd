"""Reference cases of `RigidBody` (docs/mechanisms/RigidBody.md): a rigid body turning
about a fixed pivot B,

    I_B w' + w x (I_B w) = tau + r_C x (R^T (-M g Z)),   q' = 1/2 q (x) (0, w)

References (tests/python/refs/rigid_body.py): DOP853 (rtol = atol = 1e-12) for the default
spin near the intermediate axis (it flips); torque-free, H (ground axes) and E_kin constant
and |q| = 1; a body symmetric about z: (w_x, w_y) turns at (I_3 - I_1)/I_1 w_z (closed
form); with gravity (a heavy top), H_Z and E_kin + E_pot constant.
"""

import math

import numpy as np

from mechfmu_validate.case import Case
from refs import rigid_body as rb, split

W = ["w_x", "w_y", "w_z"]
Q = ["q_w", "q_x", "q_y", "q_z"]
H = ["H_X", "H_Y", "H_Z"]
CONTRACT = [*W, *Q, *H, "E_kin", "E_pot"]


def numerical(start_values):
    p, y0 = split(rb, start_values)
    return lambda t: rb.simulate(p, y0, t)


def q_norm(r):
    return np.sqrt(sum(r[n] ** 2 for n in Q))


def initial_outputs(start_values):
    p, y0 = split(rb, start_values)
    s = {**rb.START, **y0}
    return rb.outputs_of([s[n] for n in rb.STATES], rb.params(**p))


def torque_free_invariants(start_values):
    """H (ground axes), E_kin and |q| keep their initial values (computed from the start values)."""
    o = initial_outputs(start_values)

    def reference(t):
        c = lambda v: np.full_like(t, v)  # noqa: E731
        return {**{n: c(o[n]) for n in H}, "E_kin": c(o["E_kin"]), "|q|": c(1.0)}
    return reference


def invariants_exact(start_values):
    """DOP853 for the motion, and the torque-free invariants H and E_kin at their exact values
    (a solver's round-off in a constant would leave FMPy's cross-check criterion a band of
    10 % of itself)."""
    motion, invariants = numerical(start_values), torque_free_invariants(start_values)
    return lambda t: {**motion(t), **{n: v for n, v in invariants(t).items() if n in [*H, "E_kin"]}}


def heavy_top_invariants(start_values):
    o = initial_outputs(start_values)
    return lambda t: {"H_Z": np.full_like(t, o["H_Z"]), "E": np.full_like(t, o["E_kin"] + o["E_pot"])}


def axisymmetric(start_values):
    p, y0 = split(rb, start_values)
    w0 = [y0[n] for n in W]

    def reference(t):
        wx, wy, wz = rb.torque_free_axisymmetric(rb.params(**p), w0, t)
        return {"w_x": wx, "w_y": wy, "w_z": wz}
    return reference


GENERAL = {"I_xx": 0.02, "I_yy": 0.035, "I_zz": 0.041, "I_xy": -0.003, "I_xz": 0.002, "I_yz": 0.004,
           "w_x": 1.5, "w_y": -2.0, "w_z": 3.0, "q_w": math.cos(0.3), "q_x": math.sin(0.3), "q_y": 0.0, "q_z": 0.0}
H0 = float(np.linalg.norm([initial_outputs(GENERAL)[n] for n in H]))
H_DEFAULT = float(np.linalg.norm([initial_outputs({})[n] for n in H]))
SYMMETRIC = {"I_xx": 0.02, "I_yy": 0.02, "I_zz": 0.035, "w_x": 0.8, "w_y": 0.0, "w_z": 6.0}
TOP = {"M": 1.0, "I_xx": 0.002, "I_yy": 0.002, "I_zz": 0.003, "r_Cz": 0.05,
       "q_w": math.cos(0.25), "q_x": math.sin(0.25), "q_y": 0.0, "q_z": 0.0, "w_x": 0.0, "w_y": 0.0, "w_z": 40.0}

# the reference files' columns: the states, and the invariants FMPy's cross-check criterion can
# hold an importer to. H_X and H_Z are near 1e-3 of |H|: a band of 10 % of their own value is
# narrower than an importer's error in H at a tolerance a little looser than the files' RelTol
# (FMPy's CVode at 1e-5 leaves it)
REFERENCE_FILES = [*W, *Q, "H_Y", "E_kin"]

CASES = [
    Case("default_experiment",
         description="The DefaultExperiment: a 0.3 x 0.2 x 0.1 m box spun at 5 rad/s about its intermediate axis "
                     "(with 0.01 rad/s about the others): the spin is unstable and the box flips over and back "
                     "every few seconds (the Dzhanibekov effect), against DOP853; H and E_kin at their exact "
                     "constant values, H scaled by |H(0)|.",
         stop_time=20.0, output_interval=0.01, relative_tolerance=None, outputs=CONTRACT,
         reference=invariants_exact({}), scale={n: H_DEFAULT for n in H}, tolerance=1e-6, default_experiment=True,
         reference_files=REFERENCE_FILES, plot=[*W, *Q], highlight="rigid-body-flip"),
    Case("torque_free_invariants",
         description="A general body (products of inertia, tilted start) spinning freely: H in ground axes, E_kin "
                     "and |q| keep their initial values (relative drift; H scaled by |H(0)|), rtol 1e-10.",
         start_values=GENERAL, stop_time=20.0, output_interval=0.01, relative_tolerance=1e-10,
         outputs=[*H, "E_kin"], record=[*Q, *W], derived={"|q|": q_norm}, plot=[*W, *H, "E_kin"],
         reference=torque_free_invariants(GENERAL), scale={n: H0 for n in H}, tolerance=1e-8),
    Case("axisymmetric_precession",
         description="A body symmetric about z (I_xx = I_yy): w_z constant and (w_x, w_y) turning at "
                     "(I_3 - I_1)/I_1 w_z (closed form).",
         start_values=SYMMETRIC, stop_time=20.0, output_interval=0.01, relative_tolerance=1e-8,
         outputs=W, reference=axisymmetric(SYMMETRIC), scale={n: 0.8 for n in W}, tolerance=1e-6),
    Case("heavy_top",
         description="A top (r_C = 5 cm on its axis) tilted by 0.5 rad and spun at 40 rad/s under gravity: it "
                     "precesses and nutates; H_Z (the weight's moment is horizontal) and E_kin + E_pot stay "
                     "constant, rtol 1e-10.",
         start_values=TOP, stop_time=20.0, output_interval=0.01, relative_tolerance=1e-10,
         outputs=["H_Z", "E"], reference=heavy_top_invariants(TOP), tolerance=1e-8,
         record=["r_CX", "r_CY", "r_CZ"], plot=["r_CX", "r_CY", "r_CZ", "H_Z", "E"]),
]
