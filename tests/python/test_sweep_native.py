"""The native engine of `mechfmu sweep` (`mechfmu sweep-worker`, python/mechfmu_sweep/native.py)
against the FMPy engine: for every kind of case the sweep tests run (input schedules, a CSV
input and its scale, refused parameters, a discarded step, a slack-cable warning, the sweep
each mechanism's validation/expectations.toml names), the same rows to the bit: status,
message and every summary. Then on Dask end to end, an FMU that crashes the runner (one
chunk fails, the sweep goes on), and the errors when the native engine cannot run."""

from __future__ import annotations

import math
import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

from fmutest import REPO_ROOT, fmu_path
from mechanisms import mechanisms
from mechfmu_sweep import cli as sweep_cli
from mechfmu_sweep.native import EXE_ENV, NativeRuntime
from mechfmu_sweep.results import read_results
from mechfmu_sweep.runner import Runtime
from mechfmu_validate import fmulog

MECHFMU = REPO_ROOT / "target" / "release" / "mechfmu"
TIMING = ("elapsed_s", "cpu_s", "worker")


@pytest.fixture(autouse=True)
def native_worker(monkeypatch):
    """The runner is `mechfmu sweep-worker` of the command built by the README's build
    command; the FMPy engine's in-process Runtime repoints fmpy's logger proxy, given back
    to the suite's capture afterwards."""
    if not MECHFMU.is_file():
        pytest.fail(f"{MECHFMU} is missing: run `cargo run --release -- build`", pytrace=False)
    monkeypatch.setenv(EXE_ENV, str(MECHFMU))
    yield
    fmulog.repoint()


def plan_of(*args) -> sweep_cli.Plan:
    return sweep_cli.Plan(sweep_cli.make_parser().parse_args([str(a) for a in args]))


def same(a: float, b: float) -> bool:
    return (math.isnan(a) and math.isnan(b)) or np.float64(a).tobytes() == np.float64(b).tobytes()


def assert_same_rows(native: list[dict], fmpy: list[dict]) -> None:
    assert len(native) == len(fmpy)
    for n, f in zip(native, fmpy):
        assert set(n) == set(f), (sorted(n), sorted(f))
        for key in f:
            if key in TIMING:
                continue
            if isinstance(f[key], float):
                assert same(n[key], f[key]), (f["case"], key, n[key], f[key])
            else:
                assert n[key] == f[key], (f["case"], key, n[key], f[key])


def both_engines(plan: sweep_cli.Plan, fmu: Path, repeat: int = 1) -> tuple[list[dict], list[dict]]:
    """Every case of ``plan`` (``repeat`` times: later rounds start from fmi2Reset of an
    instance that has run cases) under the native engine and the FMPy engine."""
    cases = [(i, list(plan.design.values[i])) for i in range(len(plan.design))] * repeat
    rows = {}
    for name, runtime in (("native", NativeRuntime), ("fmpy", Runtime)):
        rt = runtime(fmu, plan.setup)
        try:
            rows[name] = rt.run(cases)
        finally:
            rt.close()
    return rows["native"], rows["fmpy"]


CRANE_SUMMARIES = ["max_abs(phi)", "max(T)", "min(T)", "mean(phi)", "rms(phi)", "max|F|", "min_abs(x)"]


def summary_args(names):
    return [x for s in names for x in ("--summary", s)]


def test_crane_schedules_warnings_and_refusals_give_the_same_rows():
    """Bang-bang trolley drives of 0.1 to 30 m/s² (the hardest throw the payload off: a slack
    cable, logged as a warning), over cable lengths including refused ones (l = -1, 0)."""
    plan = plan_of(fmu_path("Crane"), "--param", "l=-1,0,2,5,10", "--input-schedule",
                   "x_ddot=bangbang(t0=1,width=2,value=0.5)", "--param", "x_ddot.value=0.1,1,30",
                   "--stop-time", "8", *summary_args(CRANE_SUMMARIES))
    native, fmpy = both_engines(plan, fmu_path("Crane"), repeat=2)
    assert_same_rows(native, fmpy)
    statuses = {r["status"] for r in fmpy}
    assert {"ok", "warning", "error"} <= statuses, statuses
    assert any("l = -1" in r["message"] for r in native)


def test_a_csv_input_and_its_scale_give_the_same_rows(tmp_path):
    csv = tmp_path / "drive.csv"
    csv.write_text("time,x_ddot\n0,0\n1,0\n1,0.8\n2.5,0.8\n2.5,-0.8\n4,-0.8\n4,0\n")
    plan = plan_of(fmu_path("Crane"), "--input", csv, "--param", "l=3,7", "--param", "x_ddot.scale=0.5,1,2",
                   "--stop-time", "6", "--output-interval", "0.05", *summary_args(CRANE_SUMMARIES))
    native, fmpy = both_engines(plan, fmu_path("Crane"))
    assert_same_rows(native, fmpy)
    assert {r["status"] for r in native} == {"ok"}


