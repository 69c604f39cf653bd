"""Reference results of an FMU in the FMI cross-check conventions, computed by the
mechanism's independent reference (its reference case), never by the FMU:

* ``<Id>_ref.csv``: ``"time"`` and at most :data:`MAX_COLUMNS` of the case's outputs at every
  communication point (quoted names on line 1, C float literals, at most 1 MB);
* ``<Id>_in.csv``: the inputs over the experiment (their start values, or the case's table);
* ``<Id>_ref.opt``: StartTime, StopTime, StepSize, RelTol (the DefaultExperiment's, what an
  importer runs the FMU with to compare), OutputIntervalLength.

The reference case is the one naming ``reference_files`` (the columns), else the default
experiment's (its outputs). An importer runs the cross-check with ``_ref.opt`` and
``_in.csv`` alone, so the case sets no start values and runs over the DefaultExperiment's
time and step; where the DefaultExperiment stands still (an equilibrium), a case that moves
through its inputs gives the files. FMPy's criterion (``fmpy.cross_check.validate_result``)
puts a band of 10 % of a signal's range around it, or of its value when it is constant: an
invariant must be written as its exact value (the case's reference gives it so), since its
solver's round-off would make a band no importer stays in.

They are written to ``<crate>/reference/`` (committed) and packaged by ``mechfmu build``
into ``extra/org.fmi-standard.fmi-ls-ref/``. Regenerate with
``mechfmu validate --write-references [NAME ...]`` (it needs the built FMU for the
DefaultExperiment and the inputs' names; rebuild afterwards to package the new files).
"""

from __future__ import annotations

import math
import textwrap
from pathlib import Path

import numpy as np

from .case import CONSTANT, Case
from .fmu import Fmu

__all__ = ["write_references", "reference_table", "reference_columns", "csv_text", "MAX_COLUMNS"]

#: the variables a reference may hold besides time (the cross-check rules)
MAX_COLUMNS = 10

README = """# Reference results of `{model}`

{source}

{why}

`mechfmu build` packages them into the FMU under `extra/org.fmi-standard.fmi-ls-ref/`, and
`mechfmu validate` checks the packaged `_ref.csv` against the reference
(to {tol:g} of each signal's range).

| file | content |
|---|---|
| `{model}_ref.csv` | `time` and {n} outputs at every communication point ({rows} rows): {columns} |
| `{model}_in.csv` | {inputs} |
| `{model}_ref.opt` | the DefaultExperiment: start {start:g} s, stop {stop:g} s, step {step:g} s, relative tolerance {rtol:g} |
{notes}
Format: the FMI cross-check CSV rules (quoted names on the first line, numbers as C float
literals with 13 significant digits). Regenerate after changing the mechanism or its case:

    cargo run --release -- build {model}
    cargo run --release -- validate --write-references {model}
    cargo run --release -- build {model}
"""


def _num(x: float, digits: int, allow_nan: bool = False) -> str:
    if not math.isfinite(x):
        if allow_nan:
            return "nan"
        raise ValueError(f"non-finite value {x} in a reference")
    s = repr(float(x)) if digits >= 17 else f"{x:.{digits}g}"
    return "0" if s in ("-0", "-0.0", "0.0") else s


def csv_text(names: list[str], columns: list[np.ndarray], digits: int = 13, allow_nan: bool = False) -> str:
    """Quoted names, then one row per time; 13 significant digits (the references are
    accurate to about 1e-12), or ``digits=17`` for values to reproduce exactly (inputs); a
    value that is not finite is ``nan`` when ``allow_nan`` (a result), an error otherwise."""
    lines = [",".join(f'"{n}"' for n in names)]
    for row in zip(*columns):
        lines.append(",".join(_num(float(v), digits, allow_nan) for v in row))
    return "\n".join(lines) + "\n"


def _experiment(fmu: Fmu) -> tuple[float, float, float, float]:
    ex = fmu.md.defaultExperiment
    if ex is None or ex.stopTime is None or ex.stepSize is None:
        raise ValueError(f"{fmu.path} has no complete DefaultExperiment (stopTime, stepSize)")
    start = float(ex.startTime or 0.0)
    tol = float(ex.tolerance) if ex.tolerance is not None else float("nan")
    return start, float(ex.stopTime), float(ex.stepSize), tol


