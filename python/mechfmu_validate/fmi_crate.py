"""The third importer: the Rust ``fmi`` crate (rust-fmi), through ``mechfmu-fmi-run`` (built
from ``tools/fmi-run``), in Co-Simulation and in Model Exchange (its own RK4), on an FMI 2.0
or an FMI 3.0 FMU.

The runner is a separate executable, found through the environment variable
``MECHFMU_FMI_RUN`` (``mechfmu validate`` builds it and sets it); it reads the experiment as
JSON and writes its result as CSV. It takes the tolerance (and the stop time) like FMPy, so
it is compared with FMPy at the case's own settings.

An FMI 3.0 FMU's experiment names its array elements as FMI 3.0 writes them (``q[2]``): the
case's FMI 2.0 names are translated with the mechanism's :class:`~.arrays.ArrayMap`, and the
result's columns back.
"""

from __future__ import annotations

import csv
import json
import os
import signal
import subprocess
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from . import progress
from .case import Case, Result
from .importers import NotSupported, input_events_on_grid, input_values

if TYPE_CHECKING:  # pragma: no cover
    from .arrays import ArrayMap
    from .importers import Fmu

__all__ = ["FMI_CRATE_NOTE", "FMI_RUN_ENV", "fmi_crate_available", "run_fmi_crate", "signal_name"]

FMI_CRATE_NOTE = "the fmi crate (rust-fmi) through mechfmu-fmi-run: compared with FMPy at the case's tolerance"

#: the environment variable naming the mechfmu-fmi-run executable
FMI_RUN_ENV = "MECHFMU_FMI_RUN"

#: how the runner says the crate could not import the FMU
CANNOT_IMPORT = "mechfmu-fmi-run: cannot import "


def signal_name(number: int) -> str:
    """``SIGSEGV (signal 11)``."""
    try:
        return f"{signal.Signals(number).name} (signal {number})"
    except ValueError:
        return f"signal {number}"


def _run_beating(command: list[str]) -> subprocess.CompletedProcess:
    """``command`` run to its end, with a :func:`.progress.beat` every second it runs (a long
    run is not a hung one)."""
    with subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) as proc:
        while True:
            try:
                stdout, stderr = proc.communicate(timeout=1.0)
                return subprocess.CompletedProcess(command, proc.returncode, stdout, stderr)
            except subprocess.TimeoutExpired:
                progress.beat()


def fmi_crate_available() -> tuple[bool, str]:
    """(True, path) when ``$MECHFMU_FMI_RUN`` names an executable file, else (False, why)."""
    path = os.environ.get(FMI_RUN_ENV)
    if not path:
        return False, (f"{FMI_RUN_ENV} is not set (`mechfmu validate` builds mechfmu-fmi-run from tools/fmi-run "
                       "and sets it; see the message above the table if that build failed)")
    if not (os.path.isfile(path) and os.access(path, os.X_OK)):
        return False, f"{FMI_RUN_ENV}={path} is not an executable file"
    return True, path


