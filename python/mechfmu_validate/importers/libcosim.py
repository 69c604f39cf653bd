"""libcosim (``libcosimpy``), in Co-Simulation on an FMI 2.0 FMU: a fixed-step execution
with the case's output interval, fed the inputs FMPy applies (:func:`~.signals.input_values`)
before every step, compared with FMPy to :data:`LIBCOSIM_TOLERANCE`.

libcosim calls ``fmi2SetupExperiment`` without a tolerance and without a stop time (its
execution sets its slaves up with neither; libcosimpy offers no way to pass a tolerance), so
an FMU with a solver of its own integrates at its own default tolerance, whatever its
DefaultExperiment says. The comparison "libcosim against FMPy at the same settings" runs FMPy
so too (:func:`run_fmpy_as_libcosim`).

Its loader (the FMI Library) refuses some model descriptions the standard allows, and drops
variables it judges wrong: on another exporter's FMU that is a SKIP row naming why
(:class:`~.fmu.NotRead`); mechfmu's FMUs promise to run under libcosim.
"""

from __future__ import annotations

import copy
from typing import Any, Iterator

import numpy as np

from .. import progress
from ..agreement import agreement
from ..case import Case, Evaluation, Result
from ..fmu import Fmu, NotRead
from ..importer import CS, FMI2, Availability, CaseRun, Curve, Importer, Runs, Words
from ..rows import Row
from ..signals import input_events_on_grid, input_values
from .fmpy import simulate

__all__ = ["IMPORTER", "NAME", "LIBCOSIM_NOTE", "LIBCOSIM_TOLERANCE", "libcosim_available", "libcosim_row",
           "run_fmpy_as_libcosim", "run_libcosim"]

NAME = "libcosim"

LIBCOSIM_NOTE = ("libcosim passes fmi2SetupExperiment no tolerance and no stop time (the FMU uses its own "
                 "default): compared with FMPy run at the same settings")

#: libcosim must agree with FMPy to this, relative (max |a - b| / max |b|), at the same settings
LIBCOSIM_TOLERANCE = 1e-9

#: libcosim's steps between two beats of :func:`.progress.beat` (a long run is not a hung one)
LIBCOSIM_BEAT = 100


def run_fmpy_as_libcosim(fmu: Fmu, case: Case) -> Result:
    """The case under FMPy at libcosim's settings: ``fmi2SetupExperiment`` without a tolerance
    and without a stop time (libcosim's execution sets up its slaves with neither), so that an
    FMU with a solver of its own integrates at its own default in both runs (FMPy, given no
    tolerance, would pass the DefaultExperiment's)."""
    md = copy.copy(fmu.md)
    md.defaultExperiment = None
    return simulate(fmu, case, None, model_description=md, set_stop_time=False)


def libcosim_available() -> tuple[bool, str]:
    """(True, version) when libcosimpy imports and its native library loads, else (False, why)."""
    try:
        import libcosimpy  # noqa: F401
        from libcosimpy._internal import libcosimc

        lib = libcosimc()
        version = "?"
        try:
            from libcosimpy.__about__ import __version__ as version
        except Exception:
            pass
        return True, f"libcosimpy {version}" if lib is not None else "libcosimpy"
    except Exception as e:  # not installed, or the native library does not load here
        return False, f"{type(e).__name__}: {e}"


def run_libcosim(fmu: Fmu, case: Case) -> Result:
    """The case under libcosim: a fixed-step execution with the case's output interval,
    start values as initial values, inputs overridden before every step, every recorded
    variable observed."""
    from libcosimpy.CosimEnums import CosimVariableType
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimManipulator import CosimManipulator
    from libcosimpy.CosimObserver import CosimObserver
    from libcosimpy.CosimSlave import CosimLocalSlave

    log_output_level(CosimLogLevel.ERROR)
    if not input_events_on_grid(case):
        raise RuntimeError("an input jump is off the communication grid: a fixed-step master cannot follow it")
    n = case.steps()
    h_ns = round(case.output_interval * 1e9)
    if abs(h_ns - case.output_interval * 1e9) > 1e-3:
        raise RuntimeError(f"output_interval {case.output_interval} s is not a whole number of nanoseconds")

    execution = CosimExecution.from_step_size(step_size=h_ns)
    try:
        slave = CosimLocalSlave(fmu_path=str(fmu.path), instance_name=fmu.model)
        index = execution.add_local_slave(local_slave=slave)
    except Exception as e:  # noqa: BLE001 (libcosimpy raises what its C library reports)
        raise NotRead(f"libcosim could not load {fmu.path.name}: {e}") from e
    if index < 0:
        raise NotRead(f"libcosim could not load {fmu.path.name}")
    variables = fmu.variables
    names = case.recorded()
    vrs = [variables[n].valueReference for n in names]
    for name, value in case.start_values.items():
        if not execution.real_initial_value(index, variables[name].valueReference, float(value)):
            raise NotRead(f"libcosim refused the start value {name} = {value}")
    input_names, initial_inputs = input_values(case, fmu, 0.0)
    input_vrs = [variables[nm].valueReference for nm in input_names]
    for vr, value in zip(input_vrs, initial_inputs):
        execution.real_initial_value(index, vr, value)

    series = CosimObserver.create_time_series(buffer_size=n + 16)
    execution.add_observer(observer=series)
    last = CosimObserver.create_last_value()
    execution.add_observer(observer=last)
    for vr in vrs:
        series.start_time_series(index, vr, CosimVariableType.REAL)
    manipulator = None
    if input_vrs:
        manipulator = CosimManipulator.create_override()
        execution.add_manipulator(manipulator=manipulator)

    if manipulator is None:
        for k in range(LIBCOSIM_BEAT, n + LIBCOSIM_BEAT, LIBCOSIM_BEAT):  # a beat every few steps: not hung
            if not execution.simulate_until(target_time=min(k, n) * h_ns):
                raise RuntimeError(f"libcosim stopped: {execution.status()}")
            progress.beat()
    else:
        for k in range(n):
            _, values = input_values(case, fmu, k * h_ns * 1e-9)
            manipulator.slave_real_values(index, input_vrs, values)
            if not execution.step(1):
                raise RuntimeError(f"libcosim step {k} failed: {execution.status()}")
            progress.beat()
    status = execution.status()
    if status.current_time != n * h_ns:
        raise RuntimeError(f"libcosim reached {status.current_time} ns, not {n * h_ns} ns")

    columns: dict[str, np.ndarray] = {"time": np.arange(n + 1) * (h_ns * 1e-9)}
    for name, vr in zip(names, vrs):
        try:
            (end,) = last.last_real_values(index, [vr])
            _, steps, values = series.time_series_real_samples(index, vr, 0, n + 1)
        except Exception as e:  # noqa: BLE001 (libcosimpy asserts on a variable it does not know)
            raise NotRead(f"libcosim cannot read {name} ({e}): its loader did not take the variable") from e
        col = np.full(n + 1, np.nan)
        for s, v in zip(steps, values):
            if 0 <= s <= n:
                col[s] = v
        col[n] = end  # the observer's series stops one step short of the last one
        if np.any(np.isnan(col)):
            raise RuntimeError(f"libcosim observed {np.count_nonzero(~np.isnan(col))} of {n + 1} samples of {name}")
        columns[name] = col
    return Result(columns)


