"""The Co-Simulation rows of a case: under FMPy against the case's reference, then under
libcosim and under the fmi crate, each against FMPy's run (:mod:`.validation` puts them in
the table, for a mechanism's cases and for the reference an FMU carries alike).

Every row is built here or not at all: a run that raises becomes a FAIL row naming what
failed, never an exception out of these functions.
"""

from __future__ import annotations

import time
from dataclasses import replace
from typing import Any

from .case import Case, Evaluation, Result, evaluate
from .fmi_crate import FMI_CRATE_NOTE, run_fmi_crate
from .importers import LIBCOSIM_NOTE, Fmu, NotRead, NotSupported, agreement, run_fmpy, run_fmpy_as_libcosim, run_libcosim

__all__ = ["LIBCOSIM_TOLERANCE", "FMI_CRATE_TOLERANCE", "FMI_CRATE", "fmpy_row", "libcosim_row", "fmi_crate_row",
           "unknown_names", "real_signals"]

#: libcosim must agree with FMPy to this, relative (max |a - b| / max |b|), at the same settings
LIBCOSIM_TOLERANCE = 1e-9

#: the fmi crate must agree with FMPy to this, relative, both at the case's tolerance
FMI_CRATE_TOLERANCE = 1e-9

#: the importer column of the fmi crate's rows
FMI_CRATE = "fmi crate"


def _row(fmu: Fmu, case: Case, importer: str, anchor: str, kind: str, **kw) -> dict[str, Any]:
    return {**dict(kind=kind, fmu=fmu.model, case=case.name, importer=importer, anchor=anchor, problems=[], notes=[]),
            **kw}


def unknown_names(case: Case, fmu: Fmu) -> list[str]:
    """The variables the case sets, feeds or records that the FMU does not have."""
    table = case.input_table()
    named = [*case.start_values, *(table.dtype.names[1:] if table is not None else ()), *case.recorded()]
    return list(dict.fromkeys(n for n in named if n not in fmu.variables))


def real_signals(case: Case, fmu: Fmu) -> tuple[Case | None, str]:
    """The case as libcosim and the fmi crate run it (Real variables only: what both runners
    set and record), and a note; None (and why) when there is nothing Real to compare."""
    variables = fmu.variables

    def is_real(name: str) -> bool:  # an FMI 3.0 array element (not a variable by that name) is mechfmu's Float64
        return name not in variables or variables[name].type in ("Real", "Float64")

    table = case.input_table()
    inputs = [n for n in (table.dtype.names[1:] if table is not None else ()) if not is_real(n)]
    if inputs:
        return None, f"this importer's runs set Real inputs only, and {', '.join(inputs)} are not Real"
    real = [n for n in case.outputs if is_real(n)]
    if not real:
        return None, "this importer's runs record Real variables only, and no compared signal is Real"
    others = [n for n in case.outputs if n not in real]
    return replace(case, outputs=real), (f"Real signals only: {', '.join(others)} not compared" if others else "")


def fmpy_row(fmu: Fmu, case: Case, anchor: str = "", kind: str = "case",
             problems: list[str] | None = None) -> tuple[dict[str, Any], Result | None, Evaluation | None]:
    """The case under FMPy against its reference: (row, result, evaluation). ``problems``:
    what fails the row whatever the run gives (the comparison is made all the same)."""
    t0 = time.perf_counter()
    try:
        result = run_fmpy(fmu, case)
        ev = evaluate(case, result)
    except Exception as e:  # noqa: BLE001 (a row, not a crash)
        row = _row(fmu, case, "FMPy", anchor, kind, max_error=None, tolerance=None, passed=False,
                   problems=[*(problems or []), f"FMPy run failed: {type(e).__name__}: {e}"])
        return row, None, None
    worst = ev.worst
    found = [*(problems or []), *([ev.problem] if ev.problem else [])]
    row = _row(fmu, case, "FMPy", anchor, kind, max_error=None if worst is None else worst.max_error,
               tolerance=None if worst is None else worst.tolerance, passed=ev.passed and not found,
               problems=found, notes=[f"worst signal {worst.name} at t = {worst.at_time:g}"] if worst else [],
               signals={s.name: dict(max_error=s.max_error, at_time=s.at_time, scale=s.scale, tolerance=s.tolerance,
                                     passed=s.passed) for s in ev.signals},
               seconds=time.perf_counter() - t0, log=result.log[-20:])
    return row, result, ev