def reference_columns(case: Case) -> list[str]:
    """The variables of ``<Id>_ref.csv``: the case's ``reference_files``, else its outputs."""
    return list(case.reference_files or case.outputs)


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
    names = reference_columns(case)
    unknown = [x for x in names if x not in variables]
    if unknown:
        raise ValueError(f"{unknown} are not variables of {fmu.model}")
    cols = [t] + [np.broadcast_to(np.asarray(ref[x], dtype=float), t.shape) for x in names]
    return ["time", *names], cols


def _written(column: np.ndarray) -> np.ndarray:
    """A column as ``<Id>_ref.csv`` holds it (13 significant digits)."""
    return np.array([float(_num(float(v), 13)) for v in column])


def _constant(column: np.ndarray) -> bool:
    return bool(np.all(column == column[0]))


def _check_columns(case: Case, names: list[str], cols: list[np.ndarray]) -> None:
    """The rules the files keep so that every importer's run can pass FMPy's criterion."""
    if len(names) - 1 > MAX_COLUMNS:
        raise ValueError(f"case {case.name!r} gives {len(names) - 1} columns (the cross-check rules allow "
                         f"{MAX_COLUMNS}): name the ones that show the mechanism in reference_files=[...]")
    if case.start_values:
        raise ValueError(f"case {case.name!r} sets start values ({', '.join(case.start_values)}): the cross-check "
                         "runs the FMU from its own, with the inputs of _in.csv only")
    written = {n: _written(c) for n, c in zip(names[1:], cols[1:])}
    for name, column in written.items():
        scale = float(np.max(np.abs(column)))
        if not _constant(column) and np.ptp(column) <= CONSTANT * scale:
            raise ValueError(
                f"case {case.name!r}: {name} varies by {np.ptp(column):.1e} of {scale:.4g}, an invariant with its "
                "solver's round-off: FMPy's criterion would hold importers to 10 % of that. Give its exact "
                "value in the case's reference (a constant), or leave it out of reference_files")
    if all(_constant(c) for c in written.values()):
        raise ValueError(f"nothing moves in case {case.name!r}: a reference that stands still tests no importer. "
                         "Take the reference files from a case that moves through its inputs from the FMU's "
                         "start values (reference_files=[...])")


def _still(case: Case | None, fmu: Fmu) -> bool:
    """Whether every output of ``case`` stays constant over the DefaultExperiment."""
    if case is None:
        return False
    start, stop, step, _ = _experiment(fmu)
    t = start + np.arange(int(round((stop - start) / step)) + 1) * step
    ref = case.reference(t)
    return all(_constant(_written(np.broadcast_to(np.asarray(ref[n], dtype=float), t.shape)))
               for n in case.outputs if n in ref)


def _source(model: str, case: Case) -> str:
    description = (case.description or "see the case").rstrip(".")
    return _paragraph(f"Computed by the independent reference, not by the FMU: written by `mechfmu validate "
                      f"--write-references {model}` from the case `{case.name}` of `../validation/cases.py` "
                      f"({description}).")


def _paragraph(text: str) -> str:
    return textwrap.fill(text, width=92, break_long_words=False, break_on_hyphens=False)


def _why(case: Case, default: Case | None, fmu: Fmu) -> str:
    if case.default_experiment and not fmu.inputs():
        return _paragraph("The case is the DefaultExperiment: an importer runs it with the settings of `_ref.opt`, "
                          "nothing else (the FMU has no input, so there is no `_in.csv`).")
    if case.default_experiment:
        return _paragraph("The case is the DefaultExperiment: an importer runs it with the settings of `_ref.opt` "
                          "and the inputs of `_in.csv`, nothing else.")
    if _still(default, fmu):
        return _paragraph(f"Not the DefaultExperiment's case `{default.name}`: nothing moves in it (every output "
                          "is constant), and a reference that stands still tests no importer. This case starts "
                          "from the FMU's start values as the DefaultExperiment does (the cross-check sets none) "
                          "and moves through its inputs (`_in.csv`), over the DefaultExperiment's time and step.")
    return _paragraph("The case's `reference_files` name these files' columns; it starts from the FMU's start values "
                      "(the cross-check sets none), its inputs in `_in.csv`, over the DefaultExperiment's time and "
                      "step.")


