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

What other exporters write, legal, is held to PASS under every
importer, each reproduced on FirstOrder: aliases sharing a value reference (as Dymola's
`mass.a` and `der(mass.v)`), XML's `xmlns:xsi` on the root (which the fmi crate's schema
refuses), a solver of its own whose result depends on the tolerance it is given (-DOWN_SOLVER);
aliases that cannot be one value fail, naming the standard's clause. And three small models
written here (data/foreign/models/: a decay, a bouncing ball with state events, a staircase
with time events that ends its simulation early), packaged with results named by an FMI-LS-REF
manifest, pass in FMI 2.0 and 3.0.
"""

from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import warnings
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path
from types import SimpleNamespace

import fmpy
import pytest

import fmutest
from mechfmu_validate import embedded_reference
from mechfmu_validate.fmu import NotRead
from mechfmu_validate.importers import fmpy as fmpy_importer, libcosim
from mechfmu_validate.importers.fmi_crate import FMI_RUN_ENV
from mechfmu_validate.fmpy_criterion import CRITERION
from mechfmu_validate.opening import OPENS, open_fmu
from mechfmu_validate.report import result_text
from mechfmu_validate.target import Target

REPO = fmutest.REPO_ROOT
SOURCE = Path(__file__).resolve().parent / "data" / "foreign"
REF_DIR = "extra/org.fmi-standard.fmi-ls-ref"
REFERENCE = {name: (SOURCE / name).read_text() for name in ("FirstOrder_ref.csv", "FirstOrder_in.csv",
                                                            "FirstOrder_ref.opt")}


def manifest(results: str) -> str:
    """The FMI-LS-REF manifest (``fmi-ls-manifest.xml``) naming ``results`` the reference results."""
    return ('<?xml version="1.0" encoding="UTF-8"?>\n<fmiReferences xmlns:fmi-ls="http://fmi-standard.org/'
            'fmi-ls-manifest" fmi-ls:fmi-ls-name="org.fmi-standard.fmi-ls-ref" fmi-ls:fmi-ls-version="1.0.0">\n'
            f'  <Related type="text/csv" source="{results}" role="result"/>\n</fmiReferences>\n')


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
    exe = fmutest.built_fmi_run()
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
    """The rows of each importer's run of the reference the FMU carries (FMPy's criterion's
    rows, judging the same runs, left out)."""
    return {r["importer"]: r for r in rows if r["fmu"] == fmu and r["case"] == embedded_reference.CASE_NAME
            and not r["importer"].endswith(CRITERION)}


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
    files = {f"{REF_DIR}/fmi-ls-manifest.xml": manifest("results.csv"),
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


def test_a_reference_without_a_number_fails_naming_where(tmp_path, fmi_run):
    """A NaN in the exporter's results is the reference's fault, said as such (not an error
    of inf at that time)."""
    lines = REFERENCE["FirstOrder_ref.csv"].splitlines()
    t, y, _ = lines[26].split(",")
    lines[26] = f"{t},{y},nan"
    files = {f"{REF_DIR}/FirstOrder_ref.csv": "\n".join(lines) + "\n",
             **{f"{REF_DIR}/{n}": REFERENCE[n] for n in ("FirstOrder_in.csv", "FirstOrder_ref.opt")}}
    proc, rows = validate(tmp_path, fmi_run, str(build(tmp_path / "fmu", files=files)))
    assert proc.returncode == 1
    [failed] = [r for r in rows if not r["passed"]]
    assert failed["problems"] == [f"{REF_DIR}/FirstOrder_ref.csv: line 27: z = nan, which is no number to compare a "
                                  "result with"], \
        failed


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
    elif kind == "two model descriptions":
        build(directory, name=path.name)
        with warnings.catch_warnings(), zipfile.ZipFile(path, "a") as z:
            warnings.simplefilter("ignore")  # zipfile's "Duplicate name": the point
            z.writestr("modelDescription.xml", (SOURCE / "modelDescription.xml").read_text().replace("5f1c1e9a", "00000000"))
    elif kind in ESCAPING:
        files = {f"{REF_DIR}/{n}": text for n, text in REFERENCE.items()}
        build(directory, name=path.name, files={**files, ESCAPING[kind]: "written outside\n"})
    return path


#: entries an importer that extracts the archive would write outside its folder with
ESCAPING = {
    "entry up the tree": "../" * 12 + "tmp/mechfmu-escaped.txt",
    "entry up through a subfolder": "resources/../../escaped.txt",
    "absolute entry": "/tmp/mechfmu-escaped.txt",
    "Windows entry up the tree": "resources\\..\\..\\escaped.txt",
}


BROKEN = {
    "not a zip": r"not an FMU: the file is not a zip archive",
    "truncated zip": r"the zip archive is truncated or damaged",
    "no Linux binary": r"no binary for linux64 in the archive \(it has: win64\)",
    "damaged modelDescription.xml": r"modelDescription\.xml is not well-formed XML \(.*line \d+",
    "refuses to instantiate": r"fmi2Instantiate returned NULL for the modelDescription's GUID \{5f1c1e9a-",
    "two model descriptions": r"the zip archive has two entries named 'modelDescription\.xml'",
    **{kind: r"the zip archive has an entry outside the FMU's folder: '" + re.escape(name.replace("\\", "\\\\"))
       for kind, name in ESCAPING.items()},
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
            row, _, _ = fmpy_importer.cs_row(Target(fmu), ref.case)
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
    assert proc.returncode == 1


def test_the_command_names_a_missing_fmu_as_a_usage_error(tmp_path):
    """Exit status 2, as for any usage error, and the path named."""
    missing = tmp_path / "Missing.fmu"
    proc = subprocess.run(["cargo", "run", "--release", "--quiet", "--", "validate", str(missing)], cwd=REPO,
                          capture_output=True, text=True, timeout=1200)
    assert proc.returncode == 2 and f"{missing} does not exist" in proc.stderr, (proc.returncode, proc.stderr)



# ---------------------------------------------------------------------------------------
# Legal FMUs that other exporters write, which strict checks or importers refuse


XML = (SOURCE / "modelDescription.xml").read_text()
#: variables sharing the value references of y and tau: aliases, which FMI 2.0 allows
ALIASES = ('<ScalarVariable name="y_alias" valueReference="1" causality="local" variability="continuous" '
           'initial="calculated"><Real/></ScalarVariable>\n'
           '<ScalarVariable name="time_constant" valueReference="3" causality="local" variability="fixed" '
           'initial="calculated"><Real/></ScalarVariable>\n')
#: aliases that cannot be one value: two start values, a constant beside a variable
CONFLICTING_ALIASES = ('<ScalarVariable name="y0_guess" valueReference="4" causality="local" variability="fixed" '
                       'initial="approx"><Real start="2"/></ScalarVariable>\n'
                       '<ScalarVariable name="z_frozen" valueReference="2" causality="local" variability="constant" '
                       '><Real start="0"/></ScalarVariable>\n')
#: XML's namespace declarations on the root, as Dymola, 20-sim and FMI Kit write them
NAMESPACES = ('<fmiModelDescription xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance" '
              'xsi:noNamespaceSchemaLocation="fmi2ModelDescription.xsd"')


def with_variables(text: str) -> str:
    return XML.replace("  </ModelVariables>", text + "  </ModelVariables>")


def all_passed(proc: subprocess.CompletedProcess, rows: list[dict]) -> None:
    assert proc.returncode == 0 and all(r["passed"] and not r.get("skipped") for r in rows), \
        ([r for r in rows if not r["passed"] or r.get("skipped")], proc.stdout[-3000:])


def test_an_fmu_accepting_any_guid_passes_with_a_note(tmp_path, fmi_run):
    """FMI 2.0 gives fmi2Instantiate the GUID to check with but does not require the check."""
    proc, rows = validate(tmp_path, fmi_run, str(build(tmp_path / "fmu", "-DANY_GUID")))
    all_passed(proc, rows)
    [guid] = [r for r in rows if r["case"] == "check: GUID accepted, wrong GUID refused"]
    assert any("accepted a wrong GUID" in n and "does not require the check" in n for n in guid["notes"]), guid


def test_aliases_sharing_a_value_reference_pass(tmp_path, fmi_run):
    """FMI 2.0.5 §2.2.7: variables of one base type may share a value reference (Dymola's do:
    `mass.a` and `der(mass.v)`); every importer runs the FMU."""
    proc, rows = validate(tmp_path, fmi_run, str(build(tmp_path / "fmu", xml=with_variables(ALIASES))))
    all_passed(proc, rows)
    [aliases] = [r for r in rows if r["case"] == "check: value references and aliases"]
    assert aliases["notes"][0] == "2 alias sets (variables sharing a value reference, FMI 2.0.5 §2.2.7: allowed)"
    assert set(reference_rows(rows)) == {"FMPy", "libcosim", "fmi crate"}


def test_aliases_that_cannot_be_one_value_fail_naming_the_clause(tmp_path, fmi_run):
    proc, rows = validate(tmp_path, fmi_run, str(build(tmp_path / "fmu", xml=with_variables(CONFLICTING_ALIASES))))
    assert proc.returncode == 1
    failed = {(r["case"], r["importer"]): r for r in rows if not r["passed"]}
    assert set(failed) == {("check: value references and aliases", "mechfmu")}
    aliases = failed["check: value references and aliases", "mechfmu"]
    constants, starts = aliases["problems"]  # in the order of the value references
    assert starts.startswith("FMI 2.0.5 §2.2.7 start: the Real value reference 4 (y0, y0_guess)") and \
        "conflicting start values (y0=1, y0_guess=2)" in starts, starts
    assert constants.startswith("FMI 2.0.5 §2.2.7 variability: the Real value reference 2 (z, z_frozen) mixes "
                                "constants (z_frozen)"), constants
    # libcosim's loader (the FMI Library) enforces the same rules: it drops these variables,
    # says so on the console, which its row keeps, and cannot record z: a row skipped, as
    # where the loader refuses a legal FMU, since the check's row gives the verdict
    libcosim = next(r for r in rows if (r["case"], r["importer"]) == ("embedded_reference", "libcosim"))
    assert libcosim.get("skipped") and "libcosim cannot read z" in libcosim["problems"][0], libcosim
    said = libcosim["output"]
    assert "[FMI Library: FMI2XML] Only constants can be aliases with constants (variables: z and z_frozen)" in said
    assert "FMI Library" not in proc.stdout.split("FAIL FirstOrder")[0], "the console output is in its row"


def test_xml_namespace_declarations_are_read_by_every_importer(tmp_path, fmi_run):
    """`xmlns:xsi` on the root is XML's, legal in any model description: the fmi crate's schema
    refuses it (`unknown field "xmlns:xsi"`), its runner gives the crate the XML without it."""
    fmu = build(tmp_path / "fmu", xml=XML.replace("<fmiModelDescription", NAMESPACES, 1))
    proc, rows = validate(tmp_path, fmi_run, str(fmu))
    all_passed(proc, rows)
    assert reference_rows(rows)["fmi crate"]["max_error"] == 0


def test_an_fmu_with_its_own_solver_is_compared_with_libcosim_at_libcosims_settings(tmp_path, fmi_run):
    """An FMU integrating at the tolerance fmi2SetupExperiment gives (its own default, 1e-2,
    when none is given, as libcosim gives none) differs between the settings by 1e-4: libcosim
    is compared with FMPy run at its own settings (no tolerance, no stop time), where the two
    agree to round-off; FMPy at the reference's tolerance meets the reference."""
    fmu = build(tmp_path / "fmu", "-DOWN_SOLVER", xml=XML.replace(
        '<DefaultExperiment startTime="0" stopTime="5" stepSize="0.1"/>',
        '<DefaultExperiment startTime="0" stopTime="5" stepSize="0.1" tolerance="1e-6"/>'))
    proc, rows = validate(tmp_path, fmi_run, str(fmu))
    all_passed(proc, rows)
    refs = reference_rows(rows)
    assert refs["libcosim"]["max_error"] < 1e-12 and "no tolerance and no stop time" in refs["libcosim"]["notes"][-1]
    assert refs["FMPy"]["max_error"] < 1e-8 and refs["fmi crate"]["max_error"] == 0


