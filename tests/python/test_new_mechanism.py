"""A new user's first mechanism, as they would go through it, outside the repository:
`mechfmu new` as created (its tests, build and validation pass; renaming the example's
variable fails both with a message naming it), then `mechfmu new DoublePendulum`, replace the
example with a double pendulum, build, validate, and check the physics (energy conserved to
1e-8 relative over 10 s at rtol 1e-10).

Then `mechfmu new CartPendulum --energies`, a mechanism declared from its energies, as
created: its tests, build and validation pass, FMPy validates both FMUs, its accelerations
under FMPy are Newton's law written here (the rod's tension a third unknown), and a kinetic
energy edited to forget the swing's velocity is refused at initialization with a message
naming `theta_dot`. Last, the tutorial's GantryCrane (two driven coordinates and a free one)
in such a crate: its tests (Newton's law for the swing and both drives' forces), build and
validation pass.

And inside a workspace that takes it (as this repository's `fmus/*` does), the new crate is
a member: one of the mechanisms every test runs on, its expectations read from its folder."""

import os
import re
import shutil
import subprocess
import zipfile
from pathlib import Path

import numpy as np
import pytest
from fmpy import simulate_fmu
from fmpy.fmi2 import fmi2Error
from fmpy.validation import validate_fmu

from fmutest import REPO_ROOT, Slave, status_name
from mechanisms import Expectations, Limit, mechanisms
from mechfmu_validate.loader import load_cases
from mechfmu_validate.importers.fmpy import EULER

MECHFMU = REPO_ROOT / "target" / "release" / "mechfmu"
DOUBLE_PENDULUM = Path(__file__).parent / "data" / "double_pendulum.rs"
DOUBLE_PENDULUM_CASES = Path(__file__).parent / "data" / "double_pendulum_cases.py"
MATH_CALLS = Path(__file__).parent / "data" / "math_calls.rs"
GANTRY_CRANE = Path(__file__).parent / "data" / "gantry_crane.rs"
GANTRY_CRANE_TESTS = Path(__file__).parent / "data" / "gantry_crane_test.rs"
GANTRY_CRANE_CASES = Path(__file__).parent / "data" / "gantry_crane_cases.py"


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


def math_calls_y(x):
    """`MathCalls`' output, from its source's formula."""
    s, c = np.sin(x), np.cos(x)
    trigonometry = s + c + s * c + np.tan(x) + np.arcsin(x) + np.arccos(x) + np.arctan(x) + np.arctan2(x, 1.0)
    hyperbolic = np.sinh(x) + np.cosh(x) + np.tanh(x) + np.arcsinh(x) + np.arccosh(1 + x) + np.arctanh(x)
    exponential = (np.exp(x) + np.exp2(x) + np.expm1(x) + np.log(x) + np.log1p(x) + np.log2(x) + np.log10(x)
                   + np.log(x) / np.log(3.0))
    powers = np.sqrt(x) + np.cbrt(x) + x**1.5 + 10.0**x + x**3 + np.hypot(x, 1.0)
    others = x * x + 1 + 1 / x + np.abs(x) - np.abs(x) + np.maximum(x, 1.0) + np.minimum(x, 1.0)
    return trigonometry + hyperbolic + exponential + powers + others


def test_every_math_function_links_on_every_platform(double_pendulum, tmp_path):
    """A mechanism whose output calls every smooth function of `Scalar` builds for every
    platform: on the Macs its binaries import the C math library (and the forms LLVM fuses
    calls into, `__sincos_stret`, `__exp10`) from the libSystem stub mechfmu links against.
    Its output under FMPy is the formula, computed here."""
    crate = tmp_path / "math_calls"
    run([MECHFMU, "new", "MathCalls", "--path", crate], cwd=tmp_path)
    shutil.copy(MATH_CALLS, crate / "src" / "lib.rs")
    for test in (crate / "tests").glob("*.rs"):
        test.unlink()
    run([MECHFMU, "build", "--manifest-path", crate / "Cargo.toml", "--out", crate / "fmu", "--platform", "all"],
        cwd=tmp_path, env=user_crate_env())
    fmu = crate / "fmu" / "fmi3" / "MathCalls.fmu"
    names = zipfile.ZipFile(fmu).namelist()
    for platform in ("x86_64-darwin", "aarch64-darwin", "x86_64-windows", "aarch64-linux", "x86_64-linux"):
        assert any(n.startswith(f"binaries/{platform}/") for n in names), (platform, names)
    result = simulate_fmu(str(fmu), stop_time=1.0, output_interval=0.25, output=["x", "y"])
    np.testing.assert_allclose(result["x"], 0.5 + 0.1 * result["time"], rtol=1e-12)
    np.testing.assert_allclose(result["y"], math_calls_y(result["x"]), rtol=1e-13)

# ---------------------------------------------------------------------------------------
# `mechfmu new --energies`: a cart on a spring carrying a pendulum, declared from T, V, Q

CART_PARAMETERS = dict(M=1.0, m=0.5, l=0.5, k=10.0, c=0.0, g=9.81)


