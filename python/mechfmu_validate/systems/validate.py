"""The rows of one SSP: per parameter set, the plain Jacobi scheme's coupling error and each
importer's at the communication step and at half of it, the order they show, and the largest
step that keeps the error under :data:`COUPLING_TOLERANCE` (see the package's documentation)."""

from __future__ import annotations

import math
import tempfile
from pathlib import Path

import fmpy
import numpy as np

from ..rows import Row
from . import archive, jacobi, solution as truth
from .figure import write_figure
from .importers import IMPORTERS

#: how many times the plain Jacobi scheme's coupling error an importer's may be
FACTOR = 5.0

#: the coupling error a user may accept, relative to each signal's range: each row says the
#: largest communication step that keeps the error under it
COUPLING_TOLERANCE = 1e-3


def validate_system(path: Path, figure_dir: Path | None = None) -> list[Row]:
    """The rows of the SSP at ``path``; with ``figure_dir``, also its coupling figure
    (:mod:`.figure`, the default set's first connected state) written there."""
    rows: list[Row] = []
    with tempfile.TemporaryDirectory(prefix="mechfmu-ssp-") as tmp:
        work = Path(tmp)
        try:
            ssp = archive.read(path, work / "ssp")
        except Exception as e:  # noqa: BLE001 (an SSP that cannot be read is one FAIL row)
            return [Row(kind="check", fmu=path.name, case="SSP", importer="-", passed=False,
                        problems=[f"cannot read {path}: {type(e).__name__}: {e}"])]
        if ssp.step is None:
            return [Row(kind="check", fmu=ssp.name, case="SSP", importer="-", passed=False,
                        problems=["the SSP gives no communication step (no OSP FixedStepAlgorithm "
                                  "and no OpenModelica FixedStepMaster annotation)"])]
        causality, states = _variables(ssp)
        connected = list(dict.fromkeys(start for start, _ in ssp.connections))
        # the system's trajectory: its connected states (an output computed from held inputs,
        # a stateless element's, shows each importer's scheme rather than where it leads)
        signals = [s for s in connected if s in states] or connected
        one_fmu = truth.system_fmu(path, ssp)
        if figure_dir is not None:
            slug = "".join(f"-{c.lower()}" if c.isupper() else c for c in ssp.name).lstrip("-")
            figure = write_figure(ssp, "default", signals[0], figure_dir / f"{slug}-coupling.png", work, one_fmu)
            print(f"figure: {figure}")
        for set_name, values in ssp.sets.items():
            case = f"{set_name} (SSP)"
            try:
                times, solution, solved_by = truth.solve(ssp, values, signals, work, one_fmu)
            except Exception as e:  # noqa: BLE001 (a solution that cannot be had is one FAIL row)
                rows.append(Row(kind="check", fmu=ssp.name, case=case, importer="solution", passed=False,
                                max_error=None, tolerance=None,
                                problems=[f"cannot solve the system: {type(e).__name__}: {e}"]))
                continue
            plain = jacobi.run(ssp, values, ssp.step, ssp.stop, signals, work)
            baseline = _error(plain, times, solution)
            baseline_half = _error(jacobi.run(ssp, values, ssp.step / 2, ssp.stop, signals, work), times, solution)
            order = _order(baseline, baseline_half)
            rows.append(Row(kind="case", fmu=ssp.name, case=case, importer="plain Jacobi", max_error=baseline,
                            tolerance=None, passed=True, step=ssp.step, file=str(path), half_step_error=baseline_half,
                            coupling_order=order, largest_step=_largest_step(ssp.step, baseline, order),
                            notes=[f"coupling error of a plain Jacobi co-simulation at h = {ssp.step:g} s against "
                                   f"{solved_by}; {baseline_half:.2e} at half the step ({_order_text(order)}); "
                                   f"{_step_text(ssp.step, baseline, order)}"]))
            schemes = {(True, False): baseline}
            for importer in IMPORTERS:
                if importer.scheme not in schemes:
                    resolved, zero_start = importer.scheme
                    own = jacobi.run(ssp, values, ssp.step, ssp.stop, signals, work, resolved, zero_start)
                    schemes[importer.scheme] = _error(own, times, solution)
                rows.append(_importer_row(importer, ssp, set_name, case, signals, times, solution, baseline,
                                          schemes[importer.scheme], causality, path))
    return rows