# ---------------------------------------------------------------------------------------
# Small models with events, in FMI 2.0 and 3.0 (data/foreign/models/)


MODELS = SOURCE / "models"


def build_model(directory: Path, model: str, version: int) -> Path:
    """``model`` of data/foreign/models/ for FMI ``version``, compiled with gcc (its C file and the
    FMI layer, fmi.c) and packaged with its results and the FMI-LS-REF manifest naming them, in
    ``extra/org.fmi-standard.fmi-ls-ref/``."""
    folder = directory / f"fmi{version}"
    folder.mkdir(parents=True, exist_ok=True)
    binary = folder / f"{model}.so"
    subprocess.run(["gcc", "-shared", "-fPIC", "-O2", "-std=c99", "-Wall", "-Werror", f"-DFMI_VERSION={version}",
                    "-I", str(Path(fmpy.__file__).parent / "c-code"), str(MODELS / f"{model}.c"),
                    str(MODELS / "fmi.c"), "-o", str(binary), "-lm"], check=True, capture_output=True, text=True)
    path = folder / f"{model}.fmu"
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        z.write(MODELS / f"{model}.fmi{version}.xml", "modelDescription.xml")
        z.write(binary, f"binaries/{'linux64' if version == 2 else 'x86_64-linux'}/{model}.so")
        z.writestr(f"{REF_DIR}/fmi-ls-manifest.xml", manifest(f"{model}_out.csv"))
        z.write(MODELS / f"{model}_out.csv", f"{REF_DIR}/{model}_out.csv")
    binary.unlink()
    return path


