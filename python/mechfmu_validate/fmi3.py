"""The FMI 3.0 FMU of a mechanism (``fmus/fmi3/<Name>.fmu``, Co-Simulation and Model Exchange
in one archive) under the same reference cases as its FMI 2.0 FMU, held to the same limits:

* ``FMPy FMI3 CS``: FMPy's FMI 3.0 Co-Simulation (``simulate_fmu``: step mode, no early
  return), against the case's reference;
* ``fmi crate FMI3 CS``: the fmi crate's FMI 3.0 import (``mechfmu-fmi-run``), which must agree
  with FMPy's FMI 3.0 run to 1e-9, relative;
* ``FMPy FMI3 ME CVode`` and ``fmi crate FMI3 ME RK4``: Model Exchange, judged as the FMI 2.0
  rows are (:mod:`.model_exchange`);
* per mechanism, ``check: FMI 3.0 CS = FMI 2.0 CS``: the DefaultExperiment under FMPy through
  both FMUs (the same step sequence), every FMI 2.0 variable against its FMI 3.0 scalar or
  array element(s), to 1e-12 relative.

A case names FMI 2.0 variables: they reach the FMI 3.0 FMU through the mechanism's
:class:`~.arrays.ArrayMap` (read from the FMU's annotations: :func:`~.arrays.derive`).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any, Callable

import numpy as np

import fmpy

from . import fmulog, model_exchange
from .arrays import ArrayMap, MappingError, derive, fmi3_sibling
from .case import Case, Result, evaluate
from .fmi_crate import run_fmi_crate
from .importers import ME_CVODE_RTOL, Fmu, MeRun, NotSupported, agreement, held_input, on_grid
from .opening import open_fmu

__all__ = ["FMI3_CS", "FMI3_CRATE", "FMI3_CVODE", "FMI3_RK4", "IMPORTERS", "AGREEMENT", "AGREEMENT_TOLERANCE",
           "CRATE_TOLERANCE", "Fmi3", "run_fmpy3", "simulate_me3", "run_fmpy3_me", "run_crate3", "case_rows",
           "agreement_row"]

FMI3_CS = "FMPy FMI3 CS"
FMI3_CRATE = "fmi crate FMI3 CS"
FMI3_CVODE = "FMPy FMI3 ME CVode"
FMI3_RK4 = "fmi crate FMI3 ME RK4"
IMPORTERS = (FMI3_CS, FMI3_CRATE, FMI3_CVODE, FMI3_RK4)

#: the check row of the FMI 3.0 and FMI 2.0 Co-Simulation runs of the DefaultExperiment
AGREEMENT = "check: FMI 3.0 CS = FMI 2.0 CS"
AGREEMENT_TOLERANCE = 1e-12
#: the fmi crate's FMI 3.0 run against FMPy's, as for FMI 2.0
CRATE_TOLERANCE = 1e-9

CS_NOTE = "FMPy's FMI 3.0 Co-Simulation (step mode, no early return), against the reference"
CRATE_NOTE = "the fmi crate's FMI 3.0 import (mechfmu-fmi-run) against FMPy's FMI 3.0 run, both at the case's tolerance"


@dataclass
class Fmi3:
    """An FMI 3.0 FMU and the FMI 2.0 names of its variables (or why there are none)."""

    fmu: Fmu
    mapping: ArrayMap | None
    problem: str | None = None

    @classmethod
    def open(cls, path: Path) -> Fmi3:
        """The FMI 3.0 FMU at ``path``, with the FMI 2.0 names of its variables; raises
        :class:`~.opening.BrokenFmu` when it cannot be opened."""
        fmu = open_fmu(path)
        try:
            return cls(fmu, derive(fmu))
        except MappingError as e:
            return cls(fmu, None, str(e))

    @classmethod
    def beside(cls, fmu2: Fmu) -> Fmi3 | None:
        """The FMI 3.0 FMU of an FMI 2.0 one (``<dir>/fmi3/<Name>.fmu``), if it was built."""
        path = fmi3_sibling(fmu2.path)
        return cls.open(path) if path is not None else None

    @property
    def names(self) -> ArrayMap:
        if self.mapping is None:
            raise MappingError(self.problem or "no mapping")
        return self.mapping

    def cleanup(self) -> None:
        self.fmu.cleanup()


# ---------------------------------------------------------------------------------------
# Runs


def _checked(table: np.ndarray, case: Case) -> np.ndarray:
    n = case.steps() + 1
    if len(table) != n:
        raise RuntimeError(f"FMPy recorded {len(table)} rows, expected {n} (did the FMU stop early?)")
    return table


def run_fmpy3(f3: Fmi3, case: Case, relative_tolerance: float | None | str = "case", **options) -> Result:
    """``fmpy.simulate_fmu`` of the case on the FMI 3.0 FMU (Co-Simulation; ``options`` go to
    ``simulate_fmu``, e.g. ``early_return_allowed``), as columns of the case's FMI 2.0 names."""
    names = f3.names
    rtol = case.relative_tolerance if relative_tolerance == "case" else relative_tolerance
    mark = fmulog.LogMark()
    try:
        table = fmpy.simulate_fmu(
            str(f3.fmu.directory), fmi_type="CoSimulation", start_time=0.0, stop_time=case.stop_time,
            output_interval=case.output_interval, relative_tolerance=rtol,
            start_values=names.fmi3_start_values(case.start_values), input=names.fmi3_input(case.input_table()),
            output=names.fmi3_record(case.recorded()), validate=False, logger=fmulog.fmi3_logger(), **options)
    except Exception as e:
        raise mark.explain(e) from None
    return Result(names.fmi2_columns(_checked(table, case), case.recorded()), [r.brief() for r in mark.records])


