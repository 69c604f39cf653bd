"""Reference cases: declared once in ``<crate>/validation/cases.py``, run by
``mechfmu validate`` (under each of its importers) and by the test suite (``tests/python/test_cases.py``).

A case says how to run the FMU (start values, an input table, stop time, output interval,
relative tolerance), what to compare (``outputs``, FMU variables, and ``derived`` signals
computed from the FMU's result, e.g. an energy the FMU does not output), and what to compare
against: ``reference(time) -> {name: array}``, built from closed forms or an independent
high-accuracy solution, never from the FMU. The error of a signal is

    max over t of |FMU(t) - reference(t)| / scale

with ``scale`` the range (max - min) of the reference signal, or ``max |reference|`` when the
reference is constant (an invariant: the error is then the relative drift), or the case's
``scale[name]``. A case passes when every signal's error is at most ``tolerance`` (a number,
or a dict by signal name). ``metric(result) -> {name: error array}`` adds checks that are not a
comparison with a reference (e.g. an identity between outputs), already normalized.

Example (``fmus/oscillator/validation/cases.py``)::

    from mechfmu_validate.case import Case
    from refs import oscillator as osc

    CASES = [
        Case("free_overdamped", start_values={"c": 5.0}, stop_time=20.0, output_interval=0.01,
             relative_tolerance=1e-8, outputs=["x", "x_dot"],
             reference=lambda t: dict(zip(["x", "x_dot"], osc.free_response({"c": 5.0}, 1.0, 0.0, t))),
             tolerance=1e-6),
    ]
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Callable, Mapping, Sequence

import numpy as np

__all__ = ["Case", "Result", "SignalError", "Evaluation", "evaluate", "signal_scale", "step_input"]

Reference = Callable[[np.ndarray], Mapping[str, np.ndarray]]


@dataclass
class Case:
    """One reference case of a mechanism (see the module docstring)."""

    name: str
    stop_time: float
    output_interval: float
    outputs: Sequence[str]
    reference: Reference
    start_values: Mapping[str, float] = field(default_factory=dict)
    #: an fmpy-style structured input array (time + named inputs), or a function making one
    input: np.ndarray | Callable[[], np.ndarray] | None = None
    #: FMPy's relative_tolerance; None: the FMU's DefaultExperiment tolerance
    relative_tolerance: float | None = 1e-8
    tolerance: float | Mapping[str, float] = 1e-6
    description: str = ""
    #: signals computed from the FMU's result (e.g. an energy), compared like outputs
    derived: Mapping[str, Callable[["Result"], np.ndarray]] = field(default_factory=dict)
    #: error signals computed from the FMU's result alone (normalized), e.g. an identity
    metric: Callable[["Result"], Mapping[str, np.ndarray]] | None = None
    #: normalizers of the error, by signal name (default: the reference's range)
    scale: Mapping[str, float] = field(default_factory=dict)
    #: extra FMU variables to record (those ``derived`` and ``metric`` need)
    record: Sequence[str] = ()
    #: the mechanism's default experiment
    default_experiment: bool = False
    #: the columns of the reference files `--write-references` takes from this case (at most
    #: 10 outputs); without such a case, the default experiment's outputs are
    reference_files: Sequence[str] = ()
    #: the signals drawn against the reference in the report's plot (default: the compared
    #: signals that vary, at most eight); every signal's error is drawn in any case
    plot: Sequence[str] = ()
    #: a plot worth showing with the validation tables (`mechfmu validate --readme DIR` writes
    #: it to DIR/validation/<stem>.png): True (the stem ``<FMU>-<case>``), or the stem
    highlight: bool | str = False

    def input_table(self) -> np.ndarray | None:
        return self.input() if callable(self.input) else self.input

    def recorded(self) -> list[str]:
        """The FMU variables to record: the compared outputs, then ``record``."""
        out: list[str] = []
        for n in [*self.outputs, *self.record]:
            if n not in out:
                out.append(n)
        return out

    def signals(self) -> list[str]:
        return [*self.outputs, *[d for d in self.derived if d not in self.outputs]]

    def tolerance_of(self, name: str) -> float:
        if isinstance(self.tolerance, Mapping):
            if name in self.tolerance:
                return float(self.tolerance[name])
            return float(self.tolerance.get("*", 1e-6))
        return float(self.tolerance)

    def steps(self) -> int:
        """Number of communication steps (stop_time / output_interval, an integer)."""
        n = self.stop_time / self.output_interval
        if abs(n - round(n)) > 1e-9 * max(1.0, n):
            raise ValueError(f"case {self.name}: stop_time {self.stop_time} is not a multiple of "
                             f"output_interval {self.output_interval}")
        return int(round(n))


class Result:
    """An FMU run: the recorded variables by name, and ``time``."""

    def __init__(self, table: np.ndarray | Mapping[str, np.ndarray], log: Sequence[str] = ()):
        if isinstance(table, np.ndarray) and table.dtype.names:
            self.columns = {n: np.asarray(table[n], dtype=float) for n in table.dtype.names}
        else:
            self.columns = {n: np.asarray(v, dtype=float) for n, v in table.items()}
        self.log = list(log)

    @property
    def time(self) -> np.ndarray:
        return self.columns["time"]

    def __getitem__(self, name: str) -> np.ndarray:
        return self.columns[name]

    def __contains__(self, name: str) -> bool:
        return name in self.columns

    def names(self) -> list[str]:
        return [n for n in self.columns if n != "time"]


#: a reference signal whose range is below this fraction of its magnitude counts as constant
#: (an invariant, or a quantity the reference holds constant up to its own round-off)
CONSTANT = 1e-6


def signal_scale(ref: np.ndarray) -> float:
    """The range of a reference signal; for a constant one (range below CONSTANT times its
    magnitude), its magnitude; for zero, 1 (an absolute error)."""
    ref = np.asarray(ref, dtype=float)
    rng = float(np.max(ref) - np.min(ref))
    mag = float(np.max(np.abs(ref)))
    if rng > CONSTANT * mag and rng > 0.0:
        return rng
    return mag if mag > 0.0 else 1.0


@dataclass
class SignalError:
    name: str
    max_error: float  # normalized
    at_time: float
    scale: float
    tolerance: float
    error: np.ndarray  # normalized, over time
    fmu: np.ndarray | None = None
    reference: np.ndarray | None = None

    @property
    def passed(self) -> bool:
        return bool(np.isfinite(self.max_error) and self.max_error <= self.tolerance)


@dataclass
class Evaluation:
    case: Case
    time: np.ndarray
    signals: list[SignalError]
    problem: str | None = None  # the run or the reference failed

    @property
    def passed(self) -> bool:
        return self.problem is None and all(s.passed for s in self.signals)

    @property
    def worst(self) -> SignalError | None:
        """The signal furthest beyond (or closest to) its tolerance."""
        if not self.signals:
            return None
        return max(self.signals, key=lambda s: (s.max_error / s.tolerance) if np.isfinite(s.max_error) else math.inf)


def _error_of(name, got, want, scale, tol, time) -> SignalError:
    got = np.asarray(got, dtype=float)
    want = np.asarray(want, dtype=float)
    if got.shape != want.shape:
        raise ValueError(f"{name}: the FMU gave {got.shape[0]} samples, the reference {want.shape[0]}")
    err = np.abs(got - want) / scale
    err = np.where(np.isfinite(err), err, np.inf)
    i = int(np.argmax(err))
    return SignalError(name, float(err[i]), float(time[i]), float(scale), tol, err, got, want)


def evaluate(case: Case, result: Result) -> Evaluation:
    """Compares an FMU result with the case's reference (and its metric)."""
    t = result.time
    try:
        ref = case.reference(t)
    except Exception as e:  # a reference that cannot be computed is the case's failure
        return Evaluation(case, t, [], problem=f"the reference failed: {type(e).__name__}: {e}")
    signals: list[SignalError] = []
    try:
        for name in case.signals():
            if name in case.derived:
                got = np.asarray(case.derived[name](result), dtype=float)
            else:
                got = result[name]
            if name not in ref:
                raise KeyError(f"the reference has no signal {name!r} (it has {sorted(ref)})")
            want = np.broadcast_to(np.asarray(ref[name], dtype=float), t.shape)
            scale = float(case.scale[name]) if name in case.scale else signal_scale(want)
            signals.append(_error_of(name, got, want, scale, case.tolerance_of(name), t))
        if case.metric is not None:
            for name, err in case.metric(result).items():
                err = np.broadcast_to(np.abs(np.asarray(err, dtype=float)), t.shape)
                err = np.where(np.isfinite(err), err, np.inf)
                i = int(np.argmax(err))
                signals.append(SignalError(name, float(err[i]), float(t[i]), 1.0, case.tolerance_of(name), err))
    except Exception as e:
        return Evaluation(case, t, signals, problem=f"{type(e).__name__}: {e}")
    return Evaluation(case, t, signals)


