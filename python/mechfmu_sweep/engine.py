"""Running a design on Dask distributed: a LocalCluster of one single-threaded worker
process per core, or an existing cluster given by its scheduler address.

The cases go out in chunks, a bounded number of them in flight at a time, and their rows come
back to ``on_rows`` in case order as soon as every earlier case is done: a sweep of any size
holds a few chunks of rows in memory, never the whole result."""

from __future__ import annotations

import logging
import math
import os
import sys
import tempfile
import time
import uuid
import zipfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Callable

import numpy as np

from .design import Design
from .runner import CaseSetup
from .tasks import SweepPlugin, rows_of, run_chunk

PACKAGE_DIR = Path(__file__).resolve().parent


@dataclass
class SweepRun:
    rows: list[dict[str, Any]]  # every row, when no ``on_rows`` took them
    wall_s: float
    workers: int
    chunk_size: int
    address: str
    errors: list[str] = field(default_factory=list)  # machinery problems (not failed cases)
    shipped_package: bool = False  # the workers lacked mechfmu_sweep: it was uploaded
    engine: str = "fmpy"


def default_workers() -> int:
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


# The most cases a task takes: enough that the scheduler's few milliseconds per task are a
# small part of it (16 FMPy cases take ~50 ms; 512 native ones, ~100 ms).
MAX_CHUNK = {"fmpy": 16, "native": 512}