def simulate_me3(f3: Fmi3, *, stop_time: float, output_interval: float, solver: str = "CVode",
                 relative_tolerance: float = ME_CVODE_RTOL, start_values=None, input=None, output=None) -> MeRun:
    """:func:`~.importers.simulate_me` on the FMI 3.0 FMU, in FMI 2.0 names (inputs, start
    values, and the table's columns)."""
    names = f3.names
    output = list(output or [])
    mark = fmulog.LogMark()
    try:
        table = fmpy.simulate_fmu(
            str(f3.fmu.directory), fmi_type="ModelExchange", solver=solver, start_time=0.0, stop_time=stop_time,
            output_interval=output_interval, step_size=output_interval, relative_tolerance=relative_tolerance,
            start_values=names.fmi3_start_values(start_values or {}), input=names.fmi3_input(input),
            output=names.fmi3_record(output), record_events=True, validate=False, logger=fmulog.fmi3_logger())
    except Exception as e:
        raise mark.explain(e) from None
    columns = names.fmi2_columns(table, output)
    flat = np.zeros(len(table), dtype=[(n, np.float64) for n in columns])
    for n, col in columns.items():
        flat[n] = col
    stops = [r.message for r in mark.records if "terminateSimulation" in r.message]
    return MeRun(flat, [r.brief() for r in mark.records], stops[-1] if stops else None)


def run_fmpy3_me(f3: Fmi3, case: Case, solver: str = "CVode", step: float | None = None) -> Result:
    """:func:`~.importers.run_fmpy_me` on the FMI 3.0 FMU."""
    run = simulate_me3(f3, stop_time=case.stop_time, output_interval=step or case.output_interval, solver=solver,
                       start_values=case.start_values, input=held_input(case, f3.names), output=case.recorded())
    if run.terminated:
        raise RuntimeError(f"the FMU asked to terminate the simulation: {run.terminated}")
    return Result(on_grid(run.table, case.output_interval, case.steps()), run.log)


def run_crate3(f3: Fmi3, case: Case, interface: str = "cs", step: float | None = None) -> Result:
    """:func:`~.fmi_crate.run_fmi_crate` on the FMI 3.0 FMU."""
    return run_fmi_crate(f3.fmu, case, interface=interface, step=step, mapping=f3.names)


# ---------------------------------------------------------------------------------------
# Rows


def _row(f3: Fmi3, case: Case, anchor: str, importer: str, **kw) -> dict[str, Any]:
    return {**dict(kind="case", fmu=f3.fmu.model, case=case.name, anchor=anchor, importer=importer, problems=[],
                   notes=[]), **kw}


def _failed(row: dict[str, Any], what: str, e: Exception) -> dict[str, Any]:
    if isinstance(e, NotSupported):  # the importer's limit, not the FMU's failure
        return dict(row, max_error=None, passed=True, skipped=True, problems=[f"{what}: {e}"])
    return dict(row, max_error=None, passed=False, problems=[f"{what} failed: {type(e).__name__}: {e}"])


def cs_row(f3: Fmi3, case: Case, anchor: str = "") -> tuple[dict[str, Any], Result | None, Any]:
    """The case under FMPy's FMI 3.0 Co-Simulation, against its reference: (row, result, evaluation)."""
    row = _row(f3, case, anchor, FMI3_CS, notes=[CS_NOTE])
    t0 = time.perf_counter()
    try:
        result = run_fmpy3(f3, case)
    except Exception as e:
        return dict(_failed(row, f"{FMI3_CS} run", e), tolerance=None), None, None
    ev = evaluate(case, result)
    worst = ev.worst
    row.update(max_error=worst.max_error if worst else None, tolerance=worst.tolerance if worst else None,
               passed=ev.passed, problems=[ev.problem] if ev.problem else [],
               signals={s.name: dict(max_error=s.max_error, at_time=s.at_time, scale=s.scale, tolerance=s.tolerance,
                                     passed=s.passed) for s in ev.signals},
               seconds=time.perf_counter() - t0, log=result.log[-20:])
    if worst:
        row["notes"] = [f"worst signal {worst.name} at t = {worst.at_time:g}", CS_NOTE]
    return row, result, ev


