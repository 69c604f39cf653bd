"""The FMI cross-check (github.com/modelica/fmi-cross-check) as input and output of
``mechfmu validate``.

**Input.** The files an exporter submits beside an FMU file: ``<Model>.fmu`` with
``<Model>_ref.csv`` (the reference results), ``<Model>_in.csv`` (the inputs, optional) and
``<Model>_ref.opt`` (``StartTime``, ``StopTime``, ``StepSize``, ``RelTol``) in its folder,
``<Model>`` being the FMU file's name. They are read as :mod:`.embedded_reference` reads the
files an FMU carries, and make the case :data:`CASE_NAME` (:func:`beside`). When the FMU
also carries reference files, both run, each its own case, unless they are the same bytes:
then only the files beside run, a note saying so (:func:`sources`).

A directory given to ``mechfmu validate`` is walked for FMUs (:func:`walk`). In the
cross-check's tree, ``fmus/<FMI version>/<cs|me>/<platform>/<Tool>/<Tool version>/<Model>/
<Model>.fmu``, those of FMI 2.0 and 3.0 for this machine's platform folder (``linux64``,
``x86_64-linux``) are validated, except in a folder marked ``notCompliantWithLatestRules``;
elsewhere every ``.fmu`` under it (an FMI 3.0 FMU beside its FMI 2.0 one, ``fmi3/<Name>.fmu``,
is validated with it). The folder ``cs`` or ``me`` says how an importer runs the FMU: the
reference's Co-Simulation rows run for every FMU; in ``me`` the reference also runs in Model
Exchange under FMPy's CVode, with mechfmu's verdict and FMPy's criterion's on it
(:func:`criterion_rows`), and an FMU without Co-Simulation is one SKIP row
(:func:`not_validated`: ``mechfmu validate`` opens every FMU through Co-Simulation), beside
the FAIL row of an FMU against which nothing was simulated.

**Output** (``--cross-check-results DIR``, :func:`write_results`): what an importer submits for
each FMU of the tree, in ``DIR/results/<FMI version>/<cs|me>/<platform>/mechfmu/<version>/
<Tool>/<Tool version>/<Model>/``: ``<Model>_out.csv``, FMPy's run of the reference's experiment
through the interface the folder names; ``passed`` or ``failed``, FMPy's cross-check criterion's
verdict on it (the rule ``fmpy.cross_check.validate_vendor_repo`` holds a ``passed`` to), or
``rejected`` when ``mechfmu validate`` did not run it (a SKIP); and ``README.md``: how it ran,
that verdict and mechfmu's own, or why it did not run.
"""

from __future__ import annotations

import importlib.metadata
import math
from collections import Counter
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable, Iterator

import numpy as np

import fmpy

from . import embedded_reference, fmpy_criterion, model_exchange
from .arrays import fmi2_sibling
from .case import Case, Result
from .embedded_reference import EmbeddedReference, Files
from .fmu import Fmu
from .host import HOST_FOLDER
from .reference import csv_text
from .rows import Row

__all__ = ["CASE_NAME", "IMPORTER", "NOT_COMPLIANT", "VERDICTS", "Place", "beside", "sources", "walk",
           "not_validated", "skip_row", "criterion_rows", "take_outputs", "write_results", "importer_version"]

#: the case of the reference files beside an FMU
CASE_NAME = "reference_beside"
#: the importing tool's name in the results' tree
IMPORTER = "mechfmu"
#: the file that marks a folder of the tree the current rules do not accept
NOT_COMPLIANT = "notCompliantWithLatestRules"
#: the files an importer's result is one of
VERDICTS = ("passed", "failed", "rejected")
#: the FMI versions whose FMUs are validated, and this machine's platform folder in each
HOST_PLATFORM = {"2.0": HOST_FOLDER["2"], "3.0": HOST_FOLDER["3"]}
INTERFACES = {"cs": "Co-Simulation", "me": "Model Exchange"}


