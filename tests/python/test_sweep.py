"""`mechfmu sweep` (python/mechfmu_sweep): parameter sweeps on Dask distributed.

* 200 Crane cases over the cable length `l` and a trolley acceleration schedule (x_ddot, a
  rest-to-rest bang-bang move of swept amplitude), on a local cluster of 2 worker
  processes, equal case by case to sequential `fmpy.simulate_fmu` runs (to 1e-12);
* an invalid case (`l = -1`) is reported as failed with the FMU's own message while the
  others complete, on an existing cluster started here (`dask scheduler` + `dask worker`
  processes that do not have the package: the sweep ships it);
* the command end to end (`cargo run --release -- sweep`): results, plot, exit codes and
  the messages of bad requests;
* the pieces: specs, designs, schedules, CSV inputs and the summaries; the grammar of the
  request (python/mechfmu_sweep owns it: `mechfmu sweep` passes its arguments through).
"""

from __future__ import annotations

import json
import math
import os
import shutil
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest

import fmpy
from fmutest import REPO_ROOT, fmu_path, make_input
from mechfmu_sweep import cli as sweep_cli
from mechfmu_sweep.design import (
    SpecError,
    build_design,
    input_table,
    parse_param,
    parse_schedule,
    parse_spec,
)
from mechfmu_sweep.results import read_results
from mechfmu_sweep.runner import (
    CaseSetup,
    Runtime,
    Summary,
    parse_summary,
)
from mechfmu_validate import fmulog

SUMMARIES = ["max_abs(phi)", "max(T)", "min(T)", "mean(phi)", "rms(phi)", "max|F|"]
L_SPEC, A_SPEC = "2:10:20", "0.1:1:10"  # 20 x 10 = 200 cases
T0, WIDTH = 1.0, 2.0


@pytest.fixture(autouse=True)
def suite_logger():
    """An in-process Runtime points fmpy's process-wide logger proxy at its own callback;
    give it back to the suite's capture (mechfmu_validate.fmulog) for the tests that follow."""
    yield
    fmulog.repoint()


def bangbang_reference(a: float) -> np.ndarray:
    """The documented table of bangbang(t0=1, width=2, value=a), written out by hand:
    a lead-in point 1 s before t0, +a on [1, 3), -a on [3, 5), 0 after."""
    return make_input([0, 1, 1, 3, 3, 5, 5], x_ddot=[0, 0, a, a, -a, -a, 0])


def reference_summaries(res) -> dict[str, float]:
    """The sweep's summary columns, computed here from a simulate_fmu result."""
    t = res["time"]
    span = t[-1] - t[0]
    out = {f"final({name})": float(res[name][-1]) for name in res.dtype.names if name != "time"}
    out["max_abs(phi)"] = float(np.max(np.abs(res["phi"])))
    out["max(T)"] = float(np.max(res["T"]))
    out["min(T)"] = float(np.min(res["T"]))
    out["mean(phi)"] = float(np.trapezoid(res["phi"], t) / span)
    out["rms(phi)"] = float(math.sqrt(np.trapezoid(res["phi"] ** 2, t) / span))
    out["max_abs(F)"] = float(np.max(np.abs(res["F"])))
    return out


def table_rows(table) -> list[dict]:
    return table.to_pylist()


def run_sweep(args: list[str]) -> int:
    return sweep_cli.main([str(a) for a in args])


# =======================================================================================
# 200 Crane cases on 2 workers == 200 sequential simulate_fmu runs


@pytest.fixture(scope="module")
def crane_sweep(tmp_path_factory):
    out = tmp_path_factory.mktemp("sweep") / "crane.parquet"
    args = [fmu_path("Crane"), "--param", f"l={L_SPEC}",
            "--input-schedule", f"x_ddot=bangbang(t0={T0},width={WIDTH},value=0.5)",
            "--param", f"x_ddot.value={A_SPEC}", "--workers", "2", "--out", out, "--no-progress"]
    for s in SUMMARIES:
        args += ["--summary", s]
    started = time.perf_counter()
    rc = run_sweep(args)
    wall = time.perf_counter() - started
    assert rc == 0
    return read_results(out), wall


