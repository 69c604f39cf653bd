"""The Windows and ARM Linux binaries of the FMUs give the numbers of the Linux x86-64 one.

Every reference case of every mechanism (fmus/*/validation/cases.py, the ones test_cases.py
and `mechfmu validate` run), on the FMI 2.0 and the FMI 3.0 FMU, in Co-Simulation, through
the fmi crate's importer `mechfmu-fmi-run` (mechfmu_validate.importers.fmi_crate) built for each
platform (mechfmu_validate.platforms):

* x86_64-linux: natively;
* x86_64-windows: the Windows runner under wine64, loading binaries/win64 (FMI 3.0:
  x86_64-windows) .dll;
* aarch64-linux: the ARM runner under qemu-aarch64, loading binaries/aarch64-linux. For FMI
  2.0, a temporary copy of the FMU with that binary in binaries/linux64/, where the fmi
  crate (as FMPy) looks for an FMI 2.0 binary on aarch64 Linux (FMI 2.0.5 itself names ARM
  Linux aarch64-linux, as mechfmu packs it).

Each must agree with the native run to 1e-12 (relative to the native signal's largest
magnitude, mechfmu_validate.agreement); whether they are bit-identical is recorded
in target/test-figures/platforms.md and .json and printed at the end of the run.

Prepared by `scripts/cross-runners` (the runners, the test-only bcryptprimitives.dll Wine 8
lacks, the wine prefix). When it has not run, the tests FAIL naming it, unless
MECHFMU_SKIP_PLATFORMS=1. The FMUs are those of fmus/ (`mechfmu build --platform all`).

Runtime: wine is started once (a persistent wineserver, mechfmu_validate.platforms.
WineSession) and the runs are spread over two processes.
"""

from __future__ import annotations

import json
import multiprocessing
import os
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import pytest

import fmutest
from mechfmu_validate.fmu import Fmu
from mechfmu_validate.host import NATIVE, PLATFORMS, binary_folders, library_extension
from mechfmu_validate.loader import load_cases
from mechfmu_validate.platforms import (EMULATED, SCRIPT, NotPrepared, Runners, WineSession, aarch64_fmi2_copy,
                                        binary_platforms, cleanup_copies, compare, run_case)
from mechfmu_validate.target import Target as Fmi3
from test_cases import CASES, CRATES

SKIP_ENV = "MECHFMU_SKIP_PLATFORMS"
TOLERANCE = 1e-12
FOREIGN = list(EMULATED)
#: the platforms whose binaries run here
RUN = (NATIVE, *FOREIGN)
VERSIONS = ("2.0", "3.0")
WORKERS = 2
CASES_FILE = {model: d / "validation" / "cases.py" for model, d in CRATES}

#: why a platform's numbers may differ, when they do (the summary's note)
WHY = {
    "x86_64-windows": "a math function taken from msvcrt rather than the libm crate (the binaries import none)",
    "aarch64-linux": "a math function taken from glibc rather than the libm crate, or LLVM fusing a*b+c into "
                     "one FMA instruction on aarch64",
}


def fmu_file(directory: Path, model: str, version: str) -> Path:
    return directory / f"{model}.fmu" if version == "2.0" else directory / "fmi3" / f"{model}.fmu"


def _complete(directory: Path) -> bool:
    """Every mechanism's two FMUs there carry the five platforms' binaries (the Mac ones are checked by
    `mechfmu build` and by test_binaries.py, and not run here)."""
    return all(fmu_file(directory, m, v).is_file() and set(PLATFORMS) <= set(binary_platforms(fmu_file(directory, m, v)))
               for m, _ in CRATES for v in VERSIONS)


@pytest.fixture(scope="module")
def runners() -> Runners:
    try:
        return Runners.load()
    except NotPrepared as e:
        if os.environ.get(SKIP_ENV) == "1":
            pytest.skip(f"{SKIP_ENV}=1 and the cross runners are not prepared: {e}")
        pytest.fail(f"the Windows and ARM runners are not prepared: {e}. Run `{SCRIPT}` first "
                    f"(or set {SKIP_ENV}=1 to skip these tests)", pytrace=False)


@pytest.fixture(scope="module")
def fmu_dir(runners) -> Path:
    d = fmutest.FMU_DIR
    if not _complete(d):
        lacking = [f"{fmu_file(d, m, v)}: {', '.join(binary_platforms(fmu_file(d, m, v))) or '-'}"
                   for m, _ in CRATES for v in VERSIONS if fmu_file(d, m, v).is_file()][:4]
        pytest.fail(f"no FMUs with binaries for {', '.join(PLATFORMS)} in {d} (e.g. {'; '.join(lacking) or 'no FMU'}): "
                    "build them with `cargo run --release -- build --platform all`", pytrace=False)
    return d


