"""``python -m mechfmu_validate`` (what ``mechfmu validate`` runs).

    python -m mechfmu_validate FMU|DIR [...] [--cases MODEL=cases.py ...] [--case TEXT ...]
                               [--report DIR] [--json FILE] [--junit FILE] [--readme DIR]
                               [--cross-check-results DIR] [--time-limit SECONDS] [--no-IMPORTER ...]
                               [--no-model-exchange] [--no-fmi3]
    python -m mechfmu_validate references FMU [FMU ...] --cases MODEL=cases.py ...

Each case runs under every importer of the registry (:mod:`.importers`; ``--no-IMPORTER``
leaves one out): first under FMPy, against the case's reference, then under the others, each
of which must agree with FMPy to its tolerance; in Co-Simulation, then in Model Exchange,
against the reference (:mod:`.model_exchange`; ``--no-model-exchange`` leaves it out); then,
when the FMI 3.0 FMU is beside the FMI 2.0 one (``<dir>/fmi3/<Name>.fmu``; ``--no-fmi3``
leaves it out), under the importers of FMI 3.0 (:mod:`.target`). An FMI 3.0 FMU given on the
command line gets its checks and the FMI 3.0 rows alone (:mod:`.validation`). An FMU without
cases is run against the reference results it carries (:mod:`.embedded_reference`) and those
beside it, ``<Model>_ref.csv`` with ``_in.csv`` and ``_ref.opt`` (:mod:`.cross_check`); one
against which nothing was simulated fails, saying so; one that cannot be opened is one FAIL
row saying why (:mod:`.opening`). A directory is walked for FMUs, an FMI cross-check tree's
as its rules lay them out, and ``--cross-check-results DIR`` writes the importer's results
the rules ask for (:mod:`.cross_check`). Each FMU is validated in a child process of its own:
one that crashes, or makes no progress for ``--time-limit`` seconds, is one FAIL row, and what
the importers write to the console goes into the rows (:mod:`.isolation`). The table and the
JUnit suites name an FMU by its model, or by its path where files given share a model name.

Exit status: 0 when everything passes, 1 when a row fails (the table is printed), 2 for a
usage error, 3 when the validator itself failed (a bug of mechfmu's: the traceback says where),
130 when interrupted (Ctrl-C).
"""

from __future__ import annotations

import argparse
import json
import math
import platform
import sys
import traceback
from pathlib import Path

import numpy as np

import fmpy

from . import fmulog
from .cross_check import take_outputs, walk, write_results
from .fmu import Fmu
from .importer import Availability, Selection
from .importers import IMPORTERS, PLATFORMS
from .isolation import TIME_LIMIT, Job, validate_isolated
from .junit import write_junit
from .loader import default_case, load_cases, reference_case
from .reference import write_references
from .platform_rows import session as platform_session
from .report import limit_text, platform_lines, result_text
from .rows import Row


def _positive_seconds(text: str) -> float:
    """``--time-limit``'s value: a finite number of seconds above 0."""
    try:
        seconds = float(text)
    except ValueError:
        seconds = math.nan
    if not (math.isfinite(seconds) and seconds > 0):
        raise argparse.ArgumentTypeError(f"{text!r} is not a number of seconds above 0")
    return seconds


