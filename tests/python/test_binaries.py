"""Every FMU carries a binary for each platform, each self-contained: `mechfmu inspect` lists
what each binary loads and exports, and this test holds it to what a stock system has.

The lists below are this test's own (what a fresh Windows 10 and a glibc Linux provide),
written independently of the build's check in crates/cli/src/package/binaries.rs."""

import json
import os
import re
import subprocess
import zipfile

import pytest

from fmutest import FMU_DIR, REPO_ROOT
from mechanisms import models

MECHFMU = REPO_ROOT / "target" / "release" / "mechfmu"
MODELS = models()

# binaries/<folder>: FMI 2.0 names the x86-64 platforms; FMI 2.0.5 says to use FMI 3.0's
# platform tuple for any other, so ARM Linux is aarch64-linux and Apple silicon aarch64-darwin
# in both. An FMI 2.0 darwin64 is universal (FMPy on Apple silicon loads darwin64): a slice each.
FOLDERS = {
    "2.0": [("linux64", "x86_64-linux"), ("win64", "x86_64-windows"), ("aarch64-linux", "aarch64-linux"),
            ("darwin64", "x86_64-darwin"), ("darwin64", "aarch64-darwin"), ("aarch64-darwin", "aarch64-darwin")],
    "3.0": [(p, p) for p in ("x86_64-linux", "x86_64-windows", "aarch64-linux", "x86_64-darwin", "aarch64-darwin")],
}
EXTENSION = {"x86_64-linux": "so", "x86_64-windows": "dll", "aarch64-linux": "so", "x86_64-darwin": "dylib",
             "aarch64-darwin": "dylib"}

GLIBC = {"libc.so.6", "libm.so.6", "libdl.so.2", "libpthread.so.0", "librt.so.1"}
LIBSYSTEM = {"/usr/lib/libSystem.B.dylib"}
STOCK = {
    "x86_64-linux": GLIBC | {"ld-linux-x86-64.so.2"},
    "aarch64-linux": GLIBC | {"ld-linux-aarch64.so.1"},
    # in C:\Windows\System32 of every Windows 10
    "x86_64-windows": {"kernel32.dll", "ntdll.dll", "msvcrt.dll", "userenv.dll", "ws2_32.dll", "advapi32.dll",
                       "bcrypt.dll", "bcryptprimitives.dll", "api-ms-win-core-synch-l1-2-0.dll"},
    "x86_64-darwin": LIBSYSTEM,
    "aarch64-darwin": LIBSYSTEM,
}
# the oldest macOS each Mac binary is for (the README says so)
MACOS = {"x86_64-darwin": "10.12.0", "aarch64-darwin": "11.0.0"}
# functions of the C library's math: most would make a platform's last bit its own, and
# none may be imported at all (the runtime computes these itself, with the libm crate)
MATH = {"sin", "cos", "tan", "sincos", "__sincos_stret", "asin", "acos", "atan", "atan2", "exp", "exp2", "exp10",
        "__exp10", "expm1", "log", "log2", "log10", "log1p", "pow", "cbrt", "hypot", "sinh", "cosh", "tanh", "fma",
        "floor", "ceil", "round", "trunc"}

MAX_FMU_BYTES = 4 * 1024 * 1024


def fmu_files():
    return [(FMU_DIR / f"{m}.fmu", "2.0") for m in MODELS] + [(FMU_DIR / "fmi3" / f"{m}.fmu", "3.0") for m in MODELS]