def libcosim_row(fmu: Fmu, case: Case, fmpy_result: Result | None, ev: Evaluation | None, anchor: str = "",
                 kind: str = "case") -> tuple[Row, dict[str, Any] | None]:
    """The case under libcosim against FMPy at the same settings (libcosim passes no
    tolerance and no stop time: nor does that FMPy run): (row, what the report plots of it)."""
    row = Row(kind=kind, fmu=fmu.model, case=case.name, importer=NAME, anchor=anchor, problems=[], notes=[],
               tolerance=LIBCOSIM_TOLERANCE)
    row["notes"] = [LIBCOSIM_NOTE]
    try:
        lc = run_libcosim(fmu, case)
    except NotRead as e:
        if fmu.by_mechfmu:  # ours promise to run under libcosim
            return row.but(max_error=None, passed=False, problems=[f"libcosim run failed: {e}"]), None
        return row.but(max_error=None, passed=True, skipped=True, problems=[
            f"{e}: a limit of libcosim's loader (the FMI Library), not a failure of the FMU, which the "
            "checks and the other importers judge"]), None
    except Exception as e:  # noqa: BLE001 (a row, not a crash)
        return row.but(max_error=None, passed=False, problems=[f"libcosim run failed: {type(e).__name__}: {e}"]), None
    try:
        same = run_fmpy_as_libcosim(fmu, case)
    except Exception as e:  # noqa: BLE001 (a row, not a crash)
        return row.but(max_error=None, passed=False, problems=[
            f"FMPy's run at libcosim's settings (no tolerance, no stop time) failed: {type(e).__name__}: {e}"]), None
    floors = {s.name: s.scale for s in ev.signals} if ev is not None else {}
    worst, where, when, over_time = agreement(lc, same, case.recorded(), floors)
    row.update(max_error=worst, passed=bool(worst <= LIBCOSIM_TOLERANCE),
               notes=[f"worst signal {where} at t = {when:g}", LIBCOSIM_NOTE])
    return row, dict(time=lc.time, error_over_time=over_time, tolerance=LIBCOSIM_TOLERANCE, max_error=worst)


def _available() -> Availability:
    ok, text = libcosim_available()
    return Availability(ok, text)


def _case_rows(run: CaseRun, interface: str) -> Iterator[Row]:
    run.progress(NAME)
    row, plotted = libcosim_row(run.fmu, run.case, run.reference, run.evaluation, run.anchor, run.kind)
    if plotted is not None and run.deviations is not None:
        run.deviations[NAME] = plotted
    yield row


IMPORTER = Importer(
    name=NAME, option="libcosim", left_out="do not run the cases under libcosim",
    runs=Runs(frozenset({CS}), frozenset({FMI2})), tolerance=LIBCOSIM_TOLERANCE, available=_available,
    case_rows=_case_rows, header_key="libcosim",
    header=lambda a: "libcosim not used" if a is None else a.text,
    unavailable="libcosim cannot run here ({why}); the cases run under FMPy only and the libcosim rows fail",
    curves={NAME: Curve("libcosim vs FMPy", "#6e7781", (0, (1, 1.5)), tolerance_label="libcosim tolerance",
                        heading=lambda d: f"libcosim vs FMPy: {d['max_error']:.1e}, tolerance {d['tolerance']:.0e}")},
    words=Words(
        report="under libcosim, max |libcosim − FMPy| / max |FMPy| at the same settings (libcosim passes no "
               "tolerance, so both use the FMU's DefaultExperiment tolerance)"))
