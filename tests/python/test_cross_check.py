"""The FMI cross-check as input and output of `mechfmu validate`, and `mechfmu build
--cross-check`.

The foreign FMU is FirstOrder (tests/python/data/foreign/, built with gcc by
test_validate_foreign.build), here without the reference it carries: its closed-form reference
files lie beside it, as the cross-check's exporters submit them. A tree of it is built at
test time (a good copy, one with a wrong reference, a Model Exchange folder whose copy has
no Co-Simulation, copies for another platform and marked not compliant): `mechfmu validate`
walks it and writes the importer's results where the rules say, which FMPy's own
`validate_vendor_repo` accepts. A run that simulates nothing fails; FMPy's criterion
(`fmpy.cross_check.validate_result`) is a row of its own beside mechfmu's verdict.
"""

from __future__ import annotations

import json
import re
import shutil
import subprocess
import warnings
import zipfile
from pathlib import Path

import pytest

import fmutest
from mechfmu_validate import cross_check, embedded_reference
from test_validate_foreign import REFERENCE, SOURCE, build, fmi_run, validate  # noqa: F401 (fixture)

REPO = fmutest.REPO_ROOT
CRITERION = "FMPy cross-check criterion"
TOOL = ("HandWritten", "1.0")


def validate_repo(root: Path) -> tuple[int, int, list[str]]:
    """FMPy's check of a cross-check repository: (FMUs, results, problems)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        from fmpy.cross_check.validate_vendor_repo import validate_repo as fmpy_validate_repo

        return fmpy_validate_repo(str(root))


def with_beside(directory: Path, files: dict[str, str] | None = None, carried: bool = False, **kw) -> Path:
    """FirstOrder with ``files`` (default: its reference files) beside it, carrying its
    reference when ``carried``, none otherwise."""
    fmu = build(directory, **({} if carried else {"files": {}}), **kw)
    for name, text in (REFERENCE if files is None else files).items():
        (directory / name).write_text(text)
    return fmu


def run(directory: Path, fmi_run: Path, *args: str):
    """:func:`test_validate_foreign.validate` in a directory of its own (several runs a test)."""
    directory.mkdir()
    return validate(directory, fmi_run, *args)


def scaled_z(factor: float) -> str:
    """FirstOrder's reference with z multiplied by ``factor`` from t = 1 on."""
    lines = REFERENCE["FirstOrder_ref.csv"].splitlines()
    out = lines[:12]
    for line in lines[12:]:
        t, y, z = line.split(",")
        out.append(f"{t},{y},{float(z) * factor!r}")
    return "\n".join(out) + "\n"


def rows_of(rows: list[dict], case: str, fmu: Path | None = None) -> dict[str, dict]:
    """The rows of ``case`` by importer (of the FMU file ``fmu``, found by walking a directory)."""
    return {r["importer"]: r for r in rows if r["case"] == case and (fmu is None or r["file"] == str(fmu.resolve()))}


def test_reference_files_beside_an_fmu_are_run_as_the_carried_ones_are(tmp_path, fmi_run):
    fmu = with_beside(tmp_path / "x")
    proc, rows = validate(tmp_path, fmi_run, str(fmu))
    assert proc.returncode == 0, proc.stdout[-4000:]
    refs = rows_of(rows, cross_check.CASE_NAME)
    assert set(refs) == {"FMPy", CRITERION, "libcosim", "fmi crate"}, refs
    assert all(r["passed"] for r in refs.values()) and refs["FMPy"]["max_error"] < 1e-12
    assert refs["FMPy"]["tolerance"] == pytest.approx(1e-4)  # from RelTol of FirstOrder_ref.opt, beside
    assert set(refs["FMPy"]["signals"]) == {"y", "z"}
    assert refs[CRITERION]["max_error"] == 0 and refs[CRITERION]["tolerance"] == 0.1
    assert not rows_of(rows, embedded_reference.CASE_NAME) and "nothing simulated" not in proc.stdout


def test_files_beside_that_the_fmu_carries_too_run_once_and_others_beside_them(tmp_path, fmi_run):
    fmu = with_beside(tmp_path / "same", carried=True)  # the same bytes beside it
    proc, rows = run(tmp_path / "a", fmi_run, str(fmu))
    assert proc.returncode == 0, proc.stdout[-4000:]
    assert not rows_of(rows, embedded_reference.CASE_NAME)
    [fmpy_row] = [r for r in rows if r["case"] == cross_check.CASE_NAME and r["importer"] == "FMPy"]
    assert any("the same files as the FMU carries" in n for n in fmpy_row["notes"]), fmpy_row["notes"]

    # carrying the right reference; beside it, z 1 % off
    fmu = with_beside(tmp_path / "other", {**REFERENCE, "FirstOrder_ref.csv": scaled_z(1.01)}, carried=True)
    proc, rows = run(tmp_path / "b", fmi_run, str(fmu))
    assert proc.returncode == 1
    carried, beside = rows_of(rows, embedded_reference.CASE_NAME), rows_of(rows, cross_check.CASE_NAME)
    assert carried["FMPy"]["passed"] and carried[CRITERION]["passed"]
    assert not beside["FMPy"]["passed"] and not beside["FMPy"]["signals"]["z"]["passed"]
    # 1 % of z's value is within FMPy's band (10 % of its range): its criterion passes
    assert beside[CRITERION]["passed"], beside[CRITERION]