def _notes(case: Case, names: list[str], cols: list[np.ndarray]) -> str:
    """The README's paragraphs on the constant columns and on the case's signals left out."""
    notes = []
    constants = [n for n, c in zip(names[1:], cols[1:]) if _constant(_written(c))]
    if constants:
        notes.append(f"{_listed(constants)} {'is' if len(constants) == 1 else 'are'} constant, written as the exact "
                     "value: FMPy's cross-check criterion allows 10 % of a constant's value, where a solver's "
                     "round-off in the column would leave a band of 10 % of that round-off.")
    others = [n for n in case.signals() if n not in names]
    if others:
        notes.append(f"The case's other signals ({_listed(others)}) are not in `_ref.csv` (the cross-check's files "
                     f"hold at most {MAX_COLUMNS} variables, chosen by the case's `reference_files`); "
                     "`mechfmu validate` compares them with the case's reference to the case's own tolerances.")
    return "".join(f"\n{_paragraph(n)}\n" for n in notes)


def _listed(names: list[str]) -> str:
    return ", ".join(f"`{n}`" for n in names)


def write_references(fmu: Fmu, case: Case, directory: Path, default: Case | None = None) -> list[Path]:
    """Writes the four files of ``case`` (``default``: the DefaultExperiment's case, which the
    README compares it with) into ``directory``."""
    directory.mkdir(parents=True, exist_ok=True)
    model = fmu.model
    start, stop, step, rtol = _experiment(fmu)
    names, cols = reference_table(fmu, case)
    _check_columns(case, names, cols)
    ref_text = csv_text(names, cols)
    if len(ref_text.encode()) > 1_000_000:
        raise ValueError(f"{model}_ref.csv would be {len(ref_text.encode())} bytes (the rules allow 1 MB): "
                         "compare fewer outputs in the reference case")
    table = case.input_table()
    inputs = fmu.inputs()
    if table is not None:
        in_names = ["time", *[n for n in table.dtype.names[1:]]]
        in_cols = [np.asarray(table[n], dtype=float) for n in table.dtype.names]
        missing = [n for n in inputs if n not in in_names]
        for n in missing:
            in_names.append(n)
            in_cols.append(np.full(len(table), float(fmu.variables[n].start or 0.0)))
        inputs_text = "the inputs, piecewise constant (a jump is two rows at the same time)"
    else:
        in_names = ["time", *inputs]
        in_cols = [np.array([start, stop])] + [np.full(2, float(fmu.variables[n].start or 0.0)) for n in inputs]
        inputs_text = "the inputs (held at their start values)"
    files = {
        f"{model}_ref.csv": ref_text,
        # without inputs there is nothing to give (the cross-check rules make the file optional)
        **({f"{model}_in.csv": csv_text(in_names, in_cols, digits=17)} if len(in_names) > 1 else {}),
        f"{model}_ref.opt": (f"StartTime, {start!r}\nStopTime, {stop!r}\nStepSize, {step!r}\n"
                             f"RelTol, {rtol!r}\nOutputIntervalLength, {step!r}\n"),
        "README.md": README.format(model=model, source=_source(model, case), why=_why(case, default, fmu),
                                   tol=1e-9, n=len(names) - 1, rows=len(cols[0]), columns=_listed(names[1:]),
                                   inputs=inputs_text, notes=_notes(case, names, cols), start=start, stop=stop,
                                   step=step, rtol=rtol),
    }
    if len(in_names) == 1:
        files["README.md"] = "\n".join(line for line in files["README.md"].split("\n")
                                        if not line.startswith(f"| `{model}_in.csv`"))
        (directory / f"{model}_in.csv").unlink(missing_ok=True)
    written = []
    for name, text in files.items():
        path = directory / name
        path.write_text(text)
        written.append(path)
    return written
