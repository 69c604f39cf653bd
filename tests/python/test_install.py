"""The `mechfmu` command as a user installs it, `cargo install --path crates/cli`, used outside
the checkout with the source tree it was built from gone: `new`, `build`, `validate` and
`sweep` work from the copies of mechfmu's files the command carries, written on first use to
its data folder (`MECHFMU_HOME`, else `$XDG_DATA_HOME/mechfmu` or `~/.local/share/mechfmu`).

The command is installed from a copy of the checkout (`target/install/src`), which is moved
away while the installed command runs, so a command that still read its source tree would
fail here. Reruns are fast: the copy is refreshed file by file (times kept, so cargo rebuilds
only what changed), cargo's target folder (`target/install/build`) and the data folder
(`target/install/home`, holding the venv and the fmi-crate importer) are kept. The first-use
path (writing the copy, creating the venv, building the importer) runs whenever the data
folder has no copy of this build yet: on a fresh clone, and after any change to what the
command carries (`python/`, the runtime, the test kit, `tools/fmi-run`).
"""

from __future__ import annotations

import csv
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import pytest

from fmutest import REPO_ROOT

WORK = REPO_ROOT / "target" / "install"
SOURCE = WORK / "src"
MOVED_AWAY = WORK / "src.moved-away"
DATA = WORK / "home"
# shared with test_new_mechanism.py: the user crates' dependencies from crates.io, built once
USER_CRATES_TARGET = REPO_ROOT / "target" / "user-crates"

FIRST_USE = "writing mechfmu's Python packages and crates to"


def skipped(path: Path) -> bool:
    """What a copy of the checkout leaves out: git, build output, Python caches, built FMUs."""
    name = path.name
    return (name in {".git", "target", "__pycache__", ".pytest_cache"}
            or name.endswith((".egg-info", ".pyc", ".fmu"))
            or path.relative_to(REPO_ROOT).as_posix() == "fmus/fmi3")


def mirror(source: Path, copy: Path) -> None:
    """Makes `copy` hold the files of `source` (but the skipped ones), with their times."""
    wanted = set()
    for folder, folders, files in os.walk(source):
        folder = Path(folder)
        folders[:] = [f for f in folders if not skipped(folder / f)]
        for name in files:
            file = folder / name
            if skipped(file) or file.is_symlink():
                continue
            relative = file.relative_to(source)
            wanted.add(relative)
            target = copy / relative
            have, want = (target.stat() if target.exists() else None), file.stat()
            if have is None or (have.st_size, have.st_mtime_ns) != (want.st_size, want.st_mtime_ns):
                target.parent.mkdir(parents=True, exist_ok=True)
                shutil.copy2(file, target)
    for folder, _, files in os.walk(copy):
        for name in files:
            file = Path(folder) / name
            if file.relative_to(copy) not in wanted:
                file.unlink()


def user_env(home: Path, **settings: str) -> dict[str, str]:
    """A user's environment, away from the checkout: another home folder (cargo, rustup and
    pip keep theirs, so nothing is downloaded twice), no mechfmu settings, no PATH entry
    inside the checkout, and this test's Python first on PATH (as `python3`)."""
    real_home = Path.home()
    env = {k: v for k, v in os.environ.items()
           if not k.startswith("MECHFMU_") and k not in {"CARGO_TARGET_DIR", "CARGO", "VIRTUAL_ENV",
                                                         "PYTHONPATH", "XDG_DATA_HOME"}}
    path = [p for p in env.get("PATH", "").split(os.pathsep) if p and not p.startswith(str(REPO_ROOT))]
    env.update(
        HOME=str(home),
        PATH=os.pathsep.join([str(Path(sys.base_prefix) / "bin"), *path]),
        CARGO_HOME=os.environ.get("CARGO_HOME", str(real_home / ".cargo")),
        RUSTUP_HOME=os.environ.get("RUSTUP_HOME", str(real_home / ".rustup")),
        PIP_CACHE_DIR=os.environ.get("PIP_CACHE_DIR", str(real_home / ".cache" / "pip")),
    )
    env.update(settings)
    return env


def run(args, cwd: Path, env: dict[str, str], timeout: float = 1800) -> subprocess.CompletedProcess:
    started = time.monotonic()
    done = subprocess.run([str(a) for a in args], cwd=cwd, env=env, capture_output=True, text=True,
                          timeout=timeout)
    print(f"{Path(str(args[0])).name} {args[1]}: {time.monotonic() - started:.0f} s")
    assert done.returncode == 0, (f"{' '.join(map(str, args))} failed ({done.returncode}):\n"
                                  f"{done.stdout[-5000:]}\n{done.stderr[-5000:]}")
    return done