def libcosim_row(fmu: Fmu, case: Case, fmpy_result: Result | None, ev: Evaluation | None, anchor: str = "",
                 kind: str = "case") -> tuple[dict[str, Any], dict[str, Any] | None]:
    """The case under libcosim against FMPy at the same settings (libcosim passes no
    tolerance and no stop time: nor does that FMPy run): (row, what the report plots of it)."""
    row = _row(fmu, case, "libcosim", anchor, kind, tolerance=LIBCOSIM_TOLERANCE, notes=[LIBCOSIM_NOTE])
    try:
        lc = run_libcosim(fmu, case)
    except NotRead as e:
        if fmu.by_mechfmu:  # ours promise to run under libcosim
            return dict(row, max_error=None, passed=False, problems=[f"libcosim run failed: {e}"]), None
        return dict(row, max_error=None, passed=True, skipped=True, problems=[
            f"{e}: a limit of libcosim's loader (the FMI Library), not a failure of the FMU, which the "
            "checks and the other importers judge"]), None
    except Exception as e:  # noqa: BLE001 (a row, not a crash)
        return dict(row, max_error=None, passed=False, problems=[f"libcosim run failed: {type(e).__name__}: {e}"]), None
    try:
        same = run_fmpy_as_libcosim(fmu, case)
    except Exception as e:  # noqa: BLE001 (a row, not a crash)
        return dict(row, max_error=None, passed=False, problems=[
            f"FMPy's run at libcosim's settings (no tolerance, no stop time) failed: {type(e).__name__}: {e}"]), None
    floors = {s.name: s.scale for s in ev.signals} if ev is not None else {}
    worst, where, when, over_time = agreement(lc, same, case.recorded(), floors)
    row.update(max_error=worst, passed=bool(worst <= LIBCOSIM_TOLERANCE),
               notes=[f"worst signal {where} at t = {when:g}", LIBCOSIM_NOTE])
    return row, dict(time=lc.time, error_over_time=over_time, tolerance=LIBCOSIM_TOLERANCE, max_error=worst)


def fmi_crate_row(fmu: Fmu, case: Case, fmpy_result: Result | None, ev: Evaluation | None, anchor: str = "",
                  kind: str = "case") -> tuple[dict[str, Any], dict[str, Any] | None]:
    """The case under the fmi crate against FMPy, both at the case's tolerance: (row, what the
    report plots of it)."""
    row = _row(fmu, case, FMI_CRATE, anchor, kind, tolerance=FMI_CRATE_TOLERANCE, notes=[FMI_CRATE_NOTE])
    t0 = time.perf_counter()
    try:
        fc = run_fmi_crate(fmu, case)
        if fmpy_result is None:
            raise RuntimeError("the FMPy run failed: nothing to compare with")
        floors = {s.name: s.scale for s in ev.signals} if ev is not None else {}
        worst, where, when, over_time = agreement(fc, fmpy_result, case.recorded(), floors)
    except NotSupported as e:  # what the runner does not do: not the FMU's failure
        return dict(row, max_error=None, passed=True, skipped=True, problems=[f"fmi crate: {e}"]), None
    except Exception as e:  # noqa: BLE001 (a row, not a crash)
        return dict(row, max_error=None, passed=False,
                    problems=[f"fmi crate run failed: {type(e).__name__}: {e}"]), None
    row.update(max_error=worst, passed=bool(worst <= FMI_CRATE_TOLERANCE),
               notes=[f"worst signal {where} at t = {when:g}", FMI_CRATE_NOTE],
               seconds=time.perf_counter() - t0, log=fc.log[-20:])
    return row, dict(time=fc.time, error_over_time=over_time, tolerance=FMI_CRATE_TOLERANCE, max_error=worst)
