"""`mechfmu validate` end to end: it passes on the real FMUs (the Model Exchange rows where
the importer's solver does not reach a case's limit are LIMIT: test_model_exchange.KNOWN_LIMITS),
and it catches a broken one.

The broken FMU is a copy of fmus/oscillator/ as an external crate (depending on mechfmu by
path, with the Oscillator's own validation/cases.py and reference/), with the sign of the
damping force flipped in `evaluate`, built by `mechfmu build --manifest-path ... --out ...`.
It is still a valid FMU (every check passes, the three importers agree on it) but its physics
is wrong: every case with damping must fail, by name, and the undamped one must pass.

Every case runs under three importers: FMPy, libcosim and the Rust fmi crate (rows
"fmi crate", through tools/fmi-run, which `mechfmu validate` builds); then in Model Exchange
under FMPy's CVode and Euler and the fmi crate's RK4; then on the mechanism's FMI 3.0 FMU
(fmus/fmi3/<Name>.fmu) under FMPy's and the fmi crate's FMI 3.0, in Co-Simulation and Model
Exchange (test_fmi3.py). An FMI 3.0 FMU given on the command line is validated as such.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import fmutest
from mechfmu_validate.importers.fmi_crate import FMI3_CRATE, FMI3_RK4, RK4
from mechfmu_validate.importers.fmpy import CVODE, EULER, FMI3_CS, FMI3_CVODE
from mechfmu_validate.target import AGREEMENT
from mechfmu_validate.validation_tables import FMI3_ROWS as FMI3_IMPORTERS
from mechanisms import mechanisms
from test_model_exchange import KNOWN_LIMITS

REPO = fmutest.REPO_ROOT
#: the other platforms' binaries (scripts/cross-runners, run by the test command, prepared them)
PLATFORM_IMPORTERS = {f"{label} {p}" for label in ("fmi crate", FMI3_CRATE) for p in ("x86_64-windows", "aarch64-linux")}
IMPORTERS = {"FMPy", "libcosim", "fmi crate", CVODE, EULER, RK4, *FMI3_IMPORTERS, *PLATFORM_IMPORTERS}
#: the LIMIT rows: the FMI 2.0 ones, and the same cases' FMI 3.0 Model Exchange rows (one
#: binary: the same numbers)
LIMITS = {*KNOWN_LIMITS,
          *((m, c, {CVODE: FMI3_CVODE, RK4: FMI3_RK4}[i]) for m, c, i in KNOWN_LIMITS if i in (CVODE, RK4))}


def mechfmu(*args: str, timeout: float = 1200) -> subprocess.CompletedProcess:
    """`cargo run --release -- <args>` from the repository root."""
    cmd = ["cargo", "run", "--release", "--quiet", "--", *args]
    return subprocess.run(cmd, cwd=REPO, capture_output=True, text=True, timeout=timeout)


def _rows(json_path: Path) -> list[dict]:
    return json.loads(json_path.read_text())["rows"]


def test_validate_passes_on_every_mechanism_fmu_and_writes_the_report(tmp_path):
    assert_validate_passes([m.model for m in mechanisms() if not m.system], tmp_path)


def assert_validate_passes(names: list[str], tmp_path: Path) -> None:
    """`mechfmu validate` of the FMUs ``names`` (of fmus/) passes every case under every
    importer and platform, and writes its report. The repository's FMUs are split over
    test_validate.py (the mechanisms) and test_validate_systems.py (the system FMUs), so that
    the two run on two cores."""
    assert names
    for model in names:
        fmutest.fmu_path(model)  # fail early, with the build hint, if one is missing
    report, js = tmp_path / "report", tmp_path / "validate.json"
    proc = mechfmu("validate", *names, "--fmu-dir", str(fmutest.FMU_DIR), "--report", str(report), "--json", str(js))
    assert js.is_file(), f"mechfmu validate wrote no JSON:\n{proc.stdout[-6000:]}\n{proc.stderr[-3000:]}"
    rows = _rows(js)
    cases = {(r["fmu"], r["case"]) for r in rows if r["kind"] == "case"}
    assert {f for f, _ in cases} == set(names) and len(cases) >= 2 * len(names), sorted(cases)
    for fmu, case in cases:
        importers = {r["importer"] for r in rows if (r["fmu"], r["case"]) == (fmu, case)}
        assert importers == IMPORTERS, (fmu, case, importers)
    failed = {(r["fmu"], r["case"], r["importer"]) for r in rows if not r["passed"]}
    assert not failed, failed
    limited = {(r["fmu"], r["case"], r["importer"]) for r in rows if r.get("limited")}
    expected = {row for row in LIMITS if row[0] in names}
    assert limited == expected, f"unexpected: {sorted(limited - expected)}; no longer limited: {sorted(expected - limited)}"
    assert proc.returncode == 0 and not any(r.get("skipped") for r in rows), proc.stderr[-3000:]
    for importer in ("fmi crate", FMI3_CRATE):
        fmi_crate = [r for r in rows if r["importer"] == importer]
        assert len(fmi_crate) == len(cases)
        assert all(r["tolerance"] == 1e-9 and r["max_error"] <= 1e-9 for r in fmi_crate), fmi_crate
    # FMI 3.0: the checks of each FMU's archive, its agreement with FMI 2.0, the same errors
    checks3 = {r["fmu"] for r in rows if r["kind"] == "check" and r["case"].startswith("check: FMI 3.0")}
    agreements = {r["fmu"]: r["max_error"] for r in rows if r["case"] == AGREEMENT}
    assert checks3 == set(agreements) == {f for f, _ in cases} and max(agreements.values()) <= 1e-12, agreements
    by = {(r["fmu"], r["case"], r["importer"]): r for r in rows if r["kind"] == "case"}
    for fmu, case in cases:
        assert by[(fmu, case, FMI3_CS)]["max_error"] == by[(fmu, case, "FMPy")]["max_error"], (fmu, case)
    # every FMU's platforms listed, the three of Linux and Windows run here, each foreign run
    # bit for bit the native one; the Mac ones packaged, checked, not run
    platforms = [r for r in rows if r["case"].startswith("(platforms, FMI ")]
    assert len(platforms) == 2 * len(names), [r["case"] for r in platforms]
    run = ["x86_64-linux", "x86_64-windows", "aarch64-linux"]
    for r in platforms:
        tuples = [*run, "x86_64-darwin", "aarch64-darwin"]
        assert r["platforms"]["found"] == tuples and r["platforms"]["run"] == run, r
        # named as the FMU's own version names its folders
        fmi2 = r["case"] == "(platforms, FMI 2.0)"
        names = "linux64, win64, aarch64-linux, darwin64, aarch64-darwin" if fmi2 else ", ".join(tuples)
        assert r["importer"] == names, r
        mac = "darwin64" if fmi2 else "x86_64-darwin"
        assert f"{mac}: packaged, checked, not run (only a Mac runs it)" in r["notes"][0], r
    foreign = [r for r in rows if r["importer"] in PLATFORM_IMPORTERS]
    assert len(foreign) == 4 * len(cases) and all(r["bit_identical"] and r["max_error"] == 0 for r in foreign)
    for found, ran in (("linux64, win64, aarch64-linux, darwin64, aarch64-darwin", "linux64, win64, aarch64-linux"),
                       (", ".join([*run, "x86_64-darwin", "aarch64-darwin"]), ", ".join(run))):
        assert f"binaries for {found}; run: {ran}" in proc.stdout
    at_limit = f", {len(limited)} at the importer's limit" if limited else ""
    assert re.search(rf"^\d+ passed, 0 failed{at_limit}$", proc.stdout, re.M), proc.stdout[-2000:]
    index = (report / "index.html").read_text()
    assert "PASS" in index and (report / "index.md").is_file()
    pngs = list(report.glob("*/*.png"))
    assert len(pngs) == len(cases), (len(pngs), len(cases))
    assert all(p.stat().st_size > 20_000 for p in pngs)


@pytest.fixture(scope="module")
def broken_oscillator(tmp_path_factory) -> Path:
    """fmus/oscillator copied as an external crate with the damping's sign flipped, built;
    returns the crate directory (the FMU is out/Oscillator.fmu)."""
    root = tmp_path_factory.mktemp("broken") / "broken-oscillator"
    shutil.copytree(REPO / "fmus/oscillator", root, ignore=shutil.ignore_patterns("target", "__pycache__"))
    manifest = root / "Cargo.toml"
    text = manifest.read_text()
    text = text.replace('name = "oscillator-fmu"', 'name = "broken-oscillator-fmu"')
    text = text.replace('name = "oscillator"', 'name = "broken_oscillator"')
    # the path dependencies (mechfmu, mechfmu-testkit), relative to fmus/oscillator: made absolute
    text = re.sub(r'path = "([^"]*)"',
                  lambda m: f'path = "{(REPO / "fmus/oscillator" / m.group(1)).resolve().as_posix()}"', text)
    # a workspace of its own, with the repository's release profile and lock file, so that the
    # shared target directory's compiled dependencies are reused
    # (its per-package settings too: other settings would rebuild, and overwrite, the dependencies)
    profiles = re.findall(r"\[profile\.release(?:\.package\.[^\]]+)?\][^\[]*", (REPO / "Cargo.toml").read_text())
    text += "\n[workspace]\n\n" + "".join(profiles)
    manifest.write_text(text)
    shutil.copy(REPO / "Cargo.lock", root / "Cargo.lock")
    lib = root / "src/lib.rs"
    src = lib.read_text()
    flipped = src.replace("- v.c * v.x_dot", "+ v.c * v.x_dot")
    assert flipped != src, "the damping term `- v.c * v.x_dot` is not in fmus/oscillator/src/lib.rs any more"
    lib.write_text(flipped)
    env = dict(os.environ, CARGO_TARGET_DIR=str(REPO / "target"))
    proc = subprocess.run(["cargo", "run", "--release", "--quiet", "--", "build", "--manifest-path", str(manifest),
                           "--out", str(root / "out"), "--platform", "x86_64-linux"], cwd=REPO, capture_output=True, text=True, timeout=1800,
                          env=env)
    assert proc.returncode == 0, f"building the broken copy failed:\n{proc.stdout}\n{proc.stderr[-4000:]}"
    assert (root / "out/Oscillator.fmu").is_file()
    return root


def test_validate_fails_on_a_broken_fmu_and_names_the_cases(broken_oscillator, tmp_path):
    root = broken_oscillator
    js = tmp_path / "broken.json"
    proc = mechfmu("validate", str(root / "out/Oscillator.fmu"), "--manifest-path", str(root / "Cargo.toml"),
                   "--json", str(js))
    assert proc.returncode != 0, f"mechfmu validate passed a broken FMU:\n{proc.stdout[-4000:]}"
    assert "validation failed" in proc.stderr
    rows = _rows(js)
    fmpy_rows = {r["case"]: r for r in rows if r["kind"] == "case" and r["importer"] == "FMPy"}
    damped = ["default_experiment", "free_overdamped", "free_critical", "free_underdamped", "step_force",
              "harmonic_near_resonance"]
    assert set(damped) <= set(fmpy_rows), sorted(fmpy_rows)
    for case in damped:
        assert not fmpy_rows[case]["passed"], f"{case} passed on the broken FMU"
        assert re.search(rf"^FAIL Oscillator / {case} / FMPy:", proc.stdout, re.M), proc.stdout[-3000:]
    assert fmpy_rows["free_undamped"]["passed"], "the undamped case does not depend on the flipped term"
    # Model Exchange sees the same physics: CVode fails the damped cases; the fixed-step
    # methods, which report their accuracy rather than fail it, say LIMIT there (the error no
    # longer falls with their order)
    me = {r["case"]: r for r in rows if r["kind"] == "case" and r["importer"] == CVODE}
    assert [c for c in damped if me[c]["passed"]] == [] and me["free_undamped"]["passed"], me
    for importer in (EULER, RK4):
        me = {r["case"]: r for r in rows if r["kind"] == "case" and r["importer"] == importer}
        assert all(me[c].get("limited") for c in damped), (importer, me)
        assert me["free_undamped"]["passed"] and not me["free_undamped"].get("limited"), (importer, me)
    # the FMI 3.0 FMU beside it (the same binary) fails the same cases
    fmi3_rows = {r["case"]: r for r in rows if r["kind"] == "case" and r["importer"] == FMI3_CS}
    assert [c for c in damped if fmi3_rows[c]["passed"]] == [] and fmi3_rows["free_undamped"]["passed"], fmi3_rows
    # still a valid FMU, imported identically by the three importers: the failure is the physics
    assert all(r["passed"] for r in rows if r["kind"] == "check"), [r for r in rows if not r["passed"]]
    for importer in ("libcosim", "fmi crate", FMI3_CRATE):
        others = {r["case"]: r for r in rows if r["kind"] == "case" and r["importer"] == importer}
        assert set(others) == set(fmpy_rows), (importer, sorted(others))
        assert all(r["passed"] for r in others.values()), [r for r in others.values() if not r["passed"]]
        assert not re.search(rf"^FAIL Oscillator / .* / {importer}:", proc.stdout, re.M), proc.stdout[-3000:]


def test_validate_without_the_fmi_crate():
    proc = mechfmu("validate", "Oscillator", "--fmu-dir", str(fmutest.FMU_DIR), "--case", "free_critical",
                   "--no-fmi-crate")
    assert proc.returncode == 0, f"{proc.stdout[-3000:]}\n{proc.stderr[-2000:]}"
    assert re.search(r"^Oscillator\s+free_critical\s+libcosim\s.*PASS$", proc.stdout, re.M), proc.stdout
    assert re.search(r"^Oscillator\s+free_critical\s+FMPy FMI3 CS\s.*PASS$", proc.stdout, re.M), proc.stdout
    assert "fmi crate" not in proc.stdout


def test_the_fmi_crate_rows_fail_when_its_runner_is_missing(tmp_path):
    """The Python side alone, without MECHFMU_FMI_RUN (what a failed build of the runner leaves):
    the fmi-crate row fails, saying why; FMPy's row still passes."""
    js = tmp_path / "missing.json"
    env = {k: v for k, v in os.environ.items() if k != "MECHFMU_FMI_RUN"}
    proc = subprocess.run([sys.executable, "-m", "mechfmu_validate", str(fmutest.fmu_path("Oscillator")),
                           "--cases", f"Oscillator={REPO / 'fmus/oscillator/validation/cases.py'}",
                           "--case", "free_critical", "--no-libcosim", "--json", str(js)],
                          cwd=REPO, capture_output=True, text=True, timeout=600, env=env)
    assert proc.returncode == 1, f"{proc.stdout[-3000:]}\n{proc.stderr[-2000:]}"
    assert "the fmi-crate importer cannot run here" in proc.stderr
    rows = {r["importer"]: r for r in _rows(js) if r["kind"] == "case"}
    assert rows["FMPy"]["passed"] and not rows["fmi crate"]["passed"]
    assert "MECHFMU_FMI_RUN is not set" in rows["fmi crate"]["problems"][0]
    assert re.search(r"^FAIL Oscillator / free_critical / fmi crate:", proc.stdout, re.M), proc.stdout