@pytest.fixture(scope="module")
def cart_pendulum(tmp_path_factory):
    """`mechfmu new CartPendulum --energies` outside the repository, as created: its tests
    pass and it builds (this machine's platform)."""
    home = tmp_path_factory.mktemp("energies")
    crate = home / "cart_pendulum"
    run([MECHFMU, "new", "CartPendulum", "--energies", "--path", crate], cwd=home)
    env = user_crate_env()
    run(["cargo", "test", "-q", "--manifest-path", crate / "Cargo.toml"], cwd=crate, env=env)
    run([MECHFMU, "build", "--manifest-path", crate / "Cargo.toml", "--out", crate / "fmu", "--platform",
         "x86_64-linux"], cwd=crate, env=env)
    return crate


def newton(M, m, l, k, c, g, F, x, x_dot, theta, theta_dot):
    """(x'', theta'') by Newton's law on each body, the rod's tension N a third unknown: the
    cart M x'' = -k x - c x' + N sin th; the bob at (x + l sin th, -l cos th),
    m (x'' + l th'' cos th - l th'^2 sin th) = F - N sin th and
    m (l th'' sin th + l th'^2 cos th) = N cos th - m g."""
    s, co = np.sin(theta), np.cos(theta)
    lhs = np.array([[M, 0.0, -s], [m, m * l * co, s], [0.0, m * l * s, -co]])
    rhs = np.array([-k * x - c * x_dot, F + m * l * theta_dot**2 * s, -m * g - m * l * theta_dot**2 * co])
    x_ddot, theta_ddot, _ = np.linalg.solve(lhs, rhs)
    return x_ddot, theta_ddot


def test_energies_scaffold_builds_and_validates(cart_pendulum):
    """As created: declared from its energies, no unsafe code; FMPy validates both FMUs;
    `mechfmu validate` passes both cases under every importer; the notes show T, V and Q."""
    lib = (cart_pendulum / "src" / "lib.rs").read_text()
    assert "#![forbid(unsafe_code)]" in lib and "impl Lagrangian<2> for CartPendulum" in lib
    assert "Self::lagrange(v);" in lib and "Self::mass_matrix_problem(v)" in lib
    fmu = cart_pendulum / "fmu" / "CartPendulum.fmu"
    assert validate_fmu(str(fmu)) == []
    assert validate_fmu(str(fmu.parent / "fmi3" / fmu.name)) == []
    page = zipfile.ZipFile(fmu).read("documentation/index.html").decode()
    for equation in ("T = ½ M ẋ²", "V = ½ k x² - m g l cos θ", "Q_x = F - c ẋ", "Q_θ = F l cos θ"):
        assert equation in page, f"the notes' `{equation}` is not on the FMU's page"
    done = subprocess.run([str(MECHFMU), "validate", "--manifest-path", str(cart_pendulum / "Cargo.toml"),
                           "--fmu-dir", str(cart_pendulum / "fmu"), "--no-fmi-crate"], cwd=cart_pendulum,
                          capture_output=True, text=True)
    assert done.returncode == 0 and re.search(r"^\d+ passed, 0 failed$", done.stdout, re.M), done.stdout + done.stderr
    for case in ("small_oscillations", "energy_conserved"):
        for importer in ("FMPy", "libcosim", "FMPy ME CVode", "FMPy FMI3 CS"):
            assert re.search(rf"^CartPendulum\s+{case}\s+{importer}\s.*PASS$", done.stdout, re.M), (case, importer)


def test_energies_scaffold_accelerations_are_newtons_law(cart_pendulum):
    """The FMU's x_ddot and theta_ddot under FMPy, at states, forces and parameters spread
    over their ranges, against Newton's law above."""
    fmu = cart_pendulum / "fmu" / "CartPendulum.fmu"
    worst = 0.0
    for k in range(8):
        point = dict(CART_PARAMETERS, M=1.0 + 0.3 * k, c=0.1 * k, F=np.sin(0.7 * k) * 2.0, x=np.cos(0.3 * k),
                     x_dot=0.4 * k - 1.5, theta=0.9 * k - 3.0, theta_dot=3.0 * np.sin(0.5 * k))
        with Slave(fmu) as s:
            s.initialize(point)
            got = s.get("x_ddot", "theta_ddot")
        want = newton(**point)
        for g, w in zip(got, want):
            worst = max(worst, abs(g - w) / (1.0 + abs(w)))
    assert worst < 1e-12, f"worst relative difference {worst:.1e}"