def test_crane_sweep_matches_sequential_simulate_fmu(crane_sweep, tmp_path):
    table, wall = crane_sweep
    rows = table_rows(table)
    assert len(rows) == 200
    meta = json.loads(table.schema.metadata[b"mechfmu_sweep"])
    assert meta["workers"] == 2 and meta["cases"] == 200
    # the full factorial, l varying slowest
    assert [r["l"] for r in rows[::10]] == list(np.linspace(2, 10, 20))
    assert [r["x_ddot.value"] for r in rows[:10]] == list(np.linspace(0.1, 1, 10))
    assert {r["status"] for r in rows} == {"ok"}, [r for r in rows if r["status"] != "ok"][:3]
    assert len({r["worker"] for r in rows}) == 2, "both worker processes ran cases"

    # The references: fresh instances, fmpy's own defaults (the FMU's DefaultExperiment)
    path = fmu_path("Crane")
    unzipdir = fmpy.extract(str(path), str(tmp_path / "crane"))
    md = fmpy.read_model_description(unzipdir)
    worst, where, compared = 0.0, None, 0
    started = time.perf_counter()
    for r in rows:
        res = fmpy.simulate_fmu(unzipdir, model_description=md, start_values={"l": r["l"]},
                                input=bangbang_reference(r["x_ddot.value"]))
        for col, want in reference_summaries(res).items():
            got = r[col]
            err = abs(got - want) / max(1.0, abs(want))
            compared += 1
            if err > worst:
                worst, where = err, (r["case"], col, got, want)
    sequential = time.perf_counter() - started
    print(f"\n200 Crane cases: sweep {wall:.1f} s on 2 workers (with the cluster's start), "
          f"sequential simulate_fmu {sequential:.1f} s; {compared} values, worst difference {worst:.1e}")
    assert worst <= 1e-12, f"case {where[0]}: {where[1]} = {where[2]!r}, simulate_fmu gives {where[3]!r}"
    # and the sweep says something: a faster move swings the payload further
    by_l = {}
    for r in rows:
        by_l.setdefault(r["l"], []).append(r["max_abs(phi)"])
    assert all(np.all(np.diff(v) > 0) for v in by_l.values())


# =======================================================================================
# An invalid case fails with the FMU's message; the others complete (existing cluster)


# Preloaded into the worker process: the venv's interpreter has mechfmu's packages installed
# (editable, python/pyproject.toml), so take them away there, as on a machine without them.
WITHOUT_THE_PACKAGE = f"""
import importlib, sys
sys.meta_path[:] = [f for f in sys.meta_path
                    if not ("__editable__" in getattr(f, "__module__", "") and "mechfmu" in f.__module__)]
sys.path[:] = [p for p in sys.path if not p.startswith({str(REPO_ROOT / "python")!r})]
for name in [n for n in sys.modules if n.split(".")[0] in ("mechfmu_sweep", "mechfmu_validate")]:
    del sys.modules[name]
importlib.invalidate_caches()
"""


