"""The FMPy engine, and what the native engine (:mod:`.native`) takes from it: a case's setup
(``CaseSetup``), its summaries, the FMU's extraction and the message of a failed row.

``Runtime`` extracts the FMU once, keeps one ``FMU2Slave`` per thread (so one per worker
process with ``threads_per_worker=1``) and runs each case after ``fmi2Reset``. A case is
simulated exactly as ``fmpy.simulate_fmu`` simulates a Co-Simulation FMU (the same calls,
start values, input interpolation and communication points; see ``fmpy.simulation.
simulateCS``), so a sweep row equals a sequential ``simulate_fmu`` run of the same case.

The FMU's log messages reach a process-wide logger callback (installed once through fmpy's
native proxy, which formats the variadic message) and are routed by instance name to the
case that is running, so a failed case carries the FMU's own explanation.
"""

from __future__ import annotations

import atexit
import bisect
import contextlib
import io
import math
import os
import re
import shutil
import socket
import tempfile
import threading
import time as _time
from ctypes import byref, c_double, c_uint
from dataclasses import dataclass, field
from math import isclose
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from .design import Schedule, SpecError, input_table

# ---------------------------------------------------------------------------------------
# Summaries


SUMMARY_FUNCS = ("final", "max", "min", "max_abs", "mean", "rms")
_RE_SUMMARY = re.compile(r"^\s*(\w+)\s*\(\s*([^()]+?)\s*\)\s*$")
_RE_BARS = re.compile(r"^\s*(max|min)\s*\|\s*([^|]+?)\s*\|\s*$")


@dataclass(frozen=True)
class Summary:
    func: str
    var: str

    @property
    def column(self) -> str:
        return f"{self.func}({self.var})"


def parse_summary(text: str) -> Summary:
    """``max_abs(phi)`` (also written ``max|phi|``), ``max(T)``, ``min(x)``, ``final(x)``,
    ``mean(x)``, ``rms(x)``."""
    m = _RE_BARS.match(text)
    if m:
        return Summary(f"{m.group(1)}_abs", m.group(2))
    m = _RE_SUMMARY.match(text)
    if not m:
        raise SpecError(f"--summary {text}: expected FUNC(variable) with FUNC one of {', '.join(SUMMARY_FUNCS)}")
    func, var = m.group(1), m.group(2)
    if func == "min_abs":
        return Summary(func, var)
    if func not in SUMMARY_FUNCS:
        raise SpecError(f"--summary {text}: unknown function `{func}` (known: {', '.join(SUMMARY_FUNCS)})")
    return Summary(func, var)


def summarize(func: str, t: np.ndarray, y: np.ndarray) -> float:
    if func == "final":
        return float(y[-1])
    if func == "max":
        return float(np.max(y))
    if func == "min":
        return float(np.min(y))
    if func == "max_abs":
        return float(np.max(np.abs(y)))
    if func == "min_abs":
        return float(np.min(np.abs(y)))
    span = float(t[-1] - t[0])
    if span <= 0:
        return float(y[-1]) if func == "mean" else float(abs(y[-1]))
    if func == "mean":
        return float(np.trapezoid(y, t) / span)
    if func == "rms":
        return float(math.sqrt(np.trapezoid(y * y, t) / span))
    raise ValueError(func)


# ---------------------------------------------------------------------------------------
# What every case shares


@dataclass
class CaseSetup:
    """Everything a worker needs besides the FMU and the per-case values (picklable)."""

    columns: list[str]  # design columns, in the order of a case's values
    start_columns: dict[str, str]  # design column -> variable set as a start value
    schedules: dict[str, Schedule]  # input -> schedule
    schedule_args: dict[str, dict[str, str]]  # input -> {arg (incl. scale): design column}
    base_input: np.ndarray | None  # the --input CSV (structured array) or None
    base_scales: dict[str, str]  # CSV column -> design column of its scale
    start_time: float
    stop_time: float
    tolerance: float | None
    output_interval: float
    summaries: list[Summary]
    set_stop_time: bool = True
    fixed_start_values: dict[str, float] = field(default_factory=dict)

    @property
    def result_columns(self) -> list[str]:
        return [s.column for s in self.summaries]

    def case_input(self, values: dict[str, float]) -> np.ndarray | None:
        """The fmpy input table of one case (None: no input)."""
        scaled_base = self.base_input
        if scaled_base is not None and self.base_scales:
            scaled_base = scaled_base.copy()
            for name, col in self.base_scales.items():
                scaled_base[name] = scaled_base[name] * values[col]
        if not self.schedules:
            return scaled_base
        signals = {}
        if scaled_base is not None:
            for name in scaled_base.dtype.names[1:]:
                signals[name] = (np.asarray(scaled_base["time"], float), np.asarray(scaled_base[name], float))
        for name, sched in self.schedules.items():
            overrides = {arg: values[col] for arg, col in self.schedule_args.get(name, {}).items()}
            signals[name] = sched.table(overrides)
        return input_table(signals)

    def case_start_values(self, values: dict[str, float]) -> dict[str, float]:
        sv = dict(self.fixed_start_values)
        sv.update({var: values[col] for col, var in self.start_columns.items()})
        return sv