def test_the_models_with_events_pass_in_both_versions(tmp_path, fmi_run):
    """Decay, BouncingBall (state events) and Staircase (time events, the end of its
    simulation at t = 9) in FMI 2.0 and 3.0, in one call: every check passes, every run meets
    the results the FMU carries, and an importer that records Real variables only skips
    Staircase's integer counter, saying so; each file is its own JUnit suite, named by its path
    (the two versions share each model name)."""
    fmus = [build_model(tmp_path / "fmus", model, version)
            for model in ("Decay", "BouncingBall", "Staircase") for version in (2, 3)]
    junit = tmp_path / "validate.xml"
    proc, rows = validate(tmp_path, fmi_run, *map(str, fmus), "--junit", str(junit))
    runs = [r for r in rows if not r["importer"].endswith(CRITERION)]  # FMPy's criterion: tests of its own
    verdicts = {(Path(r["fmu"]).stem, Path(r["fmu"]).parent.name, r["importer"]): result_text(r)
                for r in runs if r["case"] == embedded_reference.CASE_NAME}
    expected = {}
    for model in ("Decay", "BouncingBall", "Staircase"):
        others = "SKIP" if model == "Staircase" else "PASS"
        expected.update({(model, "fmi2", "FMPy"): "PASS", (model, "fmi2", "libcosim"): others,
                         (model, "fmi2", "fmi crate"): others, (model, "fmi3", "FMPy FMI3 CS"): "PASS",
                         (model, "fmi3", "fmi crate FMI3 CS"): others})
    assert verdicts == expected, proc.stdout[-6000:]
    assert all(r["passed"] for r in runs if r["kind"] == "check" or "(platforms" in r["case"]), \
        [r for r in runs if not r["passed"]]
    assert {r["fmu"] for r in rows} == set(map(str, fmus))
    assert {s.get("name") for s in ET.parse(junit).getroot().findall("testsuite")} == set(map(str, fmus))
    [stair] = [r for r in runs if r["fmu"].endswith("fmi2/Staircase.fmu") and r["importer"] == "libcosim"]
    assert stair["problems"] == ["this importer's runs record Real variables only, and no compared signal is Real"]
    # FMPy's criterion judges Staircase up to where its own reference ends: the FMU ends there
    criteria = [r for r in rows if r["importer"].endswith(CRITERION)]
    assert criteria and all(r["passed"] for r in criteria), [r for r in criteria if not r["passed"]]
    assert any("judged up to 9 s" in n for r in criteria if "Staircase" in r["fmu"] for n in r["notes"])
    assert proc.returncode == 0, proc.stdout[-6000:]