def _importer_row(importer, ssp, set_name, case, signals, times, solution, baseline, scheme_error, causality,
                  path) -> Row:
    row = Row(kind="case", fmu=ssp.name, case=case, importer=importer.name, step=ssp.step, file=str(path),
              tolerance=FACTOR * scheme_error)
    ok, why = importer.available()
    if not ok:
        row.update(passed=True, skipped=True, max_error=None, notes=[why])
        return row
    if importer.default_only and ssp.set_files[set_name] != archive.DEFAULT_SSD:
        row.update(passed=True, skipped=True, max_error=None,
                   notes=[f"{importer.name} runs the default set only (SystemStructure.ssd; it loads no variant)"])
        return row
    unapplied = sorted(f"{c}.{v}" for (c, v) in ssp.sets[set_name]
                       if importer.applies_to is not None and causality.get((c, v)) not in importer.applies_to)
    try:
        at_step = _error(importer.run(ssp, set_name, ssp.step, signals), times, solution)
        if importer.own_step_only:
            # the SSD's own step only: held to its master's error at that step, its order taken
            # to be the plain scheme's
            largest = _largest_step(ssp.step, at_step, 1.0)
            order_note = (f"{at_step / baseline:.2g} times the plain Jacobi scheme's coupling error, at the SSD's "
                          f"step; {_step_text(ssp.step, at_step, 1.0)} (taking it first order)")
            passed = at_step <= FACTOR * scheme_error
            row.update(max_error=at_step, passed=passed, notes=[order_note], largest_step=largest,
                       problems=[] if passed else [f"the coupling error, {at_step:.3e}, is more than {FACTOR:g} times "
                                                   f"that of the scheme {importer.name} runs, {scheme_error:.3e}"])
            return row
        at_half = _error(importer.run(ssp, set_name, ssp.step / 2, signals), times, solution)
    except Exception as e:  # noqa: BLE001 (an importer that fails is one FAIL row)
        row.update(passed=False, max_error=None, problems=[f"{type(e).__name__}: {e}"])
        return row
    order = _order(at_step, at_half)
    row.update(max_error=at_step, half_step_error=at_half, coupling_order=order,
               largest_step=_largest_step(ssp.step, at_step, order),
               notes=[f"{at_step / baseline:.2g} times the plain Jacobi scheme's coupling error; "
                      f"{at_step / scheme_error:.3g} times its own scheme's, run by mechfmu; "
                      f"{at_half:.2e} at half the step ({_order_text(order)}); "
                      f"{_step_text(ssp.step, at_step, order)}"])
    if unapplied:
        row.update(passed=True, limited=True,
                   notes=[f"{importer.name} applies a parameter set to parameters and inputs only: "
                          f"{', '.join(unapplied)} keep the FMU's own start values", *row.notes])
        return row
    problems = []
    if not at_step <= FACTOR * scheme_error:
        problems.append(f"the coupling error at h = {ssp.step:g} s, {at_step:.3e}, is more than {FACTOR:g} times "
                        f"that of the scheme {importer.name} runs, {scheme_error:.3e}")
    if not at_half < at_step:
        problems.append(f"the coupling error does not shrink at half the step ({at_step:.3e} at h, "
                        f"{at_half:.3e} at h/2)")
    row.update(passed=not problems, problems=problems)
    return row


def _order(at_step: float, at_half: float) -> float | None:
    """The order the errors at a step and at half of it show."""
    return math.log2(at_step / at_half) if at_half > 0 and at_step > 0 else None


def _order_text(order: float | None) -> str:
    return f"order {order:.2f}" if order is not None else "no order"


def _largest_step(step: float, error: float, order: float | None) -> float | None:
    """The largest communication step whose coupling error stays under
    :data:`COUPLING_TOLERANCE`, from the error at ``step`` and the order (``error ~ h^order``);
    None where the error does not shrink with the step."""
    if order is None or order <= 0.1 or error <= 0:
        return None
    return step * (COUPLING_TOLERANCE / error) ** (1.0 / order)


def _step_text(step: float, error: float, order: float | None) -> str:
    largest = _largest_step(step, error, order)
    if largest is None:
        return f"no step keeps it under {COUPLING_TOLERANCE:g} (it does not shrink with the step)"
    return f"h <= {largest:.2g} s keeps it under {COUPLING_TOLERANCE:g} of each signal's range"


def _error(run, times: np.ndarray, solution) -> float:
    """The largest error of a run's signals against the solution, each relative to the
    solution's range, over the times both cover."""
    run_times, values = run
    worst = 0.0
    inside = (times >= run_times[0] - 1e-9) & (times <= run_times[-1] + 1e-9)
    for s, exact in solution.items():
        got = np.interp(times[inside], run_times, values[s])
        scale = max(float(np.ptp(exact)), 1e-12)
        worst = max(worst, float(np.max(np.abs(got - exact[inside]))) / scale)
    return worst


def _variables(ssp) -> tuple[dict[tuple[str, str], str], set[tuple[str, str]]]:
    """Every variable's causality, and the continuous states, of every component."""
    causality, states = {}, set()
    for c in ssp.components:
        md = fmpy.read_model_description(str(ssp.fmu(c.name)), validate=False)
        for v in md.modelVariables:
            causality[(c.name, v.name)] = v.causality
        for d in md.derivatives:
            if d.variable.derivative is not None:
                states.add((c.name, d.variable.derivative.name))
    return causality, states
