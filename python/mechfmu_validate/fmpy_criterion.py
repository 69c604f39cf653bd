"""FMPy's cross-check criterion, a row of its own beside mechfmu's verdict on a reference: the
rule the FMI cross-check judges an importer's result by (``fmpy.cross_check.validate_result``).

FMPy resamples each signal of the reference on 1000 points over [StartTime, StopTime] and
draws a band around it: a moving minimum and maximum over 21 of those points (about 1 % of
the window each way in time), widened by 10 % of the signal's range (of its value when it
is constant; 0.5 when it is 0). A result fails when more than 10 % of its samples of any
signal lie outside their band, when it does not span the window, or when a signal is
missing. The row's verdict and its problem are ``validate_result``'s; its max error is the
largest fraction of a signal's samples outside the band (the signal named in the notes),
its tolerance :data:`LIMIT`.
"""

from __future__ import annotations

import math
import warnings
from typing import TYPE_CHECKING

import numpy as np

from fmpy.cross_check import validate_result, validate_signal

from .rows import Row

if TYPE_CHECKING:  # pragma: no cover
    from .case import Result
    from .embedded_reference import EmbeddedReference

__all__ = ["CRITERION", "LIMIT", "NOTE", "importer_name", "result_table", "judge", "criterion_row",
           "experiment_problem"]

#: what the importer column adds to the name of the run judged
CRITERION = "cross-check criterion"
#: the largest fraction of a signal's samples that may lie outside its band
LIMIT = 0.1
NOTE = ("FMPy's cross-check criterion (fmpy.cross_check.validate_result): at most 10 % of each signal's samples "
        "outside a band of 10 % of its range around the reference")


def importer_name(importer: str) -> str:
    """The importer column of the criterion's row on ``importer``'s run."""
    return f"{importer} {CRITERION}"


def result_table(result: Result, names: list[str]) -> np.ndarray:
    """``result``'s ``time`` and the ``names`` it has, as the structured array FMPy's
    criterion reads."""
    present = [n for n in names if n in result]
    table = np.zeros(len(result.time), dtype=[("time", np.float64)] + [(n, np.float64) for n in present])
    table["time"] = result.time
    for n in present:
        table[n] = result[n]
    return table


def judged_window(ref: EmbeddedReference) -> tuple[float, float]:
    """The span the criterion judges: the experiment's, or up to the reference's last time when
    the reference ends before the stop time (its FMU ends the simulation there, as the
    Reference-FMUs' Stair does at 9 s of 10): no result can show more than the exporter's own."""
    t_start, t_stop = ref.window
    return t_start, min(t_stop, float(ref.table["time"][-1]))


def judge(result: Result, ref: EmbeddedReference) -> tuple[str | None, dict[str, float]]:
    """(``validate_result``'s problem, None when the result passes; each signal's fraction of
    samples outside its band)."""
    reference = ref.table
    names = list(reference.dtype.names[1:])
    table = result_table(result, names)
    t_start, t_stop = judged_window(ref)
    with warnings.catch_warnings():  # FMPy imports its filters from a namespace scipy deprecates
        warnings.simplefilter("ignore", DeprecationWarning)
        problem = validate_result(result=table, reference=reference, t_start=t_start, t_stop=t_stop)
        outside = {}
        for n in table.dtype.names[1:]:
            *_, out = validate_signal(t=table["time"], y=table[n], t_ref=reference["time"], y_ref=reference[n],
                                      t_start=t_start, t_stop=t_stop)
            outside[n] = float(np.mean(out)) if len(out) else 0.0
    return problem, outside


def criterion_row(fmu_name: str, ref: EmbeddedReference, result: Result | None, importer: str,
                  anchor: str = "") -> Row:
    """The criterion's row on ``importer``'s run of the reference (``result``, None when that
    run failed)."""
    row = Row(kind="reference", fmu=fmu_name, case=ref.case.name, importer=importer_name(importer), anchor=anchor,
               tolerance=LIMIT, problems=[], notes=[NOTE])
    if result is None:
        return row.but(max_error=math.inf, passed=False,
                    problems=[f"the {importer} run failed: no result for the criterion to judge"])
    try:
        problem, outside = judge(result, ref)
    except Exception as e:  # noqa: BLE001 (a row, not a crash)
        return row.but(max_error=math.inf, passed=False,
                    problems=[f"FMPy's criterion failed: {type(e).__name__}: {e}"])
    worst = max(outside, key=outside.get, default=None)
    problems = [problem] if problem else []
    not_finite = [n for n in ref.table.dtype.names[1:] if n in result and not np.all(np.isfinite(result[n]))]
    if not_finite:  # FMPy's band test lets NaN through (NaN < min is false)
        problems.append(f"{', '.join(not_finite)}: samples that are not finite (NaN or infinite); FMPy's band test "
                        "does not see them, a result must not have them")
    # validate_result looks only at the signals the result has: one it lacks is every sample
    # outside its band
    missing = [n for n in ref.table.dtype.names[1:] if n not in result]
    if missing:
        problems.append(f"{', '.join(missing)}: in the reference, not in the result: the criterion judges every "
                        "signal of the reference")
        outside.update(dict.fromkeys(missing, 1.0))
        worst = max(outside, key=outside.get)
    row.update(max_error=outside[worst] if worst else 0.0, passed=not problems, problems=problems,
               signals={n: dict(max_error=f, tolerance=LIMIT, passed=f <= LIMIT) for n, f in outside.items()})
    if worst:
        row["notes"] = [f"worst signal {worst}: {outside[worst]:.1%} of its samples outside the band", NOTE]
    t_stop = judged_window(ref)[1]
    if t_stop < ref.window[1]:
        row["notes"].append(f"judged up to {t_stop:g} s, where the reference ends (the stop time is "
                            f"{ref.window[1]:g} s)")
        # a cross-check tree's verdict file is held to the whole experiment, as
        # fmpy.cross_check.validate_vendor_repo holds it
        row["experiment_problem"] = experiment_problem(result, ref)
    return row


def experiment_problem(result: Result, ref: EmbeddedReference) -> str | None:
    """``validate_result``'s problem over the whole experiment of the options file, even where
    the reference ends before its stop time; None when the result passes."""
    table = result_table(result, list(ref.table.dtype.names[1:]))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        return validate_result(result=table, reference=ref.table, t_start=ref.window[0], t_stop=ref.window[1])
