"""The reference results an FMU carries (FMI-LS-REF, ``extra/org.fmi-standard.fmi-ls-ref/``),
as a :class:`~.case.Case` that ``mechfmu validate`` runs like its own reference cases; the
same reading serves the FMI cross-check's files beside an FMU file (:mod:`.cross_check` finds
them and names their case).

What is read, from that folder of the archive:

* the results: the file ``fmi-ls-manifest.xml`` names with ``role="result"`` (the Modelica
  Reference-FMUs: ``<Id>_out.csv``), else ``<Id>_ref.csv`` (the FMI cross-check's name, and
  mechfmu's), else ``<Id>_out.csv``: ``time`` first, then one column per variable; names quoted
  or not; ``true``/``false`` read as 1/0; a column that is not numeric (a String, a Binary) is
  left out, saying so;
* the inputs, when there are: ``<Id>_in.csv`` (or the manifest's ``role="input"``), ``time``
  first, given to the importers as FMPy's input table;
* the experiment's settings, when there are: ``<Id>_ref.opt`` (``StartTime``, ``StopTime``,
  ``StepSize``, ``RelTol``, one ``Key, value`` a line, as the cross-check and the
  Reference-FMUs before FMI-LS-REF wrote them), else the model description's
  ``DefaultExperiment``.

The experiment runs from 0 to the reference's last time (where a model that ends its
simulation, as the Reference-FMUs' Stair does, ends its reference), communicating on the
reference's own time grid when its times lie on one (``k h``), so every sample is compared
with a row of the file; otherwise every ``StepSize`` (or the DefaultExperiment's) with the
reference interpolated linearly. Where the file lists a time twice (an event), the FMU is
compared with the row after the event: in Co-Simulation the values at a communication point
are those after the events at that time. A signal's error is its largest difference from the
reference over its range (:func:`~.case.signal_scale`), and it must be within
:func:`tolerance_for` the experiment's relative tolerance.
"""

from __future__ import annotations

import csv
import io
import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from .arrays import element_name
from .case import Case

if TYPE_CHECKING:  # pragma: no cover
    from .arrays import ArrayMap
    from .fmu import Fmu

__all__ = ["REFERENCE_DIR", "CASE_NAME", "ReferenceProblem", "Unsupported", "Files", "EmbeddedReference", "find",
           "carried", "read", "tolerance_for", "DEFAULT_TOLERANCE"]

REFERENCE_DIR = "extra/org.fmi-standard.fmi-ls-ref"
#: the case column of the embedded reference's rows
CASE_NAME = "embedded_reference"

#: the tolerance, as a fraction of each signal's range, is this many times the relative
#: tolerance the experiment runs at: a solver held to a relative tolerance r per step ends
#: with a global error of a few to some tens of r
TOLERANCE_FACTOR = 100
#: ... never below what a CSV of 7 significant digits can hold, nor above 1 %
TOLERANCE_BOUNDS = (1e-6, 1e-2)
#: when neither the options file nor the DefaultExperiment gives a relative tolerance (the
#: FMU then runs at its own): as for r = 1e-5, FMPy's default for its own solvers
DEFAULT_TOLERANCE = 1e-3


class ReferenceProblem(Exception):
    """The reference files cannot be read (the row fails, naming the file and the line)."""


class Unsupported(Exception):
    """An experiment ``mechfmu validate`` cannot run as the files describe it (a SKIP row)."""


def tolerance_for(relative_tolerance: float | None) -> float:
    if relative_tolerance is None or not relative_tolerance > 0:
        return DEFAULT_TOLERANCE
    low, high = TOLERANCE_BOUNDS
    return min(max(TOLERANCE_FACTOR * relative_tolerance, low), high)


@dataclass
class Files:
    """A reference's files: the folder they are in, their names there by role (``"result"``,
    ``"input"``, ``"options"``), the case they make and what it says of them."""

    folder: Path
    names: dict[str, str]
    case_name: str = CASE_NAME
    what: str = "the reference results the FMU carries"


@dataclass
class EmbeddedReference:
    """The files found, and the case made of them (:func:`read`)."""

    files: list[str]
    case: Case
    #: what makes the comparison fail whatever the FMU does (a column naming no variable)
    problems: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    #: the compared signals as the case names them -> their columns as the results file names them
    columns: dict[str, str] = field(default_factory=dict)
    #: the results file's rows of the compared signals, ``time`` first (a structured array)
    table: np.ndarray | None = None
    #: the experiment's StartTime and StopTime (the options file's, else the DefaultExperiment's,
    #: else the results file's first and last times)
    window: tuple[float, float] = (0.0, 0.0)