@pytest.fixture(scope="module")
def external_cluster(tmp_path_factory):
    """`dask scheduler` and one `dask worker` process, on loopback, whose worker does not
    have this package (the sweep must ship it)."""
    d = tmp_path_factory.mktemp("cluster")
    sched_file = d / "scheduler.json"
    preload = d / "without_mechfmu.py"
    preload.write_text(WITHOUT_THE_PACKAGE)
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    log = open(d / "log.txt", "w")
    common = dict(cwd=d, env=env, stdout=subprocess.DEVNULL, stderr=log)
    procs = [subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_scheduler", "--host", "127.0.0.1",
                               "--port", "0", "--dashboard-address", "127.0.0.1:0", "--no-dashboard",
                               "--scheduler-file", str(sched_file)], **common)]
    try:
        deadline = time.monotonic() + 60
        while not sched_file.exists() or not sched_file.read_text().strip():
            assert time.monotonic() < deadline, "the dask scheduler did not start:\n" + (d / "log.txt").read_text()
            time.sleep(0.2)
        address = json.loads(sched_file.read_text())["address"]
        procs.append(subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_worker", address,
                                       "--host", "127.0.0.1", "--nthreads", "1", "--nworkers", "1",
                                       "--no-dashboard", "--preload", str(preload)], **common))
        yield address
    finally:
        for p in reversed(procs):
            p.send_signal(signal.SIGINT)
        for p in reversed(procs):
            try:
                p.wait(timeout=20)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()
        log.close()


def test_invalid_case_fails_with_the_fmu_message(external_cluster, tmp_path):
    out = tmp_path / "invalid.parquet"
    rc = run_sweep([fmu_path("Crane"), "--param", "l=-1,2,5", "--param", "m=800,1200",
                    "--scheduler", external_cluster, "--stop-time", "5", "--summary", "max(T)",
                    "--out", out, "--no-progress"])
    assert rc == 0, "failed cases do not fail the sweep"
    table = read_results(out.with_suffix(".parquet"))
    meta = json.loads(table.schema.metadata[b"mechfmu_sweep"])
    assert meta["scheduler"] == external_cluster and meta["workers"] == 1
    assert meta["shipped_package"], "the external worker lacked mechfmu_sweep: it must have been sent"
    rows = table_rows(table)
    assert len(rows) == 6
    bad = [r for r in rows if r["l"] == -1]
    good = [r for r in rows if r["l"] > 0]
    for r in bad:
        assert r["status"] == "error"
        # the FMU's own words, logged through the logger callback
        assert "l = -1" in r["message"] and "must be > 0" in r["message"], r["message"]
        assert r["max(T)"] is None or math.isnan(r["max(T)"])
    for r in good:
        assert r["status"] == "ok" and r["message"] in ("", None)
        assert r["max(T)"] == pytest.approx(r["m"] * 9.81, rel=1e-9), "hanging still, T = m g"
    assert len({r["worker"] for r in rows}) == 1  # the one external worker, reused after errors


# =======================================================================================
# The command end to end


def mechfmu_command() -> list[str]:
    """`cargo run --release -- sweep` (MECHFMU_BIN names a built binary instead)."""
    if os.environ.get("MECHFMU_BIN"):
        return [os.environ["MECHFMU_BIN"], "sweep"]
    cargo = shutil.which("cargo") or str(Path.home() / ".cargo/bin/cargo")
    if Path(cargo).exists():
        return [cargo, "run", "--release", "--quiet", "--", "sweep"]
    binary = REPO_ROOT / "target/release/mechfmu"
    if binary.exists():
        return [str(binary), "sweep"]
    pytest.fail("neither cargo nor target/release/mechfmu found", pytrace=False)


def mechfmu(*args, timeout=600) -> subprocess.CompletedProcess:
    return subprocess.run(mechfmu_command() + [str(a) for a in args], cwd=REPO_ROOT, capture_output=True,
                          text=True, timeout=timeout)


def test_cli_end_to_end(tmp_path):
    out, png = tmp_path / "crane.csv", tmp_path / "crane.png"
    p = mechfmu(fmu_path("Crane"), "--param", "l=-1,3,6,9", "--input-schedule", "x_ddot=step(1,0.2)",
                "--param", "x_ddot.scale=1,2", "--summary", "max_abs(phi)", "--workers", "2",
                "--stop-time", "10", "--out", out, "--plot", png)
    assert p.returncode == 0, p.stderr
    # not a terminal: no bar, a plain closing line with the rate
    assert "\r" not in p.stderr
    assert "8 cases" in p.stderr and "cases/s" in p.stderr and "ok 6" in p.stderr and "error 2" in p.stderr
    rows = table_rows(read_results(out))
    assert [(r["l"], r["x_ddot.scale"]) for r in rows] == [(l, s) for l in (-1, 3, 6, 9) for s in (1, 2)]
    assert [r["status"] for r in rows] == ["error"] * 2 + ["ok"] * 6
    ok = [r for r in rows if r["status"] == "ok"]
    assert all(r["max_abs(phi)"] > 0 for r in ok)
    header = out.read_text().splitlines()[0]
    assert header.startswith('"case","l","x_ddot.scale","status","message","final(x)"')
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 10_000


