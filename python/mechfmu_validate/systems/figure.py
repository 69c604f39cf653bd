"""The figure of a system's coupling error (``docs/validation/<system>-coupling.png``): the
plain Jacobi co-simulation of its SSP at its communication step, twice and four times it,
against the system's solution (its FMU, where there is one: :mod:`.solution`), the first
connected state above and the errors below."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from . import jacobi, solution as truth
from .archive import Ssp

#: the communication steps drawn, as multiples of the SSP's
MULTIPLES = (4, 2, 1)


def write_figure(ssp: Ssp, set_name: str, signal: tuple[str, str], path: Path, work: Path,
                 fmu: Path | None = None) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    values = ssp.sets[set_name]
    times, solution, _ = truth.solve(ssp, values, [signal], work, fmu)
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(9, 6), sharex=True, height_ratios=(3, 2))
    label = f"the system's FMU ({fmu.name})" if fmu is not None else "solution (monolithic)"
    top.plot(times, solution[signal], color="black", linewidth=2.2, label=label)
    colors = {4: "tab:red", 2: "tab:orange", 1: "tab:blue"}
    for k in MULTIPLES:
        h = k * ssp.step
        run_times, run = jacobi.run(ssp, values, h, ssp.stop, [signal], work)
        exact = np.interp(run_times, times, solution[signal])
        top.plot(run_times, run[signal], color=colors[k], linewidth=1.0, label=f"co-simulation, h = {h:g} s")
        bottom.plot(run_times, run[signal] - exact, color=colors[k], linewidth=1.0, label=f"h = {h:g} s")
    name = f"{signal[0]}.{signal[1]}"
    top.set_ylabel(name)
    top.set_title(f"{ssp.name} ({set_name}): plain Jacobi co-simulation against the system's FMU"
                  if fmu is not None else f"{ssp.name} ({set_name}): plain Jacobi co-simulation against the "
                  "system's solution")
    top.legend(loc="upper right", fontsize=8)
    bottom.set_ylabel(f"error of {name}")
    bottom.set_xlabel("time (s)")
    bottom.legend(loc="upper left", fontsize=8)
    for axis in (top, bottom):
        axis.grid(True, alpha=0.3)
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path