# ---------------------------------------------------------------------------------------
# Log capture (one process-wide callback, routed by instance name)

_log_lock = threading.Lock()
_log_sinks: dict[str, list[tuple[int, str, str]]] = {}
_LOG_LIMIT = 20
_callbacks = None  # fmi2CallbackFunctions, kept alive for the life of the process
_logger_func = None  # the fmi2CallbackLoggerTYPE of _on_log, likewise


def _on_log(env, instance_name, status, category, message):  # called from C
    name = instance_name.decode("utf-8", "replace") if instance_name else ""
    sink = _log_sinks.get(name)
    if sink is not None and len(sink) < _LOG_LIMIT:
        sink.append((int(status), (category or b"").decode("utf-8", "replace"),
                     (message or b"").decode("utf-8", "replace")))


def point_logger_proxy_at(logger) -> None:
    """Make fmpy's native logger proxy call ``logger`` (an ``fmi2CallbackLoggerTYPE``,
    which the caller keeps alive). The proxy keeps ONE target for the whole process, and
    ``addLoggerProxy`` only re-points it when given callbacks whose logger is not the
    proxy already, hence the fresh struct."""
    from fmpy.fmi2 import fmi2CallbackFunctions
    from fmpy.logging import addLoggerProxy

    tmp = fmi2CallbackFunctions()
    tmp.logger = logger
    addLoggerProxy(byref(tmp))


def _install_logger():
    """The callbacks our instances are created with (their logger is the native proxy);
    the proxy is pointed at ``_on_log`` now, and again before every case (see run_case)."""
    global _callbacks, _logger_func
    with _log_lock:
        if _callbacks is None:
            import fmpy
            from fmpy.fmi2 import (
                fmi2CallbackAllocateMemoryTYPE,
                fmi2CallbackFreeMemoryTYPE,
                fmi2CallbackFunctions,
                fmi2CallbackLoggerTYPE,
            )
            from fmpy.logging import addLoggerProxy

            cb = fmi2CallbackFunctions()
            _logger_func = fmi2CallbackLoggerTYPE(_on_log)
            cb.logger = _logger_func
            cb.allocateMemory = fmi2CallbackAllocateMemoryTYPE(fmpy.calloc)
            cb.freeMemory = fmi2CallbackFreeMemoryTYPE(fmpy.free)
            cb.componentEnvironment = None
            addLoggerProxy(byref(cb))  # cb.logger becomes the proxy, which calls _on_log
            _callbacks = cb
        else:
            point_logger_proxy_at(_logger_func)
        return _callbacks


STATUS = {0: "ok", 1: "warning", 2: "discard", 3: "error", 4: "fatal", 5: "pending"}


# ---------------------------------------------------------------------------------------
# Inputs


