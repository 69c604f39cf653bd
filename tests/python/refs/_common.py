"""Shared machinery of the reference models: parameters, zero-order-hold inputs and
the DOP853 driver.

Input tables are fmpy-style structured arrays: the first field is time, the others are
named after the FMU's inputs. The references read them as a zero-order hold: at time t an
input has the value of the LAST row whose time is <= t (so the value switches AT the
listed time; before the first row the first row's value holds). The integration is
restarted at every row time, so the discontinuities never sit inside an integrator step.

Note: fmpy itself interpolates continuous Real inputs linearly between rows of different
times. A table in which every change is written as two rows with the same time (see
`step_input`) is read identically by fmpy and by these references.
"""

from __future__ import annotations

import math
from typing import Callable, Mapping, Sequence

import numpy as np
from scipy.integrate import solve_ivp

__all__ = ["merge", "case_settings", "step_input", "zoh_value", "run", "trolley_at_pivot", "with_constants",
           "split", "solution"]


def merge(defaults: Mapping[str, float], overrides: Mapping[str, float] | None, what: str) -> dict:
    """Defaults updated by overrides; unknown names are an error (typos must not pass)."""
    out = dict(defaults)
    if overrides:
        unknown = set(overrides) - set(defaults)
        if unknown:
            raise KeyError(f"unknown {what} name(s): {sorted(unknown)}; known: {sorted(defaults)}")
        out.update({k: float(v) for k, v in overrides.items()})
    return out



def case_settings(params: Mapping[str, float], start: Mapping[str, float], experiment: Mapping[str, float],
                  p: Mapping[str, float] | None, y0: Mapping[str, float] | None,
                  t_out) -> tuple[dict, dict, np.ndarray]:
    """A reference run's parameters and start values (the defaults updated by ``p`` and
    ``y0``, see ``merge``) and its output times (by default the experiment's grid)."""
    if t_out is None:
        t_out = np.arange(0.0, experiment["stop"] + 1e-12, experiment["step"])
    return merge(params, p, "parameter"), merge(start, y0, "state"), t_out


def with_constants(res: dict, values: Mapping[str, float]) -> dict:
    """A run's result ``res`` with a column, constant over its times, per entry of ``values``
    (the quantities calculated from the parameters)."""
    for k, v in values.items():
        res[k] = np.full_like(res["time"], v)
    return res


def trolley_at_pivot(t, y, p, u):
    """A crane's terminal event: the trolley (the first state, its distance along the boom)
    reaching the pivot."""
    return y[0]


trolley_at_pivot.terminal = True
trolley_at_pivot.direction = -1
trolley_at_pivot.message = "the trolley reached the pivot (x = 0)"

def step_input(names: Sequence[str], times: Sequence[float], values: Sequence[Sequence[float]],
               t_end: float | None = None) -> np.ndarray:
    """fmpy-style table of piecewise-constant inputs.

    values[i] (one entry per name) holds from times[i] to times[i+1]. Every change is
    written as two rows with the same time, so fmpy (which interpolates linearly between
    rows of different times) and these references see the same zero-order hold.
    """
    names = list(names)
    times = [float(t) for t in times]
    vals = [list(np.atleast_1d(np.asarray(v, dtype=float))) for v in values]
    if len(times) != len(vals):
        raise ValueError("one row of values per time")
    if any(len(v) != len(names) for v in vals):
        raise ValueError("each row of values needs one value per input name")
    rows = [(times[0], *vals[0])]
    for i in range(1, len(times)):
        rows.append((times[i], *vals[i - 1]))
        rows.append((times[i], *vals[i]))
    if t_end is not None and t_end > times[-1]:
        rows.append((float(t_end), *vals[-1]))
    dtype = [("time", np.float64)] + [(n, np.float64) for n in names]
    return np.array(rows, dtype=dtype)


def _table(inputs, input_names):
    """(times, values[n_rows, n_inputs]) from a structured array, inputs absent -> None."""
    if inputs is None:
        return None
    if inputs.dtype.names is None:
        raise TypeError("inputs must be a structured array (time column + named input columns)")
    tname = inputs.dtype.names[0]
    t = np.asarray(inputs[tname], dtype=float)
    if np.any(np.diff(t) < 0):
        raise ValueError("input times must be non-decreasing")
    unknown = [n for n in inputs.dtype.names[1:] if n not in input_names]
    if unknown:
        raise KeyError(f"unknown input column(s) {unknown}; inputs are {list(input_names)}")
    return t, {n: np.asarray(inputs[n], dtype=float) for n in inputs.dtype.names[1:]}


def zoh_value(table, defaults: Mapping[str, float], t: float, before: bool = False) -> dict:
    """Input values at time t (zero-order hold, last row with time <= t wins).

    before=True gives the left limit (last row with time < t), i.e. the value that was
    held over the step that ends at t.
    """
    u = dict(defaults)
    if table is None:
        return u
    times, cols = table
    side = "left" if before else "right"
    i = int(np.searchsorted(times, t, side=side)) - 1
    i = max(i, 0)
    for n, col in cols.items():
        u[n] = float(col[i])
    return u


