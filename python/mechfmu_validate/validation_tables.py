"""The validation tables of ``mechfmu validate --readme DIR``: ``DIR/validation.md``, one row
per case in two tables (the FMI 2.0 FMUs, their FMI 3.0 FMUs), a column per importer's rows
(:mod:`.importers`, in Co-Simulation then in Model Exchange), the checks in two lines, and
the highlighted cases' plots (``DIR/validation/<name>.png``, linked below the tables).
``docs/validation.md`` is this file, written with ``--readme docs``.
"""

from __future__ import annotations

import shutil
from pathlib import Path
from typing import Any

from .importer import CS, FMI2, FMI3, ME, Importer, row_name
from .importers import IMPORTERS, REFERENCE
from .model_exchange import ORDER_SLACK, FixedStep, band_text
from .report import number_text, plot_case, versions_text
from .rows import Row
from .target import AGREEMENT

__all__ = ["write_readme"]

#: the folder beside validation.md that holds the highlighted cases' plots
PLOTS = "validation"

def _columns(version: str) -> list[tuple[str, str, bool]]:
    """The columns of the importers' rows of an FMI version after the reference importer's:
    (heading, importer column, a Model Exchange row), Co-Simulation first."""
    out = []
    for importer in IMPORTERS:
        if not importer.reference and importer.runs.covers(CS, version):
            name = row_name(importer.name, version, CS)
            out.append((f"{name} vs {REFERENCE.name}", name, False))
    for importer in IMPORTERS:
        for method in importer.methods.get(version, ()) if importer.runs.covers(ME, version) else ():
            owner = "" if importer.reference else f" ({importer.name})"
            out.append((f"{'FMI3 ' if version == FMI3 else ''}ME {method}{owner}",
                        row_name(importer.name, version, ME, method), True))
    return out


def _head(version: str) -> list[str]:
    columns = _columns(version)
    reference = row_name(REFERENCE.name, version, CS)
    return [f"| FMU | reference case | {reference}: max error | tolerance | "
            + " | ".join(heading for heading, _, _ in columns) + " | result |",
            "|---|---|---:|---:|" + "---:|" * len(columns) + "---|"]


#: every importer column of an FMI 3.0 FMU's rows
FMI3_ROWS = {name for importer in IMPORTERS for name in importer.row_names(FMI3)}


def _me_cell(row: Row | None) -> str:
    """A Model Exchange row in the table: the error, the observed order when the row
    is judged by it, ✗ when it fails."""
    if row is None:
        return "-"
    if row.get("skipped"):
        return "SKIP"
    cell = number_text(row["max_error"])
    if row.get("observed_order") is not None:
        cell += f" (h {row['step'] * 1e3:g} ms, p {row['observed_order']:.2f})"
    if row.get("limited"):
        return cell + " (limit)"
    return cell if row["passed"] else cell + " **✗**"


def _cell(row: Row | None) -> str:
    if row is None:
        return "-"
    return number_text(row["max_error"]) + ("" if row["passed"] else " **✗**")


def _line(fmu: str, case: str, by: dict[str, Row], version: str) -> str:
    reference = by.get(row_name(REFERENCE.name, version, CS)) or {}
    cells = [_me_cell(by.get(name)) if me else _cell(by.get(name)) for _, name, me in _columns(version)]
    return (f"| {fmu} | {case} | {number_text(reference.get('max_error'))} | "
            f"{number_text(reference.get('tolerance'))} | " + " | ".join(cells) + " | "
            f"{'PASS' if all(r['passed'] for r in by.values()) else 'FAIL'} |")


def _tables(rows: list[Row]) -> tuple[list[str], list[str]]:
    per_case: dict[tuple[str, str], dict[str, Row]] = {}
    for r in rows:
        if r["kind"] == "case":
            per_case.setdefault((r["fmu"], r["case"]), {})[r["importer"]] = r
    fmi2, fmi3 = _head(FMI2), _head(FMI3)
    for (fmu, case), by in per_case.items():
        two = {k: r for k, r in by.items() if k not in FMI3_ROWS}
        three = {k: r for k, r in by.items() if k in FMI3_ROWS}
        if two:
            fmi2.append(_line(fmu, case, two, FMI2))
        if three:
            fmi3.append(_line(fmu, case, three, FMI3))
    return fmi2, fmi3


def _check_lines(rows: list[dict[str, Any]]) -> list[str]:
    two: dict[str, list[bool]] = {}
    three: dict[str, list[bool]] = {}
    agreement: dict[str, str] = {}
    for r in rows:
        if r["kind"] != "check":
            continue
        if r["case"] == AGREEMENT:
            agreement[r["fmu"]] = number_text(r["max_error"]) + ("" if r["passed"] else " **FAIL**")
        else:
            (three if r["case"].startswith("check: FMI 3.0") else two).setdefault(r["fmu"], []).append(r["passed"])

    def line(checks):
        return ", ".join(f"{f} {'PASS' if all(v) else 'FAIL'} ({len(v)} checks)" for f, v in checks.items())

    out = []
    if two:
        out.append(f"Model-description, binary and GUID checks: {line(two)}.")
    if three:
        out.append(f"FMI 3.0 checks (FMPy's validation, binary, instantiation token, arrays = FMI 2.0 scalars): "
                   f"{line(three)}.")
    if agreement:
        out.append("FMI 3.0 Co-Simulation against FMI 2.0 (the DefaultExperiment under FMPy through both FMUs, "
                   "every variable, max |FMI 3.0 − FMI 2.0| / max |FMI 2.0|, at most 1e-12): "
                   + ", ".join(f"{f} {v}" for f, v in agreement.items()) + ".")
    return out