def _folder_files(fmu: Fmu) -> dict[str, str]:
    folder = fmu.directory / REFERENCE_DIR
    if not folder.is_dir():
        return {}
    return {p.name: f"{REFERENCE_DIR}/{p.name}" for p in sorted(folder.iterdir()) if p.is_file()}


def _manifest_roles(fmu: Fmu) -> dict[str, str]:
    """``{role: file name}`` from ``fmi-ls-manifest.xml`` (``<Related source=... role=...>``)."""
    path = fmu.directory / REFERENCE_DIR / "fmi-ls-manifest.xml"
    if not path.is_file():
        return {}
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as e:
        raise ReferenceProblem(f"{REFERENCE_DIR}/fmi-ls-manifest.xml is not well-formed XML ({e})") from None
    return {e.get("role", ""): e.get("source", "") for e in root.iter() if e.get("source")}


def find(fmu: Fmu) -> dict[str, str]:
    """The archive's names of the results (``"result"``), inputs and options files found."""
    files = _folder_files(fmu)
    roles = _manifest_roles(fmu)
    ident = fmu.model

    def first(*names: str) -> str | None:
        return next((files[n] for n in names if n and n in files), None)

    found = {"result": first(roles.get("result", ""), f"{ident}_ref.csv", f"{ident}_out.csv")}
    if found["result"] is None:
        results = [n for n in files if n.endswith(("_ref.csv", "_out.csv"))]
        found["result"] = files[results[0]] if len(results) == 1 else None
    if found["result"] is None:
        return {}
    stem = found["result"].rsplit("/", 1)[1].rsplit("_", 1)[0]
    found["input"] = first(roles.get("input", ""), f"{ident}_in.csv", f"{stem}_in.csv")
    found["options"] = first(f"{ident}_ref.opt", f"{stem}_ref.opt")
    return {k: v for k, v in found.items() if v is not None}


def carried(fmu: Fmu) -> Files | None:
    """The reference files in the archive (:func:`find`), None when it carries none."""
    names = find(fmu)
    return Files(fmu.directory, names) if names else None


def _cell(text: str) -> float:
    low = text.strip().lower()
    if low in ("true", "false"):
        return float(low == "true")
    return float(text)


def _fmi2_names(names_of: ArrayMap | None) -> dict[str, str]:
    """An FMI 3.0 FMU's array elements (``q[2]``, as its reference names them) -> the FMI 2.0
    variables they are (``q_x``), the names its cases and importers use."""
    if names_of is None:
        return {}
    return {element_name(a, names_of.shapes[a], k): scalar
            for a, scalars in names_of.elements.items() for k, scalar in enumerate(scalars)}


def _numbers(cells: list[str]) -> list[list[float]] | None:
    """A column's cells as numbers, each cell a number or (an FMI 3.0 array, as FMPy writes
    it) the same count of numbers separated by spaces; None when they are not numbers."""
    try:
        values = [[_cell(x) for x in cell.split()] or [math.nan] for cell in cells]
    except ValueError:
        return None
    return values if len({len(v) for v in values}) == 1 else None