def _run_job(model: str, case_name: str, version: str, path: str, env_file: str) -> dict:
    """In a worker process: the case on every platform. {platform: (columns, seconds, error)}."""
    runners = Runners.load(env_file)
    case = next(c for c in load_cases(CASES_FILE[model], model) if c.name == case_name)
    if version == "3.0":
        f3 = Fmi3.open(Path(path))
        fmu, mapping = f3.fmu, f3.mapping
    else:
        fmu, mapping = Fmu(Path(path)), None
    out = {}
    try:
        for platform in RUN:
            start = time.perf_counter()
            try:
                if version == "3.0" and mapping is None:
                    raise RuntimeError(f"the FMI 3.0 FMU's arrays: {f3.problem}")
                result = run_case(fmu, case, platform, runners, mapping=mapping)
                out[platform] = (result.columns, time.perf_counter() - start, None)
            except Exception as e:  # noqa: BLE001 (reported by the test)
                out[platform] = (None, time.perf_counter() - start, f"{type(e).__name__}: {e}")
    finally:
        fmu.cleanup()
        cleanup_copies()
    return out


class _Summary:
    """Prints the platform table at the end of the pytest run (registered as a plugin)."""

    def __init__(self, rows: list[dict], timing: dict, fmu_dir: Path):
        self.rows, self.timing, self.fmu_dir = rows, timing, fmu_dir

    def pytest_terminal_summary(self, terminalreporter):
        tr = terminalreporter
        tr.write_sep("-", "platforms: Windows (wine64) and ARM Linux (qemu-aarch64) against x86-64 Linux")
        checked = [r for r in self.rows if r["error"] is None]
        same = [r for r in checked if r["bit_identical"]]
        tr.write_line(f"{len(same)} of {len(self.rows)} runs bit-identical to the native one (FMUs from {self.fmu_dir}); "
                      f"table in target/test-figures/platforms.md")
        for r in self.rows:
            if r["error"] is not None or not r["bit_identical"]:
                what = r["error"] or f"max rel diff {r['max_relative']:.2e} in {r['signal']} at t = {r['time']:g}"
                tr.write_line(f"  {r['model']} / {r['case']} FMI {r['fmi']} {r['platform']}: {what}")
        tr.write_line("  seconds per run: " + ", ".join(f"{p} {t['mean']:.2f} (n={t['n']})" for p, t in self.timing.items() if p != "wall")
                      + f"; all runs {self.timing.get('wall', 0.0):.1f} s wall")


def _write_table(rows: list[dict], timing: dict, fmu_dir: Path) -> None:
    out = fmutest.FIGURES_DIR
    out.mkdir(parents=True, exist_ok=True)
    (out / "platforms.json").write_text(json.dumps(dict(fmu_dir=str(fmu_dir), timing=timing, rows=rows), indent=2) + "\n")
    lines = ["# Platforms: the FMUs' Windows and ARM Linux binaries against the Linux x86-64 one", "",
             f"mechfmu-fmi-run (fmi crate) in Co-Simulation, FMUs from `{fmu_dir}`; Windows under wine64, "
             "ARM under qemu-aarch64. max rel diff: max |x - x_native| / max |x_native| over the run "
             f"(tolerance {TOLERANCE:g}).", "",
             "| model | case | FMI | platform | max rel diff | bit-identical | seconds | note |",
             "|---|---|---|---|---|---|---|---|"]
    for r in rows:
        diff = "-" if r["max_relative"] is None else f"{r['max_relative']:.2e}"
        same = "-" if r["bit_identical"] is None else ("yes" if r["bit_identical"] else "no")
        note = r["error"] or ("" if r["bit_identical"] else WHY.get(r["platform"], ""))
        lines.append(f"| {r['model']} | {r['case']} | {r['fmi']} | {r['platform']} | {diff} | {same} | "
                     f"{r['seconds']:.2f} | {note} |")
    (out / "platforms.md").write_text("\n".join(lines) + "\n")


@pytest.fixture(scope="module")
def results(runners, fmu_dir, request) -> dict:
    """Every (model, case, version) run on every platform, once: {key: {platform: (...)}}."""
    jobs = [(model, case.name, version, str(fmu_file(fmu_dir, model, version)))
            for model, case in CASES for version in VERSIONS]
    start = time.perf_counter()
    out = {}
    with WineSession(runners):
        with ProcessPoolExecutor(WORKERS, mp_context=multiprocessing.get_context("fork")) as pool:
            futures = {job[:3]: pool.submit(_run_job, *job, str(runners.source)) for job in jobs}
            for key, future in futures.items():
                try:
                    out[key] = future.result(timeout=900)
                except Exception as e:  # noqa: BLE001 (a worker that died)
                    out[key] = {p: (None, 0.0, f"{type(e).__name__}: {e}") for p in RUN}
    wall = time.perf_counter() - start
    rows, seconds = [], {p: [] for p in RUN}
    for (model, case, version), runs in out.items():
        native = runs[NATIVE][0]
        for platform in RUN:
            columns, dt, error = runs[platform]
            seconds[platform].append(dt)
            if platform == NATIVE:
                continue
            row = dict(model=model, case=case, fmi=version, platform=platform, seconds=dt, error=error,
                       max_relative=None, signal=None, time=None, bit_identical=None)
            if error is None and native is None:
                row["error"] = f"no native result: {runs[NATIVE][2]}"
            elif error is None:
                c = compare(native, columns)
                row.update(max_relative=c.max_relative, signal=c.signal, time=c.time, bit_identical=c.bit_identical)
            rows.append(row)
    timing = {p: dict(mean=sum(s) / len(s), n=len(s)) for p, s in seconds.items() if s}
    timing["wall"] = wall
    _write_table(rows, timing, fmu_dir)
    request.config.pluginmanager.register(_Summary(rows, timing, fmu_dir), "mechfmu-platforms-summary")
    return out