def test_a_discarded_step_gives_the_same_row_and_the_next_case_runs():
    plan = plan_of(fmu_path("Crane"), "--param", "x_dot=-1.05,0", "--param", "x=1", "--stop-time", "2",
                   "--output-interval", "0.1")
    native, fmpy = both_engines(plan, fmu_path("Crane"), repeat=2)
    assert_same_rows(native, fmpy)
    assert [r["status"] for r in native] == ["discard", "ok"] * 2
    assert "fmi2DoStep discarded the step from t = 0.9" in native[0]["message"]


@pytest.mark.parametrize("name, params", [pytest.param(m.model, list(m.expectations.sweep_parameters), id=m.model)
                                          for m in mechanisms() if m.expectations.sweep_parameters])
def test_other_mechanisms_give_the_same_rows(name, params):
    """The sweep each mechanism's validation/expectations.toml names, on the first output's summaries."""
    names = [v.name for v in plan_of(fmu_path(name), "--param", params[0]).md.modelVariables
             if v.causality == "output"]
    extra = [f"{f}({names[0]})" for f in ("max", "min", "mean", "rms", "max_abs")]
    plan = plan_of(fmu_path(name), *[x for p in params for x in ("--param", p)], *summary_args(extra))
    native, fmpy = both_engines(plan, fmu_path(name))
    assert_same_rows(native, fmpy)
    assert {r["status"] for r in native} <= {"ok", "warning"}


def sweep(*args) -> tuple[int, list[dict]]:
    out = Path(args[args.index("--out") + 1])
    rc = sweep_cli.main([str(a) for a in args])
    return rc, (read_results(out).to_pylist() if out.exists() else [])


def test_on_dask_the_native_engine_writes_the_fmpy_engines_results(tmp_path):
    common = [fmu_path("Crane"), "--param", "l=2:10:9", "--input-schedule", "x_ddot=ramp(t0=0,t1=2,value=1)",
              "--param", "x_ddot.value=0.5,1", "--stop-time", "5", "--workers", "2", "--no-progress",
              *summary_args(CRANE_SUMMARIES)]
    rc_n, native = sweep(*common, "--engine", "native", "--chunk-size", "4", "--out", tmp_path / "n.parquet")
    rc_f, fmpy = sweep(*common, "--engine", "fmpy", "--out", tmp_path / "f.parquet")
    assert rc_n == rc_f == 0
    assert [r["case"] for r in native] == list(range(18))
    assert_same_rows(native, fmpy)
    meta = read_results(tmp_path / "n.parquet").schema.metadata[b"mechfmu_sweep"]
    assert b'"engine": "native"' in meta and b'"wall_s"' in meta


def crashing_fmu(directory: Path) -> Path:
    """FirstOrder (the foreign test FMU) built to crash its importer when y0 < 0."""
    from test_validate_foreign import build

    return build(directory, "-DCRASH_IF_NEGATIVE_Y0")


def test_a_crash_of_the_fmu_fails_its_chunk_and_the_sweep_goes_on(tmp_path):
    fmu = crashing_fmu(tmp_path / "crash")
    rc, rows = sweep(fmu, "--param", "y0=1,2,-1,3,4,5", "--chunk-size", "2", "--workers", "1", "--engine", "native",
                     "--stop-time", "1", "--no-progress", "--out", tmp_path / "r.parquet")
    assert rc == 0
    assert [r["status"] for r in rows] == ["ok", "ok", "crashed", "crashed", "ok", "ok"]
    assert "crashed the native runner" in rows[2]["message"], rows[2]["message"]
    assert rows[4]["final(y)"] == pytest.approx(4 * math.exp(-1 / 0.5))


def test_without_a_runner_the_native_engine_is_refused_and_the_default_is_fmpy(tmp_path, monkeypatch, capsys):
    monkeypatch.delenv(EXE_ENV)
    args = [fmu_path("Oscillator"), "--param", "k=1,2", "--stop-time", "1", "--workers", "1", "--no-progress"]
    rc, _ = sweep(*args, "--engine", "native", "--out", tmp_path / "a.csv")
    assert rc == 2 and "--engine native: no `mechfmu` executable" in capsys.readouterr().err
    rc, rows = sweep(*args, "--out", tmp_path / "b.csv")
    assert rc == 0 and len(rows) == 2
    assert "the FMPy engine runs the cases" in capsys.readouterr().err


def test_the_command_runs_the_native_engine_by_default(tmp_path):
    """`mechfmu sweep` names itself to the Python side: its workers run the native engine."""
    out = tmp_path / "osc.parquet"
    env = {k: v for k, v in os.environ.items() if k != EXE_ENV}
    done = subprocess.run([str(MECHFMU), "sweep", str(fmu_path("Oscillator")), "--param", "k=1:4:4",
                           "--stop-time", "2", "--workers", "1", "--no-progress", "--out", str(out)],
                          capture_output=True, text=True, env=env, timeout=600)
    assert done.returncode == 0, done.stderr
    meta = read_results(out).schema.metadata[b"mechfmu_sweep"]
    assert b'"engine": "native"' in meta, done.stderr