@pytest.mark.parametrize(
    "args, message",
    [
        (["--param", "l=2:10"], "a grid is start:stop:count"),
        (["--param", "l=uniform(3,1)"], "uniform(a,b) needs a < b"),
        (["--param", "l=2", "--out", "r.xlsx"], ".parquet or .csv"),
        (["--param", "l=2", "--input-schedule", "x_ddot=sine(1)"], "unknown shape `sine`"),
        (["--param", "ll=2,3"], "Crane has no variable `ll` (did you mean l?)"),
        (["--param", "T=2,3"], "`T` cannot be set"),
        (["--param", "l=2", "--summary", "max(phi_dott)"], "no variable `phi_dott`"),
        (["--param", "x_ddot.value=1"], "has no variable `x_ddot.value`"),
        # checked by the Rust side before it passed its arguments through: now by Python
        (["--param", "l=2", "--summary", "avg(x)"], "unknown function `avg`"),
        (["--param", "l=2", "--scheduler", "localhost"], "[tcp://]HOST:PORT"),
        (["--param", "l=2", "--stop-time", "inf"], "--stop-time inf: not a number"),
        (["--param", "l=2", "--plot", "p.txt"], "give a .png file"),
    ],
)
def test_cli_names_the_problem(args, message):
    p = mechfmu(fmu_path("Crane"), *args, "--no-progress")
    assert p.returncode != 0
    assert message in p.stderr, p.stderr
    assert "the sweep was not started" in p.stderr and "Traceback" not in p.stderr, p.stderr


def test_cli_missing_fmu():
    p = mechfmu("fmus/NoSuch.fmu", "--param", "l=2")
    assert p.returncode != 0 and "no FMU at fmus/NoSuch.fmu" in p.stderr, p.stderr


# =======================================================================================
# The pieces


def test_specs():
    assert parse_spec("l", "2:10:17").values == tuple(np.linspace(2, 10, 17))
    assert parse_spec("l", "2,3,5").values == (2.0, 3.0, 5.0)
    assert parse_spec("l", "-1").values == (-1.0,)
    assert parse_spec("m", "uniform(800, 1200)").random == ("uniform", 800.0, 1200.0)
    for bad, why in [("2:10", "start:stop:count"), ("2:10:0", "n >= 1"), ("normal(0,0)", "sigma > 0"),
                     ("beta(1,2)", "unknown distribution"), ("2,,3", "not a number"), ("", "empty")]:
        with pytest.raises(SpecError, match=why):
            parse_spec("l", bad)


# The request's grammar has one implementation, python/mechfmu_sweep (design.py, runner.py,
# cli.py); `mechfmu sweep` passes its arguments through. These cases (specs, parameters,
# schedules, summaries, files and addresses) are accepted, or refused with a message
# containing the text given.

SPECS_ACCEPTED = ["5", "-1", "2:10:17", "2,3,5", "-1,2", "uniform(800,1200)", "normal(0, 0.1)", "1e3:2e3:3", "3:3:1"]
SPECS_REFUSED = [
    ("", "empty"),
    ("2:10", "start:stop:count"),
    ("2:10:0", "start:stop:count"),
    ("2:10:1.5", "start:stop:count"),
    ("2:10:1", "1 point"),
    ("uniform(2,1)", "a < b"),
    ("normal(0,-1)", "sigma > 0"),
    ("gauss(0,1)", "unknown distribution"),
    ("uniform(1)", "2 arguments"),
    ("2,x", "`x` is not a number"),
    ("inf", "not a number"),
]


