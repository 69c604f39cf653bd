"""FMPy, the reference importer: every case runs first under FMPy's ``simulate_fmu`` in
Co-Simulation against its reference, and the other importers are compared with that run;
then in Model Exchange, FMPy integrating with CVode (held to the case's limits, down to
:data:`~.model_exchange.CVODE_FLOOR`) and, on an FMI 2.0 FMU, with Euler at a fixed step
(held to its order: :mod:`.model_exchange`). An FMI 3.0 FMU runs through its FMI 2.0 names
(:class:`~.arrays.ArrayMap`).

In Model Exchange the inputs are the Co-Simulation run's, held between communication points
(:func:`~.signals.held_input`). At a communication point where the inputs jump,
Co-Simulation records the outputs before the jump; :func:`run_fmpy_me` keeps FMPy's sample
from before the event there, for the same reason.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from typing import Iterator

import numpy as np

import fmpy

from .. import fmulog
from ..case import Case, Evaluation, Result, evaluate
from ..fmu import Fmu, NotSupported
from ..importer import CS, FMI2, FMI3, ME, Availability, CaseRun, Curve, Importer, Runs, Words, row_name
from ..model_exchange import CVODE_RTOL, FixedStep, cvode_row, fixed_step_row, order_band
from ..rows import Row
from ..signals import held_input
from ..target import Target

__all__ = ["IMPORTER", "NAME", "CVODE", "EULER", "FMI3_CS", "FMI3_CVODE", "ME_CVODE_RTOL", "MeRun", "cs_row",
           "model_exchange_run", "on_grid", "run_fmpy", "run_fmpy3", "run_fmpy3_me", "run_fmpy_me",
           "run_fmpy_target", "simulate_me", "simulate_me3"]

NAME = "FMPy"
CVODE = row_name(NAME, FMI2, ME, "CVode")
EULER = row_name(NAME, FMI2, ME, "Euler")
FMI3_CS = row_name(NAME, FMI3, CS)
FMI3_CVODE = row_name(NAME, FMI3, ME, "CVode")

#: the relative tolerance of FMPy's CVode in the Model Exchange runs
ME_CVODE_RTOL = CVODE_RTOL

#: the note of an FMI 3.0 Co-Simulation row
CS_NOTE3 = "FMPy's FMI 3.0 Co-Simulation (step mode, no early return), against the reference"


# ---------------------------------------------------------------------------------------
# Co-Simulation


def run_fmpy(fmu: Fmu, case: Case, relative_tolerance: float | None | str = "case") -> Result:
    """``fmpy.simulate_fmu`` of the case; ``relative_tolerance="case"`` uses the case's,
    ``None`` the DefaultExperiment's (as FMPy does)."""
    rtol = case.relative_tolerance if relative_tolerance == "case" else relative_tolerance
    return simulate(fmu, case, rtol)


def simulate(fmu: Fmu, case: Case, rtol: float | None, **settings) -> Result:
    """``fmpy.simulate_fmu`` of the case on an FMI 2.0 FMU at ``rtol`` (``settings``: more of
    ``simulate_fmu``'s arguments)."""
    mark = fmulog.LogMark()
    try:
        table = fmpy.simulate_fmu(
            str(fmu.directory),
            start_time=0.0,
            stop_time=case.stop_time,
            output_interval=case.output_interval,
            relative_tolerance=rtol,
            start_values=dict(case.start_values),
            input=case.input_table(),
            output=case.recorded(),
            validate=False,
            **settings,
        )
    except Exception as e:
        raise mark.explain(e) from None
    return Result(_checked(table, case), [r.brief() for r in mark.records])


def _checked(table: np.ndarray, case: Case) -> np.ndarray:
    n = case.steps() + 1
    if len(table) != n:
        raise RuntimeError(f"FMPy recorded {len(table)} rows, expected {n} (did the FMU stop early?)")
    return table


def run_fmpy3(f3: Target, case: Case, relative_tolerance: float | None | str = "case", **options) -> Result:
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


def run_fmpy_target(target: Target, case: Case) -> Result:
    """The case in Co-Simulation on the FMU in its FMI version, at the case's tolerance."""
    return run_fmpy3(target, case) if target.version == FMI3 else run_fmpy(target.fmu, case)


