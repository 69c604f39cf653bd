"""Running a case under an importer: FMPy's ``simulate_fmu`` and libcosim (``libcosimpy``) in
Co-Simulation, FMPy in Model Exchange (:func:`run_fmpy_me`); and what the third importer, the
Rust ``fmi`` crate (:mod:`.fmi_crate`), shares with them: the extracted FMU (:class:`Fmu`), the
inputs every importer is fed (:func:`input_values`) and the measure of agreement.

All three run the same experiment: the case's start values, its input table (FMPy reads it
itself; libcosim and the fmi crate are fed, before every communication step, the value
FMPy's input logic gives at that communication point), a fixed communication step (the
case's ``output_interval``) from 0 to ``stop_time``.

libcosim calls ``fmi2SetupExperiment`` without a tolerance and without a stop time (its
execution sets its slaves up with neither; libcosimpy offers no way to pass a tolerance), so
an FMU with a solver of its own integrates at its own default tolerance, whatever its
DefaultExperiment says. The comparison "libcosim against FMPy at the same settings" runs FMPy
so too (:func:`run_fmpy_as_libcosim`).

The fmi crate's runner takes the tolerance (and the stop time) like FMPy, so it is compared
with FMPy at the case's own settings. The FMI 3.0 FMUs' runs are in :mod:`.fmi3`.

In Model Exchange the importer integrates. The inputs are the Co-Simulation run's: the
value FMPy applies at each communication point, held to the next (:func:`held_input`), so
every run of a case sees the same signal. At a communication point where the inputs jump,
Co-Simulation records the outputs before the jump; :func:`run_fmpy_me` keeps FMPy's sample
from before the event there, for the same reason.
"""

from __future__ import annotations

import copy
import shutil
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

import fmpy
from fmpy import read_model_description

from . import fmulog, progress
from .case import Case, Result, step_input

__all__ = ["Fmu", "NotRead", "run_fmpy", "run_fmpy_as_libcosim", "run_fmpy_me", "simulate_me", "held_input", "on_grid", "run_libcosim",
           "libcosim_available", "input_values", "input_events_on_grid", "NotSupported", "capture_fmu_log",
           "LIBCOSIM_NOTE", "ME_CVODE_RTOL", "agreement"]

LIBCOSIM_NOTE = ("libcosim passes fmi2SetupExperiment no tolerance and no stop time (the FMU uses its own "
                 "default): compared with FMPy run at the same settings")

#: the relative tolerance of FMPy's CVode in the Model Exchange runs
ME_CVODE_RTOL = 1e-10

#: libcosim's steps between two beats of :func:`.progress.beat` (a long run is not a hung one)
LIBCOSIM_BEAT = 100


class NotSupported(RuntimeError):
    """The importer cannot run this kind of experiment (a row to skip, not a failure)."""


class NotRead(RuntimeError):
    """The importer could not load the FMU or one of its variables: a limit of its loader
    when the FMU is legal (libcosim's FMI Library refuses some model descriptions the
    standard allows, and drops variables it judges wrong)."""


@dataclass
class Fmu:
    """An FMU file, extracted once."""

    path: Path
    directory: Path = field(init=False)
    md: Any = field(init=False)

    def __post_init__(self):
        self.path = Path(self.path).resolve()
        self.directory = Path(tempfile.mkdtemp(prefix=f"mechfmu-validate-{self.path.stem}-"))
        try:
            fmpy.extract(str(self.path), str(self.directory))
            self.md = read_model_description(str(self.directory), validate=False)
        except BaseException:
            self.cleanup()
            raise

    @property
    def model(self) -> str:
        cs = self.md.coSimulation
        return cs.modelIdentifier if cs is not None else self.md.modelName

    @property
    def fmi3(self) -> bool:
        """An FMI 3.0 FMU (its arrays need an :class:`~.arrays.ArrayMap` for a case's names)."""
        return self.md.fmiVersion.startswith("3.")

    @property
    def variables(self) -> dict[str, Any]:
        return {v.name: v for v in self.md.modelVariables}

    def inputs(self) -> list[str]:
        return [v.name for v in self.md.modelVariables if v.causality == "input"]

    def outputs(self) -> list[str]:
        return [v.name for v in self.md.modelVariables if v.causality == "output"]

    @property
    def by_mechfmu(self) -> bool:
        """Built by mechfmu (whose own rules the checks then hold it to), not by another exporter."""
        return (self.md.generationTool or "").startswith("mechfmu")

    def cleanup(self) -> None:
        shutil.rmtree(self.directory, ignore_errors=True)

    def __enter__(self) -> Fmu:
        return self

    def __exit__(self, *exc) -> None:
        self.cleanup()


# ---------------------------------------------------------------------------------------
# FMU log messages


def capture_fmu_log() -> None:
    """Routes the FMUs' log messages (under FMPy) into :mod:`.fmulog` instead of stdout:
    the one capture of mechfmu's Python side, which the test suite installs too."""
    fmulog.install()


# ---------------------------------------------------------------------------------------
# FMPy


def run_fmpy(fmu: Fmu, case: Case, relative_tolerance: float | None | str = "case") -> Result:
    """``fmpy.simulate_fmu`` of the case; ``relative_tolerance="case"`` uses the case's,
    ``None`` the DefaultExperiment's (as FMPy does)."""
    rtol = case.relative_tolerance if relative_tolerance == "case" else relative_tolerance
    return _simulate(fmu, case, rtol)