def _steps(method: FixedStep) -> str:
    """``2, 4 or 8``: the divisions of the output interval a fixed-step method tries."""
    divisions = [method.divisions]
    while divisions[-1] < method.max_divisions:
        divisions.append(2 * divisions[-1])
    words = [str(d) for d in divisions]
    return words[0] if len(words) == 1 else f"{', '.join(words[:-1])} or {words[-1]}"


def _fixed_steps() -> list[tuple[Importer, FixedStep, str]]:
    """The fixed-step methods of FMI 2.0 Model Exchange: (importer, method, its name)."""
    return [(i, i.fixed_step, i.fixed_step.importer.rsplit(" ", 1)[1])
            for i in IMPORTERS if i.fixed_step is not None and i.runs.covers(ME, FMI2)]


def _legend() -> str:
    """What the tables' columns measure, from the importers' declarations."""
    others = [row_name(i.name, FMI2, CS) for i in IMPORTERS if not i.reference and i.runs.covers(CS, FMI2)]
    compared = others[0] + (f" ({', '.join(others[1:])})" if others[1:] else "") if others else ""
    methods = _fixed_steps()

    def band(method: FixedStep, name: str) -> str:
        drift = round(method.band[1] - ORDER_SLACK)
        return f"{band_text(method.band)} for {name}" + (
            f" (whose conserved quantities drift at order {drift})" if drift > method.order else "")

    return (
        "Max error: max over time and signals of |FMU − reference| / (range of the reference), or the relative "
        f"drift of an invariant; {compared} vs FMPy: max |{compared} − FMPy| / max |FMPy| "
        "at the same settings. "
        "ME: the same cases in Model Exchange, against the reference: FMPy's CVode at relative tolerance "
        f"1e-10, held to the case's tolerance; {' and '.join(f'{i.words.owner} {name}' for i, _, name in methods)} "
        "at a fixed step h and at h/2, held to the case's tolerance or to their order: p = log2(e(h)/e(h/2)) in "
        f"{', '.join(band(m, name) for _, m, name in methods)}, h being the output interval over "
        f"{', '.join(f'{_steps(m)} for {name}' for _, m, name in methods)}: the first at which the error neither "
        "falls faster than that nor is as large as the signal. (limit): the importer's solver does not reach the "
        "case's tolerance; the error it reaches is reported, not failed (CVode up to 1e-6; a fixed-step method "
        "that passes neither way). ✗: a failure."
    )


LEGEND = _legend()

LEGEND3 = (
    "FMI 3.0 (fmus/fmi3/<Name>.fmu, its arrays matched with the FMI 2.0 variables the cases name): "
    + "; ".join(i.words.tables3 for i in IMPORTERS if i.words.tables3 and i.runs.covers(CS, FMI3)) + "."
)


def _highlighted(cases: list[dict[str, Any]]) -> list[tuple[dict[str, Any], str]]:
    """The highlighted cases, each with its plot's path relative to validation.md."""
    out = []
    for entry in cases:
        if entry.get("highlight"):
            stem = entry["highlight"] if isinstance(entry["highlight"], str) else f"{entry['fmu']}-{entry['case']}"
            out.append((entry, f"{PLOTS}/{stem}.png"))
    return out


def write_readme(directory: Path, rows: list[Row], cases: list[dict[str, Any]],
                 header: dict[str, Any]) -> list[Path]:
    """The tables (``validation.md``) and the highlighted cases' plots they link to (in
    ``validation/`` beside it)."""
    directory.mkdir(parents=True, exist_ok=True)
    highlighted = _highlighted(cases)
    fmi2, fmi3 = _tables(rows)
    parts = ["<!-- written by `cargo run --release -- validate --readme docs` -->"]
    if len(fmi2) > 2:
        parts.append("\n".join(fmi2))
    if len(fmi3) > 2:
        parts.append("FMI 3.0:\n\n" + "\n".join(fmi3))
    parts += _check_lines(rows)
    versions = f"{versions_text(header)}."
    parts.append(LEGEND + (" " + LEGEND3 if len(fmi3) > 2 else "") + " " + versions)
    if highlighted:
        parts.append("\n".join(f"![{entry['fmu']} {entry['case']}]({png})" for entry, png in highlighted))
    path = directory / "validation.md"
    path.write_text("\n\n".join(parts) + "\n")
    written = [path]
    for entry, png in highlighted:
        dest = directory / png
        dest.parent.mkdir(exist_ok=True)
        if entry.get("png_path"):
            shutil.copyfile(entry["png_path"], dest)
        else:
            plot_case(entry, dest)
        written.append(dest)
    return written