def step_input(names: Sequence[str], times: Sequence[float], values: Sequence[Sequence[float]],
               stop_time: float) -> np.ndarray:
    """A piecewise-constant input table in fmpy's format: ``values[i]`` holds from
    ``times[i]`` to ``times[i+1]``; every change is written as two rows at the same time, so
    FMPy (which interpolates between rows of different times), an importer fed the same
    values at every communication point, and a zero-order-hold reference all agree. Put the
    change times on the communication grid."""
    names = list(names)
    rows = [(float(times[0]), *map(float, values[0]))]
    for i in range(1, len(times)):
        rows.append((float(times[i]), *map(float, values[i - 1])))
        rows.append((float(times[i]), *map(float, values[i])))
    if stop_time > times[-1]:
        rows.append((float(stop_time), *map(float, values[-1])))
    return np.array(rows, dtype=[("time", np.float64)] + [(n, np.float64) for n in names])


def describe(case: Case) -> dict[str, Any]:
    """The case's settings, for JSON and the report."""
    return {
        "name": case.name,
        "description": case.description,
        "start_values": dict(case.start_values),
        "stop_time": case.stop_time,
        "output_interval": case.output_interval,
        "relative_tolerance": case.relative_tolerance,
        "outputs": list(case.outputs),
        "derived": list(case.derived),
        "has_input": case.input is not None,
    }