@dataclass(frozen=True)
class Place:
    """Where an FMU is in a cross-check tree: ``fmus/<fmi_version>/<interface>/<platform>/<tool>/
    <tool_version>/<model>/<model>.fmu``."""

    fmi_version: str
    interface: str
    platform: str
    tool: str
    tool_version: str
    model: str

    @classmethod
    def of(cls, path: Path) -> Place | None:
        parts = Path(path).resolve().parts
        if len(parts) < 8 or parts[-8] != "fmus" or parts[-2] != Path(path).stem or parts[-6] not in INTERFACES:
            return None
        return cls(*parts[-7:-1])

    def results_folder(self, root: Path) -> Path:
        """This FMU's folder in the results' tree under ``root``."""
        return (root / "results" / self.fmi_version / self.interface / self.platform / IMPORTER / importer_version()
                / self.tool / self.tool_version / self.model)

    def text(self) -> str:
        return (f"FMI {self.fmi_version} {INTERFACES[self.interface]}, {self.platform}, exported by {self.tool} "
                f"{self.tool_version}")


def importer_version() -> str:
    """mechfmu's version (its Python package's, the same as the command's)."""
    return importlib.metadata.version("mechfmu-python")


# ---------------------------------------------------------------------------------------
# Input


def beside(fmu: Fmu) -> Files | None:
    """The cross-check's files beside the FMU file (``<stem>_ref.csv`` required), None when
    there are none."""
    folder, stem = fmu.path.parent, fmu.path.stem
    names = {role: f"{stem}{suffix}" for role, suffix in
             (("result", "_ref.csv"), ("input", "_in.csv"), ("options", "_ref.opt"))}
    names = {role: name for role, name in names.items() if (folder / name).is_file()}
    if "result" not in names:
        return None
    return Files(folder, names, CASE_NAME, f"the reference results beside {fmu.path.name}")


def _same(carried: Files, files: Files) -> bool:
    """Whether the files beside are byte for byte those the FMU carries (by role)."""
    return carried.names.keys() == files.names.keys() and all(
        (carried.folder / carried.names[r]).read_bytes() == (files.folder / files.names[r]).read_bytes()
        for r in files.names)


def sources(fmu: Fmu) -> list[tuple[Files | None, str | None]]:
    """The references to run, each with a note: the FMU's own (``None``: what
    :func:`~.embedded_reference.read` finds in the archive, which may raise), and the files
    beside it, which alone run when they are the same bytes."""
    files = beside(fmu)
    if files is None:
        return [(None, None)]
    try:
        carried = embedded_reference.carried(fmu)
    except embedded_reference.ReferenceProblem:
        return [(None, None), (files, None)]
    if carried is not None and _same(carried, files):
        return [(files, f"the same files as the FMU carries in {embedded_reference.REFERENCE_DIR}/")]
    return [(None, None), (files, None)]


def _fmu_files(directory: Path) -> list[Path]:
    return sorted(p.resolve() for p in Path(directory).rglob("*.fmu") if p.is_file())


def walk(directory: Path) -> tuple[list[Path], str | None]:
    """The FMUs to validate under ``directory`` (see the module's documentation), and what
    was left out of them (None when nothing was)."""
    found = _fmu_files(directory)
    chosen, left_out = [], Counter()
    for path in found:
        place = Place.of(path)
        if (path.parent / NOT_COMPLIANT).exists():
            left_out[f"marked {NOT_COMPLIANT}"] += 1
        elif place is not None and place.fmi_version not in HOST_PLATFORM:
            left_out[f"of FMI {place.fmi_version}"] += 1
        elif place is not None and place.platform != HOST_PLATFORM[place.fmi_version]:
            left_out[f"for {place.platform}"] += 1
        elif place is None and fmi2_sibling(path) in found:
            continue  # validated with its FMI 2.0 FMU
        else:
            chosen.append(path)
    if not left_out:
        return chosen, None
    return chosen, f"left out of {directory}: " + ", ".join(f"{n} FMU{'s' if n > 1 else ''} {why}"
                                                          for why, n in sorted(left_out.items()))