def refused(parse, text) -> str:
    with pytest.raises(SpecError) as info:
        parse(text)
    return str(info.value)


@pytest.mark.parametrize("spec", SPECS_ACCEPTED)
def test_spec_grammar_accepts(spec):
    parse_spec("l", spec)


@pytest.mark.parametrize("spec, why", SPECS_REFUSED)
def test_spec_grammar_names_the_problem(spec, why):
    message = refused(lambda t: parse_spec("l", t), spec)
    assert why in message, f"{spec!r}: {message}"


def test_param_schedule_and_summary_grammar():
    assert parse_param("l=2:10:17").values == tuple(np.linspace(2, 10, 17))
    assert parse_param("x_ddot.value=0.1,1").name == "x_ddot.value"
    for bad in ["=3", "l"]:
        assert "NAME=SPEC" in refused(parse_param, bad), bad
    for ok in ["x_ddot=bangbang(t0=1,width=2,value=0.5)", "x_ddot=step(1, 0.5)", "x_ddot=step()"]:
        parse_schedule(ok)
    for bad, why in [("x_ddot=sine(1)", "unknown shape"), ("x_ddot=step(t0=1,amp=2)", "no argument `amp`"),
                     ("x_ddot=step(t0=1,2)", "positional"), ("x_ddot=step(1,2,3)", "at most 2")]:
        message = refused(parse_schedule, bad)
        assert why in message, f"{bad}: {message}"
    for ok in ["max_abs(phi)", "max|phi|", "max(T)", "min(x)", "rms(x)"]:
        parse_summary(ok)
    assert "unknown function" in refused(parse_summary, "avg(x)")
    assert "FUNC(variable)" in refused(parse_summary, "phi")


def test_files_and_addresses():
    sweep_cli.check_out(Path("r.parquet"))
    sweep_cli.check_out(Path("r.CSV"))
    assert ".parquet or .csv" in refused(sweep_cli.check_out, Path("r.xlsx"))
    refused(sweep_cli.check_plot, Path("p.txt"))
    sweep_cli.check_scheduler("tcp://127.0.0.1:8786")
    sweep_cli.check_scheduler("localhost:8786")
    refused(sweep_cli.check_scheduler, "localhost")


def test_the_numbers_of_the_request_are_checked_before_the_fmu_is_read():
    """What clap's value parsers of the Rust side refused (a non-finite time, a step or a
    tolerance <= 0) is refused here, before the FMU is even looked at."""
    parser = sweep_cli.make_parser()
    for extra, why in [(["--start-time", "nan"], "--start-time nan: not a number"),
                       (["--stop-time", "inf"], "--stop-time inf: not a number"),
                       (["--output-interval", "0"], "--output-interval 0.0: must be a finite number > 0"),
                       (["--tolerance=-1e-6"], "--tolerance -1e-06: must be a finite number > 0"),
                       (["--tolerance", "inf"], "must be a finite number > 0"),
                       (["--workers", "0"], "--workers must be >= 1"),
                       (["--seed", "-1"], "--seed -1: must be an integer from 0")]:
        args = parser.parse_args(["no/such.fmu", "--param", "l=2", *extra])
        message = refused(sweep_cli.Plan, args)
        assert why in message, f"{extra}: {message}"


def test_design_full_factorial_and_seeded_draws():
    specs = [parse_spec("a", "1,2,3"), parse_spec("m", "uniform(800,1200)"), parse_spec("b", "10,20")]
    d1 = build_design(specs, cases=4, seed=7)
    d2 = build_design(specs, cases=4, seed=7)
    assert len(d1) == 3 * 2 * 4
    assert np.array_equal(d1.values, d2.values)
    a, m, b = d1.values.T
    assert list(a) == [1] * 8 + [2] * 8 + [3] * 8  # the first --param varies slowest
    assert list(b[:8]) == [10] * 4 + [20] * 4
    assert len(set(m)) == 24 and np.all((800 <= m) & (m <= 1200))
    assert not np.array_equal(build_design(specs, cases=4, seed=8).values, d1.values)
    with pytest.raises(SpecError, match="no --param is random"):
        build_design([parse_spec("a", "1,2")], cases=5, seed=None)


