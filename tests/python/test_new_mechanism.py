"""A new user's first mechanism, as they would go through it, outside the repository:
`mechfmu new` as created (its tests, build and validation pass; renaming the example's
variable fails both with a message naming it), then `mechfmu new DoublePendulum`, replace the
example with a double pendulum, build, validate, and check the physics (energy conserved to
1e-8 relative over 10 s at rtol 1e-10)."""

import os
import re
import shutil
import subprocess
import zipfile
from pathlib import Path

import numpy as np
import pytest
from fmpy import simulate_fmu
from fmpy.validation import validate_fmu

from fmutest import REPO_ROOT

MECHFMU = REPO_ROOT / "target" / "release" / "mechfmu"
DOUBLE_PENDULUM = Path(__file__).parent / "data" / "double_pendulum.rs"
DOUBLE_PENDULUM_CASES = Path(__file__).parent / "data" / "double_pendulum_cases.py"


def run(args, cwd, env=None):
    done = subprocess.run([str(a) for a in args], cwd=cwd, env=env, capture_output=True, text=True)
    assert done.returncode == 0, f"{' '.join(map(str, args))} failed:\n{done.stdout}\n{done.stderr}"
    return done


@pytest.fixture(scope="module")
def double_pendulum(tmp_path_factory):
    if not MECHFMU.exists():
        pytest.fail(f"{MECHFMU} is missing: run `cargo run --release -- build` first", pytrace=False)
    home = tmp_path_factory.mktemp("user")
    crate = home / "double_pendulum"
    run([MECHFMU, "new", "DoublePendulum", "--path", crate], cwd=home)
    assert (crate / "src" / "lib.rs").read_text().count("pendulum") > 0
    assert (crate / "validation" / "cases.py").exists()
    shutil.copy(DOUBLE_PENDULUM, crate / "src" / "lib.rs")
    shutil.copy(DOUBLE_PENDULUM_CASES, crate / "validation" / "cases.py")
    # The scaffold's own tests are about the example pendulum; the user replaces them.
    for test in (crate / "tests").glob("*.rs"):
        test.write_text("#[test]\nfn conforms() {\n    mechfmu_testkit::conformance::check::<double_pendulum::DoublePendulum>();\n}\n")
    env = user_crate_env()
    run([MECHFMU, "build", "--manifest-path", crate / "Cargo.toml", "--out", crate / "fmu"], cwd=home, env=env)
    run(["cargo", "test", "-q", "--manifest-path", crate / "Cargo.toml"], cwd=home, env=env)
    return crate / "fmu" / "DoublePendulum.fmu"


def user_crate_env():
    """Share compiled dependencies with the repository's build: same compiler, same flags."""
    return dict(os.environ, CARGO_TARGET_DIR=str(REPO_ROOT / "target" / "user-crates"))


def test_scaffold_as_created_passes_and_a_renamed_variable_is_named(tmp_path):
    """The tutorial's first commands on the scaffold as written: its tests pass, it builds,
    `mechfmu validate` passes its cases. Then the user renames the example's `theta`: the Rust
    tests stop compiling, and validation fails, each naming `theta`."""
    crate = tmp_path / "spinner"
    run([MECHFMU, "new", "Spinner", "--path", crate], cwd=tmp_path)
    env = user_crate_env()
    lib = (crate / "src" / "lib.rs").read_text()
    assert "const NOTES" in lib and "fn outputs" in lib and "sin(v.theta)" in lib
    run(["cargo", "test", "-q", "--manifest-path", crate / "Cargo.toml"], cwd=crate, env=env)
    build = [MECHFMU, "build", "--manifest-path", crate / "Cargo.toml", "--out", crate / "fmu",
             "--platform", "x86_64-linux"]
    run(build, cwd=crate, env=env)
    validate = [MECHFMU, "validate", "--manifest-path", crate / "Cargo.toml", "--fmu-dir", crate / "fmu",
                "--no-fmi-crate"]
    done = run(validate, cwd=crate)
    assert re.search(r"^Spinner\s+small_swings\s+FMPy\s.*PASS$", done.stdout, re.M), done.stdout
    page = zipfile.ZipFile(crate / "fmu" / "Spinner.fmu").read("documentation/index.html").decode()
    assert "Moments about the pivot" in page, "the scaffold's NOTES reach the FMU's page"

    (crate / "src" / "lib.rs").write_text(re.sub(r"\btheta\b", "phi", lib))
    tests = subprocess.run(["cargo", "test", "--no-run", "--manifest-path", str(crate / "Cargo.toml")], cwd=crate,
                           env=env, capture_output=True, text=True)
    assert tests.returncode != 0 and "no field `theta`" in tests.stderr, tests.stderr[-2000:]
    run(build, cwd=crate, env=env)
    done = subprocess.run([str(a) for a in validate], cwd=crate, capture_output=True, text=True)
    assert done.returncode == 1, done.stdout + done.stderr
    assert "Traceback" not in done.stderr and "KeyError" not in done.stdout + done.stderr, done.stderr
    assert re.search(r"^Spinner\s+small_swings\s.*FAIL$", done.stdout, re.M), done.stdout
    assert re.search(r"names .?theta.?, which Spinner.fmu does not have", done.stdout), done.stdout


