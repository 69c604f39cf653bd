"""The validation tables of ``mechfmu validate --readme DIR``: ``DIR/validation.md``, one row
per case in two tables (the FMI 2.0 FMUs under FMPy, libcosim, the fmi crate and in Model
Exchange; their FMI 3.0 FMUs under FMPy's and the fmi crate's FMI 3.0), the checks in two
lines, and the highlighted cases' plots (``DIR/validation/<name>.png``, linked below the
tables). ``docs/validation.md`` is this file, written with ``--readme docs``.
"""

from __future__ import annotations

import shutil
from pathlib import Path
from typing import Any

from .fmi3 import AGREEMENT, FMI3_CRATE, FMI3_CS, FMI3_CVODE, FMI3_RK4, IMPORTERS as FMI3_IMPORTERS
from .model_exchange import CVODE, EULER, METHODS, RK4, band_text
from .report import number_text, plot_case

__all__ = ["write_readme"]

#: the folder beside validation.md that holds the highlighted cases' plots
PLOTS = "validation"

FMI2_HEAD = ["| FMU | reference case | FMPy: max error | tolerance | libcosim vs FMPy | fmi crate vs FMPy | "
             "ME CVode | ME Euler | ME RK4 (fmi crate) | result |",
             "|---|---|---:|---:|---:|---:|---:|---:|---:|---|"]

FMI3_HEAD = ["| FMU | reference case | FMPy FMI3 CS: max error | tolerance | fmi crate FMI3 CS vs FMPy | "
             "FMI3 ME CVode | FMI3 ME RK4 (fmi crate) | result |",
             "|---|---|---:|---:|---:|---:|---:|---|"]


def _me_cell(row: dict[str, Any] | None) -> str:
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


def _cell(row: dict[str, Any] | None) -> str:
    if row is None:
        return "-"
    return number_text(row["max_error"]) + ("" if row["passed"] else " **✗**")


def _tables(rows: list[dict[str, Any]]) -> tuple[list[str], list[str]]:
    per_case: dict[tuple[str, str], dict[str, dict[str, Any]]] = {}
    for r in rows:
        if r["kind"] == "case":
            per_case.setdefault((r["fmu"], r["case"]), {})[r["importer"]] = r
    fmi2, fmi3 = list(FMI2_HEAD), list(FMI3_HEAD)
    for (fmu, case), by in per_case.items():
        two = {k: r for k, r in by.items() if k not in FMI3_IMPORTERS}
        three = {k: r for k, r in by.items() if k in FMI3_IMPORTERS}
        if two:
            fmpy = two.get("FMPy") or {}
            me = " | ".join(_me_cell(two.get(importer)) for importer in (CVODE, EULER, RK4))
            fmi2.append(f"| {fmu} | {case} | {number_text(fmpy.get('max_error'))} | "
                        f"{number_text(fmpy.get('tolerance'))} | {_cell(two.get('libcosim'))} | "
                        f"{_cell(two.get('fmi crate'))} | {me} | "
                        f"{'PASS' if all(r['passed'] for r in two.values()) else 'FAIL'} |")
        if three:
            cs = three.get(FMI3_CS) or {}
            me = " | ".join(_me_cell(three.get(importer)) for importer in (FMI3_CVODE, FMI3_RK4))
            fmi3.append(f"| {fmu} | {case} | {number_text(cs.get('max_error'))} | "
                        f"{number_text(cs.get('tolerance'))} | {_cell(three.get(FMI3_CRATE))} | {me} | "
                        f"{'PASS' if all(r['passed'] for r in three.values()) else 'FAIL'} |")
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


LEGEND = (
    "Max error: max over time and signals of |FMU − reference| / (range of the reference), or the relative "
    "drift of an invariant; libcosim (fmi crate) vs FMPy: max |libcosim (fmi crate) − FMPy| / max |FMPy| "
    "at the same settings. "
    "ME: the same cases in Model Exchange, against the reference: FMPy's CVode at relative tolerance "
    "1e-10, held to the case's tolerance; FMPy's Euler and the fmi crate's RK4 at a fixed step h and "
    "at h/2, held to the case's tolerance or to their order: p = log2(e(h)/e(h/2)) in "
    f"{band_text(METHODS[EULER].band)} for Euler, {band_text(METHODS[RK4].band)} for RK4 (whose "
    "conserved quantities drift at order 5), h being the output interval over 2, 4 or 8 for Euler, "
    "1 or 2 for RK4: the first at which the error neither falls faster than that nor is as large as "
    "the signal. (limit): the importer's solver does not reach the case's tolerance; the error it "
    "reaches is reported, not failed (CVode up to 1e-6; a fixed-step method that passes neither way). "
    "✗: a failure."
)

LEGEND3 = (
    "FMI 3.0 (fmus/fmi3/<Name>.fmu, its arrays matched with the FMI 2.0 variables the cases name): FMPy's FMI 3.0 "
    "Co-Simulation (step mode, no early return) and Model Exchange (CVode at 1e-10) against the reference, held to "
    "the same limits; the fmi crate's FMI 3.0 import (mechfmu-fmi-run) against FMPy's FMI 3.0 run (1e-9) and its "
    "RK4 held to its order, as above."
)


def _highlighted(cases: list[dict[str, Any]]) -> list[tuple[dict[str, Any], str]]:
    """The highlighted cases, each with its plot's path relative to validation.md."""
    out = []
    for entry in cases:
        if entry.get("highlight"):
            stem = entry["highlight"] if isinstance(entry["highlight"], str) else f"{entry['fmu']}-{entry['case']}"
            out.append((entry, f"{PLOTS}/{stem}.png"))
    return out


def write_readme(directory: Path, rows: list[dict[str, Any]], cases: list[dict[str, Any]],
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
    versions = f"FMPy {header['fmpy']}, {header['libcosim']}, {header.get('fmi_crate', '-')}."
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