@pytest.fixture(scope="module")
def inspected():
    """`mechfmu inspect --json` of every FMU, by path."""
    paths = [p for p, _ in fmu_files()]
    missing = [p for p in paths if not p.is_file()]
    if missing or not MECHFMU.exists():
        pytest.fail(f"missing {missing or MECHFMU}: run `cargo run --release -- build` first", pytrace=False)
    done = subprocess.run([str(MECHFMU), "inspect", "--json", *map(str, paths)], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return {report["fmu"]: report for report in json.loads(done.stdout)}


@pytest.mark.parametrize("path,version", fmu_files(), ids=lambda x: str(x).split("fmus/")[-1])
def test_every_platform_is_there_and_self_contained(inspected, path, version):
    binaries = inspected[str(path)]["binaries"]
    model = path.stem
    expected = sorted((f"binaries/{folder}/{model}.{EXTENSION[p]}", p) for folder, p in FOLDERS[version])
    assert sorted((b["path"], b["platform"]) for b in binaries) == expected
    exports = None
    for b in binaries:
        stock = STOCK[b["platform"]]
        loads = [d.lower() if b["platform"] == "x86_64-windows" else d for d in b["dependencies"]]
        print(f"{b['path']} ({b['platform']}): loads {', '.join(b['dependencies'])}")
        assert set(loads) <= stock, f"{b['path']} loads {set(loads) - stock}"
        assert not any(d.startswith(("libgcc", "libwinpthread", "libstdc++")) for d in loads)
        assert b["foreign_dependencies"] == []
        # the same functions on every platform, FMI's alone: FMI 2.0's 44, FMI 3.0's 75
        if exports is None:
            exports = b["exports"]
            assert len([e for e in exports if e.startswith("fmi2")]) == 44
            assert len([e for e in exports if e.startswith("fmi3")]) == 75
            assert [e for e in exports if not e.startswith(("fmi2", "fmi3"))] == []
        assert b["exports"] == exports, b["path"]
        # the runtime's own math (the libm crate): the same bits on every platform, and no
        # import of the C library's, not even from code no call reaches (which a Windows
        # DLL keeps whole: x86_64-pc-windows-gnu compiles without function sections)
        math = {i for i in b["imports"] if i.lstrip("_") in MATH or i in MATH}
        assert not math, f"{b['path']} ({b['platform']}) takes {sorted(math)} from its platform's C library"


def libsystem_symbols() -> set[str]:
    """Every symbol the libSystem stub lists, for any architecture (a looser reading
    than the build's, per architecture)."""
    text = (REPO_ROOT / "crates/cli/src/build/macos/libSystem.tbd").read_text()
    lists = re.findall(r"(?:symbols|objc-classes|reexports):\s*\[([^\]]*)\]", text)
    return {name.strip().strip("'\"") for items in lists for name in items.replace("\n", " ").split(",")}


@pytest.mark.parametrize("path,version", fmu_files(), ids=lambda x: str(x).split("fmus/")[-1])
def test_mac_binaries_import_only_what_libsystem_exports(inspected, path, version):
    exported = libsystem_symbols()
    for b in inspected[str(path)]["binaries"]:
        if b["platform"].endswith("-darwin"):
            unknown = [i for i in b["imports"] if i not in exported]
            assert b["imports"] and not unknown, (b["path"], b["platform"], unknown)


@pytest.mark.parametrize("path,version", fmu_files(), ids=lambda x: str(x).split("fmus/")[-1])
def test_mac_binaries_load_as_they_are(inspected, path, version):
    """What a Mac's loader needs, read here: an install name of the binary's own, no newer
    macOS than the README says, and on Apple silicon a valid (ad hoc) code signature."""
    macs = [b for b in inspected[str(path)]["binaries"] if b["platform"].endswith("-darwin")]
    assert len(macs) == (3 if version == "2.0" else 2)
    for b in macs:
        assert b["install_name"] == f"@rpath/{path.stem}.dylib", b["path"]
        assert b["minimum_macos"] == MACOS[b["platform"]], b["path"]
        if b["platform"] == "aarch64-darwin":
            assert b["signature"] == "valid (ad hoc)", (b["path"], b["signature"])
        else:
            assert b["signature"] in ("none", "valid (ad hoc)"), (b["path"], b["signature"])
    if version == "2.0":
        universal = [b for b in macs if b["path"].startswith("binaries/darwin64/")]
        assert len(universal) == 2 and all(b.get("slice") for b in universal)


@pytest.mark.parametrize("path,version", fmu_files(), ids=lambda x: str(x).split("fmus/")[-1])
def test_fmu_size(path, version):
    size = path.stat().st_size
    assert size <= MAX_FMU_BYTES, f"{path} is {size / 2**20:.2f} MiB"
    with zipfile.ZipFile(path) as z:
        names = z.namelist()
    assert "modelDescription.xml" in names


def test_inspect_names_what_is_not_a_binary(tmp_path):
    fmu = tmp_path / "Odd.fmu"
    with zipfile.ZipFile(fmu, "w") as z:
        z.writestr("modelDescription.xml", "<fmiModelDescription/>")
        z.writestr("binaries/linux64/Odd.so", b"not a shared library")
    done = subprocess.run([str(MECHFMU), "inspect", str(fmu)], capture_output=True, text=True)
    assert done.returncode == 1
    assert "problem: not a shared library we can read" in done.stdout
    assert "1 binary with a problem" in done.stderr
    (tmp_path / "not.fmu").write_text("plain text")
    done = subprocess.run([str(MECHFMU), "inspect", str(tmp_path / "not.fmu")], capture_output=True, text=True)
    assert done.returncode == 1 and "not a zip archive" in done.stderr


def test_missing_toolchain_is_named_and_the_rest_is_built(tmp_path):
    """Without the cross linkers on PATH, `mechfmu build` packages this machine's binary and
    the Mac ones (rustc's own rust-lld links them), says which platforms it left out and how
    to install them; asked for one, it refuses."""
    cargo_bin = os.path.dirname(subprocess.run(["rustup", "which", "cargo"], capture_output=True,
                                               text=True).stdout.strip() or "/root/.cargo/bin/cargo")
    env = {k: v for k, v in os.environ.items() if not k.startswith("CARGO_TARGET_")}
    # only cargo and rustc: the host build is fresh (the build stage made it), so nothing links
    env["PATH"] = str(cargo_bin)
    done = subprocess.run([str(MECHFMU), "build", "Oscillator", "--out", str(tmp_path)], cwd=REPO_ROOT, env=env,
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert ("not built for x86_64-windows: the linker x86_64-w64-mingw32-gcc is missing "
            "(install: apt-get install gcc-mingw-w64-x86-64 mingw-w64-x86-64-dev)") in done.stdout
    assert "not built for aarch64-linux: the linker aarch64-linux-gnu-gcc is missing" in done.stdout
    assert "Oscillator.fmu (" in done.stdout and "): linux64, darwin64, aarch64-darwin\n" in done.stdout
    with zipfile.ZipFile(tmp_path / "Oscillator.fmu") as z:
        assert sorted(n for n in z.namelist() if n.startswith("binaries/") and not n.endswith("/")) == [
            "binaries/aarch64-darwin/Oscillator.dylib", "binaries/darwin64/Oscillator.dylib",
            "binaries/linux64/Oscillator.so"]
    done = subprocess.run([str(MECHFMU), "build", "Oscillator", "--out", str(tmp_path), "--platform", "win64"],
                          cwd=REPO_ROOT, env=env, capture_output=True, text=True)
    assert done.returncode == 1
    assert "error: no x86_64-windows binary: the linker x86_64-w64-mingw32-gcc is missing" in done.stderr
    done = subprocess.run([str(MECHFMU), "build", "--platform", "darwin32"], cwd=REPO_ROOT, capture_output=True,
                          text=True)
    assert done.returncode != 0 and "unknown platform `darwin32`" in done.stderr


def test_a_cross_linker_without_its_c_library_is_named(tmp_path):
    """Debian installs a cross linker without its C library when recommendations are left out,
    and the link then fails on a missing crti.o: `mechfmu build` names the package instead."""
    cargo_bin = os.path.dirname(subprocess.run(["rustup", "which", "cargo"], capture_output=True,
                                               text=True).stdout.strip() or "/root/.cargo/bin/cargo")
    linkers = tmp_path / "bin"
    linkers.mkdir()
    # a linker that finds no file: `-print-file-name=F` answers the bare F, as gcc does
    fake = linkers / "aarch64-linux-gnu-gcc"
    fake.write_text('#!/bin/sh\necho "${1#-print-file-name=}"\n')
    fake.chmod(0o755)
    env = {k: v for k, v in os.environ.items() if not k.startswith("CARGO_TARGET_")}
    env["PATH"] = f"{linkers}:{cargo_bin}"
    done = subprocess.run([str(MECHFMU), "build", "Oscillator", "--out", str(tmp_path / "out")], cwd=REPO_ROOT,
                          env=env, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert ("not built for aarch64-linux: the C library for aarch64-linux-gnu-gcc (crti.o) is missing "
            "(install: apt-get install libc6-dev-arm64-cross)") in done.stdout