def test_validate_an_fmi3_fmu_given_on_the_command_line(tmp_path):
    """An FMI 3.0 .fmu named on the command line: its checks (FMPy's validation among them),
    its agreement with the FMI 2.0 FMU beside it (whose variables name its array elements),
    and the cases under the FMI 3.0 importers only (and on its other platforms' binaries); the
    report's plots are FMPy's FMI 3.0 runs."""
    js, report = tmp_path / "fmi3.json", tmp_path / "report"
    path = fmutest.FMU_DIR / "fmi3" / "RigidBody.fmu"
    proc = mechfmu("validate", str(path), "--case", "heavy_top", "--case", "axisymmetric", "--json", str(js),
                   "--report", str(report))
    assert proc.returncode == 0, f"{proc.stdout[-4000:]}\n{proc.stderr[-2000:]}"
    rows = _rows(js)
    checks = {r["case"] for r in rows if r["kind"] == "check"}
    assert checks == {"check: FMI 3.0 fmpy validate", "check: FMI 3.0 identifier = binary",
                      "check: FMI 3.0 instantiation token accepted, wrong token refused",
                      "check: FMI 3.0 arrays = FMI 2.0 scalars", AGREEMENT}, checks
    cases = {(r["case"], r["importer"]) for r in rows if r["kind"] == "case"}
    importers = {*FMI3_IMPORTERS, *(i for i in PLATFORM_IMPORTERS if i.startswith(FMI3_CRATE))}
    assert cases == {(c, i) for c in ("heavy_top", "axisymmetric_precession") for i in importers}, cases
    assert all(r["passed"] for r in rows), [r for r in rows if not r["passed"]]
    assert re.search(r"^RigidBody\s+check: FMI 3\.0 fmpy validate\s+fmpy\s+0\s+0\s+PASS$", proc.stdout, re.M)
    assert len(list(report.glob("RigidBody/*.png"))) == 2


def test_validate_reports_an_unknown_mechanism():
    proc = mechfmu("validate", "NoSuchMechanism")
    assert proc.returncode != 0
    assert "NoSuchMechanism" in proc.stderr and "known:" in proc.stderr