class FastInput:
    """``fmpy.simulation.Input`` for continuous Real inputs, with the same arithmetic.

    fmpy's Input costs tens of microseconds a step (numpy on 1-element arrays), more than
    a step of a mechfmu FMU. This does the same interpolation (same index search, same
    ``math.isclose`` tests, the same floating-point operations in the same order, so the
    same values to the bit) on Python floats. ``make_input`` falls back on fmpy's class
    for anything else (discrete or tunable columns).
    """

    def __init__(self, fmu, table: np.ndarray, vrs: list[int]):
        names = table.dtype.names
        self.t = [float(x) for x in table[names[0]]]
        self.cols = [[float(x) for x in table[n]] for n in names[1:]]
        self.n = len(self.cols)
        self.vr = (c_uint * self.n)(*vrs)
        self.values = (c_double * self.n)()
        self.set_real = _raw(fmu, "fmi2SetReal")
        self.component = fmu.component
        t = self.t
        self.events = sorted({t[i] for i in range(len(t) - 1) if t[i + 1] - t[i] == 0} | {math.inf})

    def values_at(self, time: float, after_event: bool) -> list[float]:
        t, cols = self.t, self.cols
        n = len(t)
        if n < 2:
            return [c[0] for c in cols]
        i0 = bisect.bisect_left(t, time)
        if i0 == 0:
            return [c[0] for c in cols]
        if i0 == n:
            return [c[-1] for c in cols]
        if isclose(time, t[i0]) and i0 < n - 1 and isclose(t[i0], t[i0 + 1]):
            if after_event:
                while i0 < n - 1 and isclose(t[i0], t[i0 + 1]):
                    i0 += 1
            return [c[i0] for c in cols]
        i0 -= 1
        t0, t1 = t[i0], t[i0 + 1]
        w0 = (t1 - time) / (t1 - t0)
        w1 = 1 - w0
        return [w0 * c[i0] + w1 * c[i0 + 1] for c in cols]

    def apply(self, time: float, continuous=True, discrete=True, after_event=False) -> None:
        self.values[:] = self.values_at(time, after_event)
        self.set_real(self.component, self.vr, self.n, self.values)

    def nextEvent(self, time: float) -> float:
        ev = self.events
        i = bisect.bisect_right(ev, time)
        while isclose(ev[i], time):
            i += 1
        return ev[i]


def make_input(fmu, md, table: np.ndarray | None):
    """The fastest equivalent of ``fmpy.simulation.Input(fmu, md, table)``."""
    if table is None:
        return None
    by_name = {v.name: v for v in md.modelVariables}
    cols = table.dtype.names[1:]
    fast = all(
        c in by_name and by_name[c].type == "Real" and by_name[c].causality == "input"
        and by_name[c].variability == "continuous" and table[c].ndim == 1
        for c in cols
    )
    if fast:
        return FastInput(fmu, table, [by_name[c].valueReference for c in cols])
    from fmpy.simulation import Input

    with contextlib.redirect_stdout(io.StringIO()):  # fmpy's "missing input" notes
        return Input(fmu=fmu, modelDescription=md, signals=table)


def _raw(fmu, name: str):
    """The FMI function itself, with fmpy's status check (its `_call` wrapper costs more
    than a step of a small FMU)."""
    from fmpy.fmi1 import FMICallException

    f = getattr(fmu, "_functions", {}).get(name)
    if f is None or getattr(fmu, "fmiCallLogger", None) is not None:
        return getattr(fmu, name)

    def call(*args):
        status = f(*args)
        if status > 1:
            raise FMICallException(function=name, status=status)
        return status

    return call


# ---------------------------------------------------------------------------------------
# One instance


class Instance:
    """One FMU2Slave, instantiated once, reset between cases."""

    _count = 0

    def __init__(self, runtime: "Runtime"):
        from fmpy.fmi2 import FMU2Slave

        Instance._count += 1
        self.rt = runtime
        self.name = f"sweep-{os.getpid()}-{threading.get_ident()}-{Instance._count}"
        self.log: list[tuple[int, str, str]] = []
        _log_sinks[self.name] = self.log
        md = runtime.md
        self.fmu = FMU2Slave(
            guid=md.guid,
            unzipDirectory=runtime.unzipdir,
            modelIdentifier=md.coSimulation.modelIdentifier,
            instanceName=self.name,
        )
        self.fmu.instantiate(callbacks=_install_logger(), loggingOn=False)
        self.fresh = True
        self.broken = False
        self.freed = False

    def free(self) -> None:
        """fmi2FreeInstance and unload the library (once: each load is counted)."""
        if self.freed:
            return
        self.freed = True
        _log_sinks.pop(self.name, None)
        try:
            if self.fmu.component:
                self.fmu.fmi2FreeInstance(self.fmu.component)
                self.fmu.component = None
        finally:
            self.fmu.freeLibrary()

    def reset(self) -> None:
        if not self.fresh:
            self.fmu.reset()
        self.fresh = False


