"""Symbolic derivations (sympy) of the equations of motion by two independent routes.

* Lagrange: T and V from the positions of the bodies, generalized forces from the virtual
  work of the non-conservative forces and couples, d/dt(dL/dq') - dL/dq = Xi.
* Newton-Euler: free-body diagrams of every body with the reaction forces as unknowns,
  accelerations from differentiating the position vectors twice (not from the notes'
  rotating-frame formulas), solved as one linear system.

Nothing here reuses the equations written in the other reference modules; the functions
return lambdified callables so a test can evaluate both routes at random states and
compare them with each other, with the reference modules and with the FMUs' outputs.

Callables take a state tuple/array (the contract's state order), a parameter dict and an
input dict (contract names) and return numpy arrays / dicts. Derivations are cached.

One module per mechanism; the helpers both routes share are in ``_sympy``.
"""

from __future__ import annotations

from .pendulum_cart import pendulum_cart_lagrange, pendulum_cart_newton_euler, pendulum_cart_symbolic
from .crane import crane_lagrange, crane_newton_euler
from .crane_dynamics import crane_dynamics_lagrange, crane_dynamics_newton_euler, crane_dynamics_symbolic
from .rigid_body import rigid_body_lagrange, rigid_body_quaternion_rate
from .double_pendulum_cart import (double_pendulum_cart_lagrange, double_pendulum_cart_newton_euler,
                                   double_pendulum_cart_symbolic)

__all__ = [
    "pendulum_cart_lagrange", "pendulum_cart_newton_euler", "pendulum_cart_symbolic",
    "crane_lagrange", "crane_newton_euler",
    "crane_dynamics_lagrange", "crane_dynamics_newton_euler", "crane_dynamics_symbolic",
    "rigid_body_lagrange", "rigid_body_quaternion_rate",
    "double_pendulum_cart_symbolic", "double_pendulum_cart_lagrange", "double_pendulum_cart_newton_euler",
]
