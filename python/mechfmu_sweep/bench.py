"""What a sweep costs per case, engine by engine, and what Dask adds.

    target/venv/bin/python -m mechfmu_sweep.bench fmus/Crane.fmu fmus/Oscillator.fmu fmus/RigidBody.fmu \\
        [--cases 200] [--engines native,fmpy] [--workers 1,2] [--scaling 20000] [--memory 1000000]

(The native engine is `mechfmu sweep-worker` of the `mechfmu` named by ``MECHFMU_EXE``, by
default the checkout's ``target/release/mechfmu``.)

For each FMU, its DefaultExperiment (the Crane's: 1,000 communication steps), a parameter
swept over ``--cases`` values (``--dask-cases`` on Dask; ``l``, else the first Real
parameter, from half to 1.5 times its default):

* per engine, the cases run one after the other in this process and the worker it drives:
  cases per second per core (CPU time of every process involved), and the FMU's own
  stepping for the same work (the native runner's ``bare`` cases: fmi2Reset, the setup and
  fmi2DoStep alone, no sampling, no summaries);
* per engine, on a Dask LocalCluster of 1, 2, ... single-threaded workers: cases per second.

``--scaling N``: N cases of the first FMU on the native engine, 1 worker then 2 workers.
``--memory N``: N cases of the first FMU (``--memory-stop`` s each) streamed to a Parquet
file by the native engine on every core, with the peak memory (RSS) of all the processes
together.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import threading
import time
from pathlib import Path

from .cli import Plan, make_parser
from .engine import run_on_dask
from .native import EXE_ENV, NativeRuntime
from .results import ResultsWriter
from .runner import Runtime

CHECKOUT_EXE = Path(__file__).resolve().parents[2] / "target" / "release" / "mechfmu"


def _plan(fmu: Path, cases: int, extra: list[str] = ()) -> Plan:
    from fmpy import read_model_description

    md = read_model_description(str(fmu), validate=False)
    names = [v.name for v in md.modelVariables if v.causality == "parameter" and v.type == "Real"]
    name = "l" if "l" in names else names[0]
    start = next(float(v.start) for v in md.modelVariables if v.name == name)
    return Plan(make_parser().parse_args([str(fmu), "--param", f"{name}={start * 0.5}:{start * 1.5}:{cases}",
                                          *extra]))


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


def tree_rss() -> int:
    import psutil

    me = psutil.Process()
    total = 0
    for p in [me, *me.children(recursive=True)]:
        try:
            total += p.memory_info().rss
        except psutil.Error:
            pass
    return total


def in_process(engine: str, fmu: Path, plan: Plan, bare: bool = False, seconds: float = 2.0) -> float:
    """CPU seconds per case, every process included, the cases one after the other (the
    design repeated until ``seconds`` of CPU time: psutil's clock counts in 10 ms ticks)."""
    cases = [(i, list(plan.design.values[i])) for i in range(len(plan.design))]
    rt = NativeRuntime(fmu, plan.setup, bare=bare) if engine == "native" else Runtime(fmu, plan.setup)
    try:
        rt.run(cases[:2])  # instantiate, warm up
        c0, ran = tree_cpu(), 0
        while True:
            rows = rt.run(cases)
            ran += len(cases)
            cpu = tree_cpu() - c0
            if cpu >= seconds:
                break
    finally:
        rt.close()
    bad = [r for r in rows if r["status"] not in ("ok", "warning")]
    assert not bad, bad[:2]
    return cpu / ran


def on_dask(engine: str, fmu: Path, plan: Plan, workers: int) -> float:
    """Cases per second on a LocalCluster of ``workers`` (without the cluster's start)."""
    run = run_on_dask(fmu.read_bytes(), plan.setup, plan.design, workers=workers, progress=False,
                      engine=engine, on_rows=lambda rows: None)
    return len(plan.design) / run.wall_s


def memory(fmu: Path, n: int, stop: float) -> None:
    plan = _plan(fmu, n, ["--stop-time", str(stop)])
    peak = [0]
    done = threading.Event()

    def sample():
        while not done.wait(0.2):
            peak[0] = max(peak[0], tree_rss())

    sampler = threading.Thread(target=sample, daemon=True)
    sampler.start()
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "results.parquet"
        writer = ResultsWriter(plan.design, plan.setup.result_columns, {}, out)
        t0 = time.perf_counter()
        run = run_on_dask(fmu.read_bytes(), plan.setup, plan.design, progress=False, engine="native",
                          on_rows=writer.add)
        writer.close({})
        wall = time.perf_counter() - t0
        size = out.stat().st_size
    done.set()
    sampler.join()
    print(f"\n{plan.model}: {n} cases of {stop:g} s on {run.workers} workers, native engine, streamed to "
          f"Parquet ({size / 2**20:.0f} MiB): {wall:.0f} s ({n / run.wall_s:.0f} cases/s), peak RSS of all "
          f"processes {peak[0] / 2**30:.2f} GiB; failed {writer.n_failed}")


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python -m mechfmu_sweep.bench", description=__doc__.split("\n\n")[0])
    p.add_argument("fmus", type=Path, nargs="+")
    p.add_argument("--cases", type=int, default=200, help="the design of the in-process runs")
    p.add_argument("--dask-cases", type=int, default=4000, help="the design of the runs on Dask")
    p.add_argument("--engines", default="native,fmpy")
    p.add_argument("--workers", default="1,2", help="comma-separated worker counts")
    p.add_argument("--scaling", type=int, metavar="N", help="N native cases of the first FMU on 1, then 2 workers")
    p.add_argument("--memory", type=int, metavar="N", help="N native cases of the first FMU streamed to Parquet")
    p.add_argument("--memory-stop", type=float, default=2.0, metavar="T", help="their stop time (s)")
    a = p.parse_args(argv)
    if EXE_ENV not in os.environ and CHECKOUT_EXE.is_file():
        os.environ[EXE_ENV] = str(CHECKOUT_EXE)  # inherited by the cluster's workers
    engines = a.engines.split(",")
    workers = [int(x) for x in a.workers.split(",")]
    print(f"{os.cpu_count()} cores, load average {os.getloadavg()[0]:.1f}", file=sys.stderr)
    head = "| FMU | steps per case | engine | cases/s per core | CPU ms per case | FMU's own stepping ms per case | " \
           + " | ".join(f"Dask {w} worker{'s' if w > 1 else ''} cases/s" for w in workers) + " |"
    print(head)
    print("|" + "---|" * (6 + len(workers)))
    for fmu in a.fmus:
        plan, dask_plan = _plan(fmu, a.cases), _plan(fmu, a.dask_cases)
        steps = round((plan.setup.stop_time - plan.setup.start_time) / plan.setup.output_interval)
        own = in_process("native", fmu, plan, bare=True)
        for engine in engines:
            per_case = in_process(engine, fmu, plan)
            rates = [on_dask(engine, fmu, dask_plan, w) for w in workers]
            print(f"| {plan.model} | {steps} | {engine} | {1 / per_case:.0f} | {1e3 * per_case:.3f} | "
                  f"{1e3 * own:.3f} | " + " | ".join(f"{r:.0f}" for r in rates) + " |", flush=True)
    if a.scaling:
        plan = _plan(a.fmus[0], a.scaling)
        one, two = on_dask("native", a.fmus[0], plan, 1), on_dask("native", a.fmus[0], plan, 2)
        print(f"\n{plan.model}, {a.scaling} cases, native engine: 1 worker {one:.0f} cases/s, 2 workers {two:.0f} "
              f"cases/s: {two / one:.2f}x")
    if a.memory:
        memory(a.fmus[0], a.memory, a.memory_stop)
    print(f"\nload average after: {os.getloadavg()[0]:.1f} (on {os.cpu_count()} cores)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