def cs_row(target: Target, case: Case, anchor: str = "", kind: str = "case",
           problems: list[str] | None = None) -> tuple[Row, Result | None, Evaluation | None]:
    """The case under FMPy's Co-Simulation against its reference: (row, result, evaluation).
    ``problems``: what fails the row whatever the run gives (the comparison is made all the same)."""
    importer = row_name(NAME, target.version, CS)
    note = [CS_NOTE3] if target.version == FMI3 else []
    row = Row(kind=kind, fmu=target.fmu.model, case=case.name, importer=importer, anchor=anchor, problems=[],
               notes=note)
    problems = list(problems or [])
    t0 = time.perf_counter()
    try:
        result = run_fmpy_target(target, case)
        ev = evaluate(case, result)
    except NotSupported as e:  # the importer's limit, not the FMU's failure
        return row.but(max_error=None, tolerance=None, passed=not problems, skipped=True,
                    problems=[*problems, f"{importer} run: {e}"]), None, None
    except Exception as e:  # noqa: BLE001 (a row, not a crash)
        return row.but(max_error=None, tolerance=None, passed=False,
                    problems=[*problems, f"{importer} run failed: {type(e).__name__}: {e}"]), None, None
    worst = ev.worst
    found = [*problems, *([ev.problem] if ev.problem else [])]
    row.update(max_error=None if worst is None else worst.max_error,
               tolerance=None if worst is None else worst.tolerance, passed=ev.passed and not found,
               problems=found, notes=[f"worst signal {worst.name} at t = {worst.at_time:g}", *note] if worst else note,
               signals={s.name: dict(max_error=s.max_error, at_time=s.at_time, scale=s.scale, tolerance=s.tolerance,
                                     passed=s.passed) for s in ev.signals},
               seconds=time.perf_counter() - t0, log=result.log[-20:])
    return row, result, ev


# ---------------------------------------------------------------------------------------
# Model Exchange


@dataclass
class MeRun:
    """An FMPy Model Exchange run as FMPy recorded it (every event's samples included)."""

    table: np.ndarray
    log: list[str]
    #: the reason the FMU gave for terminateSimulation, when it asked for it
    terminated: str | None = None

    @property
    def end_time(self) -> float:
        return float(self.table["time"][-1])


def simulate_me(fmu: Fmu, *, stop_time: float, output_interval: float, solver: str = "CVode",
                relative_tolerance: float = ME_CVODE_RTOL, start_values=None, input=None,
                output=None) -> MeRun:
    """``fmpy.simulate_fmu`` in Model Exchange, recording events. FMPy 0.3's Euler steps from
    one output point to the next (``step_size`` is only checked to divide the interval), so
    Euler's step is ``output_interval``. The run ends early only when the FMU asks for
    terminateSimulation (FMPy stops there without a word): the reason is in its log."""
    mark = fmulog.LogMark()
    try:
        table = fmpy.simulate_fmu(
            str(fmu.directory), fmi_type="ModelExchange", solver=solver, start_time=0.0, stop_time=stop_time,
            output_interval=output_interval, step_size=output_interval, relative_tolerance=relative_tolerance,
            start_values=dict(start_values or {}), input=input, output=output, record_events=True, validate=False)
    except Exception as e:
        raise mark.explain(e) from None
    stops = [r.message for r in mark.records if "terminateSimulation" in r.message]
    return MeRun(table, [r.brief() for r in mark.records], stops[-1] if stops else None)


def simulate_me3(f3: Target, *, stop_time: float, output_interval: float, solver: str = "CVode",
                 relative_tolerance: float = ME_CVODE_RTOL, start_values=None, input=None, output=None) -> MeRun:
    """:func:`simulate_me` on the FMI 3.0 FMU, in FMI 2.0 names (inputs, start values, and the
    table's columns)."""
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


