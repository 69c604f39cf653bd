"""Reference cases of the `TwoOscillators` system compiled into one FMU (docs/systems.md):
two `Oscillator`s joined by a `SpringDamper`, integrated together. Its equations are
`TwoMassOscillator`'s (m1 = a.m, k1 = a.k, c1 = a.c, m2 = b.m, k2 = b.k, c2 = b.c,
k3 = spring.k, c3 = spring.c), so the references are TwoMassOscillator's
(tests/python/refs/two_mass.py: DOP853, rtol = atol = 1e-12), the spring's force and energy
from its formulas at the reference's positions and velocities.
"""

import numpy as np
from scipy.integrate import solve_ivp

from mechfmu_validate.case import Case
from refs import two_mass as tm

STOP = 30.0
H = 0.01
STATES = ["a.x", "b.x", "a.x_dot", "b.x_dot"]
ALL = [*STATES, "a.x_ddot", "b.x_ddot", "spring.F_a", "spring.F_b", "spring.E"]

#: the system's names of TwoMassOscillator's parameters and states
AS_TWO_MASS = {"a.m": "m1", "a.k": "k1", "a.c": "c1", "b.m": "m2", "b.k": "k2", "b.c": "c2",
               "spring.k": "k3", "spring.c": "c3", "a.x": "x1", "b.x": "x2", "a.x_dot": "x1_dot",
               "b.x_dot": "x2_dot"}
#: the system's `default` parameter set (TwoMassOscillator's defaults)
DEFAULT = {"a.m": 1.0, "a.k": 1.0, "a.c": 0.0, "b.m": 1.0, "b.k": 1.0, "b.c": 0.0, "spring.k": 1.0,
           "spring.c": 0.0, "a.x": 1.0, "b.x": 0.0}
#: the system's `damped` parameter set, over the default one
DAMPED = {"b.m": 2.0, "b.k": 0.5, "spring.k": 2.0, "a.c": 0.1, "b.c": 0.2, "spring.c": 0.05}


def reference(start_values, forcing=(0.0, 1.0)):
    """The system's variables from TwoMassOscillator's equations at the system's values (the
    default set's, then `start_values`), with a.F0 sin(a.omega t) pushing the first mass."""
    values = {**DEFAULT, **start_values}
    p = tm.params(**{AS_TWO_MASS[n]: v for n, v in values.items() if AS_TWO_MASS[n] in tm.PARAMS})
    y0 = [values.get(n, 0.0) for n in STATES]
    F0, omega = forcing

    def rhs(t, y):
        return tm.rhs(t, y, p, {"F1": F0 * np.sin(omega * t), "F2": 0.0})

    def at(t):
        sol = solve_ivp(rhs, (t[0], t[-1]), y0, method="DOP853", t_eval=t, rtol=1e-12, atol=1e-12)
        x1, x2, v1, v2 = sol.y
        d = np.array([rhs(ti, yi) for ti, yi in zip(t, sol.y.T)]).T
        force = p["k3"] * (x2 - x1) + p["c3"] * (v2 - v1)
        return {"a.x": x1, "b.x": x2, "a.x_dot": v1, "b.x_dot": v2, "a.x_ddot": d[2], "b.x_ddot": d[3],
                "spring.F_a": force, "spring.F_b": -force, "spring.E": 0.5 * p["k3"] * (x2 - x1) ** 2}
    return at


CASES = [
    Case("default_experiment",
         description="The DefaultExperiment with the `default` parameter set: TwoMassOscillator at its "
                     "defaults (the first mass displaced by 1 m, no damping) against DOP853.",
         stop_time=STOP, output_interval=H, relative_tolerance=None, outputs=ALL, reference=reference({}),
         tolerance=1e-6, default_experiment=True),
    Case("damped",
         description="The `damped` parameter set (b.m = 2, b.k = 0.5, spring.k = 2, a.c = 0.1, b.c = 0.2, "
                     "spring.c = 0.05) against DOP853.",
         start_values=DAMPED, stop_time=STOP, output_interval=H, relative_tolerance=1e-8, outputs=ALL,
         reference=reference(DAMPED), tolerance=1e-6),
    Case("forced_first_mass",
         description="The first oscillator's harmonic forcing (a.F0 = 0.5 N at a.omega = 1.3 rad/s) on the "
                     "damped system, from rest apart (a.x = 0.2, b.x = -0.4): the force reaches the second "
                     "mass through the spring only.",
         start_values={**DAMPED, "a.F0": 0.5, "a.omega": 1.3, "a.x": 0.2, "b.x": -0.4}, stop_time=STOP,
         output_interval=H, relative_tolerance=1e-8, outputs=ALL,
         reference=reference({**DAMPED, "a.x": 0.2, "b.x": -0.4}, forcing=(0.5, 1.3)), tolerance=1e-6),
]