def read_table(fmu: Fmu, name: str, renames: dict[str, str] | None = None,
               folder: Path | None = None) -> tuple[list[str], np.ndarray, list[str]]:
    """(names, numeric columns by row, left-out names) of a CSV of ``folder`` (the archive's,
    by default): ``time`` first, an array's column split into its elements (``y[1]``, ...);
    ``renames``: the names to give some columns."""
    text = ((folder or fmu.directory) / name).read_text(encoding="utf-8", errors="replace")
    lines = [row for row in csv.reader(io.StringIO(text), skipinitialspace=True) if any(c.strip() for c in row)]
    if len(lines) < 2:
        raise ReferenceProblem(f"{name} has no rows of values")
    header = [n.strip() for n in lines[0]]
    if header[0] != "time":
        raise ReferenceProblem(f"{name}: the first column is {header[0]!r}, not \"time\"")
    for number, row in enumerate(lines[1:], start=2):
        if len(row) != len(header):
            raise ReferenceProblem(f"{name}: line {number} has {len(row)} cells, the header {len(header)}")
    names, columns, left_out = [], [], []
    variables = fmu.variables
    for j, column in enumerate(header):
        values = _numbers([row[j] for row in lines[1:]])
        if values is None or (j == 0 and len(values[0]) > 1):
            if j == 0:
                number, cell = next((k, row[0]) for k, row in enumerate(lines[1:], start=2)
                                    if _numbers([row[0]]) is None or len(row[0].split()) != 1)
                raise ReferenceProblem(f"{name}: line {number}: the time {cell!r} is not a number")
            left_out.append(column)  # a String or Binary column: not compared
            continue
        width = len(values[0])
        shape = tuple(getattr(variables.get(column), "shape", None) or (width,))
        shape = shape if math.prod(shape) == width else (width,)
        elements = [column] if width == 1 else [element_name(column, shape, k) for k in range(width)]
        names += [(renames or {}).get(e, e) for e in elements]
        columns += list(zip(*values))
    table = np.array(columns, dtype=float).T
    if not np.all(np.isfinite(table)):
        row, col = (int(k) for k in np.argwhere(~np.isfinite(table))[0])
        raise ReferenceProblem(f"{name}: line {row + 2}: {names[col]} = {table[row, col]}, which is no number "
                               "to compare a result with")
    if np.any(np.diff(table[:, 0]) < 0):
        raise ReferenceProblem(f"{name}: time decreases at line {int(np.argmax(np.diff(table[:, 0]) < 0)) + 3}")
    return names, table, left_out


def _options(folder: Path, name: str | None) -> dict[str, float]:
    if name is None:
        return {}
    options = {}
    for number, line in enumerate((folder / name).read_text(errors="replace").splitlines(), start=1):
        if line.strip():
            key, sep, value = line.partition(",")
            try:
                options[key.strip()] = float(value)
            except ValueError:
                raise ReferenceProblem(f"{name}: line {number} is not `Key, number`: {line!r}") from None
    return options


def _grid(time: np.ndarray) -> float | None:
    """The step h of a reference whose times all lie on k h, those of events (listed twice)
    apart, or None."""
    unique, counts = np.unique(time, return_counts=True)
    points = unique[(counts == 1) | (unique == time[-1])]
    steps = np.diff(points)
    if len(steps) == 0:
        return None
    h = float(np.median(steps))
    k = points / h
    return h if h > 0 and np.all(np.abs(k - np.round(k)) < 1e-6) else None


def _interpolator(time: np.ndarray, values: np.ndarray, eps: float):
    """The reference at the FMU's times: the row at that time (the last one, after an event,
    where there are two), else linear between the rows around it."""

    def at(t: np.ndarray) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        j = np.searchsorted(time, t + eps, side="right") - 1  # the last row at or before t
        exact = (j >= 0) & (np.abs(time[np.clip(j, 0, None)] - t) <= eps)
        left, right = np.clip(j, 0, len(time) - 1), np.clip(j + 1, 0, len(time) - 1)
        span = time[right] - time[left]
        w = np.clip(np.where(span > 0, (t - time[left]) / np.where(span > 0, span, 1.0), 0.0), 0.0, 1.0)
        w = np.where(exact, 0.0, w)[:, None]
        return values[left] + w * (values[right] - values[left])

    return at


def _setting(options: dict[str, float], key: str, experiment, attribute: str) -> float | None:
    """A setting of the options file, else the DefaultExperiment's, else None."""
    if key in options:
        return options[key]
    value = getattr(experiment, attribute, None) if experiment is not None else None
    return float(value) if value not in (None, "") else None


def _communication_step(time: np.ndarray, options: dict[str, float], experiment, notes: list[str]) -> float:
    """The reference's own grid step, else the settings' (the reference then interpolated),
    made to divide the reference's span."""
    stop = float(time[-1])
    h = _grid(time)
    if h is None:
        h = options.get("OutputIntervalLength") or _setting(options, "StepSize", experiment, "stepSize") or stop / 500
        notes.append(f"the reference's times are not on one grid: it is interpolated linearly at every {h:g} s")
    return stop / max(1, round(stop / h))