def on_grid(table: np.ndarray, h: float, n: int) -> np.ndarray:
    """The rows at t = k h, k = 0 .. n: the first sample of each time, which at an event is
    the one FMPy takes before it (the outputs before an input jump, as Co-Simulation has them)."""
    t = np.asarray(table["time"], dtype=float)
    grid = np.arange(n + 1) * h
    idx = np.minimum(np.searchsorted(t, grid - 1e-9 * h), len(t) - 1)
    off = np.abs(t[idx] - grid) > 1e-9 * h
    if np.any(off):
        raise RuntimeError(f"FMPy recorded no sample at t = {grid[np.argmax(off)]:g}")
    return table[idx]


def _on_grid(run: MeRun, case: Case) -> Result:
    if run.terminated:
        raise RuntimeError(f"the FMU asked to terminate the simulation: {run.terminated}")
    return Result(on_grid(run.table, case.output_interval, case.steps()), run.log)


def run_fmpy_me(fmu: Fmu, case: Case, solver: str = "CVode", step: float | None = None) -> Result:
    """The case in Model Exchange under FMPy: CVode at :data:`ME_CVODE_RTOL`, or Euler with
    the fixed ``step`` (a divisor of the output interval), at the case's communication points.
    Raises when the FMU asks to terminate."""
    return _on_grid(simulate_me(fmu, stop_time=case.stop_time, output_interval=step or case.output_interval,
                                solver=solver, start_values=case.start_values, input=held_input(case, fmu),
                                output=case.recorded()), case)


def run_fmpy3_me(f3: Target, case: Case, solver: str = "CVode", step: float | None = None) -> Result:
    """:func:`run_fmpy_me` on the FMI 3.0 FMU."""
    return _on_grid(simulate_me3(f3, stop_time=case.stop_time, output_interval=step or case.output_interval,
                                 solver=solver, start_values=case.start_values, input=held_input(case, f3.names),
                                 output=case.recorded()), case)


def model_exchange_run(target: Target, solver: str = "CVode"):
    """(the importer column, how a case runs) of the FMU's Model Exchange runs under ``solver``."""
    if target.version == FMI3:
        return row_name(NAME, FMI3, ME, solver), lambda case, step=None: run_fmpy3_me(target, case, solver, step)
    return row_name(NAME, FMI2, ME, solver), lambda case, step=None: run_fmpy_me(target.fmu, case, solver, step)


#: Euler at a fixed step: order 1, the output interval over 2, 4 or 8
EULER_METHOD = FixedStep(EULER, 1, order_band(1), 2, 8, lambda fmu, case, h: run_fmpy_me(fmu, case, "Euler", h))


# ---------------------------------------------------------------------------------------
# The importer


def _available() -> Availability:
    return Availability(True, fmpy.__version__)


def _case_rows(run: CaseRun, interface: str) -> Iterator[Row]:
    if interface == CS:
        run.progress(row_name(NAME, run.version, CS))
        row, run.reference, run.evaluation = cs_row(run.target, run.case, run.anchor, run.kind, run.problems)
        if run.plot is not None:
            run.plot.update(evaluation=run.evaluation, result=run.reference)
        yield row
        return
    name, cvode = model_exchange_run(run.target, "CVode")
    run.progress(name)
    yield cvode_row(run.fmu, run.case, run.anchor, run.deviations, importer=name, run=lambda _, case: cvode(case))
    if run.version == FMI2:
        run.progress(EULER)
        yield fixed_step_row(run.fmu, run.case, EULER_METHOD, run.anchor)


IMPORTER = Importer(
    name=NAME, option=None, left_out="", runs=Runs(frozenset({CS, ME}), frozenset({FMI2, FMI3})), tolerance=None,
    available=_available, case_rows=_case_rows, header_key="fmpy",
    methods={FMI2: ("CVode", "Euler"), FMI3: ("CVode",)},
    fixed_step=EULER_METHOD,
    curves={CVODE: Curve("ME CVode", "#bf8700", (0, (5, 2)))},
    words=Words(report="for a case under FMPy, max over time and signals of |FMU − reference| / scale, the scale "
                       "being the reference signal's range (or its magnitude when it is constant: a relative drift)",
                report3="FMPy FMI3 CS and FMPy FMI3 ME CVode against the reference as above",
                tables3="FMPy's FMI 3.0 Co-Simulation (step mode, no early return) and Model Exchange (CVode at "
                        "1e-10) against the reference, held to the same limits",
                owner="FMPy's"))