def not_validated(path: Path) -> str | None:
    """Why the FMU at ``path`` is not validated (an FMI version other than 2.0 and 3.0, or no
    Co-Simulation interface: ``mechfmu validate`` opens and checks every FMU through it), None
    when it is (or when its model description cannot be read: opening it says why)."""
    try:
        md = fmpy.read_model_description(str(path), validate=False)
    except Exception:  # noqa: BLE001 (opening the FMU will say what is wrong)
        return None
    version = str(md.fmiVersion or "")
    if version.split(".")[0] not in HOST_FOLDER:
        return f"FMI {version or '(no version given)'} is not validated here (FMI 2.0 and 3.0 are)"
    if md.coSimulation is not None:
        return None
    offered = [name for name, interface in (("Model Exchange", md.modelExchange),
                                            ("Scheduled Execution", getattr(md, "scheduledExecution", None)))
               if interface is not None]
    return (f"{' and '.join(offered) or 'no interface'} only: mechfmu validate opens and checks every FMU "
            "through its Co-Simulation interface, which this one does not have")


def skip_row(path: Path, why: str) -> Row:
    """The SKIP row of an FMU that is not validated (:func:`not_validated`)."""
    return Row(kind="reference", fmu=path.stem, case=CASE_NAME, importer="mechfmu", max_error=None, tolerance=None,
                passed=True, skipped=True, problems=[why], notes=[])


# ---------------------------------------------------------------------------------------
# The criterion's rows, and the result of an FMU of the tree


def _output_csv(ref: EmbeddedReference, result: Result) -> str:
    """``<Model>_out.csv``: ``time`` and the reference's columns, named as its file names them
    (a column the result lacks is ``nan``), to 13 significant digits (the rules cap a result's
    size)."""
    names = list(ref.columns)
    time = np.asarray(result.time, dtype=float)
    columns = [np.asarray(result[n], dtype=float) if n in result else np.full(len(time), np.nan) for n in names]
    return csv_text(["time", *[ref.columns[n] for n in names]], [time, *columns], digits=13, allow_nan=True)


def _tree_result(row: Row, ours: Row, ref: EmbeddedReference, result: Result | None,
                 how: str) -> None:
    """Marks the criterion's ``row`` as the result of the FMU's folder in the tree."""
    row["cross_check"] = dict(
        how=how, output=_output_csv(ref, result) if result is not None else None,
        ours=dict(importer=ours["importer"], passed=ours["passed"], max_error=ours.get("max_error"),
                  tolerance=ours.get("tolerance"), problems=ours.get("problems", [])))


def criterion_rows(fmu: Fmu, ref: EmbeddedReference, ours: Row, result: Result | None, importer: str,
                   run_model_exchange: tuple[str, Callable[[Case], Result] | None]) -> Iterator[Row]:
    """FMPy's criterion on ``importer``'s Co-Simulation run of the reference (``ours`` its row,
    ``result`` its result); for the files beside an FMU in a tree's ``me`` folder, the
    reference's run under FMPy's CVode as well (``run_model_exchange``: its importer's name and
    how it runs a case, None when Model Exchange is left out), mechfmu's row and the criterion's. The
    criterion's row of the run the folder names is the FMU's result in the tree. Each row is
    made when it is taken (the Model Exchange run's console output is its own row's)."""
    first = fmpy_criterion.criterion_row(fmu.model, ref, result, importer, ours.get("anchor", ""))
    place = Place.of(fmu.path) if ref.case.name == CASE_NAME else None
    if place is not None and place.interface == "cs":
        rtol = ref.case.relative_tolerance
        how = (f"FMPy {fmpy.__version__}'s simulate_fmu in Co-Simulation, relative tolerance "
               + (f"{rtol:g} (RelTol)" if rtol else "the FMU's default"))
        _tree_result(first, ours, ref, result, how)
    yield first
    if place is None or place.interface == "cs":
        return
    me_importer, run = run_model_exchange
    if run is None:
        yield skip_row(fmu.path, "Model Exchange runs left out (--no-model-exchange)").but(fmu=fmu.model,
                   importer=me_importer)
        return
    got: dict[str, Result] = {}

    def recorded(_fmu: Fmu, case: Case) -> Result:
        got["result"] = run(case)
        return got["result"]

    me_row = model_exchange.cvode_row(fmu, ref.case, importer=me_importer, run=recorded).but(kind="reference")
    yield me_row
    me_criterion = fmpy_criterion.criterion_row(fmu.model, ref, got.get("result"), me_importer)
    _tree_result(me_criterion, me_row, ref, got.get("result"),
                 f"FMPy {fmpy.__version__}'s simulate_fmu in Model Exchange, CVode at relative tolerance "
                 f"{model_exchange.CVODE_RTOL:g}")
    yield me_criterion


