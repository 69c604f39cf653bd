"""Writes FirstOrder's reference results (``FirstOrder_ref.csv``, ``_in.csv``, ``_ref.opt``):
the closed-form solution of tau y' = u - y, z' = y with the piecewise-constant input of
``_in.csv``, independent of the C code. Run from this folder: ``python reference.py``."""

import math

TAU, Y0 = 0.5, 1.0
STOP, STEP = 5.0, 0.1
#: (from t, u): the input holds each value until the next change
INPUT = [(0.0, 0.0), (1.0, 1.0), (3.0, -0.5)]


def solution(t: float) -> tuple[float, float]:
    y, z = Y0, 0.0
    for k, (start, u) in enumerate(INPUT):
        end = INPUT[k + 1][0] if k + 1 < len(INPUT) else math.inf
        h = min(t, end) - start
        if h < 0:
            break
        decay = math.exp(-h / TAU)
        y, z = u + (y - u) * decay, z + u * h + (y - u) * TAU * (1 - decay)
    return y, z


def main() -> None:
    n = round(STOP / STEP)
    rows = ['"time","y","z"'] + [",".join(f"{x:.15g}" for x in (k * STEP, *solution(k * STEP))) for k in range(n + 1)]
    open("FirstOrder_ref.csv", "w").write("\n".join(rows) + "\n")
    changes = [f"{INPUT[0][0]:g},{INPUT[0][1]:g}"]
    for (t, u), (_, before) in zip(INPUT[1:], INPUT):
        changes += [f"{t:g},{before:g}", f"{t:g},{u:g}"]
    changes.append(f"{STOP:g},{INPUT[-1][1]:g}")
    open("FirstOrder_in.csv", "w").write('"time","u"\n' + "\n".join(changes) + "\n")
    open("FirstOrder_ref.opt", "w").write(f"StartTime, 0\nStopTime, {STOP:g}\nStepSize, {STEP:g}\nRelTol, 1e-06\n")


if __name__ == "__main__":
    main()
