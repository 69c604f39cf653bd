"""Reference results of an FMU's default experiment, in the FMI cross-check conventions,
computed by the mechanism's independent reference (its ``default_experiment`` case), never
by the FMU:

* ``<Id>_ref.csv``: ``"time"`` and the case's outputs at every communication point of the
  default experiment (quoted names on line 1, C float literals, at most 1 MB);
* ``<Id>_in.csv``: the inputs over the experiment (their start values, or the case's table);
* ``<Id>_ref.opt``: StartTime, StopTime, StepSize, RelTol (the DefaultExperiment's, what an
  importer runs the FMU with to compare), OutputIntervalLength.

They are written to ``<crate>/reference/`` (committed) and packaged by ``mechfmu build``
into ``extra/org.fmi-standard.fmi-ls-ref/``. Regenerate with
``mechfmu validate --write-references [NAME ...]`` (it needs the built FMU for the
DefaultExperiment and the inputs' names; rebuild afterwards to package the new files).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from .case import Case
from .importers import Fmu

__all__ = ["write_references", "reference_table", "csv_text"]

README = """# Reference results of `{model}`'s default experiment

Computed by the independent reference, not by the FMU: written by
`mechfmu validate --write-references {model}` from the case `{case}` of
`../validation/cases.py` ({description}).
`mechfmu build` packages them into the FMU under `extra/org.fmi-standard.fmi-ls-ref/`, and
`mechfmu validate` checks the packaged `_ref.csv` against the reference
(to {tol:g} of each signal's range).

| file | content |
|---|---|
| `{model}_ref.csv` | `time` and {n} outputs at every communication point ({rows} rows) |
| `{model}_in.csv` | the inputs (held at their start values) |
| `{model}_ref.opt` | the DefaultExperiment: start {start:g} s, stop {stop:g} s, step {step:g} s, relative tolerance {rtol:g} |

Format: the FMI cross-check CSV rules (quoted names on the first line, numbers as C float
literals with 13 significant digits). Regenerate after changing the mechanism's defaults:

    cargo run --release -- build {model}
    cargo run --release -- validate --write-references {model}
    cargo run --release -- build {model}
"""


def _num(x: float, digits: int) -> str:
    if not math.isfinite(x):
        raise ValueError(f"non-finite value {x} in a reference")
    s = repr(float(x)) if digits >= 17 else f"{x:.{digits}g}"
    return "0" if s in ("-0", "-0.0", "0.0") else s


def csv_text(names: list[str], columns: list[np.ndarray], digits: int = 13) -> str:
    """Quoted names, then one row per time; 13 significant digits (the references are
    accurate to about 1e-12), or ``digits=17`` for values to reproduce exactly (inputs)."""
    lines = [",".join(f'"{n}"' for n in names)]
    for row in zip(*columns):
        lines.append(",".join(_num(float(v), digits) for v in row))
    return "\n".join(lines) + "\n"


def _experiment(fmu: Fmu) -> tuple[float, float, float, float]:
    ex = fmu.md.defaultExperiment
    if ex is None or ex.stopTime is None or ex.stepSize is None:
        raise ValueError(f"{fmu.path} has no complete DefaultExperiment (stopTime, stepSize)")
    start = float(ex.startTime or 0.0)
    tol = float(ex.tolerance) if ex.tolerance is not None else float("nan")
    return start, float(ex.stopTime), float(ex.stepSize), tol


def reference_table(fmu: Fmu, case: Case) -> tuple[list[str], list[np.ndarray]]:
    """(names, columns) of ``<Id>_ref.csv``: the case's reference on the default grid."""
    start, stop, step, _ = _experiment(fmu)
    if abs(case.stop_time - (stop - start)) > 1e-12 * stop or abs(case.output_interval - step) > 1e-15:
        raise ValueError(f"case {case.name!r} (stop {case.stop_time}, interval {case.output_interval}) is not "
                         f"the DefaultExperiment (stop {stop}, step {step})")
    n = int(round((stop - start) / step))
    t = start + np.arange(n + 1) * step
    ref = case.reference(t)
    variables = fmu.variables
    names = list(case.outputs)
    unknown = [x for x in names if x not in variables]
    if unknown:
        raise ValueError(f"{unknown} are not variables of {fmu.model}")
    cols = [t] + [np.broadcast_to(np.asarray(ref[x], dtype=float), t.shape) for x in names]
    return ["time", *names], cols


def write_references(fmu: Fmu, case: Case, directory: Path) -> list[Path]:
    directory.mkdir(parents=True, exist_ok=True)
    model = fmu.model
    start, stop, step, rtol = _experiment(fmu)
    names, cols = reference_table(fmu, case)
    ref_text = csv_text(names, cols)
    if len(ref_text.encode()) > 1_000_000:
        raise ValueError(f"{model}_ref.csv would be {len(ref_text.encode())} bytes (the rules allow 1 MB): "
                         "compare fewer outputs in the default-experiment case")
    table = case.input_table()
    inputs = fmu.inputs()
    if table is not None:
        in_names = ["time", *[n for n in table.dtype.names[1:]]]
        in_cols = [np.asarray(table[n], dtype=float) for n in table.dtype.names]
        missing = [n for n in inputs if n not in in_names]
        for n in missing:
            in_names.append(n)
            in_cols.append(np.full(len(table), float(fmu.variables[n].start or 0.0)))
    else:
        in_names = ["time", *inputs]
        in_cols = [np.array([start, stop])] + [np.full(2, float(fmu.variables[n].start or 0.0)) for n in inputs]
    files = {
        f"{model}_ref.csv": ref_text,
        f"{model}_in.csv": csv_text(in_names, in_cols, digits=17),
        f"{model}_ref.opt": (f"StartTime, {start!r}\nStopTime, {stop!r}\nStepSize, {step!r}\n"
                             f"RelTol, {rtol!r}\nOutputIntervalLength, {step!r}\n"),
        "README.md": README.format(model=model, case=case.name,
                                   description=(case.description or "see the case").rstrip("."),
                                   tol=1e-9, n=len(names) - 1, rows=len(cols[0]), start=start, stop=stop,
                                   step=step, rtol=rtol),
    }
    written = []
    for name, text in files.items():
        path = directory / name
        path.write_text(text)
        written.append(path)
    return written
