"""The reference cases in Model Exchange, and how their rows are judged.

In Model Exchange the importer's solver integrates, so a row measures that solver as much as
the FMU. A row is PASS, FAIL, or LIMIT: the importer's solver did not reach the case's
limit, and the error it reached is reported, not failed. What fails is what the FMU can be
blamed for.

* ``FMPy ME CVode``: FMPy's CVode (BDF) at relative tolerance 1e-10, against the case's
  reference and held to the case's own limits, as the Co-Simulation rows are, down to
  :data:`CVODE_FLOOR`: a case that asks more of an invariant (1e-8) than CVode reaches at
  that tolerance (up to 4e-7 over the cases' horizons; they pass at 1e-12) is LIMIT. This is
  the row that gates the FMU: a wrong derivative shows far above the floor.
* ``FMPy ME Euler`` and ``... ME RK4``: fixed-step methods of order p, whose error is
  their truncation error C h^p + O(h^(p+1)), far above most cases' limits for Euler. Each runs
  at two steps, h and h/2, and a signal passes when its error meets the case's limit, or when
  halving the step divides it by 2^p: the observed order log2(e(h) / e(h/2)) within
  :data:`ORDER_SLACK` of p. Below, part of the error does not scale with h^p: it is not the
  method's but the FMU's (a wrong derivative, an input or an event handled differently).
  Above, the error falls faster than the method's order says: h is not yet in the method's
  asymptotic range (nor is it while the error is as large as the signal), and h is halved,
  down to a floor, until it is. RK4 may also be one order above: a quantity the flow
  conserves drifts at O(h^5) under it (on an undamped oscillation |R(i w h)|^2 =
  1 - (w h)^6 / 72 per step), and at O(h) under Euler, as its solution's error
  (|1 + i w h|^2 = 1 + (w h)^2).

The step is the case's output interval over 2, 4 or 8 for Euler, over 1 or 2 for RK4 (the
case's step, as in Co-Simulation): the first of them at which h is not too coarse. A
fixed-step row that completes but passes neither way is LIMIT, with its orders reported:
outside the method's asymptotic range at the finest step tried (a top spinning at 40 rad/s
under Euler), or limited by what the FMU holds to its own tolerance (the rigid body's |q|, which
the importer's solver keeps about its own tolerance from 1). It fails when the
run does (an error status, a crash, a missed termination).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass
from typing import Any, Callable

import numpy as np

from .case import Case, Evaluation, Result, evaluate
from .fmu import Fmu, NotSupported
from .rows import Row

__all__ = ["CVODE_FLOOR", "CVODE_RTOL", "FixedStep", "OrderCheck", "ORDER_SLACK", "band_text", "order_band",
           "run_cvode", "run_fixed_step", "cvode_row", "fixed_step_row"]

#: the relative tolerance of CVode in the Model Exchange runs
CVODE_RTOL = 1e-10

#: how far the observed order may be from the method's: it tolerates a next term of the
#: error's expansion of about a quarter of the leading one at h, and a part b of the error
#: that does not scale with h only while b < 0.23 C h (Euler; 0.14 C h when b cancels
#: the truncation error), b < 0.013 C h^4 (RK4; 0.037 C h^4)
ORDER_SLACK = 0.25

CVODE_NOTE = f"FMPy's CVode (BDF) at relative tolerance {CVODE_RTOL:g}, against the reference"

#: the largest error of a CVode row that is LIMIT rather than FAIL: the limit of most cases,
#: 2.5 times CVode's worst measured drift of an invariant at rtol 1e-10 (4e-7)
CVODE_FLOOR = 1e-6


@dataclass(frozen=True)
class FixedStep:
    """A fixed-step Model Exchange importer: its row name, its order, the observed orders it
    passes with, the steps it tries (the output interval over ``divisions``, doubled up to
    ``max_divisions``), and how it runs a case at step h."""

    importer: str
    order: int
    band: tuple[float, float]
    divisions: int
    max_divisions: int
    run: Callable[[Fmu, Case, float], Result]


def order_band(order: int, highest: int | None = None) -> tuple[float, float]:
    """The observed orders a method of ``order`` passes with: ``order`` within
    :data:`ORDER_SLACK`, up to ``highest`` (a conserved quantity drifting one order above)."""
    return order - ORDER_SLACK, (highest or order) + ORDER_SLACK


@dataclass
class OrderCheck:
    """One signal of a fixed-step run: its error at h and at h/2 (fractions of its scale)."""

    name: str
    error: float
    error_half: float
    tolerance: float  # the case's
    band: tuple[float, float]  # the observed orders that pass

    @property
    def observed(self) -> float:
        """log2(e(h) / e(h/2)); nan when both are 0."""
        if not (math.isfinite(self.error) and math.isfinite(self.error_half)):
            return math.nan
        if self.error_half == 0.0:
            return math.inf if self.error > 0.0 else math.nan
        return math.log2(self.error / self.error_half) if self.error > 0.0 else -math.inf

    @property
    def within_tolerance(self) -> bool:
        return bool(math.isfinite(self.error) and self.error <= self.tolerance)

    @property
    def passed(self) -> bool:
        return self.within_tolerance or self.band[0] <= self.observed <= self.band[1]

    @property
    def too_coarse(self) -> bool:
        """h is outside the method's asymptotic range: the error falls faster than its order
        says, or as fast but is as large as the signal (C h^p describes a small error). An
        error falling slower is not the method's: a finer h would not help."""
        falls = self.observed > self.band[1] or (self.observed >= self.band[0] and self.error >= 1.0)
        return not self.within_tolerance and falls

    def describe(self) -> str:
        return (f"{self.name}: {self.error:.3e} at h, {self.error_half:.3e} at h/2: observed order "
                f"{self.observed:.2f} (allowed {band_text(self.band)}; case limit {self.tolerance:g})")


