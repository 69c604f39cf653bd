"""Reference cases of `TwoMassOscillator` (docs/mechanisms/TwoMassOscillator.md):

    m1 x1'' + (c1+c3) x1' - c3 x2' + (k1+k3) x1 - k3 x2 = F1
    m2 x2'' + (c2+c3) x2' - c3 x1' + (k2+k3) x2 - k3 x1 = F2

References (tests/python/refs/two_mass.py): the closed-form frequencies and mode shapes of
det(K - w^2 M) = 0; a start on a mode shape stays a pure cosine at that mode's frequency;
DOP853 (rtol = atol = 1e-12) for the default experiment and for damped, forced motion.
"""

import numpy as np

from mechfmu_validate.case import Case, step_input
from refs import two_mass as tm, split

STOP = 30.0
H = 0.01
STATES = ["x1", "x2", "x1_dot", "x2_dot"]
ALL = [*STATES, "x1_ddot", "x2_ddot", "E"]
MODES = ["omega_n1", "omega_n2", "mode1_x1", "mode1_x2", "mode2_x1", "mode2_x2"]


def energy(r, p):
    """Kinetic energy of the masses plus the energy in the three springs."""
    q = tm.params(**p)
    x1, x2, v1, v2 = (r[n] for n in STATES)
    return (0.5 * q["m1"] * v1 ** 2 + 0.5 * q["m2"] * v2 ** 2 + 0.5 * q["k1"] * x1 ** 2
            + 0.5 * q["k2"] * x2 ** 2 + 0.5 * q["k3"] * (x2 - x1) ** 2)


def numerical(start_values, inputs=None):
    p, y0 = split(tm, start_values)

    def reference(t):
        r = tm.simulate(p, y0, t, inputs, switch_outputs="before")
        r["E"] = energy(r, p)
        return r
    return reference


def energy_exact(start_values):
    """DOP853 for the motion, and E at its exact constant value, from the start values (a
    solver's round-off in a constant would leave FMPy's cross-check criterion a band of 10 %
    of itself)."""
    p, y0 = split(tm, start_values)
    E0 = energy({**tm.START, **y0}, p)
    motion = numerical(start_values)
    return lambda t: {**motion(t), "E": np.full_like(t, E0)}


def modal(start_values, mode, amplitude):
    p, _ = split(tm, start_values)

    def reference(t):
        x1, x2 = tm.modal_response(p, mode, amplitude, t)
        md = tm.modes(p)
        w = md[f"omega_n{mode}"]
        a = np.array([md[f"mode{mode}_x1"], md[f"mode{mode}_x2"]]) * amplitude
        v1, v2 = -w * a[0] * np.sin(w * t), -w * a[1] * np.sin(w * t)
        return {"x1": x1, "x2": x2, "x1_dot": v1, "x2_dot": v2,
                "E": energy({"x1": x1, "x2": x2, "x1_dot": v1, "x2_dot": v2}, p),
                **{k: np.full_like(t, v) for k, v in md.items()}}
    return reference


def on_mode(p, mode, amplitude):
    md = tm.modes(p)
    return {**p, "x1": amplitude * md[f"mode{mode}_x1"], "x2": amplitude * md[f"mode{mode}_x2"],
            "x1_dot": 0.0, "x2_dot": 0.0}


UNEQUAL = {"m1": 1.0, "m2": 2.0, "k1": 1.0, "k2": 2.0, "k3": 0.5}
DAMPED = {"c1": 0.2, "c2": 0.1, "c3": 0.3}
SWITCHES = [0.0, 3.0, 7.5, 12.0, 20.0]
FORCES = [(0.0, 0.0), (1.0, 0.0), (1.0, -2.0), (-0.5, 0.7), (0.0, 0.0)]

CASES = [
    Case("default_experiment",
         description="The DefaultExperiment (x1 = 1, both masses at rest, no damping) against DOP853 "
                     "(rtol = atol = 1e-12); E (kinetic + springs) at its exact constant value.",
         stop_time=STOP, output_interval=H, relative_tolerance=None, outputs=ALL,
         reference=energy_exact({}), tolerance=1e-6, default_experiment=True),
    Case("mode1_unequal_masses",
         description="Start on mode 1 of m1 = 1, m2 = 2, k1 = 1, k2 = 2, k3 = 0.5 (shape and frequency from the "
                     "closed form of det(K - w^2 M) = 0): stays a pure cosine at omega_n1; the calculated "
                     "frequencies and shapes equal the closed form.",
         start_values=on_mode(UNEQUAL, 1, 0.5), stop_time=STOP, output_interval=H, relative_tolerance=1e-8,
         outputs=[*STATES, *MODES], reference=modal(UNEQUAL, 1, 0.5), tolerance=1e-6),
    Case("mode2_symmetric",
         description="Start on mode 2 of the symmetric default (m1 = m2, k1 = k2 = k3): the 1 : -1 mode at "
                     "sqrt(3 k / m), a pure cosine.",
         start_values=on_mode({}, 2, 0.3), stop_time=STOP, output_interval=H, relative_tolerance=1e-8,
         outputs=[*STATES, *MODES], reference=modal({}, 2, 0.3), tolerance=1e-6),
    Case("damped_forced",
         description="Dampers c1 = 0.2, c2 = 0.1, c3 = 0.3 and step forces F1, F2 switching at 3, 7.5, 12 and "
                     "20 s, against DOP853 restarted at every switch.",
         start_values={**DAMPED, "x1": 0.2, "x2": -0.1},
         input=step_input(["F1", "F2"], SWITCHES, FORCES, STOP), stop_time=STOP, output_interval=H,
         relative_tolerance=1e-8, outputs=ALL,
         reference=numerical({**DAMPED, "x1": 0.2, "x2": -0.1}, step_input(["F1", "F2"], SWITCHES, FORCES, STOP)),
         tolerance=1e-6),
]
