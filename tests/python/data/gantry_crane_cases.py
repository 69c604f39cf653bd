"""Reference cases of the tutorial's GantryCrane (a user's own crate, declared from its
energies): its two drives, each against the mechanics written out."""

import numpy as np

from mechfmu_validate.case import Case

# the FMU's variables these cases use
X, L, PHI = "x", "l", "phi"
TROLLEY_ACCELERATION, HOIST_ACCELERATION = "x_ddot", "l_ddot"
TROLLEY_FORCE, TENSION = "F_trolley", "T_cable"

M, MP, G, L0 = 500.0, 1000.0, 9.81, 5.0  # the FMU's defaults: trolley, payload, gravity, cable

A = 0.1  # the trolley's acceleration
G_EFF = np.hypot(G, A)  # gravity in the trolley's frame, tilted by PHI_E
PHI_E = -np.arctan(A / G)


def trolley_starts(t):
    """The trolley accelerates at A from rest: x = A t²/2. In its frame the payload hangs in
    gravity G_EFF, tilted to PHI_E: a pendulum released at rest |PHI_E| from its equilibrium,
    at sqrt(G_EFF / l) slowed by the amplitude (1 - PHI_E²/16). Along the cable, Newton's law
    gives the tension; along the rail, on the trolley, the drive's force."""
    w = np.sqrt(G_EFF / L0) * (1.0 - PHI_E**2 / 16.0)
    phi = PHI_E * (1.0 - np.cos(w * t))
    phi_dot = PHI_E * w * np.sin(w * t)
    tension = MP * (G_EFF * np.cos(phi - PHI_E) + L0 * phi_dot**2)
    return {X: 0.5 * A * t**2, PHI: phi, TENSION: tension, TROLLEY_FORCE: M * A - tension * np.sin(phi)}


LIFT = -0.2  # the cable's length accelerates at this: the winch lifts the payload


def hoisting(t):
    """The winch lifts the hanging payload at constant acceleration: l = l0 + LIFT t²/2, and
    the cable holds its weight plus m |LIFT|."""
    return {L: L0 + 0.5 * LIFT * t**2, TENSION: np.full_like(t, MP * (G - LIFT))}


CASES = [
    Case("trolley_starts", description="The trolley accelerates from rest; the payload swings behind it.",
         start_values={TROLLEY_ACCELERATION: A}, stop_time=10.0, output_interval=0.01, relative_tolerance=1e-10,
         outputs=[X, PHI, TENSION, TROLLEY_FORCE], reference=trolley_starts, tolerance=1e-5),
    Case("hoisting", description="The winch lifts the payload at constant acceleration.",
         start_values={HOIST_ACCELERATION: LIFT}, stop_time=5.0, output_interval=0.01, relative_tolerance=1e-10,
         outputs=[L, TENSION], reference=hoisting, tolerance=1e-9),
]
