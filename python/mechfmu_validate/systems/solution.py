"""A system's solution, against which each co-simulation's coupling error is measured: the
system compiled into one FMU (``<System>.fmu`` beside the SSP, as ``mechfmu build`` writes
both), its components' equations integrated together by one error-controlled solver, so with
no coupling error; for an SSP without it (another exporter's), the plain Jacobi scheme of the
SSP's own FMUs at an eighth and a sixteenth of the step, extrapolated to a step of zero
(:func:`.jacobi.solution`)."""

from __future__ import annotations

from pathlib import Path

import fmpy
import numpy as np

from . import jacobi
from .archive import Ssp

#: the relative tolerance the system's FMU is run at: its error is then far below any
#: co-simulation's
TOLERANCE = 1e-10


def system_fmu(ssp_path: Path, ssp: Ssp) -> Path | None:
    """The system's own FMU beside its SSP (the same name, ``.fmu``), when it is one of this
    system: its model is named as the system and has every component's variables."""
    path = ssp_path.with_suffix(".fmu")
    if not path.is_file():
        return None
    md = fmpy.read_model_description(str(path), validate=False)
    names = {v.name for v in md.modelVariables}
    wanted = {f"{a}.{b}" for pair in ssp.connections for a, b in pair}
    return path if md.modelName == ssp.name and wanted <= names else None


def solve(ssp: Ssp, values, signals, work: Path, fmu: Path | None) -> tuple[np.ndarray, dict, str]:
    """The solution at the SSP's communication points for the parameter set ``values``: the
    times, each signal's values, and what the solution is."""
    if fmu is None:
        times, solved = jacobi.solution(ssp, values, ssp.stop, signals, work)
        return times, solved, ("the system's solution (the plain Jacobi scheme at h/8 and h/16, "
                               "extrapolated to a step of zero)")
    md = fmpy.read_model_description(str(fmu), validate=False)
    settable = {v.name for v in md.modelVariables
                if v.causality in ("parameter", "input") or v.initial in ("exact", "approx")}
    start = {f"{c}.{v}": x for (c, v), x in values.items() if f"{c}.{v}" in settable}
    result = fmpy.simulate_fmu(str(fmu), validate=False, start_time=ssp.start, stop_time=ssp.stop,
                               relative_tolerance=TOLERANCE, output_interval=ssp.step, start_values=start,
                               output=[f"{c}.{v}" for c, v in signals])
    return (np.asarray(result["time"]), {s: np.asarray(result[f"{s[0]}.{s[1]}"]) for s in signals},
            f"the system's FMU ({fmu.name}: its components integrated together, relative tolerance "
            f"{TOLERANCE:g})")
