"""Writes the reference results of the models of this folder (``<Model>_out.csv``, as the
FMI-LS-REF manifest the tests package beside them names them): each model's closed-form
solution at every output point of its default experiment, independent of the C code (which
steps). Run from this folder: ``python reference.py``."""

import math

#: BouncingBall's parameters and the speed off the floor below which the ball stays on it
H0, G, E, V_REST = 1.0, 9.81, 0.7, 0.1


def decay(t: float) -> tuple[float, ...]:
    return (math.exp(-t),)


def bouncing_ball(t: float) -> tuple[float, ...]:
    """The fall from H0, then the k-th flight leaving the floor at time T_k with speed E^k of
    the first impact's, 2 w / G long; from the first flight too slow, the ball lies still."""
    fall = math.sqrt(2 * H0 / G)
    if t < fall:
        return H0 - G * t * t / 2, -G * t
    took_off, speed = fall, E * G * fall
    while speed >= V_REST:
        s = t - took_off
        if s < 2 * speed / G:
            return speed * s - G * s * s / 2, speed - G * s
        took_off, speed = took_off + 2 * speed / G, E * speed
    return 0.0, 0.0


def staircase(t: float) -> tuple[float, ...]:
    return (1 + math.floor(t + 1e-9),)


#: model: (its signals, its solution, the stop time of its results, their interval)
MODELS = {
    "Decay": (["x"], decay, 10.0, 0.1),
    "BouncingBall": (["h", "v"], bouncing_ball, 3.0, 0.01),
    "Staircase": (["counter"], staircase, 9.0, 0.2),  # it ends the simulation at t = 9
}


def main() -> None:
    for model, (names, solution, stop, step) in MODELS.items():
        rows = [",".join(["time", *names])]
        for k in range(round(stop / step) + 1):
            t = k * step
            rows.append(",".join(f"{x + 0.0:.15g}" for x in (t, *solution(t))))
        open(f"{model}_out.csv", "w").write("\n".join(rows) + "\n")


if __name__ == "__main__":
    main()
