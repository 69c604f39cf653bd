"""Reference cases of `DoublePendulumCart` (docs/mechanisms/DoublePendulumCart.md): a cart M
(force F, drag c x'), a massless rod l1 to a point mass m1, a massless rod l2 from m1 to a
point mass m2, declared from

    T = 1/2 M x'^2 + 1/2 m1 |p1'|^2 + 1/2 m2 |p2'|^2,   V = g (m1 p1y + m2 p2y),   Q = (F - c x', 0, 0)

References (tests/python/refs/double_pendulum_cart.py): Newton's law for the cart, m1 and m2
separately (the rod tensions as unknowns, a linear system solved at each call), integrated
by DOP853 (rtol = atol = 1e-12); E = T + V and the horizontal momentum p_x constant without
F and c; otherwise dE/dt = F x' - c x'^2 and dp_x/dt = F - c x', integrated along the
FMU's own run.

How far a trajectory can be compared: a perturbation of the default start (phi1 = 1,
phi2 = 0.5 at rest) grows by less than 10 relative to each signal's range over 10 s, so the
DefaultExperiment is compared over all of it. From phi1 = 2, phi2 = 1 the lower rod
flips over and the motion is chaotic: a perturbation grows by 8 in 2 s, 300 in 4 s and
2e5 in 10 s, so beyond a few seconds a comparison measures the amplified errors of both
solvers, not the FMU's equations; that trajectory is compared over 2 s, and its invariants
over 10 s.
"""

import numpy as np
from scipy.integrate import cumulative_simpson

from mechfmu_validate.case import Case, step_input
from refs import double_pendulum_cart as dpc, split, solution

STATES = ["x", "x_dot", "phi1", "phi1_dot", "phi2", "phi2_dot"]
ACCELERATIONS = ["x_ddot", "phi1_ddot", "phi2_ddot"]
ALL = [*STATES, *ACCELERATIONS, "tip_x", "tip_y", "E", "p_x"]


def numerical(start_values, inputs=None):
    return solution(dpc, start_values, inputs)


def invariants(start_values):
    """E(t) = E(0) and p_x(t) = p_x(0), computed from the start values alone."""
    p, y0 = split(dpc, start_values)
    q, s = dpc.params(**p), {**dpc.START, **y0}
    y = [s[n] for n in STATES]
    E0, P0 = dpc.energy(y, q), dpc.momentum(y, q)
    return lambda t: {"E": np.full_like(t, E0), "p_x": np.full_like(t, P0)}


def invariants_exact(start_values):
    """DOP853 for the motion, and E and p_x at their exact constant values (a solver's
    round-off in a constant would leave FMPy's cross-check criterion a band of 10 % of
    itself)."""
    motion, constant = numerical(start_values), invariants(start_values)
    return lambda t: {**motion(t), **constant(t)}


def balances(c, times, forces):
    """The errors of the two balances along the FMU's run, each from its own outputs: with F
    held at forces[k] from times[k],

        p_x(t) - p_x(0) = integral of F dt - c (x(t) - x(0))                       (exact)
        E(t) - E(0)     = sum_k forces[k] (x at the segment's end - x(times[k])) - c integral of x'^2 dt

    the dissipation integrated by Simpson's rule on each segment of constant F (x'' jumps
    where F does). Relative to what the run exchanges: the impulse of F and of the drag,
    the work of F and the energy the drag dissipates, each summed segment by segment."""
    def metric(r):
        t, x, v, E, P = r.time, r["x"], r["x_dot"], r["E"], r["p_x"]
        edges = [*times[1:], t[-1]]
        impulse, work, dissipated = np.zeros_like(t), np.zeros_like(t), np.zeros_like(t)
        base_j = base_w = base_d = 0.0
        p_scale = e_scale = 0.0
        for a, b, f in zip(times, edges, forces):
            sel = np.flatnonzero((t >= a - 1e-9) & (t <= b + 1e-9))
            i0, i1 = sel[0], sel[-1]
            impulse[sel] = base_j + f * (t[sel] - t[i0])
            work[sel] = base_w + f * (x[sel] - x[i0])
            dissipated[sel] = base_d + c * cumulative_simpson(v[sel] ** 2, x=t[sel], initial=0.0)
            p_scale += abs(impulse[i1] - base_j) + c * abs(x[i1] - x[i0])
            e_scale += abs(work[i1] - base_w) + (dissipated[i1] - base_d)
            base_j, base_w, base_d = impulse[i1], work[i1], dissipated[i1]
        return {"p_x - p_x(0) = J_F - c (x - x(0))": np.abs(P - P[0] - impulse + c * (x - x[0])) / p_scale,
                "E - E(0) = W_F - c int x'^2": np.abs(E - E[0] - work + dissipated) / e_scale}
    return metric


