"""The Rust ``fmi`` crate (rust-fmi), through ``mechfmu-fmi-run`` (built from
``tools/fmi-run``), in Co-Simulation and in Model Exchange (its own RK4, held to its order:
:mod:`.model_exchange`), on an FMI 2.0 or an FMI 3.0 FMU; compared with FMPy's run of the
same FMU to :data:`FMI_CRATE_TOLERANCE`.

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
import subprocess
import tempfile
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any, Iterator

import numpy as np

from .. import progress
from ..fmulog import signal_name
from ..agreement import agreement
from ..case import Case, Result
from ..fmu import NotSupported
from ..importer import CS, FMI2, FMI3, ME, Availability, CaseRun, Curve, Importer, Runs, Words, row_name
from ..model_exchange import FixedStep, fixed_step_row, order_band
from ..rows import Row
from ..signals import input_events_on_grid, input_values
from ..target import Target

if TYPE_CHECKING:  # pragma: no cover
    from ..arrays import ArrayMap
    from ..fmu import Fmu

__all__ = ["IMPORTER", "NAME", "RK4", "FMI3_CRATE", "FMI3_RK4", "FMI_CRATE_NOTE", "FMI_CRATE_TOLERANCE", "FMI_RUN_ENV",
           "fmi_crate_available", "fmi_crate_row", "rk4", "run_crate3", "run_fmi_crate"]

#: the importer column of its FMI 2.0 Co-Simulation rows
NAME = "fmi crate"
RK4 = row_name(NAME, FMI2, ME, "RK4")
FMI3_CRATE = row_name(NAME, FMI3, CS)
FMI3_RK4 = row_name(NAME, FMI3, ME, "RK4")

#: the fmi crate must agree with FMPy to this, relative, both at the case's tolerance
FMI_CRATE_TOLERANCE = 1e-9

FMI_CRATE_NOTE = "the fmi crate (rust-fmi) through mechfmu-fmi-run: compared with FMPy at the case's tolerance"
#: the note of its FMI 3.0 Co-Simulation rows
FMI3_NOTE = ("the fmi crate's FMI 3.0 import (mechfmu-fmi-run) against FMPy's FMI 3.0 run, both at the case's "
             "tolerance")

#: the environment variable naming the mechfmu-fmi-run executable
FMI_RUN_ENV = "MECHFMU_FMI_RUN"

#: how the runner says the crate could not import the FMU
CANNOT_IMPORT = "mechfmu-fmi-run: cannot import "


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


def run_crate3(f3: Target, case: Case, interface: str = "cs", step: float | None = None) -> Result:
    """:func:`run_fmi_crate` on the FMI 3.0 FMU."""
    return run_fmi_crate(f3.fmu, case, interface=interface, step=step, mapping=f3.names)


def fmi_crate_row(target: Target, case: Case, reference: Result | None, floors: dict[str, float],
                  anchor: str = "", kind: str = "case") -> tuple[Row, dict[str, Any] | None]:
    """The case under the fmi crate in Co-Simulation against FMPy's run (``reference``), both
    at the case's tolerance: (row, what the report plots of it)."""
    importer = row_name(NAME, target.version, CS)
    note = FMI3_NOTE if target.version == FMI3 else FMI_CRATE_NOTE
    row = Row(kind=kind, fmu=target.fmu.model, case=case.name, importer=importer, anchor=anchor, problems=[],
               notes=[note], tolerance=FMI_CRATE_TOLERANCE)
    t0 = time.perf_counter()
    try:
        fc = run_fmi_crate(target.fmu, case, mapping=target.names if target.fmu.fmi3 else None)
        if reference is None:
            raise RuntimeError(f"the {row_name('FMPy', target.version, CS)} run failed: nothing to compare with")
        worst, where, when, over_time = agreement(fc, reference, case.recorded(), floors)
    except NotSupported as e:  # what the runner does not do: not the FMU's failure
        return row.but(max_error=None, passed=True, skipped=True, problems=[f"{importer}: {e}"]), None
    except Exception as e:  # noqa: BLE001 (a row, not a crash)
        return row.but(max_error=None, passed=False,
                    problems=[f"{importer} run failed: {type(e).__name__}: {e}"]), None
    row.update(max_error=worst, passed=bool(worst <= FMI_CRATE_TOLERANCE),
               notes=[f"worst signal {where} at t = {when:g}", note],
               seconds=time.perf_counter() - t0, log=fc.log[-20:])
    return row, dict(time=fc.time, error_over_time=over_time, tolerance=FMI_CRATE_TOLERANCE, max_error=worst)


def rk4(target: Target | None = None) -> FixedStep:
    """The crate's RK4 at a fixed step (order 4; a conserved quantity drifts at order 5): the
    output interval over 1 or 2 (``target``: the FMU in its FMI version; None: an FMI 2.0 FMU
    given at each run)."""
    version = target.version if target is not None else FMI2

    def run(fmu: Fmu, case: Case, h: float) -> Result:
        mapping = target.names if target is not None and target.fmu.fmi3 else None
        return run_fmi_crate(fmu, case, interface="me", step=h, mapping=mapping)

    return FixedStep(row_name(NAME, version, ME, "RK4"), 4, order_band(4, 5), 1, 2, run)


def _available() -> Availability:
    ok, found = fmi_crate_available()
    return Availability(ok, "fmi crate 0.8 (mechfmu-fmi-run)" if ok else found)


def _case_rows(run: CaseRun, interface: str) -> Iterator[Row]:
    if interface == ME:
        method = rk4(run.target)
        run.progress(method.importer)
        yield fixed_step_row(run.fmu, run.case, method, run.anchor)
        return
    run.progress(row_name(NAME, run.version, CS))
    row, plotted = fmi_crate_row(run.target, run.case, run.reference, run.floors(), run.anchor, run.kind)
    if plotted is not None and run.deviations is not None:
        run.deviations[NAME] = plotted
    yield row


def _identical(d: dict[str, Any]) -> str:
    return "fmi crate vs FMPy: " + ("0 (identical)" if d["max_error"] == 0 else f"{d['max_error']:.1e}")


IMPORTER = Importer(
    name=NAME, option="fmi-crate", left_out="do not run the cases under the Rust fmi crate (mechfmu-fmi-run)",
    runs=Runs(frozenset({CS, ME}), frozenset({FMI2, FMI3})), tolerance=FMI_CRATE_TOLERANCE, available=_available,
    case_rows=_case_rows, header_key="fmi_crate",
    header=lambda a: "fmi crate not used" if a is None else a.text if a.ok else "fmi crate unavailable",
    unavailable="the fmi-crate importer cannot run here ({why}); its rows fail",
    methods={FMI2: ("RK4",), FMI3: ("RK4",)}, fixed_step=rk4(), platforms=True,
    curves={NAME: Curve("fmi crate vs FMPy", "#8250df", (0, (3, 1.5)), only_nonzero=True, heading=_identical)},
    words=Words(
        report="under the fmi crate (rust-fmi), max |fmi crate − FMPy| / max |FMPy|, both at the case's tolerance",
        report3="fmi crate FMI3 CS against FMPy's FMI 3.0 run (1e-9); fmi crate FMI3 ME RK4 as the RK4 row",
        tables3="the fmi crate's FMI 3.0 import (mechfmu-fmi-run) against FMPy's FMI 3.0 run (1e-9) and its RK4 "
                "held to its order, as above",
        owner="the fmi crate's"))
