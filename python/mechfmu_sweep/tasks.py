"""What each Dask worker of a sweep runs: the plugin that holds the engine's runtime for the
sweep (:class:`~.runner.Runtime` or :class:`~.native.NativeRuntime`), and the task that runs a
chunk of cases on it. :mod:`.engine` submits them."""

from __future__ import annotations

import pickle
from typing import Any

import numpy as np

from .native import NativeRuntime, find_worker
from .runner import CaseSetup, Runtime

try:  # distributed is only needed when running on Dask
    from distributed.diagnostics.plugin import WorkerPlugin
except Exception:  # pragma: no cover
    WorkerPlugin = object  # type: ignore[misc,assignment]


class SweepPlugin(WorkerPlugin):  # type: ignore[misc]
    """Installed on every worker of the sweep: extracts the FMU once (``setup``), for the
    FMPy engine (``Runtime``) or the native one (``NativeRuntime``), and frees the
    instances, the native runner and the extracted files when the sweep ends (``teardown``)."""

    def __init__(self, name: str, fmu_bytes: bytes, setup: CaseSetup, engine: str = "fmpy",
                 exe: str | None = None):
        self.name = name
        self.fmu_bytes = fmu_bytes
        self.case_setup = setup
        self.engine = engine
        self.exe = exe  # the client's `mechfmu`, for the native engine (workers may have their own)
        self.runtime = None

    def setup(self, worker=None):
        if self.engine == "native":
            exe = find_worker() or self.exe
            self.runtime = NativeRuntime(self.fmu_bytes, self.case_setup, exe=exe)
        else:
            self.runtime = Runtime(self.fmu_bytes, self.case_setup)

    def teardown(self, worker=None):
        if self.runtime is not None:
            self.runtime.close()
            self.runtime = None


def run_chunk(plugin_name: str, first: int, values: np.ndarray) -> bytes:
    """A Dask task: run cases ``first``, ``first + 1``, ... (their design values, one row
    each) on this worker's instance; their rows, pickled here (``rows_of`` unpickles them).
    Dask serializes lists and dicts element by element, which costs more per case than a
    case of the native engine: the cases travel as one array, their rows as one bytes."""
    from distributed import get_worker

    plugin = get_worker().plugins[plugin_name]
    if plugin.runtime is None:
        plugin.setup()
    cases = [(first + k, row.tolist()) for k, row in enumerate(values)]
    return pickle.dumps(plugin.runtime.run(cases), protocol=pickle.HIGHEST_PROTOCOL)


def rows_of(result: bytes) -> list[dict[str, Any]]:
    """The rows a ``run_chunk`` task returned."""
    return pickle.loads(result)