def test_energies_scaffold_refuses_a_kinetic_energy_that_forgets_a_velocity(tmp_path):
    """The user writes the bob as moving with the cart, its swing forgotten: T no longer
    depends on theta_dot, so the mass matrix is singular. Initialization fails, and the
    message names `theta_dot`."""
    crate = tmp_path / "forgetful"
    run([MECHFMU, "new", "Forgetful", "--energies", "--path", crate], cwd=tmp_path)
    lib = crate / "src" / "lib.rs"
    whole = "half * v.M * v.x_dot * v.x_dot + half * v.m * (r_dot_x * r_dot_x + r_dot_y * r_dot_y)"
    assert whole in lib.read_text()
    lib.write_text(lib.read_text().replace(whole, "half * (v.M + v.m) * v.x_dot * v.x_dot"))
    run([MECHFMU, "build", "--manifest-path", crate / "Cargo.toml", "--out", crate / "fmu", "--platform",
         "x86_64-linux"], cwd=crate, env=user_crate_env())
    with Slave(crate / "fmu" / "Forgetful.fmu", logging_on=True) as s:
        s.setup()
        s.enter()
        status = s.call("fmi2ExitInitializationMode")
        assert status == fmi2Error, f"{status_name(status)}; log:\n{s.log.text()}"
        named = s.log.find(r"does not depend on `theta_dot`", status=fmi2Error)
        assert named, f"no error naming `theta_dot`; log:\n{s.log.text()}"


def test_tutorial_gantry_crane_from_its_energies(tmp_path):
    """The tutorial's chapter 7: `mechfmu new GantryCrane --energies`, its three files
    replaced by the crane's (trolley and hoist driven, swing free), then `cargo test`
    (Newton's law for the swing and the drives' forces, conformance), build and validate."""
    crate = tmp_path / "gantry_crane"
    run([MECHFMU, "new", "GantryCrane", "--energies", "--path", crate], cwd=tmp_path)
    shutil.copy(GANTRY_CRANE, crate / "src" / "lib.rs")
    shutil.copy(GANTRY_CRANE_TESTS, crate / "tests" / "gantry_crane.rs")
    shutil.copy(GANTRY_CRANE_CASES, crate / "validation" / "cases.py")
    env = user_crate_env()
    tests = run(["cargo", "test", "--manifest-path", crate / "Cargo.toml"], cwd=crate, env=env)
    assert "test swing_and_drive_forces_follow_newtons_law ... ok" in tests.stdout, tests.stdout
    run([MECHFMU, "build", "--manifest-path", crate / "Cargo.toml", "--out", crate / "fmu", "--platform",
         "x86_64-linux"], cwd=crate, env=env)
    assert validate_fmu(str(crate / "fmu" / "GantryCrane.fmu")) == []
    done = subprocess.run([str(MECHFMU), "validate", "--manifest-path", str(crate / "Cargo.toml"), "--fmu-dir",
                           str(crate / "fmu"), "--no-fmi-crate"], cwd=crate, capture_output=True, text=True)
    assert done.returncode == 0 and re.search(r"^\d+ passed, 0 failed$", done.stdout, re.M), done.stdout + done.stderr
    for case in ("trolley_starts", "hoisting"):
        assert re.search(rf"^GantryCrane\s+{case}\s+FMPy ME CVode\s.*PASS$", done.stdout, re.M), case


# ---------------------------------------------------------------------------------------
# `mechfmu new` inside a workspace: a member, one of its mechanisms


def test_a_new_crate_in_the_workspace_is_one_of_its_mechanisms(tmp_path):
    """A workspace whose members are `fmus/*`, as this repository's: `mechfmu new Probe --path
    fmus/probe` makes a member (its dependencies relative paths, no workspace or profile of its
    own), and the mechanisms the tests run on (tests/python/mechanisms.py, from cargo metadata)
    are then it, with its cases; what its `validation/expectations.toml` says loads; `--energies`
    gives a second."""
    workspace = tmp_path / "workspace"
    (workspace / "fmus").mkdir(parents=True)
    (workspace / "Cargo.toml").write_text('[workspace]\nmembers = ["fmus/*"]\nresolver = "2"\n')
    run([MECHFMU, "new", "Probe", "--path", workspace / "fmus" / "probe"], cwd=workspace)
    crate = workspace / "fmus" / "probe"
    manifest = (crate / "Cargo.toml").read_text()
    assert "[workspace]" not in manifest and "[profile" not in manifest, manifest
    assert re.search(r'^mechfmu = \{ path = "(\.\./)+[^"]*crates/runtime" \}$', manifest, re.M), manifest
    assert not (crate / ".gitignore").exists()

    [probe] = mechanisms(workspace / "Cargo.toml")
    assert (probe.model, probe.package, probe.crate) == ("Probe", "probe", crate.resolve())
    assert [c.name for c in load_cases(probe.cases_file, "Probe")], "the scaffold's cases"
    assert probe.contract is None and probe.expectations == Expectations()
    (probe.validation / "expectations.toml").write_text(
        '[[limit]]\ncase = "small_swings"\nimporter = "FMPy ME Euler"\nwhy = "measured"\n\n'
        '[sweep]\nparameters = ["l=1,2"]\n')
    assert probe.expectations == Expectations((Limit("small_swings", EULER, "measured"),), ("l=1,2",))
    (probe.validation / "expectations.toml").write_text('[[limit]]\ncase = "small_swings"\nimporter = "Euler"\n')
    with pytest.raises(ValueError, match="expectations.toml"):
        probe.expectations  # noqa: B018 (read to be refused)

    run([MECHFMU, "new", "Cart", "--energies", "--path", workspace / "fmus" / "cart"], cwd=workspace)
    assert [m.model for m in mechanisms(workspace / "Cargo.toml")] == ["Cart", "Probe"]