def test_scaffold_refuses_bad_names_and_existing_dirs(tmp_path):
    for bad in ["doublePendulum", "Double-Pendulum"]:
        done = subprocess.run([str(MECHFMU), "new", bad, "--path", str(tmp_path / bad)], capture_output=True, text=True)
        assert done.returncode != 0 and "UpperCamelCase" in done.stderr
    # names the crate's own code or cargo already takes: refused before anything is written
    for taken in ["Self", "Fn", "Test", "Mechanism", "Harness"]:
        done = subprocess.run([str(MECHFMU), "new", taken, "--path", str(tmp_path / taken)], capture_output=True,
                              text=True)
        assert done.returncode != 0 and f"`{taken}` cannot name a mechanism" in done.stderr, done.stderr
        assert not (tmp_path / taken).exists()
    (tmp_path / "taken").mkdir()
    (tmp_path / "taken" / "file").write_text("x")
    done = subprocess.run([str(MECHFMU), "new", "Taken", "--path", str(tmp_path / "taken")], capture_output=True, text=True)
    assert done.returncode != 0 and "not empty" in done.stderr


def test_user_fmu_passes_fmpy_validation(double_pendulum):
    assert validate_fmu(str(double_pendulum)) == []


def test_user_fmu_conserves_energy(double_pendulum):
    result = simulate_fmu(str(double_pendulum), stop_time=10.0, output_interval=0.01, relative_tolerance=1e-10)
    energy = result["E"]
    drift = np.max(np.abs(energy - energy[0])) / abs(energy[0])
    assert drift < 1e-8, f"energy drift {drift:.2e} relative"
    # The motion is chaotic at this amplitude: the second rod really swings.
    assert np.ptp(result["theta2"]) > 1.0


def test_mechfmu_validate_runs_the_crates_own_cases(double_pendulum):
    """Every row passes but Model Exchange under FMPy's CVode (FMI 2.0 and FMI 3.0), which is LIMIT: at rtol 1e-10
    its energy drifts by 3e-7 on this chaotic swing, against the case's 1e-8 (as for
    PendulumCart's energy_conserved, test_model_exchange.KNOWN_LIMITS); validate reports it
    and passes."""
    crate = double_pendulum.parents[1]
    done = subprocess.run([str(MECHFMU), "validate", "--manifest-path", str(crate / "Cargo.toml"), "--fmu-dir",
                           str(crate / "fmu")], cwd=crate, capture_output=True, text=True)
    # The user's FMI 3.0 FMU (fmu/fmi3/) is validated too, with the same limit.
    assert "0 failed, 2 at the importer's limit" in done.stdout, done.stdout
    assert done.returncode == 0 and "LIMIT DoublePendulum / energy_conserved / FMPy ME CVode" in done.stdout
    assert "LIMIT DoublePendulum / energy_conserved / FMPy FMI3 ME CVode" in done.stdout
    for importer in ("FMPy", "libcosim", "fmi crate", "FMPy ME Euler", "fmi crate ME RK4"):
        assert re.search(rf"^DoublePendulum\s+energy_conserved\s+{importer}\s.*PASS$", done.stdout, re.M), importer


def test_user_mechanism_comes_out_as_fmi3_too(double_pendulum):
    """No extra line in the user's crate: `mechfmu build` writes the FMI 3.0 FMU beside the
    FMI 2.0 one, FMPy validates it, and its Co-Simulation results equal FMI 2.0's."""
    fmi3 = double_pendulum.parent / "fmi3" / double_pendulum.name
    assert fmi3.exists(), f"no {fmi3}"
    assert validate_fmu(str(fmi3)) == []
    kwargs = dict(stop_time=2.0, output_interval=0.01, relative_tolerance=1e-10)
    a = simulate_fmu(str(double_pendulum), **kwargs)
    b = simulate_fmu(str(fmi3), **kwargs)
    for name in ("theta1", "theta2", "E"):
        assert np.array_equal(a[name], b[name]), name