def take_outputs(rows: list[Row]) -> dict[str, str | None]:
    """The ``<Model>_out.csv`` texts of the FMUs of a tree, by the FMU file of their rows
    (``file``), taken out of the rows (which go on to the JSON file without them)."""
    return {r["file"]: r["cross_check"].pop("output", None) for r in rows if "cross_check" in r}


def _verdict(result_row: Row | None, mine: list[Row]) -> str:
    if result_row is not None:
        return "passed" if result_row["passed"] and not result_row.get("experiment_problem") else "failed"
    return "rejected" if any(r.get("skipped") for r in mine) else "failed"


def _cell(x: Any) -> str:
    if x is None:
        return "-"
    return ("0" if x == 0 else f"{x:.2e}") if isinstance(x, float) and math.isfinite(x) else str(x)


def _readme(place: Place, path: Path, verdict: str, result_row: Row | None,
            mine: list[Row], header: dict[str, Any]) -> str:
    model = place.model
    lines = [f"# {model}: {verdict}", "",
             f"{place.text()}; imported by mechfmu {importer_version()} (`mechfmu validate`, FMPy {header['fmpy']}).",
             ""]
    if result_row is not None:
        ours = result_row["cross_check"]["ours"]
        lines += [f"{result_row['cross_check']['how']}, from the StartTime to the StopTime of `{model}_ref.opt` on "
                  f"the reference's time grid, with the inputs of `{model}_in.csv` when there is one: "
                  f"`{model}_out.csv`.", "",
                  "| verdict | criterion | max error | limit |", "|---|---|---:|---:|",
                  f"| {verdict} | FMPy's cross-check criterion (`fmpy.cross_check.validate_result`): at most 10 % of "
                  f"each signal's samples outside a band of 10 % of its range | {_cell(result_row['max_error'])} | "
                  f"{_cell(result_row['tolerance'])} |",
                  f"| {'PASS' if ours['passed'] else 'FAIL'} | mechfmu's: each signal's largest difference from the "
                  f"reference, over its range | {_cell(ours['max_error'])} | {_cell(ours['tolerance'])} |", ""]
        problems = [*result_row["problems"], *ours["problems"]]
    else:
        lines += ["`mechfmu validate` did not run the experiment of the reference:", ""]
        problems = [p for r in mine if not r["passed"] or r.get("skipped") for p in r["problems"]]
    lines += [f"- {p}" for p in problems]
    lines += ["", f"To repeat: `mechfmu validate {path} --cross-check-results DIR`.", ""]
    return "\n".join(lines)


def write_results(root: Path, fmus: list[Path], rows: list[Row], outputs: dict[str, str | None],
                  header: dict[str, Any]) -> list[Path]:
    """The results' folder of each FMU of ``fmus`` in a tree (see the module's documentation)
    under ``root``, from the rows of the run, each naming its FMU file (``file``; ``outputs``:
    :func:`take_outputs`); the folders written."""
    written = []
    for path in fmus:
        place = Place.of(path)
        if place is None:
            continue
        key = str(path)
        mine = [r for r in rows if r.get("file") == key]
        result_row = next((r for r in mine if "cross_check" in r), None)
        verdict = _verdict(result_row, mine)
        folder = place.results_folder(root)
        folder.mkdir(parents=True, exist_ok=True)
        out = folder / f"{place.model}_out.csv"
        for stale in [out, *(folder / v for v in VERDICTS)]:
            stale.unlink(missing_ok=True)
        if outputs.get(key):
            out.write_text(outputs[key])
        (folder / verdict).write_text("")
        (folder / "README.md").write_text(_readme(place, path, verdict, result_row, mine, header))
        written.append(folder)
    return written
