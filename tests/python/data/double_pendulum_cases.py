"""Reference cases of the tutorial's DoublePendulum (a user's own crate)."""

import numpy as np

from mechfmu_validate.case import Case

G = 9.81
# Released at rest from theta1 = 2, theta2 = 1 (m1 = m2 = l1 = l2 = 1): E = V(0) forever.
E0 = -2.0 * G * np.cos(2.0) - G * np.cos(1.0)

CASES = [
    Case("energy_conserved", description="Chaotic swing from rest: the mechanical energy stays E(0).",
         stop_time=10.0, output_interval=0.01, relative_tolerance=1e-10, outputs=["E"],
         reference=lambda t: {"E": np.full_like(t, E0)}, tolerance=1e-8),
]