def test_fmpy_criterion_is_a_row_of_its_own(tmp_path, fmi_run):
    """z doubled from t = 1: both fail, FMPy's criterion saying so in its own words."""
    fmu = with_beside(tmp_path / "x", {**REFERENCE, "FirstOrder_ref.csv": scaled_z(2.0)})
    proc, rows = validate(tmp_path, fmi_run, str(fmu))
    assert proc.returncode == 1
    refs = rows_of(rows, cross_check.CASE_NAME)
    assert not refs["FMPy"]["passed"] and not refs[CRITERION]["passed"]
    criterion = refs[CRITERION]
    assert criterion["problems"] == ['More than 10% of the samples outside epsilon band for variable "z"']
    assert criterion["max_error"] > 0.5 and criterion["signals"]["y"]["max_error"] == 0
    assert re.search(rf"^FAIL FirstOrder / {cross_check.CASE_NAME} / {CRITERION}:", proc.stdout, re.M)
    # libcosim and the fmi crate still agree with FMPy: the reference is wrong, not the runs
    assert refs["libcosim"]["passed"] and refs["fmi crate"]["passed"]


def test_a_run_that_simulated_nothing_fails_saying_so(tmp_path, fmi_run):
    fmu = build(tmp_path / "x", files={})
    proc, rows = validate(tmp_path, fmi_run, str(fmu))
    assert proc.returncode == 1
    [row] = [r for r in rows if not r["passed"]]
    assert row["case"] == "(nothing simulated)" and not [r for r in rows if r["kind"] in ("case", "reference")]
    assert "FirstOrder_ref.csv beside it" in row["problems"][0] and str(fmu) in row["problems"][0]
    assert re.search(r"^FAIL FirstOrder / \(nothing simulated\)", proc.stdout, re.M)
    assert re.search(r"^\d+ passed, 1 failed", proc.stdout, re.M)


def test_a_reference_that_cannot_be_run_is_a_skip_and_nothing_simulated_fails(tmp_path, fmi_run):
    """A reference starting at t = 1 (mechfmu validate runs from t = 0) is not a simulation."""
    opt = REFERENCE["FirstOrder_ref.opt"].replace("StartTime, 0", "StartTime, 1")
    fmu = with_beside(tmp_path / "x", {**REFERENCE, "FirstOrder_ref.opt": opt})
    proc, rows = validate(tmp_path, fmi_run, str(fmu))
    assert proc.returncode == 1, proc.stdout[-3000:]
    [skipped] = [r for r in rows if r.get("skipped")]
    assert "starts at t = 1" in skipped["problems"][0]
    [failed] = [r for r in rows if not r["passed"]]
    assert failed["case"] == "(nothing simulated)" and "a SKIP row says why" in failed["problems"][0]


def test_a_scheduled_execution_only_fmu_is_said_to_be_one(tmp_path):
    """The SKIP's reason names the interface the FMU has (as the Reference-FMUs' Clocks)."""
    md = ('<?xml version="1.0" encoding="UTF-8"?>\n'
          '<fmiModelDescription fmiVersion="3.0" modelName="Clocks" instantiationToken="{x}">\n'
          '  <ScheduledExecution modelIdentifier="Clocks"/>\n'
          '  <ModelVariables><Float64 name="time" valueReference="0" causality="independent"/></ModelVariables>\n'
          '  <ModelStructure/>\n'
          '</fmiModelDescription>\n')
    fmu = tmp_path / "Clocks.fmu"
    with zipfile.ZipFile(fmu, "w") as z:
        z.writestr("modelDescription.xml", md)
    why = cross_check.not_validated(fmu)
    assert why is not None and why.startswith("Scheduled Execution only:"), why