def test_schedules_and_merged_inputs():
    s = parse_schedule("x_ddot=bangbang(t0=1,width=2,value=0.5)")
    t, v = s.table({"value": 2.0, "scale": 0.5})
    assert list(t) == [0, 1, 1, 3, 3, 5, 5] and list(v) == [0, 0, 1, 1, -1, -1, 0]
    assert parse_schedule("u=step(2, 3)").args == {"t0": 2.0, "value": 3.0}
    with pytest.raises(SpecError, match="width must be > 0"):
        parse_schedule("u=pulse(width=0)")
    merged = input_table({"u": (np.array([0.0, 1, 1]), np.array([0.0, 0, 1])),
                          "w": (np.array([0.0, 2]), np.array([0.0, 4]))})
    assert merged.tolist() == [(0, 0, 0), (1, 0, 2), (1, 1, 2), (2, 1, 4)]


def test_summaries():
    assert parse_summary("max|phi|") == Summary("max_abs", "phi")
    assert parse_summary("max_abs(phi)").column == "max_abs(phi)"
    with pytest.raises(SpecError, match="unknown function"):
        parse_summary("avg(x)")


def test_csv_input_and_its_scale_match_simulate_fmu(tmp_path):
    """--input FILE.csv for every case, NAME.scale per case: the same as simulate_fmu."""
    csv = tmp_path / "drive.csv"
    csv.write_text("time,x_ddot,theta_ddot\n0,0,0\n1,0,0\n1,0.4,0.01\n2.5,0.4,0.01\n2.5,-0.4,-0.01\n4,-0.4,-0.01\n4,0,0\n")
    path = fmu_path("Crane")
    args = sweep_cli.make_parser().parse_args(
        [str(path), "--param", "l=3,7", "--param", "x_ddot.scale=0.5,1", "--input", str(csv),
         "--stop-time", "6", "--output-interval", "0.05", "--summary", "max_abs(phi)", "--summary", "mean(phi)"])
    plan = sweep_cli.Plan(args)
    rt = Runtime(path, plan.setup)
    try:
        rows = rt.run([(i, plan.design.values[i]) for i in range(len(plan.design))])
    finally:
        rt.close()
    table = fmpy.util.read_csv(str(csv))
    for r, (l, scale) in zip(rows, plan.design.values):
        assert r["status"] == "ok", r
        signals = table.copy()
        signals["x_ddot"] *= scale
        res = fmpy.simulate_fmu(str(path), start_values={"l": l}, input=signals, stop_time=6, output_interval=0.05)
        want = reference_summaries(res)
        for col in ["max_abs(phi)", "mean(phi)", "final(x)", "final(theta)", "final(phi)", "final(W_drives)"]:
            assert r[col] == pytest.approx(want[col], rel=1e-12, abs=1e-12), col


def test_runtime_reuses_one_instance_after_failures():
    """fmi2Reset after a failed initialization; a fresh instance only when reset fails."""
    path = fmu_path("Crane")
    setup = CaseSetup(columns=["l"], start_columns={"l": "l"}, schedules={}, schedule_args={}, base_input=None,
                      base_scales={}, start_time=0.0, stop_time=2.0, tolerance=1e-6, output_interval=0.01,
                      summaries=[Summary("final", "phi"), Summary("max", "T")])
    rt = Runtime(path, setup)
    try:
        rows = rt.run([(0, [5.0]), (1, [-1.0]), (2, [0.0]), (3, [5.0])])
        assert [r["status"] for r in rows] == ["ok", "error", "error", "ok"]
        assert rows[0]["max(T)"] == rows[3]["max(T)"] == pytest.approx(9810.0)
        assert "l = 0" in rows[2]["message"]
        assert len(rt._instances) == 1
    finally:
        rt.close()