def log_message(log: Sequence[tuple[int, str, str]], min_status: int) -> str:
    """A row's message: the FMU's distinct messages of at least ``min_status``, the first three."""
    seen: list[str] = []
    for status, _cat, msg in log:
        if status >= min_status and msg not in seen:
            seen.append(msg)
    text = " | ".join(seen[:3])
    return text if len(text) <= 1000 else text[:997] + "..."


def extract(fmu: bytes | str | Path):
    """The FMU (its bytes, or its path) extracted into a new temporary folder: (the folder,
    the extracted FMU in it, its model description). The caller removes the folder when
    done; so does the end of the process, if it ends first (a worker stopped early)."""
    import fmpy
    from fmpy import read_model_description

    tmpdir = tempfile.mkdtemp(prefix="mechfmu-sweep-")
    atexit.register(shutil.rmtree, tmpdir, True)
    try:
        if isinstance(fmu, (bytes, bytearray)):
            path = os.path.join(tmpdir, "model.fmu")
            with open(path, "wb") as f:
                f.write(fmu)
        else:
            path = str(fmu)
        unzipdir = os.path.join(tmpdir, "unzipped")
        fmpy.extract(path, unzipdir)
        return tmpdir, unzipdir, read_model_description(unzipdir, validate=False)
    except BaseException:
        shutil.rmtree(tmpdir, ignore_errors=True)
        raise