def test_a_model_exchange_only_fmu_given_alone_is_a_skip_and_nothing_simulated_fails(tmp_path, fmi_run):
    """As in a cross-check tree's me folder: not the FMU's FAIL, but not a pass either."""
    me_only = (SOURCE / "modelDescription.xml").read_text().replace(
        '<CoSimulation modelIdentifier="FirstOrder" canHandleVariableCommunicationStepSize="true"/>',
        '<ModelExchange modelIdentifier="FirstOrder"/>')
    fmu = build(tmp_path / "x", xml=me_only)
    proc, rows = validate(tmp_path, fmi_run, str(fmu))
    assert proc.returncode == 1, proc.stdout[-3000:]
    assert [r["case"] for r in rows] == [cross_check.CASE_NAME, "(nothing simulated)"]
    assert rows[0]["skipped"] and "Model Exchange only" in rows[0]["problems"][0]
    assert not rows[1]["passed"] and "is not validated" in rows[1]["problems"][0]


def tree(root: Path) -> dict[str, Path]:
    """A cross-check repository of FirstOrder: the FMUs by what each is for."""
    def folder(version="2.0", interface="cs", platform="linux64", tool_version=TOOL[1]) -> Path:
        return root / "fmus" / version / interface / platform / TOOL[0] / tool_version / "FirstOrder"

    me_only = (SOURCE / "modelDescription.xml").read_text().replace(
        '<CoSimulation modelIdentifier="FirstOrder" canHandleVariableCommunicationStepSize="true"/>',
        '<ModelExchange modelIdentifier="FirstOrder"/>')
    fmus = dict(good=with_beside(folder()),
                wrong=with_beside(folder(tool_version="2.0"), {**REFERENCE, "FirstOrder_ref.csv": scaled_z(2.0)}),
                me_only=with_beside(folder(interface="me"), xml=me_only),
                win64=with_beside(folder(platform="win64"), binary_folder="win64"),
                not_compliant=with_beside(folder(tool_version="0.9")))
    (fmus["not_compliant"].parent / cross_check.NOT_COMPLIANT).write_text("")
    for fmu in fmus.values():
        (fmu.parent / "README.md").write_text("FirstOrder, hand-written in C.\n")
    return fmus


def test_a_cross_check_tree_is_walked_and_its_results_written_as_the_rules_ask(tmp_path, fmi_run):
    root = tmp_path / "fmi-cross-check"
    fmus = tree(root)
    proc, rows = validate(tmp_path, fmi_run, str(root), "--cross-check-results", str(root))
    assert proc.returncode == 1, proc.stdout[-4000:]
    assert "left out of" in proc.stderr and "1 FMU for win64" in proc.stderr \
        and f"1 FMU marked {cross_check.NOT_COMPLIANT}" in proc.stderr, proc.stderr[-2000:]
    walked = {r["file"] for r in rows}
    assert walked == {str(fmus[k].resolve()) for k in ("good", "wrong", "me_only")}, walked
    good, wrong = rows_of(rows, cross_check.CASE_NAME, fmus["good"]), rows_of(rows, cross_check.CASE_NAME, fmus["wrong"])
    assert good["FMPy"]["passed"] and good[CRITERION]["passed"]
    assert not wrong["FMPy"]["passed"] and not wrong[CRITERION]["passed"]
    [skipped] = rows_of(rows, cross_check.CASE_NAME, fmus["me_only"]).values()
    assert skipped.get("skipped") and "Model Exchange only" in skipped["problems"][0]

    results = root / "results" / "2.0"
    version = cross_check.importer_version()

    def result(interface: str, tool_version: str) -> Path:
        return results / interface / "linux64" / "mechfmu" / version / TOOL[0] / tool_version / "FirstOrder"

    written = {p.relative_to(root).as_posix() for p in (root / "results").rglob("*") if p.is_file()}
    expected = {(result("cs", "1.0"), "passed"), (result("cs", "2.0"), "failed"), (result("me", "1.0"), "rejected")}
    assert written == {(d / f).relative_to(root).as_posix() for d, verdict in expected
                       for f in ([verdict, "README.md"] + (["FirstOrder_out.csv"] if verdict != "rejected" else []))}
    out = (result("cs", "1.0") / "FirstOrder_out.csv").read_text().splitlines()
    assert out[0] == '"time","y","z"' and len(out) == len(REFERENCE["FirstOrder_ref.csv"].splitlines())
    readme = (result("cs", "2.0") / "README.md").read_text()
    assert readme.startswith("# FirstOrder: failed") and "More than 10% of the samples" in readme
    assert "Model Exchange only" in (result("me", "1.0") / "README.md").read_text()
    # FMPy's own check of the repository: the FMUs' files and every `passed` result
    assert validate_repo(root) == (5, 3, [])

    # again: the verdicts are replaced, not added to
    (fmus["wrong"].parent / "FirstOrder_ref.csv").write_text(REFERENCE["FirstOrder_ref.csv"])
    proc, _ = run(tmp_path / "again", fmi_run, str(root / "fmus" / "2.0" / "cs"), "--cross-check-results", str(root))
    assert proc.returncode == 0, proc.stdout[-3000:]
    assert sorted(p.name for p in result("cs", "2.0").iterdir()) == ["FirstOrder_out.csv", "README.md", "passed"]


