"""Independent Python references for the mechfmu mechanisms (see docs/derivations.md).

Each module is written from the equations of docs/mechanisms/README.md as re-derived in
docs/derivations.md, never from the Rust sources. Every module has:

* ``PARAMS`` / ``START`` / ``INPUTS``: the contract's defaults under the contract's names;
* ``rhs(t, y, p, u)``: the state derivative (``p`` and ``u`` are dicts keyed by contract names);
* ``simulate(p=None, y0=None, t_out=None, inputs=None, rtol=1e-12, atol=1e-12)``: DOP853 with
  zero-order-hold inputs given as an fmpy-style structured array, returning a dict
  name -> array at t_out for every state, output, input and calculated parameter;
* closed forms where they exist.

``derive`` holds the sympy derivations (Lagrange and Newton-Euler) used to cross-check them.
"""

from . import (oscillator, two_mass, pendulum_cart, crane, crane_dynamics, rigid_body, double_pendulum_cart,  # noqa: F401
               spring_damper, crane_controller)
from ._common import solution, split, step_input  # noqa: F401

__all__ = ["oscillator", "two_mass", "pendulum_cart", "crane", "crane_dynamics", "rigid_body",
           "double_pendulum_cart", "spring_damper", "crane_controller", "solution", "split", "step_input"]