@pytest.fixture(scope="module")
def mechfmu(tmp_path_factory):
    """The installed command (in a temporary `--root`), with its source tree moved away."""
    if MOVED_AWAY.exists():  # an interrupted run's
        shutil.rmtree(SOURCE, ignore_errors=True)
        MOVED_AWAY.rename(SOURCE)
    mirror(REPO_ROOT, SOURCE)
    root = tmp_path_factory.mktemp("cargo-root")
    env = {k: v for k, v in os.environ.items() if k != "CARGO_TARGET_DIR"}
    run(["cargo", "install", "--locked", "--path", SOURCE / "crates" / "cli", "--root", root,
         "--target-dir", WORK / "build"], cwd=REPO_ROOT, env=env, timeout=3600)
    SOURCE.rename(MOVED_AWAY)
    try:
        yield root / "bin" / "mechfmu"
    finally:
        MOVED_AWAY.rename(SOURCE)


def dependency_path(crate: Path, package: str) -> Path:
    manifest = (crate / "Cargo.toml").read_text()
    found = re.search(rf'^{re.escape(package)} = {{ path = "([^"]+)" }}', manifest, re.M)
    assert found, f"{package} is not a path dependency:\n{manifest}"
    return Path(found[1])


def test_new_writes_the_copy_to_the_users_data_folder(mechfmu, tmp_path):
    """Without MECHFMU_HOME: `$XDG_DATA_HOME/mechfmu/<version>-<hash>/`, written once, holding
    the runtime and test kit the scaffold depends on, with manifests that stand alone."""
    env = user_env(tmp_path / "home", XDG_DATA_HOME=str(tmp_path / "data"))
    first = run([mechfmu, "new", "Spinner"], cwd=tmp_path, env=env)
    (copy,) = (tmp_path / "data" / "mechfmu").iterdir()
    assert re.fullmatch(r"\d+\.\d+\.\d+.*-[0-9a-f]{16}", copy.name), copy.name
    assert f"{FIRST_USE} {copy}" in first.stderr, first.stderr
    assert dependency_path(tmp_path / "spinner", "mechfmu") == copy / "crates" / "runtime"
    assert dependency_path(tmp_path / "spinner", "mechfmu-testkit") == copy / "crates" / "testkit"
    for manifest in copy.glob("**/Cargo.toml"):
        assert ".workspace = true" not in manifest.read_text(), manifest
    assert (copy / "python" / "mechfmu_validate" / "__main__.py").is_file()
    assert (copy / "tests" / "python" / "requirements.txt").is_file()
    again = run([mechfmu, "new", "Spinner", "--path", tmp_path / "again"], cwd=tmp_path, env=env)
    assert FIRST_USE not in again.stderr


def importers() -> set[Path]:
    return set((DATA / "bin").glob("mechfmu-fmi-run-*"))


def test_build_validate_and_sweep_outside_the_checkout(mechfmu, tmp_path):
    env = user_env(tmp_path / "home", MECHFMU_HOME=str(DATA))
    copies_before = set(DATA.iterdir()) if DATA.exists() else set()
    importers_before = importers()
    run([mechfmu, "new", "Spinner"], cwd=tmp_path, env=env)
    crate = tmp_path / "spinner"
    copy = dependency_path(crate, "mechfmu").parents[1]
    assert copy.parent == DATA
    fresh = copy not in copies_before
    for other in copies_before - {copy, DATA / "bin"}:  # earlier builds': some 800 MB each
        shutil.rmtree(other)

    run([mechfmu, "build", "--manifest-path", crate / "Cargo.toml", "--out", crate / "fmu",
         "--platform", "x86_64-linux"], cwd=tmp_path, env={**env, "CARGO_TARGET_DIR": str(USER_CRATES_TARGET)})
    assert (crate / "fmu" / "Spinner.fmu").is_file() and (crate / "fmu" / "fmi3" / "Spinner.fmu").is_file()

    done = run([mechfmu, "validate", "--manifest-path", crate / "Cargo.toml", "--fmu-dir", crate / "fmu"],
               cwd=tmp_path, env=env)
    assert re.search(r"^\d+ passed, 0 failed", done.stdout, re.M), done.stdout
    for importer in ("FMPy", "libcosim", "fmi crate", "fmi crate ME RK4", "fmi crate FMI3 CS"):
        assert re.search(rf"^Spinner\s+\w+\s+{importer}\s.*PASS$", done.stdout, re.M), importer
    if fresh:
        venv = copy / "target" / "venv"
        assert f"setting up mechfmu's Python environment in {venv} (first use, about a minute)" in done.stderr
    assert (copy / "target" / "venv" / "bin" / "python").exists()
    # the importer, built once for its sources and kept beside the copies; its build's files are not
    if importers() != importers_before:
        assert "building the fmi-crate importer" in done.stderr, done.stderr
    assert importers() and not (copy / "target" / "fmi-run").exists()

    out = tmp_path / "sweep.csv"
    run([mechfmu, "sweep", crate / "fmu" / "Spinner.fmu", "--param", "m=1,2", "--stop-time", "1",
         "--workers", "1", "--out", out, "--no-progress"], cwd=tmp_path, env=env)
    with out.open() as f:
        rows = list(csv.DictReader(f))
    assert sorted(float(r["m"]) for r in rows) == [1.0, 2.0], rows