def default_chunk_size(n_cases: int, n_workers: int, engine: str = "fmpy") -> int:
    """Cases per Dask task: about 8 tasks per worker (load balance, a live progress bar)
    but at most ``MAX_CHUNK`` cases each, so the scheduler's per-task cost is shared."""
    return max(1, min(MAX_CHUNK[engine], -(-n_cases // (8 * max(1, n_workers)))))


class InOrder:
    """Hands chunks of rows to ``sink`` in case order, holding those that finish early."""

    def __init__(self, sink: Callable[[list[dict[str, Any]]], None]):
        self.sink = sink
        self.next = 0  # the first case not handed on yet
        self.waiting: dict[int, list[dict[str, Any]]] = {}  # first case of a chunk -> its rows

    def add(self, first: int, rows: list[dict[str, Any]]) -> None:
        self.waiting[first] = rows
        while self.next in self.waiting:
            rows = self.waiting.pop(self.next)
            self.next += len(rows)
            self.sink(rows)


def _package_zip() -> str:
    """This package as a zip, for workers of an external cluster that lack it."""
    fd, path = tempfile.mkstemp(prefix="mechfmu_sweep-", suffix=".zip")
    with os.fdopen(fd, "wb") as f, zipfile.ZipFile(f, "w") as z:
        for p in sorted(PACKAGE_DIR.glob("*.py")):
            z.write(p, f"mechfmu_sweep/{p.name}")
    return path


# Run on the workers through the builtin eval: a function of this package could not be
# unpickled by a worker that lacks the package, which is what this asks.
_HAS_PACKAGE = "__import__('importlib.util').util.find_spec('mechfmu_sweep') is not None"


class Progress:
    """A tqdm bar with the rate in cases/s on a terminal; plain lines otherwise."""

    def __init__(self, total: int, enabled: bool = True, stream=None):
        self.total, self.done, self.failed = total, 0, 0
        self.stream = stream or sys.stderr
        self.start = time.perf_counter()
        self.last_line = self.start
        self.bar = None
        self.enabled = enabled
        if enabled and hasattr(self.stream, "isatty") and self.stream.isatty():
            from tqdm import tqdm

            self.bar = tqdm(total=total, unit="case", file=self.stream, dynamic_ncols=True,
                            smoothing=0.1, desc="sweep")

    def update(self, n: int, failed: int) -> None:
        self.done += n
        self.failed += failed
        if self.bar is not None:
            self.bar.update(n)
            if self.failed:
                self.bar.set_postfix(failed=self.failed, refresh=False)
        elif self.enabled:
            now = time.perf_counter()
            if now - self.last_line >= 10.0 and self.done < self.total:
                self.last_line = now
                self._line(now)

    def _line(self, now: float) -> None:
        rate = self.done / max(now - self.start, 1e-9)
        print(f"sweep: {self.done}/{self.total} cases, {rate:.1f} cases/s, {self.failed} failed",
              file=self.stream, flush=True)

    def close(self) -> None:
        if self.bar is not None:
            self.bar.close()


def _local_cluster(n: int):
    from distributed import LocalCluster

    return LocalCluster(
        n_workers=n,
        threads_per_worker=1,
        processes=True,
        host="127.0.0.1",
        scheduler_port=0,
        # no dashboard; the scheduler's HTTP routes on a free loopback port, not 8787
        dashboard_address="127.0.0.1:0",
        scheduler_kwargs={"dashboard": False},
        silence_logs=logging.ERROR,
    )


def _connect(client, cluster) -> tuple[Any, int]:
    """The client (of ``cluster`` when none is given) once a worker is up, and the number of
    workers."""
    from distributed import Client

    if client is None:
        client = Client(cluster)
    n_workers = len(client.scheduler_info().get("workers", {}))
    if n_workers == 0:
        client.wait_for_workers(1, timeout=60)
        n_workers = len(client.scheduler_info().get("workers", {}))
    return client, n_workers


def _ship_package(client) -> bool:
    """Uploads this package to the workers of an external cluster that lack it; whether it did."""
    if all(client.run(eval, _HAS_PACKAGE).values()):
        return False
    path = _package_zip()
    try:
        client.upload_file(path)
    finally:
        os.unlink(path)
    return True


def _run_chunks(client, plugin_name: str, design: Design, chunk_size: int, n_workers: int, in_order: InOrder,
                bar: Progress) -> list[str]:
    """Submits the design's cases in chunks, a window of them in flight, and hands their rows
    to ``in_order`` as they finish; the machinery's errors (a chunk whose task died fails its
    cases as ``crashed``)."""
    from distributed import as_completed

    errors: list[str] = []
    starts = iter(range(0, len(design), chunk_size))
    chunk_of: dict[str, tuple[int, int]] = {}  # task key -> (first case, number of cases)

    def submit(first: int):
        values = np.ascontiguousarray(design.values[first:first + chunk_size], dtype=float)
        key = f"{plugin_name}-chunk-{first}"
        chunk_of[key] = (first, len(values))
        return client.submit(run_chunk, plugin_name, first, values, pure=False, key=key)

    # enough chunks in flight to keep every worker busy, few enough that their cases and
    # rows stay a small part of memory however large the design (also when a slow chunk
    # holds back the ones after it)
    window = 4 * n_workers
    pending = as_completed(with_results=True, raise_errors=False)
    running = 0

    def fill() -> None:
        nonlocal running
        while running < window and len(in_order.waiting) < 4 * window:
            first = next(starts, None)
            if first is None:
                return
            pending.add(submit(first))
            running += 1

    fill()
    for future, result in pending:
        first, count = chunk_of.pop(future.key)
        if isinstance(result, BaseException) or future.status != "finished":
            # the task itself died (a worker killed by a crashing FMU, ...)
            exc = result if isinstance(result, BaseException) else future.exception()
            message = f"{type(exc).__name__}: {exc}"
            errors.append(message)
            result = [{"case": i, "status": "crashed", "message": message} for i in range(first, first + count)]
        else:
            result = rows_of(result)
        future.release()
        running -= 1
        in_order.add(first, result)
        fill()
        bar.update(len(result), sum(r["status"] not in ("ok", "warning") for r in result))
    return errors


def run_on_dask(
    fmu_bytes: bytes,
    setup: CaseSetup,
    design: Design,
    *,
    scheduler: str | None = None,
    workers: int | None = None,
    chunk_size: int | None = None,
    progress: bool = True,
    probe: Callable[[str], None] | None = None,
    engine: str = "fmpy",
    on_rows: Callable[[list[dict[str, Any]]], None] | None = None,
) -> SweepRun:
    """Runs every case of ``design``; failed cases come back as rows with their status, in
    case order, to ``on_rows`` (else in ``SweepRun.rows``)."""
    import dask
    from distributed import Client

    cluster = client = None
    if scheduler:
        client = Client(scheduler, timeout="30s")
    else:
        n = workers or default_workers()
        # The worker processes run this interpreter, which has the package installed
        # (python/pyproject.toml); multiprocessing's spawn also hands them this sys.path.
        # Queue every task on the workers at once: with the default (1.1 tasks per
        # thread) a worker idles for a round trip to the scheduler after each task, which
        # costs more than a case on a busy machine. Work stealing still balances the load.
        with dask.config.set({"distributed.scheduler.worker-saturation": math.inf}):
            cluster = _local_cluster(n)
    plugin_name = f"mechfmu-sweep-{uuid.uuid4().hex[:12]}"
    bar = None
    try:
        client, n_workers = _connect(client, cluster)
        shipped = _ship_package(client) if scheduler else False
        from .native import find_worker

        plugin = SweepPlugin(plugin_name, fmu_bytes, setup, engine, exe=find_worker())
        client.register_plugin(plugin, name=plugin_name)

        n = len(design)
        cs = chunk_size or default_chunk_size(n, n_workers, engine)
        collected: list[dict[str, Any]] = []
        bar = Progress(n, enabled=progress)
        if probe is not None:
            probe("start")  # measurements (bench.py): the cluster is up, nothing submitted
        t_submit = time.perf_counter()
        errors = _run_chunks(client, plugin_name, design, cs, n_workers, InOrder(on_rows or collected.extend), bar)
        bar.close()
        wall = time.perf_counter() - t_submit
        if probe is not None:
            probe("end")
        if scheduler:
            try:
                client.unregister_worker_plugin(plugin_name)  # frees instances, temp files
            except Exception as e:  # noqa: BLE001
                errors.append(f"could not remove the worker plugin: {e}")
        return SweepRun(rows=collected, wall_s=wall, workers=n_workers, chunk_size=cs,
                        address=client.scheduler.address, errors=errors, shipped_package=shipped, engine=engine)
    finally:
        if bar is not None:
            bar.close()
        if client is not None:
            client.close()
        if cluster is not None:
            cluster.close()
