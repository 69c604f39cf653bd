"""Reference cases of `Crane` (docs/mechanisms/Crane.md): boom and trolley massless,
their motion prescribed by the inputs x_ddot and theta_ddot; with s = theta - phi,

    l phi'' = -g sin phi - (x'' - th'^2 x) cos s + (2 th' x' + th'' x) sin s
    T = m [(x'' - th'^2 x) sin s + (2 th' x' + th'' x) cos s + l phi'^2 + g cos phi]
    F = T sin s,  tau = x T cos s

References (tests/python/refs/crane.py): with the drives still, the exact large-amplitude
pendulum (Jacobi elliptic functions, period 4 sqrt(l/g) K(sin(phi0/2))) and a constant
payload energy; with the drives moving, DOP853 (rtol = atol = 1e-12), the work of F and tau
equal to the payload's gain of energy, and T = sqrt(F^2 + (tau/x)^2).
"""

import math

import numpy as np

from mechfmu_validate.case import Case, step_input
from refs import crane as cr, split, solution

STATES = ["x", "x_dot", "theta", "theta_dot", "phi", "phi_dot"]
CONTRACT = [*STATES, "T", "F", "tau", "payload_x", "payload_y"]


def numerical(start_values, inputs=None):
    return solution(cr, start_values, inputs)


def still_swing(start_values, phi0):
    """Drives still: phi(t) exact (elliptic functions); T, F, tau, the payload's position and
    energy follow from phi, phi_dot and the fixed x, theta."""
    p, y0 = split(cr, start_values)
    q = cr.params(**p)
    s = {**cr.START, **y0}
    x, th = s["x"], s["theta"]

    def reference(t):
        phi, phid = cr.pendulum(p, phi0, t)
        T = q["m"] * (q["g"] * np.cos(phi) + q["l"] * phid ** 2)
        E0 = q["m"] * q["g"] * (x * math.sin(th) - q["l"] * math.cos(phi0))
        return {"x": np.full_like(t, x), "x_dot": np.zeros_like(t), "theta": np.full_like(t, th),
                "theta_dot": np.zeros_like(t), "phi": phi, "phi_dot": phid, "T": T,
                "F": T * np.sin(th - phi), "tau": x * T * np.cos(th - phi),
                "payload_x": x * math.cos(th) + q["l"] * np.sin(phi),
                "payload_y": x * math.sin(th) - q["l"] * np.cos(phi),
                "E_payload": np.full_like(t, E0)}
    return reference


def drive_identities(r):
    """Errors of two identities among the outputs: the tension is the resultant of the drive
    loads, T = sqrt(F^2 + (tau/x)^2), relative to max |T|; the work of the drives equals the
    payload's gain of energy, relative to the largest of max |W| and the range of E."""
    T, F, tau, x = r["T"], r["F"], r["tau"], r["x"]
    E, W = r["E_payload"], r["W_drives"]
    scale_e = max(np.max(np.abs(W)), np.ptp(E))
    return {"T = sqrt(F^2 + (tau/x)^2)": np.abs(np.abs(T) - np.hypot(F, tau / x)) / np.max(np.abs(T)),
            "E_payload - E_payload(0) = W_drives": np.abs(E - E[0] - W) / scale_e}


PHI0 = math.radians(60.0)
SWING = {"phi": PHI0}
MOVING_TIMES = [0.0, 1.0, 2.5, 4.0, 6.0, 7.5, 9.0, 11.0, 13.0, 14.5, 16.0]
MOVING_VALUES = [[0.5, 0.0], [0.5, 0.04], [0.0, 0.04], [-0.5, 0.0], [0.0, -0.04], [0.0, 0.0],
                 [-0.3, -0.03], [0.3, 0.03], [0.4, 0.0], [0.0, 0.02], [-0.2, -0.02]]
MOVING_INPUT = step_input(["x_ddot", "theta_ddot"], MOVING_TIMES, MOVING_VALUES, 20.0)
MOVING_START = {"x_dot": 0.2, "theta_dot": -0.02, "phi": 0.1}
# from the DefaultExperiment's rest: the trolley out 10 -> 13 m and back, the boom luffed
# 0.5 -> 0.7 rad and back, then the drives still while the payload swings on
FROM_REST_TIMES = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 8.0, 10.0, 11.0, 12.0, 13.0, 14.0, 16.0]
FROM_REST_VALUES = [[0.0, 0.0], [0.5, 0.0], [0.5, 0.05], [0.0, 0.05], [-0.5, -0.05], [-0.5, -0.05], [0.0, 0.0],
                    [-0.5, 0.0], [0.0, 0.0], [0.5, 0.0], [0.5, -0.05], [0.0, -0.05], [0.0, 0.05], [0.0, 0.0]]
FROM_REST_INPUT = step_input(["x_ddot", "theta_ddot"], FROM_REST_TIMES, FROM_REST_VALUES, 20.0)

CASES = [
    Case("default_experiment",
         description="The DefaultExperiment: drives still, payload hanging at rest (T = m g, F = m g sin theta, "
                     "tau = x m g cos theta), against DOP853.",
         stop_time=20.0, output_interval=0.01, relative_tolerance=None, outputs=CONTRACT,
         reference=numerical({}), tolerance=1e-6, default_experiment=True),
    Case("swing_60deg",
         description="Drives still, payload released at phi0 = 60 deg: the exact pendulum (Jacobi elliptic "
                     "functions; period 4 sqrt(l/g) K(sin 30 deg) = 4.82 s, 7 % longer than the small-angle "
                     "one), the loads it puts on the drives, and the payload's constant energy.",
         start_values=SWING, stop_time=20.0, output_interval=0.01, relative_tolerance=1e-8,
         outputs=[*CONTRACT, "E_payload"], reference=still_swing(SWING, PHI0), tolerance=1e-6,
         plot=["phi", "payload_x", "payload_y", "T", "F"], highlight="crane-swing"),
    Case("moving_drives",
         description="Trolley and boom accelerations switching 10 times (trolley 10 -> 12 m, boom swinging by "
                     "0.1 rad): DOP853 restarted at every switch; the drives' work equals the payload's gain of "
                     "energy and T = sqrt(F^2 + (tau/x)^2) at every point.",
         start_values=MOVING_START, input=MOVING_INPUT, stop_time=20.0, output_interval=0.01,
         relative_tolerance=1e-8, outputs=[*CONTRACT, "E_payload", "W_drives"],
         reference=numerical(MOVING_START, MOVING_INPUT), metric=drive_identities,
         plot=["x", "payload_x", "payload_y", "theta", "phi", "T", "F"],
         tolerance={"*": 1e-6, "T = sqrt(F^2 + (tau/x)^2)": 1e-10}),
    Case("driven_from_rest",
         description="From the DefaultExperiment's rest, the drives alone move the crane: the trolley out "
                     "10 -> 13 m and back (x_ddot = +-0.5 m/s2), the boom luffed 0.5 -> 0.7 rad and back "
                     "(theta_ddot = +-0.05 rad/s2); the payload swings up to 0.23 rad and swings on after the "
                     "drives stop at 16 s. DOP853 restarted at every switch; the drives' work equals the "
                     "payload's gain of energy.",
         input=FROM_REST_INPUT, stop_time=20.0, output_interval=0.01, relative_tolerance=1e-8,
         outputs=[*CONTRACT, "E_payload", "W_drives"], reference=numerical({}, FROM_REST_INPUT),
         metric=drive_identities, tolerance={"*": 1e-6, "T = sqrt(F^2 + (tau/x)^2)": 1e-10},
         reference_files=[*STATES, "T", "F", "tau", "payload_x"]),
]