def band_text(band) -> str:
    return f"{band[0]:g} to {band[1]:g}"


def run_cvode(fmu: Fmu, case: Case, run: Callable[[Fmu, Case], Result]) -> tuple[Result, Evaluation]:
    """The case under CVode, as ``run`` runs it, and its evaluation."""
    result = run(fmu, case)
    return result, evaluate(case, result)


def run_fixed_step(fmu: Fmu, case: Case, method: FixedStep) -> tuple[Evaluation, list[OrderCheck], float]:
    """The case at h and h/2, h halved (up to the method's floor) while it is too coarse for
    a signal: the evaluation at the last h, the order check of every signal, and h."""
    k = method.divisions
    coarse = evaluate(case, method.run(fmu, case, case.output_interval / k))
    while True:
        fine = evaluate(case, method.run(fmu, case, case.output_interval / (2 * k)))
        if coarse.problem or fine.problem:
            return Evaluation(case, coarse.time, coarse.signals, coarse.problem or fine.problem), [], \
                case.output_interval / k
        checks = [OrderCheck(a.name, a.max_error, b.max_error, a.tolerance, method.band)
                  for a, b in zip(coarse.signals, fine.signals)]
        if k >= method.max_divisions or not any(c.too_coarse for c in checks):
            return coarse, checks, case.output_interval / k
        coarse, k = fine, 2 * k


def _worst(checks: list[OrderCheck]) -> OrderCheck | None:
    """The failing signal with the largest error, else the largest one judged by its order."""
    return max(checks, key=lambda c: (not c.passed, not c.within_tolerance, c.error), default=None)


def cvode_row(fmu: Fmu, case: Case, anchor: str = "", entry: dict[str, Any] | None = None, *, importer: str,
              run: Callable[[Fmu, Case], Result]) -> Row:
    """The case's row under FMPy's CVode, held to the case's limits (named ``importer``, run by
    ``run``); ``entry`` (the case's plot's errors) gets its error over time."""
    row = Row(kind="case", fmu=fmu.model, case=case.name, anchor=anchor, importer=importer, problems=[],
               notes=[CVODE_NOTE])
    t0 = time.perf_counter()
    try:
        result, ev = run_cvode(fmu, case, run)
    except Exception as e:
        return row.but(max_error=None, tolerance=None, passed=False,
                    problems=[f"{importer} run failed: {type(e).__name__}: {e}"])
    worst = ev.worst
    limited = not ev.passed and ev.problem is None and all(x.passed or x.max_error <= CVODE_FLOOR
                                                           for x in ev.signals)
    row.update(max_error=worst.max_error if worst else None, tolerance=worst.tolerance if worst else None,
               passed=ev.passed or limited, limited=limited, problems=[ev.problem] if ev.problem else [],
               signals={s.name: dict(max_error=s.max_error, at_time=s.at_time, scale=s.scale,
                                     tolerance=s.tolerance, passed=s.passed) for s in ev.signals},
               seconds=time.perf_counter() - t0, log=result.log[-20:])
    if worst:
        row["notes"] = [f"worst signal {worst.name} at t = {worst.at_time:g}", CVODE_NOTE]
        if limited:
            row["notes"].insert(0, f"LIMIT: CVode reaches {worst.max_error:.1e}, not the case's {worst.tolerance:g}"
                                   f" (reported up to {CVODE_FLOOR:g})")
        if entry is not None:
            entry[importer] = dict(time=ev.time, error_over_time=np.max([s.error for s in ev.signals], axis=0))
    return row


def fixed_step_row(fmu: Fmu, case: Case, method: FixedStep, anchor: str = "") -> Row:
    """The case's row under a fixed-step method; SKIP when the importer cannot run it."""
    rule = (f"passes at the case's limit, or with an observed order of {band_text(method.band)} "
            f"(the method's: {method.order})")
    row = Row(kind="case", fmu=fmu.model, case=case.name, anchor=anchor, importer=method.importer,
               order=method.order, order_band=list(method.band), tolerance=None, problems=[], notes=[rule])
    t0 = time.perf_counter()
    try:
        ev, checks, h = run_fixed_step(fmu, case, method)
    except NotSupported as e:
        return row.but(max_error=None, passed=True, skipped=True, problems=[str(e)])
    except Exception as e:
        return row.but(max_error=None, passed=False, problems=[f"{method.importer} run failed: "
                                                                     f"{type(e).__name__}: {e}"])
    worst = _worst(checks)
    note = f"fixed step h = {h:g} s and h/2: {rule}"
    limited = ev.problem is None and not all(c.passed for c in checks)
    row.update(max_error=worst.error if worst else None, passed=ev.problem is None, limited=limited,
               problems=[ev.problem] if ev.problem else [],
               signals={c.name: dict(max_error=c.error, half_step_error=c.error_half, observed_order=c.observed,
                                     tolerance=c.tolerance, passed=c.passed) for c in checks},
               step=h, notes=[note], seconds=time.perf_counter() - t0)
    if worst and worst.within_tolerance:  # every signal meets the case's limit
        row["tolerance"] = worst.tolerance
    elif worst:
        row.update(observed_order=worst.observed, half_step_error=worst.error_half)
        row["notes"] = [f"worst signal {worst.describe()}", note]
    if limited:
        row["notes"] = [f"LIMIT: {c.describe()}" for c in checks if not c.passed] + [note]
    return row