def make_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="mechfmu validate", description=__doc__.split("\n\n")[0])
    p.add_argument("fmus", nargs="+", type=Path, metavar="FMU",
                   help="the FMU files, or directories to find them in (an FMI cross-check tree)")
    p.add_argument("--cases", action="append", default=[], metavar="MODEL=PATH",
                   help="the validation/cases.py of a model identifier (repeatable)")
    p.add_argument("--case", action="append", default=[], metavar="TEXT",
                   help="only the cases whose name contains TEXT (repeatable)")
    p.add_argument("--report", type=Path, metavar="DIR", help="write DIR/index.md, DIR/index.html and the plots")
    p.add_argument("--json", type=Path, metavar="FILE", help="write the results as JSON")
    p.add_argument("--junit", type=Path, metavar="FILE", help="write the results as JUnit XML (one testcase per row)")
    p.add_argument("--readme", type=Path, metavar="DIR",
                   help="write DIR/validation.md (the validation tables) and the highlighted cases' plots "
                        "in DIR/validation/; for an SSP, its coupling figure there")
    p.add_argument("--cross-check-results", type=Path, metavar="DIR",
                   help="for each FMU of an FMI cross-check tree, write what an importer submits to "
                        "DIR/results/<version>/<cs|me>/<platform>/mechfmu/<version>/<tool>/<version>/<model>/")
    p.add_argument("--time-limit", type=_positive_seconds, default=TIME_LIMIT, metavar="SECONDS",
                   help="stop an FMU's validation as hung after SECONDS without progress (no result, no FMI call; "
                        f"default {TIME_LIMIT:g})")
    for importer in IMPORTERS:
        if importer.option is not None:
            p.add_argument(f"--no-{importer.option}", action="append_const", const=importer.option, dest="left_out",
                           default=[], help=importer.left_out)
    p.add_argument("--no-model-exchange", action="store_true", help="do not run the cases in Model Exchange")
    p.add_argument("--no-fmi3", action="store_true",
                   help="do not validate the FMI 3.0 FMU beside an FMI 2.0 one (<dir>/fmi3/<Name>.fmu)")
    return p


def _cases_map(items: list[str]) -> dict[str, Path]:
    out = {}
    for item in items:
        model, sep, path = item.partition("=")
        if not sep or not model or not path:
            raise SystemExit(f"mechfmu validate: --cases takes MODEL=PATH, not {item!r}")
        out[model] = Path(path)
    return out


def print_table(rows: list[Row]) -> None:
    def fmt(x):
        if x is None:
            return "-"
        if isinstance(x, float) and (x == 0 or not math.isfinite(x)):
            return "0" if x == 0 else str(x)
        return f"{x:.2e}"

    head = ("FMU", "case", "importer", "max error", "tolerance", "result")
    table = [head] + [(r["fmu"], r["case"], r["importer"], fmt(r["max_error"]), limit_text(r, fmt),
                       result_text(r)) for r in rows]
    widths = [max(len(str(row[i])) for row in table) for i in range(len(head))]
    for k, row in enumerate(table):
        print("  ".join(str(c).ljust(w) if i < 3 else str(c).rjust(w) if i < 5 else str(c)
                        for i, (c, w) in enumerate(zip(row, widths))))
        if k == 0:
            print("  ".join("-" * w for w in widths))
    failed = [r for r in rows if not r["passed"]]
    for r in failed:
        print(f"\nFAIL {r['fmu']} / {r['case']} / {r['importer']}:")
        for p in r["problems"][:20]:
            print(f"  - {p}")
        for n in r.get("notes", []):
            print(f"  ({n})")
        for name, s in (r.get("signals") or {}).items():
            if not s["passed"] and "scale" in s:
                print(f"  - {name}: {s['max_error']:.3e} of scale {s['scale']:.4g} at t = {s['at_time']:g} "
                      f"(tolerance {s['tolerance']:.0e})")
        said = (r.get("output") or "").strip().splitlines()
        if said:
            last = ", the last 10" if len(said) > 10 else ""
            print(f"  the importer's and the FMU's console output ({len(said)} lines{last}):")
            for line in said[-10:]:
                print(f"  | {line}")
    skipped = [r for r in rows if r.get("skipped")]
    for r in skipped:
        print(f"\nSKIP {r['fmu']} / {r['case']} / {r['importer']}: {'; '.join(r['problems'])}")
    limited = [r for r in rows if r.get("limited")]
    for r in limited:
        print(f"\nLIMIT {r['fmu']} / {r['case']} / {r['importer']} (the importer's solver; reported, not failed):")
        for n in r.get("notes", [])[:4]:
            print(f"  ({n})")
    n_fail = len(failed)
    talkative = [r for r in rows if r["passed"] and (r.get("output") or "").strip()]
    if talkative:
        print(f"\n({len(talkative)} rows that pass captured the importers' console output: "
              "in the JSON and JUnit files)")
    print(f"\n{len(rows) - n_fail - len(skipped) - len(limited)} passed, {n_fail} failed" +
          (f", {len(limited)} at the importer's limit" if limited else "") +
          (f", {len(skipped)} skipped" if skipped else ""))