def crate_row(f3: Fmi3, case: Case, fmpy3: Result | None, ev, anchor: str = "") -> dict[str, Any]:
    """The case under the fmi crate's FMI 3.0 import, against FMPy's FMI 3.0 run."""
    row = _row(f3, case, anchor, FMI3_CRATE, tolerance=CRATE_TOLERANCE, notes=[CRATE_NOTE])
    t0 = time.perf_counter()
    try:
        fc = run_crate3(f3, case)
        if fmpy3 is None:
            raise RuntimeError(f"the {FMI3_CS} run failed: nothing to compare with")
        floors = {s.name: s.scale for s in ev.signals} if ev is not None else {}
        worst, where, when, _ = agreement(fc, fmpy3, case.recorded(), floors)
    except Exception as e:
        return _failed(row, f"{FMI3_CRATE} run", e)
    return dict(row, max_error=worst, passed=bool(worst <= CRATE_TOLERANCE), seconds=time.perf_counter() - t0,
                notes=[f"worst signal {where} at t = {when:g}", CRATE_NOTE], log=fc.log[-20:])


def case_rows(f3: Fmi3, case: Case, emit: Callable[[dict[str, Any]], None], anchor: str = "",
              use_fmi_crate: bool = True, use_model_exchange: bool = True,
              progress: Callable[[str], None] = lambda _: None) -> tuple[Result | None, Any]:
    """The case's FMI 3.0 rows (see the module's documentation), each given to ``emit`` as soon
    as it is made (what the importers print while it runs is its own); FMPy's FMI 3.0 result
    and its evaluation."""
    progress(FMI3_CS)
    row, result, ev = cs_row(f3, case, anchor)
    emit(row)
    if use_fmi_crate:
        progress(FMI3_CRATE)
        emit(crate_row(f3, case, result, ev, anchor))
    if use_model_exchange:
        progress(FMI3_CVODE)
        emit(model_exchange.cvode_row(f3.fmu, case, anchor, None, FMI3_CVODE,
                                      lambda _, c: run_fmpy3_me(f3, c, "CVode")))
        if use_fmi_crate:
            progress(FMI3_RK4)
            rk4 = replace(model_exchange.METHODS[model_exchange.RK4], importer=FMI3_RK4,
                          run=lambda _, c, h: run_crate3(f3, c, interface="me", step=h))
            emit(model_exchange.fixed_step_row(f3.fmu, case, rk4, anchor))
    return result, ev


def agreement_row(f3: Fmi3, fmu2: Fmu) -> dict[str, Any]:
    """The DefaultExperiment under FMPy's Co-Simulation through both FMUs: every FMI 2.0
    variable against its FMI 3.0 counterpart (each place of an array element)."""
    row = dict(kind="check", fmu=fmu2.model, case=AGREEMENT, importer="FMPy", tolerance=AGREEMENT_TOLERANCE,
               problems=[], notes=[])
    mark = fmulog.LogMark()
    try:
        names = f3.names
        fmi2 = [v.name for v in fmu2.md.modelVariables if v.type == "Real"]
        cs2 = fmpy.simulate_fmu(str(fmu2.directory), output=fmi2, validate=False)
        cs3 = fmpy.simulate_fmu(str(f3.fmu.directory), output=names.fmi3_record(fmi2), validate=False,
                                logger=fmulog.fmi3_logger())
        if not np.array_equal(cs2["time"], cs3["time"]):
            raise RuntimeError(f"the two runs have different times ({len(cs2)} and {len(cs3)} points)")
        worst, where = 0.0, ""
        for name in fmi2:
            for a, k in names.places(name):
                col = np.asarray(cs3[a], dtype=float)
                got = col if k < 0 else col.reshape(len(col), -1)[:, k]
                want = np.asarray(cs2[name], dtype=float)
                err = float(np.max(np.abs(got - want))) / (float(np.max(np.abs(want))) or 1.0)
                err = err if math.isfinite(err) else math.inf
                if err > worst or not where:
                    worst, where = err, name if k < 0 else f"{name} = {names.element_names_of(name)[0]}"
    except Exception as e:
        return dict(row, max_error=None, passed=False, problems=[f"{type(e).__name__}: {mark.explain(e)}"])
    row.update(max_error=worst, passed=worst <= AGREEMENT_TOLERANCE,
               notes=[f"{len(fmi2)} variables over {len(cs2)} points of the DefaultExperiment; worst: {where}"])
    if not row["passed"]:
        row["problems"] = [f"{where} differs by {worst:.2e} (relative) between the FMI 3.0 and FMI 2.0 runs"]
    return row