def test_an_fmu_the_fmi_crate_cannot_read_is_its_skip(tmp_path, fmi_run):
    """`<Annotations>` in a `<ScalarVariable>` is FMI 2.0's schema (FMPy's validation passes);
    the crate's schema refuses it: the crate's limit, a SKIP row saying so, not the FMU's FAIL."""
    xml = XML.replace('<Real start="0.5"/></ScalarVariable>',
                      '<Real start="0.5"/><Annotations><Tool name="org.example"/></Annotations></ScalarVariable>')
    proc, rows = validate(tmp_path, fmi_run, str(build(tmp_path / "fmu", xml=xml)))
    assert proc.returncode == 0 and all(r["passed"] for r in rows)
    crate = reference_rows(rows)["fmi crate"]
    assert crate["skipped"] and crate["max_error"] is None
    assert crate["problems"] == ['fmi crate: cannot read FirstOrder.fmu (unknown field "Annotations" in element '
                                 '"ScalarVariable"): the crate\'s limit, stricter than the standard (the checks hold '
                                 'the model description to the standard)'], crate["problems"]


@pytest.mark.parametrize("by_mechfmu", [False, True])
def test_an_fmu_libcosims_loader_refuses_is_its_limit_unless_ours(monkeypatch, by_mechfmu):
    """libcosim's loader (the FMI Library) refuses some legal model descriptions: for another
    exporter's FMU that is a skipped row naming why; ours promise to run under libcosim."""
    def refuse(fmu, case):
        raise NotRead("libcosim could not load X.fmu")

    monkeypatch.setattr(libcosim, "run_libcosim", refuse)
    fmu, case = SimpleNamespace(model="X", by_mechfmu=by_mechfmu), SimpleNamespace(name="default")
    row, plotted = libcosim.libcosim_row(fmu, case, None, None)
    assert plotted is None and row["problems"][0].startswith("libcosim")
    assert "could not load X.fmu" in row["problems"][0]
    if by_mechfmu:
        assert not row["passed"] and not row.get("skipped")
    else:
        assert row["passed"] and row["skipped"] and "a limit of libcosim's loader" in row["problems"][0]
