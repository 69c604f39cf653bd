"""Reference cases of the `ControlledCrane` system compiled into one FMU (docs/systems.md):
`CraneDynamics` driven at every instant by the `CraneController`'s law, integrated together.
The reference solves the two references' equations together (tests/python/refs/
controlled_crane.py: DOP853, rtol = atol = 1e-11), the drive force and torque from the
controller's law at the reference's states.
"""

import numpy as np

from mechfmu_validate.case import Case
from refs import controlled_crane as cc, crane_controller

STOP = 30.0
H = 0.01
STATES = ["x", "x_dot", "theta", "theta_dot", "phi", "phi_dot"]
OUTPUTS = [*(f"crane.{s}" for s in STATES), "controller.F", "controller.tau"]


def reference(controller=None, crane=None):
    """The crane's states and the controller's drives, with the controller's and the crane's
    parameters (the components' defaults overridden)."""
    pc = {**crane_controller.PARAMS, **(controller or {})}

    def at(t):
        r = cc.simulate(controller=controller, crane=crane, t_out=t)
        drives = [crane_controller.drives(pc, {"x": r["x"][i], "x_dot": r["x_dot"][i], "theta": r["theta"][i],
                                               "theta_dot": r["theta_dot"][i], "phi_dot": r["phi_dot"][i]})
                  for i in range(len(t))]
        return {**{f"crane.{s}": r[s] for s in STATES},
                "controller.F": np.array([d["F"] for d in drives]),
                "controller.tau": np.array([d["tau"] for d in drives])}
    return at


REACH = {"x_ref": 15.0, "theta_ref": 0.3}
HEAVY = {"m": 1500.0}

CASES = [
    Case("default_experiment",
         description="The DefaultExperiment with the `default` parameter set: the crane at rest at x = 10 m, "
                     "theta = 0.5 rad, moved to 12 m and 0.6 rad, against the closed loop solved by DOP853.",
         stop_time=STOP, output_interval=H, relative_tolerance=None, outputs=OUTPUTS, reference=reference(),
         tolerance=1e-6, default_experiment=True),
    Case("reach",
         description="The `reach` parameter set (controller.x_ref = 15 m, controller.theta_ref = 0.3 rad).",
         start_values={f"controller.{n}": v for n, v in REACH.items()}, stop_time=STOP, output_interval=H,
         relative_tolerance=1e-8, outputs=OUTPUTS, reference=reference(controller=REACH), tolerance=1e-6),
    Case("heavy_payload",
         description="A payload of 1500 kg, which the controller's feed-forward knows (crane.m = "
                     "controller.m = 1500).",
         start_values={"crane.m": 1500.0, "controller.m": 1500.0}, stop_time=STOP, output_interval=H,
         relative_tolerance=1e-8, outputs=OUTPUTS, reference=reference(controller=HEAVY, crane=HEAVY),
         tolerance=1e-6),
]
