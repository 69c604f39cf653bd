"""Reference for the `ControlledCrane` system: `CraneDynamics` with its drive force and torque
given at every instant by the `CraneController`'s law (the two references' equations, solved
together: the monolithic solution a co-simulation of the system approaches as its step
shrinks)."""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp

from . import crane_controller, crane_dynamics
from ._common import merge

STATES = crane_dynamics.STATES


def simulate(controller=None, crane=None, t_out=None, rtol=1e-11, atol=1e-11) -> dict:
    """The crane's states at ``t_out`` (default: 0 to 30 s every 0.01 s), from rest at the
    crane's start, with the controller's and the crane's parameters (defaults overridden)."""
    pc = merge(crane_controller.PARAMS, controller, "controller parameter")
    pd = merge(crane_dynamics.PARAMS, crane, "crane parameter")
    t_out = np.linspace(0.0, 30.0, 3001) if t_out is None else np.asarray(t_out)
    y0 = [crane_dynamics.START[s] for s in STATES]

    def rhs(t, y):
        u = crane_controller.drives(pc, {"x": y[0], "x_dot": y[1], "theta": y[2], "theta_dot": y[3],
                                         "phi_dot": y[5]})
        return crane_dynamics.rhs(t, y, pd, u)

    sol = solve_ivp(rhs, (t_out[0], t_out[-1]), y0, method="DOP853", t_eval=t_out, rtol=rtol, atol=atol)
    if not sol.success:
        raise RuntimeError(sol.message)
    return {"time": sol.t, **{s: sol.y[i] for i, s in enumerate(STATES)}}