class Runtime:
    """An extracted FMU and its instances (one per thread) on one process."""

    def __init__(self, fmu: bytes | str | Path, setup: CaseSetup):
        self.setup = setup
        self.tmpdir, self.unzipdir, self.md = extract(fmu)
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}
        self.can_vary_step = bool(self.md.coSimulation.canHandleVariableCommunicationStepSize)
        self.host = f"{socket.gethostname()}:{os.getpid()}"
        self._local = threading.local()
        self._instances: list[Instance] = []
        self._lock = threading.Lock()
        # variables sampled at every communication point, and read only at the end
        trajectory_vars = sorted({s.var for s in setup.summaries if s.func != "final"})
        final_vars = sorted({s.var for s in setup.summaries if s.func == "final"} - set(trajectory_vars))
        self.trajectory_vars = trajectory_vars
        self.final_vars = final_vars
        self._traj_vr = (c_uint * len(trajectory_vars))(*[self.vr[n] for n in trajectory_vars])
        self._final_vr = (c_uint * len(final_vars))(*[self.vr[n] for n in final_vars])

    # instances -------------------------------------------------------------------------
    def instance(self) -> Instance:
        inst = getattr(self._local, "inst", None)
        if inst is None or inst.broken:
            if inst is not None:
                with self._lock:
                    self._instances.remove(inst)
                with contextlib.suppress(Exception):
                    inst.free()
            inst = Instance(self)
            self._local.inst = inst
            with self._lock:
                self._instances.append(inst)
        return inst

    def close(self) -> None:
        with self._lock:
            for inst in self._instances:
                with contextlib.suppress(Exception):
                    inst.free()
            self._instances.clear()
        shutil.rmtree(self.tmpdir, ignore_errors=True)

    # cases -----------------------------------------------------------------------------
    def run(self, cases: Sequence[tuple[int, Sequence[float]]]) -> list[dict[str, Any]]:
        return [self.run_case(i, values) for i, values in cases]

    def run_case(self, index: int, values: Sequence[float]) -> dict[str, Any]:
        from fmpy.fmi1 import FMICallException

        setup = self.setup
        case = dict(zip(setup.columns, (float(v) for v in values)))
        row: dict[str, Any] = {"case": index, "status": "ok", "message": ""}
        started, cpu_started = _time.perf_counter(), _time.thread_time()
        inst = None
        stage = "setting up the case"
        try:
            start_values = setup.case_start_values(case)
            table = setup.case_input(case)
            inst = self.instance()
            inst.log.clear()
            _install_logger()  # someone in this process may have re-pointed fmpy's proxy
            stage = "fmi2Reset"
            inst.reset()
            stage = "simulating"
            t, y, finals = self._simulate(inst, start_values, table)
            row.update(self._summaries(t, y, finals))
            warn = log_message(inst.log, 1)
            if warn:
                row["status"], row["message"] = "warning", warn
        except FMICallException as e:
            status = STATUS.get(int(e.status), f"status {e.status}")
            row["status"] = status
            log = inst.log if inst is not None else []
            row["message"] = log_message(log, 2) or log_message(log, 0) or f"{e.function} returned fmi2{status.title()}"
            if inst is not None and (int(e.status) >= 4 or stage == "fmi2Reset"):
                inst.broken = True  # Fatal, or a reset that failed: a new instance next time
        except SpecError as e:
            row["status"], row["message"] = "error", str(e)
        except Exception as e:  # noqa: BLE001 - a case must never take the sweep down
            row["status"], row["message"] = "error", f"{type(e).__name__}: {e}"
            if inst is not None:
                inst.broken = True
        if row["status"] not in ("ok", "warning"):
            for s in setup.summaries:
                row.setdefault(s.column, float("nan"))
        row["elapsed_s"] = _time.perf_counter() - started
        row["cpu_s"] = _time.thread_time() - cpu_started
        row["worker"] = self.host
        return row

    def _summaries(self, t, y, finals) -> dict[str, float]:
        out = {}
        for s in self.setup.summaries:
            if s.var in finals and s.func == "final":
                out[s.column] = finals[s.var]
            else:
                j = self.trajectory_vars.index(s.var)
                out[s.column] = summarize(s.func, t, y[:, j])
        return out

    def _simulate(self, inst: Instance, start_values: dict[str, float], table):
        """fmpy.simulation.simulateCS for FMI 2.0, recording only what the summaries need."""
        from fmpy.fmi2 import fmi2Discard, fmi2LastSuccessfulTime, fmi2Terminated, fmi2True
        from fmpy.fmi1 import FMICallException
        from fmpy.simulation import (
            apply_start_values,
            settable_in_initialization_mode,
            settable_in_instantiated,
        )

        setup, md, fmu = self.setup, self.md, inst.fmu
        start_time, stop_time, interval = setup.start_time, setup.stop_time, setup.output_interval
        inp = make_input(fmu, md, table)

        time = start_time
        fmu.setupExperiment(tolerance=setup.tolerance, startTime=time,
                            stopTime=stop_time if setup.set_stop_time else None)
        rest = apply_start_values(fmu, md, start_values, settable=settable_in_instantiated)
        fmu.enterInitializationMode()
        rest = apply_start_values(fmu, md, rest, settable=settable_in_initialization_mode)
        if inp is not None:
            inp.apply(time)
        fmu.exitInitializationMode()
        if rest:
            raise SpecError("these variables could not be set: " + ", ".join(rest))

        component = fmu.component
        get_real, do_step = _raw(fmu, "fmi2GetReal"), _raw(fmu, "fmi2DoStep")
        traj_vr, nt = self._traj_vr, len(self.trajectory_vars)
        buf = (c_double * max(nt, 1))()
        times: list[float] = []
        rows: list[list[float]] = []

        def sample(t: float) -> None:
            if nt:
                get_real(component, traj_vr, nt, buf)
                rows.append(buf[:nt])
            times.append(t)

        sample(time)
        n_steps = 0
        can_vary = self.can_vary_step
        while True:
            if time > stop_time or isclose(time, stop_time):
                break
            next_regular_point = start_time + (n_steps + 1) * interval
            next_cp = next_regular_point
            next_event = inp.nextEvent(time) if inp is not None else math.inf
            if can_vary and next_cp > next_event and not isclose(next_cp, next_event):
                next_cp = next_event
            if next_cp > stop_time and not isclose(next_cp, stop_time):
                if can_vary:
                    next_cp = stop_time
                else:
                    break
            if inp is not None:
                inp.apply(time, continuous=True, discrete=True, after_event=True)
            try:
                do_step(component, time, next_cp - time, fmi2True)
            except FMICallException as e:
                if e.status == fmi2Discard:
                    last = time
                    with contextlib.suppress(Exception):
                        if fmu.getBooleanStatus(fmi2Terminated):
                            last = fmu.getRealStatus(fmi2LastSuccessfulTime)
                    inst.log.append((2, "", f"fmi2DoStep discarded the step from t = {time:g} "
                                            f"(last successful time {last:g})"))
                raise
            time = next_cp
            sample(time)
            if isclose(time, next_regular_point):
                n_steps += 1

        finals = {}
        if self.final_vars:
            fb = (c_double * len(self.final_vars))()
            get_real(component, self._final_vr, len(self.final_vars), fb)
            finals = dict(zip(self.final_vars, fb[:]))
        fmu.terminate()
        y = np.array(rows, dtype=float) if nt else np.empty((len(times), 0))
        return np.array(times), y, finals