def run(rhs: Callable, outputs: Callable, state_names: Sequence[str], y0: Sequence[float],
        t_out, p: dict, input_defaults: Mapping[str, float], inputs, rtol: float, atol: float,
        switch_outputs: str = "after", events=None, max_evals: int = 300_000) -> dict:
    """Integrate rhs(t, y, p, u) with DOP853, restarting at every input row time.

    Returns {'time': t_out, state: array, output: array, input: array}. Outputs that
    depend on the inputs are evaluated with the input value AFTER a switch at a switch
    time (switch_outputs="after"), or with the value held over the step that ends there
    (switch_outputs="before": what fmpy records for a co-simulation FMU, which computes
    the outputs at the end of doStep with the input it was given at the step's start).
    More than max_evals right-hand-side calls raise RuntimeError (a runaway solution must
    fail a test, not hang it).
    """
    t_out = np.asarray(t_out, dtype=float)
    if t_out.ndim != 1 or t_out.size < 1 or np.any(np.diff(t_out) < 0):
        raise ValueError("t_out must be a non-empty non-decreasing 1-D array")
    if switch_outputs not in ("after", "before"):
        raise ValueError("switch_outputs is 'after' or 'before'")
    table = _table(inputs, input_defaults)
    t0, t1 = float(t_out[0]), float(t_out[-1])
    cuts = [t0]
    if table is not None:
        cuts += sorted({float(t) for t in table[0] if t0 < t < t1})
    cuts.append(t1)

    count = [0]

    def f(t, y, p_, u_):
        count[0] += 1
        if count[0] > max_evals:
            raise RuntimeError(f"more than {max_evals} right-hand-side calls by t = {t:.9g}: "
                               "the solution runs away or is very stiff")
        return rhs(t, y, p_, u_)

    n = len(state_names)
    Y = np.empty((n, t_out.size))
    y = np.asarray(y0, dtype=float).copy()
    for a, b in zip(cuts[:-1] if n else [], cuts[1:]):  # a stateless element integrates nothing
        u = zoh_value(table, input_defaults, a)
        mask = (t_out >= a) & (t_out <= b)
        idx = np.flatnonzero(mask)
        if b > a:
            te_ = t_out[idx]
            extra = not (idx.size and te_[-1] == b)
            if extra:
                te_ = np.append(te_, b)
            sol = solve_ivp(f, (a, b), y, method="DOP853", t_eval=te_,
                            args=(p, u), rtol=rtol, atol=atol, events=events)
            if sol.status == 1:  # a terminal event fired
                fired = [len(e) > 0 for e in sol.t_events].index(True)
                te = sol.t_events[fired][0]
                raise RuntimeError(f"reference stopped at t = {te:.9g}: "
                                   f"{getattr(events[fired], 'message', 'terminal event')}")
            if not sol.success:
                raise RuntimeError(f"solve_ivp failed on [{a}, {b}]: {sol.message}")
            if idx.size:
                Y[:, idx] = sol.y[:, :idx.size]
            y = sol.y[:, -1].copy()
        else:
            Y[:, idx] = y[:, None]

    res = {"time": t_out.copy()}
    for i, name in enumerate(state_names):
        res[name] = Y[i].copy()
    out_cols: dict[str, list] = {}
    for j, t in enumerate(t_out):
        before = switch_outputs == "before" and j > 0
        u = zoh_value(table, input_defaults, t, before=before)
        o = outputs(t, Y[:, j], p, u)
        for k, v in o.items():
            out_cols.setdefault(k, []).append(v)
        for k, v in u.items():
            out_cols.setdefault(k, []).append(v)
    for k, v in out_cols.items():
        res[k] = np.asarray(v, dtype=float)
    return res


def isclose_rel(a: float, b: float, rel: float = 1e-9) -> bool:
    return abs(a - b) <= rel * max(abs(a), abs(b))


def finite(*xs: float) -> bool:
    return all(math.isfinite(x) for x in xs)


def split(ref, start_values: Mapping[str, float]) -> tuple[dict, dict]:
    """A case's start values as the reference module ``ref`` takes them: (its parameters, the
    start values of its states)."""
    return ({k: v for k, v in start_values.items() if k in ref.PARAMS},
            {k: v for k, v in start_values.items() if k in ref.START})


def solution(ref, start_values: Mapping[str, float], inputs=None) -> Callable:
    """``ref``'s DOP853 solution from a case's start values, as a function of the output times
    (an output at an input's switch takes its value from before the switch, as an FMU's
    output at a communication point does)."""
    p, y0 = split(ref, start_values)
    return lambda t: ref.simulate(p, y0, t, inputs, switch_outputs="before")
