"""Throughput of a sweep and the cost of Dask per case.

    target/venv/bin/python -m mechfmu_sweep.bench fmus/Crane.fmu \\
        [--cases 200] [--workers 1,2] [--param l=2:10:200] [--input-schedule ...] [--repeat 3]

Runs the same cases (default: the FMU's DefaultExperiment with `l`, or else the first
Real parameter, swept over --cases values from half to 1.5 times its default) three ways
and prints a Markdown table:

* a plain loop in this process: one FMU2Slave, fmi2Reset between cases (the floor);
* Dask: a LocalCluster of 1, 2, ... single-threaded worker processes, default chunks;
* Dask: 1 worker, one case per task (the scheduler's cost per task, unshared).

For each: wall time and cases/s (without the cluster's start, reported apart), and the CPU
time per case summed over every process involved (this one, which holds the client and a
LocalCluster's scheduler, and the worker processes), from psutil. On a machine others are
using too, wall times say how much CPU the sweep was given; CPU times do not depend on it,
and their difference from the plain loop is what Dask costs per case.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
from pathlib import Path

from .cli import Plan, make_parser
from .engine import run_on_dask
from .runner import Runtime


def _plan(fmu: Path, params: list[str], schedules: list[str], cases: int) -> Plan:
    from fmpy import read_model_description

    if not params:
        md = read_model_description(str(fmu), validate=False)
        names = [v.name for v in md.modelVariables if v.causality == "parameter" and v.type == "Real"]
        name = "l" if "l" in names else names[0]
        start = next(float(v.start) for v in md.modelVariables if v.name == name)
        params = [f"{name}={start * 0.5}:{start * 1.5}:{cases}"]
    argv = [str(fmu)] + [x for p in params for x in ("--param", p)]
    argv += [x for s in schedules for x in ("--input-schedule", s)]
    return Plan(make_parser().parse_args(argv))


def tree_cpu() -> float:
    """User + system CPU seconds of this process and all its descendants, alive now."""
    import psutil

    me = psutil.Process()
    total = 0.0
    for p in [me, *me.children(recursive=True)]:
        try:
            t = p.cpu_times()
            total += t.user + t.system
        except psutil.Error:
            pass
    return total


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python -m mechfmu_sweep.bench", description=__doc__.split("\n\n")[0])
    p.add_argument("fmu", type=Path)
    p.add_argument("--cases", type=int, default=200)
    p.add_argument("--workers", default="1,2", help="comma-separated worker counts")
    p.add_argument("--param", action="append", default=[])
    p.add_argument("--input-schedule", action="append", default=[])
    p.add_argument("--repeat", type=int, default=1, help="runs of each; the fastest is kept")
    a = p.parse_args(argv)
    plan = _plan(a.fmu, a.param, a.input_schedule, a.cases)
    n = len(plan.design)
    fmu_bytes = a.fmu.read_bytes()
    cases = [(i, list(plan.design.values[i])) for i in range(n)]
    print(f"{plan.model}: {n} cases ({', '.join(s.name + '=' + s.text for s in plan.specs)}), "
          f"t = {plan.setup.start_time:g}..{plan.setup.stop_time:g} s every {plan.setup.output_interval:g} s, "
          f"tolerance {plan.setup.tolerance}; {os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f}",
          file=sys.stderr)

    rows = []  # (name, cases per task, wall s, cpu s, cluster start+stop s)
    rt = Runtime(fmu_bytes, plan.setup)
    try:
        rt.run(cases[:2])  # instantiate, warm up
        best = None
        for _ in range(a.repeat):
            w0, c0 = time.perf_counter(), time.process_time()
            rt.run(cases)
            m = (time.perf_counter() - w0, time.process_time() - c0)
            best = m if best is None or m[0] < best[0] else best
    finally:
        rt.close()
    plain_wall, plain_cpu = best
    rows.append(("plain loop: FMU2Slave + reset, this process", "-", plain_wall, plain_cpu, None))

    def dask(workers: int, chunk: int | None):
        best = None
        for _ in range(a.repeat):
            marks: dict[str, float] = {}
            t0 = time.perf_counter()
            run = run_on_dask(fmu_bytes, plan.setup, plan.design, workers=workers, chunk_size=chunk,
                              progress=False, probe=lambda phase: marks.__setitem__(phase, tree_cpu()))
            total = time.perf_counter() - t0
            bad = [r for r in run.rows if r["status"] not in ("ok", "warning")]
            assert not bad, bad[:2]
            m = (run.wall_s, marks["end"] - marks["start"], total - run.wall_s, run.chunk_size)
            best = m if best is None or m[0] < best[0] else best
        return best

    for w in [int(x) for x in a.workers.split(",")]:
        wall, cpu, start, cs = dask(w, None)
        rows.append((f"Dask LocalCluster, {w} worker{'s' if w > 1 else ''}", str(cs), wall, cpu, start))
    wall, cpu, start, _ = dask(1, 1)
    rows.append(("Dask LocalCluster, 1 worker, 1 case per task", "1", wall, cpu, start))

    print("\n| run | cases per task | wall (s) | cases/s | wall ms/case | CPU ms/case (all processes) "
          "| Dask's CPU ms/case | cluster start + stop (s) |")
    print("|---|---|---|---|---|---|---|---|")
    for name, cs, wall, cpu, start in rows:
        extra = "-" if start is None else f"{1e3 * (cpu - plain_cpu) / n:.2f}"
        print(f"| {name} | {cs} | {wall:.2f} | {n / wall:.0f} | {1e3 * wall / n:.2f} | {1e3 * cpu / n:.2f} "
              f"| {extra} | {'-' if start is None else f'{start:.1f}'} |")
    print(f"\nload average after: {os.getloadavg()[0]:.1f} (on {os.cpu_count()} cores)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