def _name_files_apart(rows: list[Row], plots: list[dict]) -> None:
    """The FMU column names a model; where two FMU files given are models of one name (an FMI
    2.0 and an FMI 3.0 FMU, a model from several exporters), each file's rows and plots are
    named by its path instead, so that neither the table nor the JUnit suites merge them."""
    models: dict[str, set[str]] = {}
    for r in rows:
        models.setdefault(r["fmu"], set()).add(r["file"])
    shared = {name for name, files in models.items() if len(files) > 1}
    for item in (*rows, *plots):
        if item.get("fmu") in shared:
            item["fmu"] = item["file"]
            if item.get("anchor"):
                item["anchor"] = f"{item['file']}-{item['case']}".replace(" ", "-").replace("/", "-")


def _jsonable(x):
    if isinstance(x, Row):
        return _jsonable(x.to_json())
    if isinstance(x, dict):
        return {k: _jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [_jsonable(v) for v in x]
    if isinstance(x, (np.floating, float)):
        x = float(x)
        return x if math.isfinite(x) else str(x)
    if isinstance(x, (np.integer,)):
        return int(x)
    return x


def references_main(argv: list[str]) -> int:
    p = argparse.ArgumentParser(prog="mechfmu validate --write-references")
    p.add_argument("fmus", nargs="+", type=Path)
    p.add_argument("--cases", action="append", default=[], metavar="MODEL=PATH")
    args = p.parse_args(argv)
    cases_map = _cases_map(args.cases)
    status = 0
    for path in args.fmus:
        fmu = Fmu(path)
        try:
            if fmu.model not in cases_map:
                print(f"{fmu.model}: no validation/cases.py", file=sys.stderr)
                status = 1
                continue
            cases_file = cases_map[fmu.model]
            cases = load_cases(cases_file, fmu.model)
            case = reference_case(cases)
            if case is None:
                print(f"{fmu.model}: no case in {cases_file} names reference_files or is marked "
                      "default_experiment=True", file=sys.stderr)
                status = 1
                continue
            directory = cases_file.resolve().parent.parent / "reference"
            try:
                written_files = write_references(fmu, case, directory, default_case(cases))
            except ValueError as e:
                print(f"{fmu.model}: {e}", file=sys.stderr)
                status = 1
                continue
            for written in written_files:
                print(f"{fmu.model:<20} {written}")
        finally:
            fmu.cleanup()
    return status


def _fmu_files(targets: list[Path]) -> list[Path] | None:
    """The FMU files given, and those found in the directories given (:func:`.cross_check.walk`);
    None after saying what is wrong (a usage error)."""
    paths = []
    for target in targets:
        if target.is_dir():
            found, left_out = walk(target)
            if left_out:
                print(f"mechfmu validate: {left_out}", file=sys.stderr)
            if not found:
                print(f"mechfmu validate: no FMU to validate in {target}", file=sys.stderr)
                return None
            paths += found
        elif target.is_file():
            paths.append(target)
        else:
            print(f"mechfmu validate: {target} does not exist", file=sys.stderr)
            return None
    return paths


def _header(selection: Selection) -> dict[str, str]:
    """The versions of what ran (each importer's, or why it did not), saying on stderr which
    importer asked for cannot run here."""
    header = {}
    for importer in IMPORTERS:
        available: Availability | None = None
        if selection.uses(importer):
            available = importer.available()
            if not available.ok:
                print(f"mechfmu validate: {importer.unavailable.format(why=available.text)}", file=sys.stderr)
        header[importer.header_key] = importer.header(available)
    return dict(header, python=platform.python_version())


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv and argv[0] == "references":
        return references_main(argv[1:])
    args = make_parser().parse_args(argv)
    cases_map = _cases_map(args.cases)
    fmulog.install()
    selection = Selection(frozenset(args.left_out), not args.no_model_exchange, not args.no_fmi3)
    header = _header(selection)
    rows: list[Row] = []
    plots: list[dict] = []
    details: list[dict] = []
    # a system's SSP: its parameter sets in every SSP importer (:mod:`.systems`)
    ssps = [p for p in args.fmus if p.suffix.lower() == ".ssp"]
    for ssp in ssps:
        if not ssp.is_file():
            print(f"mechfmu validate: {ssp} does not exist", file=sys.stderr)
            return 2
    others = [p for p in args.fmus if p not in ssps]
    paths = _fmu_files(others) if others else []
    if paths is None:
        return 2
    if ssps:
        from .systems import validate_system

        for ssp in ssps:
            rows += validate_system(ssp, args.readme / "validation" if args.readme else None)
    # the Windows binaries run under one wine session (when scripts/cross-runners prepared it)
    with platform_session(selection.uses(PLATFORMS)):
        for path in paths:
            md_model = None
            try:
                md_model = fmpy.read_model_description(str(path), validate=False).coSimulation.modelIdentifier
            except Exception:
                pass
            # in a child process: an FMU that crashes or hangs is one FAIL row (:mod:`.isolation`)
            job = Job(path, md_model or path.name, cases_map.get(md_model or path.stem), tuple(args.case), selection)
            fmu_rows, fmu_plots, fmu_details = validate_isolated(job, args.time_limit)
            for item in (*fmu_rows, *fmu_plots):
                item["file"] = str(path)
            rows += fmu_rows
            plots += fmu_plots
            details += fmu_details
    _name_files_apart(rows, plots)
    outputs = take_outputs(rows)
    print_table(rows)
    platforms = platform_lines(rows)
    if platforms:
        print("\nplatforms:")
        for line in platforms:
            print(f"  {line}")
    if args.report:
        from .report import write_report

        write_report(args.report, rows, plots, header)
        for e in plots:
            e["png_path"] = args.report / e["png"]
        print(f"report: {args.report / 'index.html'} (and index.md)")
    if args.readme and paths:
        from .validation_tables import write_readme

        for path in write_readme(args.readme, rows, plots, header):
            print(f"readme: {path}")
    if args.json:
        args.json.parent.mkdir(parents=True, exist_ok=True)
        args.json.write_text(json.dumps(_jsonable(dict(header=header, rows=rows, cases=details)), indent=2) + "\n")
        print(f"json: {args.json}")
    if args.junit:
        write_junit(args.junit, rows)
        print(f"junit: {args.junit}")
    if args.cross_check_results:
        written = write_results(args.cross_check_results, paths, rows, outputs, header)
        print(f"cross-check results: {len(written)} in {args.cross_check_results / 'results'}")
    return 0 if all(r["passed"] for r in rows) else 1


def run(argv: list[str] | None = None) -> int:
    """:func:`main`, with the exit status 3 (and the traceback) when the validator itself
    fails: status 1 always means FAIL rows in a printed table."""
    try:
        return main(argv)
    except KeyboardInterrupt:
        print("\nmechfmu validate: interrupted", file=sys.stderr)
        return 130
    except Exception:  # noqa: BLE001
        traceback.print_exc()
        print("mechfmu validate: the validator failed (the traceback above): a bug of mechfmu's", file=sys.stderr)
        return 3