def test_our_fmus_as_a_cross_check_tree(tmp_path):
    """`mechfmu build --cross-check DIR`: the tree FMPy's validate_vendor_repo accepts; then
    `mechfmu validate DIR` writes results for both interfaces of both versions, which it
    accepts too."""
    root = tmp_path / "xc"
    done = subprocess.run(["cargo", "run", "--release", "--quiet", "--", "build", "Oscillator", "--platform",
                           "x86_64-linux", "--out", str(tmp_path / "fmus"), "--cross-check", str(root)],
                          cwd=REPO, capture_output=True, text=True, timeout=1800)
    assert done.returncode == 0, done.stderr[-3000:]
    version = cross_check.importer_version()
    folders = {(v, i, p): root / "fmus" / v / i / p / "mechfmu" / version / "Oscillator"
               for v, p in (("2.0", "linux64"), ("3.0", "x86_64-linux")) for i in ("cs", "me")}
    reference = REPO / "fmus" / "oscillator" / "reference"
    for (v, _, _), folder in folders.items():
        names = sorted(p.name for p in folder.iterdir())
        assert names == ["Oscillator.fmu", "Oscillator_in.csv", "Oscillator_ref.csv", "Oscillator_ref.opt",
                         "README.md"], (folder, names)
        built = tmp_path / "fmus" / ("fmi3" if v == "3.0" else "") / "Oscillator.fmu"
        assert (folder / "Oscillator.fmu").read_bytes() == built.read_bytes()
        assert (folder / "Oscillator_ref.opt").read_bytes() == (reference / "Oscillator_ref.opt").read_bytes()
    fmu_count, result_count, problems = validate_repo(root)
    assert (fmu_count, result_count, problems) == (4, 0, []), problems

    # the Rust command hands the directory and the option over; no case of cases.py matches
    # "none": the reference beside each FMU alone runs, in both interfaces where the folder says me
    js = tmp_path / "rows.json"
    done = subprocess.run(["cargo", "run", "--release", "--quiet", "--", "validate", str(root), "--case", "none",
                           "--no-fmi-crate", "--cross-check-results", str(root), "--json", str(js)],
                          cwd=REPO, capture_output=True, text=True, timeout=1800)
    assert done.returncode == 0, done.stdout[-4000:] + done.stderr[-3000:]
    rows = json.loads(js.read_text())["rows"]
    for (v, interface, _), folder in folders.items():
        mine = rows_of(rows, cross_check.CASE_NAME, folder / "Oscillator.fmu")
        cs, me = ("FMPy", "FMPy ME CVode") if v == "2.0" else ("FMPy FMI3 CS", "FMPy FMI3 ME CVode")
        wanted = {cs, f"{cs} cross-check criterion"} | ({me, f"{me} cross-check criterion"} if interface == "me"
                                                        else set())
        assert set(mine) == wanted and all(r["passed"] for r in mine.values()), (folder, mine)
    passed = sorted(p.parent.relative_to(root / "results").parts[:2] for p in (root / "results").rglob("passed"))
    assert passed == [("2.0", "cs"), ("2.0", "me"), ("3.0", "cs"), ("3.0", "me")]
    assert validate_repo(root) == (4, 4, [])  # it counts the FMI 3.0 ones, and checks FMI 1.0 and 2.0 only
    shutil.rmtree(root)


def test_fmpy_criterion_fails_a_result_without_a_signal_of_the_reference():
    """FMPy's validate_result judges the signals a result has: one it lacks must fail the row
    (the docs' 'when a signal is missing'), as a reference with more columns than the FMU's
    outputs (the Reference-FMUs' FMI 2.0 Feedthrough, packed with FMI 3.0's results)."""
    from types import SimpleNamespace

    import numpy as np

    from mechfmu_validate import fmpy_criterion

    t = np.linspace(0.0, 1.0, 101)
    table = np.zeros(len(t), dtype=[("time", float), ("y", float), ("z", float)])
    table["time"], table["y"], table["z"] = t, np.sin(t), np.cos(t)
    ref = SimpleNamespace(table=table, window=(0.0, 1.0), case=SimpleNamespace(name="reference"))

    class Result(dict):
        time = t

    whole = fmpy_criterion.criterion_row("X", ref, Result(y=np.sin(t), z=np.cos(t)), "FMPy")
    assert whole["passed"], whole
    lacking = fmpy_criterion.criterion_row("X", ref, Result(y=np.sin(t)), "FMPy")
    assert not lacking["passed"] and lacking["max_error"] == 1.0, lacking
    assert lacking["problems"][-1].startswith("z: in the reference, not in the result"), lacking["problems"]
    assert not lacking["signals"]["z"]["passed"] and lacking["signals"]["y"]["passed"]
