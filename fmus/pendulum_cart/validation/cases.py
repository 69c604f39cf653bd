"""Reference cases of `PendulumCart` (docs/mechanisms/PendulumCart.md):

    (M+m) x'' + c1 x' + k x + m l (th'' cos th - th'^2 sin th) = F
    m l x'' cos th + 7/3 m l^2 th'' + c2 th' + m g l sin th    = 3 F l cos th
    F_N = (M+m) g + m l (th'' sin th + th'^2 cos th)
    E   = 1/2 (M+m) x'^2 + m l x' th' cos th + 7/6 m l^2 th'^2 + 1/2 k x^2 - m g l cos th

References (tests/python/refs/pendulum_cart.py): DOP853 (rtol = atol = 1e-12); E constant
without damping and force; small oscillations follow the linearized modes (mass matrix
[[M+m, m l], [m l, 7/3 m l^2]], stiffness diag(k, m g l)), whose frequencies are the
calculated omega_n1, omega_n2.
"""

import numpy as np
from scipy.linalg import eigh

from mechfmu_validate.case import Case, step_input
from refs import pendulum_cart as pc, split, solution

STATES = ["x", "x_dot", "theta", "theta_dot"]
ALL = [*STATES, "x_ddot", "theta_ddot", "F_N", "E"]


def numerical(start_values, inputs=None):
    return solution(pc, start_values, inputs)


def constant_energy(start_values):
    """E(t) = E(0), computed from the start values alone."""
    p, y0 = split(pc, start_values)
    s = {**pc.START, **y0}
    E0 = pc.energy([s[n] for n in STATES], pc.params(**p))
    return lambda t: {"E": np.full_like(t, E0)}


def energy_exact(start_values):
    """DOP853 for the motion, and E at its exact constant value (a solver's round-off in a
    constant would leave FMPy's cross-check criterion a band of 10 % of itself)."""
    motion, energy = numerical(start_values), constant_energy(start_values)
    return lambda t: {**motion(t), **energy(t)}


def linearized(start_values):
    """q(t) = V diag(cos w t) V^T M q(0) for a start from rest (V: M-orthonormal modes of
    K a = w^2 M a), and the frequencies from det(K - w^2 M) = 0 written out."""
    p, y0 = split(pc, start_values)
    Mm, _, K = pc.linear_matrices(p)
    w2, V = eigh(K, Mm)
    w = np.sqrt(w2)
    s = {**pc.START, **y0}
    q0 = np.array([s["x"], s["theta"]])
    c = V.T @ Mm @ q0
    closed = pc.calculated_closed_form(p)

    def reference(t):
        q = V @ (c[:, None] * np.cos(np.outer(w, t)))
        qd = V @ (-(c * w)[:, None] * np.sin(np.outer(w, t)))
        return {"x": q[0], "theta": q[1], "x_dot": qd[0], "theta_dot": qd[1],
                "omega_n1": np.full_like(t, closed["omega_n1"]), "omega_n2": np.full_like(t, closed["omega_n2"])}
    return reference


SMALL = {"x": 2e-4, "theta": 1e-3}
LARGE = {"theta": 1.2, "x_dot": 0.3}
BAL = {"c1": 0.5, "c2": 0.02, "theta": 0.8, "x_dot": 0.3}
BAL_INPUT = step_input(["F"], [0.0, 1.0, 4.0, 7.0], [[0.8], [-1.2], [2.0], [0.0]], 10.0)

CASES = [
    Case("default_experiment",
         description="The DefaultExperiment (rod released at theta = 0.3 rad, no damping, no force) against "
                     "DOP853 (rtol = atol = 1e-12): states, accelerations, normal force, and the energy at its "
                     "exact constant value.",
         stop_time=10.0, output_interval=0.01, relative_tolerance=None, outputs=ALL,
         reference=energy_exact({}), tolerance=1e-6, default_experiment=True),
    Case("energy_conserved",
         description="A large swing (theta0 = 1.2 rad, x_dot0 = 0.3 m/s), no damping, no force, 20 s at "
                     "relative tolerance 1e-10: the drift of E relative to |E(0)| (E(0) from the start values).",
         start_values=LARGE, stop_time=20.0, output_interval=0.01, relative_tolerance=1e-10,
         outputs=["E"], reference=constant_energy(LARGE), tolerance=1e-8,
         record=["x", "theta"], plot=["theta", "x", "E"]),
    Case("damped_forced",
         description="Dashpot c1 = 0.5, pin damping c2 = 0.02 and a step force F at D (switching at 1, 4, 7 s): "
                     "DOP853 restarted at every switch; E then follows dE/dt = F (x' + 3 l th' cos th) - c1 x'^2 "
                     "- c2 th'^2.",
         start_values=BAL, input=BAL_INPUT, stop_time=10.0, output_interval=0.01, relative_tolerance=1e-8,
         outputs=ALL, reference=numerical(BAL, BAL_INPUT), tolerance=1e-6),
    Case("small_oscillations",
         description="Released from rest at x = 0.2 mm, theta = 1 mrad: the motion is the sum of the two "
                     "linearized modes (closed form), and the calculated omega_n1, omega_n2 are the closed-form "
                     "frequencies. The tolerance covers the neglected nonlinearity (~theta0^2).",
         start_values=SMALL, stop_time=10.0, output_interval=0.01, relative_tolerance=1e-10,
         outputs=[*STATES, "omega_n1", "omega_n2"], reference=linearized(SMALL),
         tolerance={"*": 1e-5, "omega_n1": 1e-12, "omega_n2": 1e-12}),
]