def run_fmi_crate(fmu: Fmu, case: Case, relative_tolerance: float | None | str = "case", interface: str = "cs",
                  step: float | None = None, mapping: ArrayMap | None = None) -> Result:
    """The case under the Rust ``fmi`` crate: ``mechfmu-fmi-run`` runs a fixed-step experiment
    with the case's output interval, start values and stop time, the tolerance
    (``"case"``: the case's; ``None``: none), the inputs FMPy applies set before every step,
    and records the case's variables. Raises with the runner's message when it fails.

    ``interface="me"``: Model Exchange, the runner integrating with its own RK4 at ``step``
    (a divisor of the output interval, run as ``--substeps``; default: the output interval).
    Raises :class:`~.importers.NotSupported` when the runner does not accept ``--interface``.

    ``mapping``: the FMU is the FMI 3.0 one of a mechanism, whose case names FMI 2.0
    variables: they are translated to FMI 3.0 array elements (an element at several places of
    its array set at each), and the result's columns back to the case's names."""
    ok, found = fmi_crate_available()
    if not ok:
        raise RuntimeError(f"the fmi-crate importer is not available: {found}")
    rtol = case.relative_tolerance if relative_tolerance == "case" else relative_tolerance
    if not input_events_on_grid(case):
        raise RuntimeError("an input jump is off the communication grid: a fixed-step master cannot follow it")
    n, h = case.steps(), case.output_interval
    substeps = 1 if step is None else round(h / step)
    if abs(substeps * (step or h) - h) > 1e-9 * h:
        raise ValueError(f"the step {step} does not divide the output interval {h}")
    names_of = mapping if mapping is not None else fmu
    input_names, _ = input_values(case, names_of, 0.0)
    rows = [input_values(case, names_of, k * h)[1] for k in range(n + 1)] if input_names else []
    names = case.recorded()
    start_values = {k: float(v) for k, v in case.start_values.items()}
    inputs, record = input_names, names
    if mapping is not None:
        start_values = mapping.fmi3_elements(start_values)
        # each input's every place is a column of its own
        places = [mapping.element_names_of(name) for name in input_names]
        inputs = [e for p in places for e in p]
        rows = [[v for p, v in zip(places, row) for _ in p] for row in rows]
        record = [mapping.element_names_of(name)[0] for name in names]
    experiment = dict(fmu=str(fmu.path), relative_tolerance=rtol, stop_time=float(case.stop_time), step_size=h,
                      steps=n, start_values=start_values, inputs=inputs, input_values=rows, record=record)
    options = [] if interface == "cs" else ["--interface", interface]
    if substeps > 1:
        options += ["--substeps", str(substeps)]
    with tempfile.TemporaryDirectory(prefix="mechfmu-fmi-run-") as tmp:
        spec, out = Path(tmp) / "experiment.json", Path(tmp) / "result.csv"
        spec.write_text(json.dumps(experiment, allow_nan=False))
        proc = _run_beating([found, str(spec), "--out", str(out), *options])
        log = [line for line in proc.stderr.splitlines() if line.strip()]
        if options and proc.returncode == 2 and log and log[-1].startswith("usage:"):
            raise NotSupported(f"mechfmu-fmi-run does not accept {' '.join(options)} ({log[-1]})")
        if proc.returncode < 0:
            raise RuntimeError(f"mechfmu-fmi-run died of {signal_name(-proc.returncode)} running the FMU"
                               + (f"; its last words: {' | '.join(log[-5:])}" if log else ""))
        if proc.returncode != 0:
            problem = next((line for line in reversed(log) if line.startswith("mechfmu-fmi-run:")),
                           log[-1] if log else f"exit status {proc.returncode}")
            fmu_log = [line for line in log if line.startswith("[FMU")][-5:]
            if problem.endswith("(not supported)"):  # what the runner does not do (not the FMU's fault)
                raise NotSupported(problem)
            if problem.startswith(CANNOT_IMPORT) and not fmu.by_mechfmu:  # the crate's reading, stricter than
                # the standard: another exporter's legal FMU it refuses is its limit (mechfmu's must be read)
                why = problem.removeprefix(CANNOT_IMPORT).removeprefix(f"{fmu.path}: ")
                raise NotSupported(f"cannot read {fmu.path.name} ({why}): the crate's limit, stricter than the "
                                   "standard (the checks hold the model description to the standard)")
            raise RuntimeError(problem + ("; FMU log: " + " | ".join(fmu_log) if fmu_log else ""))
        with out.open(newline="") as f:
            table = list(csv.reader(f))
    if not table or table[0] != ["time", *record]:
        raise RuntimeError(f"mechfmu-fmi-run wrote the columns {table[0] if table else []}, "
                           f"expected {['time', *record]}")
    if len(table) != n + 2:
        raise RuntimeError(f"mechfmu-fmi-run wrote {len(table) - 1} rows, expected {n + 1}")
    data = np.array([[float(x) for x in row] for row in table[1:]], dtype=float)
    columns = {"time": data[:, 0], **{name: data[:, i + 1] for i, name in enumerate(names)}}
    return Result(columns, log)