def _input_table(fmu: Fmu, files: Files, variables: dict, renames: dict[str, str],
                 problems: list[str]) -> np.ndarray | None:
    """FMPy's input table from the inputs file, without the columns that are not inputs of the
    FMU (each named in ``problems``)."""
    name = files.names["input"]
    names, table, left_out = read_table(fmu, name, renames, files.folder)
    not_inputs = [x for x in names[1:] + left_out
                  if x not in variables or getattr(variables[x], "causality", "input") != "input"]
    if not_inputs:
        problems.append(f"{name} has columns that are not inputs of the FMU: {', '.join(not_inputs)}")
    kept = [j for j, x in enumerate(names) if j == 0 or x not in not_inputs]
    if len(kept) == 1:
        return None
    inputs = np.zeros(len(table), dtype=[(names[j], np.float64) for j in kept])
    for j in kept:
        inputs[names[j]] = table[:, j]
    return inputs


def read(fmu: Fmu, names_of: ArrayMap | None = None, files: Files | None = None) -> EmbeddedReference | None:
    """The reference of ``files`` (by default the FMU's embedded one) as a case, None when
    there is none. Raises :class:`ReferenceProblem` (unreadable files) or :class:`Unsupported`.
    ``names_of``: an FMI 3.0 FMU's FMI 2.0 names (:mod:`.arrays`), which its reference may use."""
    files = files or carried(fmu)
    if files is None:
        return None
    found = files.names
    problems, notes = [], []
    renames = _fmi2_names(names_of)
    names, table, left_out = read_table(fmu, found["result"], renames, files.folder)
    if left_out:
        notes.append(f"not compared (not numbers): {', '.join(left_out)}")
    variables = {**(names_of.variables if names_of is not None else {}), **fmu.variables}
    unknown = [n for n in names[1:] if n not in variables]
    outputs = [n for n in names[1:] if n in variables]
    if not outputs:
        problems.append(f"{found['result']} names no variable of the FMU (its columns: {', '.join(names[1:])})")
    elif unknown:
        problems.append(f"{found['result']} has columns that are not variables of the FMU: {', '.join(unknown)}")
    options = _options(files.folder, found.get("options"))
    experiment = fmu.md.defaultExperiment
    time = table[:, 0]
    start = _setting(options, "StartTime", experiment, "startTime") or float(time[0])
    if start != 0.0 or time[0] != 0.0:
        if problems:
            raise ReferenceProblem("; ".join(problems))
        raise Unsupported(f"the experiment starts at t = {start or time[0]:g}: mechfmu validate runs experiments "
                          "from t = 0")
    stop = float(time[-1])
    if stop <= 0:
        raise ReferenceProblem(f"{found['result']} ends at t = {stop:g}")
    h = _communication_step(time, options, experiment, notes)
    wanted_stop = _setting(options, "StopTime", experiment, "stopTime") or stop
    if not math.isclose(wanted_stop, stop, rel_tol=1e-9):
        notes.append(f"the reference ends at t = {stop:g} (the experiment at {wanted_stop:g}): compared up to there")
    rtol = _setting(options, "RelTol", experiment, "tolerance")
    inputs = _input_table(fmu, files, variables, renames, problems) if "input" in found else None
    interpolate = _interpolator(time, table[:, 1:], 1e-9 * h)
    columns = {n: j for j, n in enumerate(names[1:])}

    def reference(t: np.ndarray) -> dict[str, np.ndarray]:
        at = interpolate(t)
        return {n: at[:, columns[n]] for n in outputs}

    case = Case(files.case_name, stop_time=stop, output_interval=h, outputs=outputs, reference=reference,
                input=inputs, relative_tolerance=rtol, tolerance=tolerance_for(rtol),
                description=f"{files.what}: {', '.join(found.values())}")
    notes.append(f"{found['result']}: {len(outputs)} signals, tolerance {case.tolerance:g} of each one's range "
                 + (f"(from RelTol {rtol:g})" if rtol else "(no relative tolerance given: the default)"))
    inverse = {scalar: element for element, scalar in renames.items()}
    rows = np.zeros(len(time), dtype=[("time", np.float64)] + [(n, np.float64) for n in outputs])
    rows["time"] = time
    for n in outputs:
        rows[n] = table[:, 1 + columns[n]]
    return EmbeddedReference(list(found.values()), case, problems, notes, {n: inverse.get(n, n) for n in outputs},
                             rows, (0.0, wanted_stop))