CHAOTIC = {"phi1": 2.0, "phi2": 1.0, "x_dot": 0.4}
FD = {"c": 1.0}
FD_TIMES, FD_FORCES = [0.0, 1.0, 3.0, 5.0, 7.0], [0.0, 2.0, -3.0, 1.5, 0.0]
FD_INPUT = step_input(["F"], FD_TIMES, [[f] for f in FD_FORCES], 10.0)

CASES = [
    Case("default_experiment",
         description="The DefaultExperiment (phi1 = 1, phi2 = 0.5 rad released at rest, no force, no drag) "
                     "against Newton's law per body integrated by DOP853 (rtol = atol = 1e-12): states, "
                     "accelerations, the tip, and E and p_x at their exact constant values. The motion is "
                     "regular (a perturbation grows less than 10-fold against each signal's range in 10 s): "
                     "compared over the whole 10 s.",
         stop_time=10.0, output_interval=0.01, relative_tolerance=None, outputs=ALL,
         reference=invariants_exact({}), tolerance=1e-6, default_experiment=True,
         reference_files=[*STATES, *ACCELERATIONS, "E"], plot=["x", "phi1", "phi2", "tip_x", "tip_y"]),
    Case("chaotic_swing",
         description="Released from phi1 = 2, phi2 = 1 rad with the cart at x_dot = 0.4 m/s: the lower rod "
                     "flips over and the motion is chaotic (a perturbation grows 8-fold in 2 s, 300-fold in 4 s, "
                     "2e5-fold in 10 s), so the trajectory is compared with DOP853 over the first 2 s only, at "
                     "relative tolerance 1e-10; its invariants over 10 s are the next case.",
         start_values=CHAOTIC, stop_time=2.0, output_interval=0.01, relative_tolerance=1e-10, outputs=ALL,
         reference=invariants_exact(CHAOTIC), tolerance=1e-6, plot=["x", "phi1", "phi2", "tip_x", "tip_y"]),
    Case("chaotic_invariants",
         description="The chaotic swing over 10 s, no force, no drag, at relative tolerance 1e-10: E and p_x "
                     "stay at their start values (computed from the start values alone), however unpredictable "
                     "the motion; the drift relative to |E(0)| and |p_x(0)|. Only the invariants are recorded: "
                     "two importers' runs of the FMU differ in their last bits (libcosim's and FMPy's by about "
                     "1e-14 in the regular cases), which the chaos amplifies in the states (to 1e-10 at 10 s, "
                     "1e-2 at 20 s), not in E and p_x.",
         start_values=CHAOTIC, stop_time=10.0, output_interval=0.01, relative_tolerance=1e-10,
         outputs=["E", "p_x"], reference=invariants(CHAOTIC), tolerance=1e-8, plot=["E", "p_x"]),
    Case("forced_damped",
         description="Drag c = 1 N.s/m and a step force F (2, -3, 1.5, 0 N from 1, 3, 5, 7 s) from the "
                     "default start: DOP853 of Newton's law per body restarted at every switch; a regular motion "
                     "(a perturbation grows less than 5-fold against each signal's range), compared over 10 s.",
         start_values=FD, input=FD_INPUT, stop_time=10.0, output_interval=0.01, relative_tolerance=1e-10,
         outputs=ALL, reference=numerical(FD, FD_INPUT), tolerance=1e-6,
         plot=["x", "x_dot", "phi1", "phi2", "E", "p_x"]),
    Case("forced_damped_balances",
         description="The forced and damped run, output every 1 ms: along the FMU's own run, "
                     "p_x - p_x(0) = integral of F - c (x - x(0)) (exact) and E - E(0) = work of F - c integral "
                     "of x'^2 (Simpson's rule on each segment of constant F), relative to the impulse and the "
                     "energy exchanged; x, x_dot, E and p_x against DOP853.",
         start_values=FD, input=FD_INPUT, stop_time=10.0, output_interval=0.001, relative_tolerance=1e-10,
         outputs=["x", "x_dot", "E", "p_x"], reference=numerical(FD, FD_INPUT),
         metric=balances(FD["c"], FD_TIMES, FD_FORCES),
         tolerance={"*": 1e-6, "p_x - p_x(0) = J_F - c (x - x(0))": 1e-8, "E - E(0) = W_F - c int x'^2": 1e-8},
         plot=["x", "E", "p_x"]),
]