def _params():
    return [pytest.param(model, case.name, version, id=f"{model}-{case.name}-fmi{version[0]}")
            for model, case in CASES for version in VERSIONS]


@pytest.mark.parametrize("model, case_name, version", _params())
def test_windows_and_arm_binaries_agree_with_linux_x86_64(results, model, case_name, version):
    runs = results[(model, case_name, version)]
    native, _, error = runs[NATIVE]
    assert error is None, f"the native run failed: {error}"
    problems = []
    for platform in FOREIGN:
        columns, _, error = runs[platform]
        if error is not None:
            problems.append(f"{platform}: {error}")
            continue
        c = compare(native, columns)
        if not c.max_relative <= TOLERANCE:
            problems.append(f"{platform}: {c} (tolerance {TOLERANCE:g}; {WHY[platform]})")
    assert not problems, f"{model} / {case_name} FMI {version}:\n" + "\n".join(problems)


def test_every_fmu_lists_the_five_platforms(fmu_dir):
    for model, _ in CRATES:
        for version in VERSIONS:
            path = fmu_file(fmu_dir, model, version)
            found = binary_platforms(path)
            assert sorted(found) == sorted(PLATFORMS), f"{path}: {found}"
            folders = {p: name.split("/")[1] for p, name in found.items()}
            expected = ({"x86_64-linux": "linux64", "x86_64-windows": "win64", "aarch64-linux": "aarch64-linux",
                         "x86_64-darwin": "darwin64", "aarch64-darwin": "aarch64-darwin"}
                        if version == "2.0" else {p: p for p in PLATFORMS})
            assert folders == expected, path


def test_the_fmi2_aarch64_copy_has_the_arm_binary_in_linux64(fmu_dir, tmp_path):
    import zipfile
    path = fmu_file(fmu_dir, "Oscillator", "2.0")
    copy = aarch64_fmi2_copy(path)
    try:
        with zipfile.ZipFile(copy) as z:
            binary = z.read("binaries/linux64/Oscillator.so")
            assert binary[:4] == b"\x7fELF" and int.from_bytes(binary[18:20], "little") == 183  # EM_AARCH64
            with zipfile.ZipFile(path) as original:
                assert binary == original.read("binaries/aarch64-linux/Oscillator.so")
                assert z.read("modelDescription.xml") == original.read("modelDescription.xml")
    finally:
        cleanup_copies()


def test_compare_tells_bit_identity_from_agreement():
    import numpy as np
    t = np.linspace(0.0, 1.0, 11)
    native = {"time": t, "x": np.sin(t), "z": np.zeros_like(t)}
    assert compare(native, dict(native)).bit_identical
    ulp = dict(native, x=np.nextafter(native["x"], np.inf))
    c = compare(native, ulp)
    assert not c.bit_identical and c.differing == ["x"] and 0 < c.max_relative <= TOLERANCE
    signed_zero = dict(native, z=-native["z"])  # equal as numbers, not as bits
    assert compare(native, signed_zero).max_relative == 0.0 and not compare(native, signed_zero).bit_identical
    assert compare(native, dict(native, z=native["z"] + 1e-9)).max_relative == 1e-9  # a zero signal: absolute


def test_each_machine_validates_the_binary_fmpy_loads_there():
    """`mechfmu validate` opens and checks the binary FMPy loads on the machine it runs on: on a
    Mac its own (FMI 2.0: the universal darwin64), as the Linux one here."""
    assert binary_folders("x86_64-linux") == {"2": "linux64", "3": "x86_64-linux"}
    assert binary_folders("aarch64-darwin") == {"2": "darwin64", "3": "aarch64-darwin"}
    assert binary_folders("x86_64-darwin") == {"2": "darwin64", "3": "x86_64-darwin"}
    assert binary_folders("x86_64-windows") == {"2": "win64", "3": "x86_64-windows"}
    assert binary_folders("aarch64-linux") == {"2": "aarch64-linux", "3": "aarch64-linux"}
    assert [library_extension(p) for p in PLATFORMS] == ["so", "dll", "so", "dylib", "dylib"]
