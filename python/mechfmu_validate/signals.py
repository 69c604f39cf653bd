"""The signals of a case as every importer sees them: the inputs it is fed (the values FMPy's
input logic gives at each communication point, :func:`input_values`, held between them in
Model Exchange, :func:`held_input`), and the variables a case names (:func:`unknown_names`;
:func:`real_signals` for the importers that set and record Real variables only).

Every importer runs the same experiment: the case's start values, its input table (FMPy
reads it itself; the other importers are fed, before every communication step, the value
FMPy's input logic gives at that communication point), a fixed communication step (the
case's ``output_interval``) from 0 to ``stop_time``. In Model Exchange the inputs are the
Co-Simulation run's: the value FMPy applies at each communication point, held to the next
(:func:`held_input`), so every run of a case sees the same signal.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Any, Protocol

import numpy as np

from .case import Case, step_input

__all__ = ["held_input", "input_events_on_grid", "input_values", "real_signals", "unknown_names"]


class Named(Protocol):
    """What names variables: an :class:`~.fmu.Fmu`, or an FMI 3.0 FMU's :class:`~.arrays.ArrayMap`."""

    @property
    def variables(self) -> dict[str, Any]: ...


def input_values(case: Case, fmu: Named, t: float) -> tuple[list[str], list[float]]:
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


def held_input(case: Case, fmu: Named) -> np.ndarray | None:
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


def unknown_names(case: Case, fmu: Named) -> list[str]:
    """The variables the case sets, feeds or records that the FMU does not have."""
    table = case.input_table()
    named = [*case.start_values, *(table.dtype.names[1:] if table is not None else ()), *case.recorded()]
    return list(dict.fromkeys(n for n in named if n not in fmu.variables))


def real_signals(case: Case, fmu: Named) -> tuple[Case | None, str]:
    """The case as an importer of Real variables only runs it (what it can set and record),
    and a note; None (and why) when there is nothing Real to compare."""
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