def run_fmpy_as_libcosim(fmu: Fmu, case: Case) -> Result:
    """The case under FMPy at libcosim's settings: ``fmi2SetupExperiment`` without a tolerance
    and without a stop time (libcosim's execution sets up its slaves with neither), so that an
    FMU with a solver of its own integrates at its own default in both runs (FMPy, given no
    tolerance, would pass the DefaultExperiment's)."""
    md = copy.copy(fmu.md)
    md.defaultExperiment = None
    return _simulate(fmu, case, None, model_description=md, set_stop_time=False)


def _simulate(fmu: Fmu, case: Case, rtol: float | None, **settings) -> Result:
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
    n = case.steps() + 1
    if len(table) != n:
        raise RuntimeError(f"FMPy recorded {len(table)} rows, expected {n} (did the FMU stop early?)")
    return Result(table, [r.brief() for r in mark.records])


# ---------------------------------------------------------------------------------------
# FMPy, Model Exchange


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


def held_input(case: Case, fmu: Fmu) -> np.ndarray | None:
    """The case's inputs as its Co-Simulation runs see them: the value FMPy applies at each
    communication point, held until the next (a jump only where the value changes). A table
    that already holds its values between jumps on the grid is that signal: it is kept as is
    (resampled, FMPy's interpolation would add jumps of one ulp)."""
    names, _ = input_values(case, fmu, 0.0)
    if not names:
        return None
    table = case.input_table()
    t = np.asarray(table[table.dtype.names[0]], dtype=float)
    spans = np.diff(t) > 0  # the rows that begin a span of time (the others begin a jump)
    if input_events_on_grid(case) and all(np.array_equal(table[n][:-1][spans], table[n][1:][spans]) for n in names):
        return table
    h = case.output_interval
    times, values = [], []
    for k in range(case.steps()):  # the value at the stop time is never applied
        v = input_values(case, fmu, k * h)[1]
        if not values or v != values[-1]:
            times.append(k * h)
            values.append(v)
    return step_input(names, times, values, case.stop_time)


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


def run_fmpy_me(fmu: Fmu, case: Case, solver: str = "CVode", step: float | None = None) -> Result:
    """The case in Model Exchange under FMPy: CVode at :data:`ME_CVODE_RTOL`, or Euler with
    the fixed ``step`` (a divisor of the output interval), at the case's communication points.
    Raises when the FMU asks to terminate."""
    run = simulate_me(fmu, stop_time=case.stop_time, output_interval=step or case.output_interval, solver=solver,
                      start_values=case.start_values, input=held_input(case, fmu), output=case.recorded())
    if run.terminated:
        raise RuntimeError(f"the FMU asked to terminate the simulation: {run.terminated}")
    return Result(on_grid(run.table, case.output_interval, case.steps()), run.log)


# ---------------------------------------------------------------------------------------
# libcosim


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


def input_values(case: Case, fmu: Fmu, t: float) -> tuple[list[str], list[float]]:
    """The inputs' values FMPy applies at communication point t (its interpolation, the
    value after a jump at t): the same signal for every importer."""
    table = case.input_table()
    if table is None:
        return [], []
    from fmpy.simulation import Input

    names = [n for n in table.dtype.names[1:] if n in fmu.variables]
    times = np.asarray(table[table.dtype.names[0]], dtype=float)
    values = np.vstack([np.asarray(table[n], dtype=float) for n in names])
    v, _ = Input.interpolate(time=t, t=times, table=values, discrete=False, after_event=True)
    return names, [float(x) for x in np.atleast_1d(v)]


def input_events_on_grid(case: Case) -> bool:
    """Whether every jump of the case's inputs is at a communication point (the only jumps a
    fixed-step master can follow)."""
    table = case.input_table()
    if table is None:
        return True
    t = np.asarray(table[table.dtype.names[0]], dtype=float)
    events = t[1:][np.diff(t) == 0]
    k = events / case.output_interval
    return bool(np.all(np.abs(k - np.round(k)) < 1e-9 * np.maximum(1.0, k)))


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


def agreement(a: Result, b: Result, names: list[str],
              floors: dict[str, float] | None = None) -> tuple[float, str, float, np.ndarray]:
    """Largest |a - b| / max|b| over the signals (b the reference importer), the scale of a
    signal floored by ``floors[name]`` (the case's scale: a signal that stays at zero is
    compared in absolute terms): (value, signal, time, error over time (max over signals))."""
    worst, where, when = 0.0, "", 0.0
    over_time = np.zeros_like(b.time)
    floors = floors or {}
    for name in names:
        x, y = a[name], b[name]
        if x.shape != y.shape:
            return np.inf, name, 0.0, over_time + np.inf
        scale = max(float(np.max(np.abs(y))), floors.get(name, 0.0)) or 1.0
        err = np.abs(x - y) / scale
        err = np.where(np.isfinite(err), err, np.inf)
        over_time = np.maximum(over_time, err)
        i = int(np.argmax(err))
        if err[i] > worst or not where:
            worst, where, when = float(err[i]), name, float(b.time[i])
    return worst, where, when, over_time