def test_the_suite_logger_works_after_an_in_process_runtime(slave):
    setup = CaseSetup(columns=["l"], start_columns={"l": "l"}, schedules={}, schedule_args={}, base_input=None,
                      base_scales={}, start_time=0.0, stop_time=1.0, tolerance=1e-6, output_interval=0.1,
                      summaries=[Summary("final", "phi")])
    rt = Runtime(fmu_path("Crane"), setup)
    try:
        assert "l = -2" in rt.run([(0, [-2.0])])[0]["message"]
    finally:
        rt.close()
    fmulog.repoint()  # what the autouse fixture does after each test
    s = slave("Crane")
    s.setup()
    s.set(l=-3.0)
    s.call("fmi2EnterInitializationMode")
    s.call("fmi2ExitInitializationMode")
    assert s.log.find(r"l = -3"), s.log.text()


def test_a_discarded_step_is_a_failed_case_and_the_next_case_runs():
    """The trolley driven into the pivot (x = 1 - 1.05 t): fmi2DoStep returns fmi2Discard
    with the FMU's reason; the instance is reset and the next case completes."""
    args = sweep_cli.make_parser().parse_args(
        [str(fmu_path("Crane")), "--param", "x_dot=-1.05,0", "--param", "x=1", "--stop-time", "2",
         "--output-interval", "0.1"])
    plan = sweep_cli.Plan(args)
    rt = Runtime(fmu_path("Crane"), plan.setup)
    try:
        rows = rt.run([(i, plan.design.values[i]) for i in range(len(plan.design))] * 2)
    finally:
        rt.close()
    assert [r["status"] for r in rows] == ["discard", "ok"] * 2
    assert "trolley reached the pivot" in rows[0]["message"], rows[0]["message"]
    assert "fmi2DoStep discarded the step from t = 0.9" in rows[0]["message"]
    assert rows[1]["final(x)"] == rows[3]["final(x)"] == 1.0


# =======================================================================================
# A system compiled into one FMU sweeps like any FMU: its variables are `component.variable`


@pytest.mark.parametrize("engine", ["native", "fmpy"])
def test_a_system_fmu_sweeps_by_its_components_variables(engine, tmp_path):
    """`spring.k` of TwoOscillators.fmu, on the command line (the native engine) and through
    the Python package (the FMPy engine): each case's summary is FMPy's own run at that value."""
    out = tmp_path / "two.csv"
    args = [fmu_path("TwoOscillators"), "--param", "spring.k=0.5,1,2", "--param", "b.m=1,3",
            "--summary", "max_abs(b.x)", "--summary", "final(a.x)", "--stop-time", "10", "--engine", engine,
            "--workers", "1", "--out", out, "--no-progress"]
    if engine == "native":
        p = mechfmu(*args)
        assert p.returncode == 0, p.stderr
    else:
        assert run_sweep(args) == 0
    rows = table_rows(read_results(out))
    assert [(r["spring.k"], r["b.m"]) for r in rows] == [(k, m) for k in (0.5, 1.0, 2.0) for m in (1.0, 3.0)]
    for r in rows:
        assert r["status"] == "ok", r
        res = fmpy.simulate_fmu(str(fmu_path("TwoOscillators")), stop_time=10.0,
                                start_values={"spring.k": r["spring.k"], "b.m": r["b.m"]}, output=["a.x", "b.x"])
        assert math.isclose(r["max_abs(b.x)"], float(np.max(np.abs(res["b.x"]))), rel_tol=1e-9), r
        assert math.isclose(r["final(a.x)"], float(res["a.x"][-1]), rel_tol=1e-9, abs_tol=1e-12), r
