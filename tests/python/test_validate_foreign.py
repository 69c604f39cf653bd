"""`mechfmu validate` on FMUs mechfmu did not build, and on broken ones.

The foreign FMU is FirstOrder (tests/python/data/foreign/: a first-order lag and its integral,
an FMI 2.0 Co-Simulation FMU written in C, exact over each step), built here with gcc against
FMPy's copy of the FMI 2.0 headers and packaged with the reference results it carries in
extra/org.fmi-standard.fmi-ls-ref/ (closed forms, written by reference.py there). It has no
validation/cases.py: validate runs it against that reference under FMPy, libcosim and the fmi
crate. Broken copies of it (not a zip, a truncated zip, no Linux binary, a damaged
modelDescription.xml, an fmi2Instantiate that returns NULL, an fmi2DoStep that fails) must
each be one FAIL row saying why, beside the good FMU still passing: exit status 1, no Python
traceback, nothing left in the temporary directory.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

import fmpy
import pytest

import fmutest
from mechfmu_validate import cs_rows, embedded_reference
from mechfmu_validate.fmi_crate import FMI_RUN_ENV
from mechfmu_validate.opening import OPENS, open_fmu

REPO = fmutest.REPO_ROOT
SOURCE = Path(__file__).resolve().parent / "data" / "foreign"
REF_DIR = "extra/org.fmi-standard.fmi-ls-ref"
REFERENCE = {name: (SOURCE / name).read_text() for name in ("FirstOrder_ref.csv", "FirstOrder_in.csv",
                                                            "FirstOrder_ref.opt")}


def build(directory: Path, *defines: str, name: str = "FirstOrder.fmu", binary_folder: str = "linux64",
          files: dict[str, str] | None = None, xml: str | None = None) -> Path:
    """FirstOrder compiled with ``defines`` (``-DREFUSE_INSTANTIATE``), packaged with ``files``
    (archive name -> text; default: its reference files) and ``xml`` as modelDescription.xml."""
    directory.mkdir(parents=True, exist_ok=True)
    binary = directory / f"{name}.so"
    subprocess.run(["gcc", "-shared", "-fPIC", "-O2", "-std=c99", "-Wall", "-Werror", *defines,
                    "-I", str(Path(fmpy.__file__).parent / "c-code"), str(SOURCE / "FirstOrder.c"),
                    "-o", str(binary), "-lm"], check=True, capture_output=True, text=True)
    files = {f"{REF_DIR}/{n}": text for n, text in REFERENCE.items()} if files is None else files
    path = directory / name
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("modelDescription.xml", xml if xml is not None else (SOURCE / "modelDescription.xml").read_text())
        z.write(binary, f"binaries/{binary_folder}/FirstOrder.{'dll' if 'win' in binary_folder else 'so'}")
        for archive_name, text in files.items():
            z.writestr(archive_name, text)
    binary.unlink()
    return path


@pytest.fixture(scope="module")
def fmi_run():
    """mechfmu-fmi-run (the fmi crate's importer), as `mechfmu validate` builds and names it."""
    exe = REPO / "target" / "release" / "mechfmu-fmi-run"
    done = subprocess.run(["cargo", "build", "--release", "--quiet", "-p", "mechfmu-fmi-run"], cwd=REPO,
                          capture_output=True, text=True)
    assert done.returncode == 0 and exe.is_file(), f"cannot build mechfmu-fmi-run:\n{done.stderr[-3000:]}"
    return exe


@pytest.fixture(scope="module")
def good(tmp_path_factory) -> Path:
    return build(tmp_path_factory.mktemp("good"))


def validate(tmp_path: Path, fmi_run: Path, *args: str) -> tuple[subprocess.CompletedProcess, list[dict]]:
    """The Python side of `mechfmu validate` on ``args``, with a temporary directory of its own
    that must be empty afterwards; (the process, the JSON rows)."""
    tmp = tmp_path / "tmpdir"
    tmp.mkdir()
    js = tmp_path / "rows.json"
    env = dict(os.environ, TMPDIR=str(tmp), **{FMI_RUN_ENV: str(fmi_run)})
    proc = subprocess.run([sys.executable, "-m", "mechfmu_validate", *args, "--json", str(js)], cwd=REPO,
                          capture_output=True, text=True, timeout=600, env=env)
    assert "Traceback" not in proc.stderr + proc.stdout, proc.stderr[-4000:]
    assert not list(tmp.iterdir()), f"left in the temporary directory: {[p.name for p in tmp.iterdir()]}"
    assert js.is_file(), f"no JSON written:\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}"
    return proc, json.loads(js.read_text())["rows"]


def reference_rows(rows: list[dict], fmu: str = "FirstOrder") -> dict[str, dict]:
    return {r["importer"]: r for r in rows if r["fmu"] == fmu and r["case"] == embedded_reference.CASE_NAME}


def test_a_foreign_fmu_passes_against_the_reference_it_carries(good, fmi_run, tmp_path):
    proc, rows = validate(tmp_path, fmi_run, str(good))
    assert proc.returncode == 0, proc.stdout[-4000:]
    assert all(r["passed"] for r in rows), [r for r in rows if not r["passed"]]
    refs = reference_rows(rows)
    assert set(refs) == {"FMPy", "libcosim", "fmi crate"}, refs
    # the FMU is exact over each step: the closed form to round-off, the importers identical
    assert refs["FMPy"]["max_error"] < 1e-12
    assert refs["FMPy"]["tolerance"] == pytest.approx(1e-4)  # 100 x the RelTol of FirstOrder_ref.opt
    assert set(refs["FMPy"]["signals"]) == {"y", "z"}
    assert refs["libcosim"]["max_error"] <= 1e-9 and refs["fmi crate"]["max_error"] <= 1e-9
    # a foreign FMU is held to the standard: no units and no documentation are notes
    checks = [r for r in rows if r["kind"] == "check"]
    assert len(checks) == 8 and any("declares no unit" in n for r in checks for n in r["notes"])
    assert "no validation/cases.py" not in proc.stdout


def test_the_reference_fmus_layout_is_read_too(tmp_path, fmi_run):
    """As the Modelica Reference-FMUs package theirs: <Id>_out.csv named by fmi-ls-manifest.xml,
    unquoted names, no options file (the tolerance is then the default, 1e-3 of the range)."""
    manifest = ('<?xml version="1.0" encoding="UTF-8"?>\n<fmiReferences xmlns:fmi-ls="http://fmi-standard.org/'
                'fmi-ls-manifest" fmi-ls:fmi-ls-name="org.fmi-standard.fmi-ls-ref" fmi-ls:fmi-ls-version="1.0.0">\n'
                '  <Related type="text/csv" source="results.csv" role="result"/>\n</fmiReferences>\n')
    files = {f"{REF_DIR}/fmi-ls-manifest.xml": manifest,
             f"{REF_DIR}/results.csv": REFERENCE["FirstOrder_ref.csv"].replace('"', ""),
             f"{REF_DIR}/FirstOrder_in.csv": REFERENCE["FirstOrder_in.csv"]}
    proc, rows = validate(tmp_path, fmi_run, str(build(tmp_path / "fmu", files=files)))
    fmpy_row = reference_rows(rows)["FMPy"]
    assert proc.returncode == 0 and fmpy_row["passed"], proc.stdout[-3000:]
    assert fmpy_row["tolerance"] == embedded_reference.DEFAULT_TOLERANCE and fmpy_row["max_error"] < 1e-12


def test_a_corrupted_reference_fails_naming_the_signal(tmp_path, fmi_run):
    lines = REFERENCE["FirstOrder_ref.csv"].splitlines()
    t, y, z = lines[26].split(",")  # t = 2.5
    lines[26] = f"{t},{y},{float(z) + 2e-3}"  # 9e-4 of z's range: beyond the tolerance of 1e-4
    files = {f"{REF_DIR}/FirstOrder_ref.csv": "\n".join(lines) + "\n",
             **{f"{REF_DIR}/{n}": REFERENCE[n] for n in ("FirstOrder_in.csv", "FirstOrder_ref.opt")}}
    proc, rows = validate(tmp_path, fmi_run, str(build(tmp_path / "fmu", files=files)))
    assert proc.returncode == 1
    fmpy_row = reference_rows(rows)["FMPy"]
    assert not fmpy_row["passed"] and 5e-4 < fmpy_row["max_error"] < 1e-3, fmpy_row
    assert not fmpy_row["signals"]["z"]["passed"] and fmpy_row["signals"]["z"]["at_time"] == 2.5
    assert fmpy_row["signals"]["y"]["passed"]
    assert re.search(r"^  - z: \d\.\d+e-04 of scale .* at t = 2\.5 \(tolerance 1e-04\)$", proc.stdout, re.M), \
        proc.stdout[-3000:]


def _broken(kind: str, good: Path, directory: Path) -> Path:
    path = directory / f"{kind}.fmu"
    if kind == "not a zip":
        path.write_text("This is a text file, not an FMU.\n")
    elif kind == "truncated zip":
        path.write_bytes(good.read_bytes()[: good.stat().st_size // 2])
    elif kind == "no Linux binary":
        build(directory, name=path.name, binary_folder="win64")
    elif kind == "damaged modelDescription.xml":
        build(directory, name=path.name, xml=(SOURCE / "modelDescription.xml").read_text()[:900])
    elif kind == "refuses to instantiate":
        build(directory, "-DREFUSE_INSTANTIATE", name=path.name)
    return path


BROKEN = {
    "not a zip": r"not an FMU: the file is not a zip archive",
    "truncated zip": r"the zip archive is truncated or damaged",
    "no Linux binary": r"no binary for linux64 in the archive \(it has: win64\)",
    "damaged modelDescription.xml": r"modelDescription\.xml is not well-formed XML \(.*line \d+",
    "refuses to instantiate": r"fmi2Instantiate returned NULL for the modelDescription's GUID \{5f1c1e9a-",
}


@pytest.mark.parametrize("kind", BROKEN)
def test_a_broken_fmu_is_one_fail_row_and_the_others_still_run(kind, good, fmi_run, tmp_path):
    broken = _broken(kind, good, tmp_path)
    proc, rows = validate(tmp_path, fmi_run, str(broken), str(good))
    assert proc.returncode == 1
    mine = [r for r in rows if str(broken) in " ".join(r["problems"])]
    assert len(mine) == 1 and len([r for r in rows if not r["passed"]]) == 1, [r for r in rows if not r["passed"]]
    assert mine[0]["case"] == OPENS and re.search(BROKEN[kind], mine[0]["problems"][0]), mine[0]
    assert f"FAIL {mine[0]['fmu']} / {OPENS}" in proc.stdout and re.search(BROKEN[kind], proc.stdout)
    assert reference_rows(rows)["FMPy"]["passed"] and re.search(r"^\d+ passed, 1 failed", proc.stdout, re.M)


def test_an_fmu_failing_during_the_simulation_fails_its_runs(tmp_path, fmi_run):
    """fmi2DoStep fails from t = 2: every importer's row fails, saying so; the checks pass."""
    proc, rows = validate(tmp_path, fmi_run, str(build(tmp_path / "fmu", "-DFAIL_AT=2.0")))
    assert proc.returncode == 1
    refs = reference_rows(rows)
    assert all(not r["passed"] for r in refs.values()) and set(refs) == {"FMPy", "libcosim", "fmi crate"}
    assert "fmi2DoStep failed" in refs["FMPy"]["problems"][0], refs["FMPy"]
    assert all(r["passed"] for r in rows if r["kind"] == "check")


def test_a_case_naming_a_variable_the_fmu_lacks_fails_naming_it(good, fmi_run, tmp_path):
    cases = tmp_path / "validation" / "cases.py"
    cases.parent.mkdir()
    cases.write_text("from mechfmu_validate.case import Case\n\n"
                     "CASES = [Case('swing', stop_time=1.0, output_interval=0.1, outputs=['y', 'theta'],\n"
                     "              reference=lambda t: {'y': t, 'theta': t})]\n")
    proc, rows = validate(tmp_path, fmi_run, str(good), "--cases", f"FirstOrder={cases}")
    assert proc.returncode == 1
    [row] = [r for r in rows if r["case"] == "swing"]
    assert not row["passed"] and all(s in row["problems"][0] for s in ("'swing'", str(cases), "theta")), row
    # the FMU's own reference runs beside the cases, under FMPy
    assert set(reference_rows(rows)) == {"FMPy"} and reference_rows(rows)["FMPy"]["passed"]


def test_an_event_in_the_reference_is_compared_after_it(tmp_path):
    """A time listed twice in the reference is an event: Co-Simulation's values at that
    communication point are the ones after it, the second row."""
    lines = REFERENCE["FirstOrder_ref.csv"].splitlines()
    t, y, z = lines[11].split(",")  # t = 1
    for order, passes in (([f"{t},{float(y) + 0.5},{z}", lines[11]], True),
                          ([lines[11], f"{t},{float(y) + 0.5},{z}"], False)):
        text = "\n".join(lines[:11] + order + lines[12:]) + "\n"
        files = {f"{REF_DIR}/FirstOrder_ref.csv": text,
                 **{f"{REF_DIR}/{n}": REFERENCE[n] for n in ("FirstOrder_in.csv", "FirstOrder_ref.opt")}}
        with open_fmu(build(tmp_path / str(passes), files=files)) as fmu:
            ref = embedded_reference.read(fmu)
            row, _, _ = cs_rows.fmpy_row(fmu, ref.case)
        assert row["passed"] == passes and ref.case.output_interval == pytest.approx(0.1), (order, row)


def test_junit_has_one_testcase_per_row(good, fmi_run, tmp_path):
    broken = _broken("not a zip", good, tmp_path)
    junit = tmp_path / "out" / "validate.xml"
    proc, rows = validate(tmp_path, fmi_run, str(good), str(broken), "--junit", str(junit))
    assert proc.returncode == 1
    root = ET.parse(junit).getroot()
    cases = root.findall("testsuite/testcase")
    assert root.tag == "testsuites" and int(root.get("tests")) == len(cases) == len(rows)
    assert int(root.get("failures")) == 1 == sum(not r["passed"] for r in rows)
    [failed] = [c for c in cases if c.find("failure") is not None]
    assert failed.get("classname") == broken.name and failed.get("name") == f"{OPENS} (mechfmu)"
    assert "not a zip archive" in failed.find("failure").get("message")
    names = {(c.get("classname"), c.get("name")) for c in cases}
    assert ("FirstOrder", "embedded_reference (fmi crate)") in names
    suites = {s.get("name"): s for s in root.findall("testsuite")}
    assert set(suites) == {"FirstOrder", broken.name} and suites["FirstOrder"].get("failures") == "0"


def test_the_command_passes_junit_through_and_says_what_failed(good, tmp_path):
    """`mechfmu validate` (the Rust command) on a broken and a good FMU: the table, the JUnit
    file, and a last message that points at the table's FAIL row."""
    broken = _broken("truncated zip", good, tmp_path)
    junit = tmp_path / "validate.xml"
    proc = subprocess.run(["cargo", "run", "--release", "--quiet", "--", "validate", str(broken), str(good),
                           "--junit", str(junit)], cwd=REPO, capture_output=True, text=True, timeout=1200)
    assert proc.returncode != 0 and "Traceback" not in proc.stderr, proc.stderr[-3000:]
    assert re.search(rf"^FAIL {re.escape(broken.name)} / {OPENS}", proc.stdout, re.M), proc.stdout[-3000:]
    assert "validation failed" in proc.stderr and "table above" in proc.stderr, proc.stderr[-2000:]
    assert int(ET.parse(junit).getroot().get("failures")) == 1

