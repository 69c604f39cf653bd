"""Helpers shared by the FMPy test suite.

* ``fmu_path(name)``: ``fmus/<name>.fmu``; fails (never skips) when it has not been built.
* ``simulate(path, ...)``: ``fmpy.simulate_fmu`` with the FMU's log messages captured.
* ``Slave(path)``: a thin wrapper around fmpy's low-level ``FMU2Slave`` that returns raw
  status codes, captures every message sent to the logger and frees the instance on exit.
* ``max_error(...)``, ``record_figures(...)``: compare against a reference and keep the
  achieved errors in ``target/test-figures/<name>.json`` for the lead to quote.

About the logger: the FMUs' messages are captured by ``mechfmu_validate.fmulog``, the one
log capture of mechfmu's Python side (``mechfmu validate`` uses it too; see its docstring).
This module installs it at import: fmpy's process-wide logger proxy then calls its callback,
and ``LogMark``, ``LogRecord`` and ``CALLBACKS`` here are its. Never pass ``logger=`` to
``fmpy.simulate_fmu`` in these tests: fmpy would repoint the proxy at a temporary callback
that is freed after the call, and the next FMU message would jump to freed memory.
"""

from __future__ import annotations

import json
import math
import os
import re
import shutil
import subprocess
import tempfile
import threading
from ctypes import c_double, c_uint
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterable, Sequence

import numpy as np
import pytest

import fmpy
from fmpy import read_model_description
from fmpy.fmi1 import FMICallException
from fmpy.fmi2 import FMU2Slave, fmi2Error, fmi2OK, fmi2Warning

from mechfmu_validate import fmulog
from mechfmu_validate.fmu import Fmu
from mechfmu_validate.fmulog import LogMark, LogRecord, status_name  # noqa: F401 (the suite's names)

REPO_ROOT = Path(__file__).resolve().parents[2]
# MECHFMU_FMU_DIR points the suite at FMUs built elsewhere (`mechfmu build --out DIR`).
FMU_DIR = Path(os.environ.get("MECHFMU_FMU_DIR") or REPO_ROOT / "fmus").resolve()
FIGURES_DIR = REPO_ROOT / "target" / "test-figures"

BUILD_HINT = "run `cargo run --release -- build` first"


def built_fmi_run() -> Path:
    """mechfmu-fmi-run (the fmi crate's importer) built as `mechfmu validate` builds it: cargo
    profile `importer` (scripts/cross-runners has built it already, so this is quick)."""
    exe = REPO_ROOT / "target" / "importer" / "mechfmu-fmi-run"
    done = subprocess.run(["cargo", "build", "--profile", "importer", "--quiet", "-p", "mechfmu-fmi-run"],
                          cwd=REPO_ROOT, capture_output=True, text=True)
    assert done.returncode == 0 and exe.is_file(), f"cannot build mechfmu-fmi-run:\n{done.stderr[-3000:]}"
    return exe


# ---------------------------------------------------------------------------------------
# FMU files


def fmu_path(name: str) -> Path:
    """``fmus/<name>.fmu``. A missing file is a failure, never a skip."""
    path = FMU_DIR / f"{name}.fmu"
    if not path.is_file():
        pytest.fail(f"{path} does not exist: {BUILD_HINT}", pytrace=False)
    return path


_extract_lock = threading.Lock()
_extracted: dict[tuple[str, float], tuple[str, Any]] = {}
_extract_root = tempfile.mkdtemp(prefix="mechfmu-pytest-")


def extracted(path: Path) -> tuple[str, Any]:
    """Extract an FMU once per process; returns (directory, model description)."""
    path = Path(path)
    key = (str(path.resolve()), path.stat().st_mtime)
    with _extract_lock:
        if key not in _extracted:
            target = tempfile.mkdtemp(prefix=path.stem + "-", dir=_extract_root)
            fmpy.extract(str(path), target)
            md = read_model_description(target, validate=False)
            _extracted[key] = (target, md)
        return _extracted[key]


_validation_fmus: dict[str, Any] = {}


def validation_fmu(model: str) -> Any:
    """``model``'s FMU as mechfmu_validate opens it (``fmu.Fmu``, extracted), once per session
    (fails, never skips, when it is not built)."""
    with _extract_lock:
        if model not in _validation_fmus:
            _validation_fmus[model] = Fmu(fmu_path(model))
        return _validation_fmus[model]


def cleanup_extracted() -> None:
    for fmu in _validation_fmus.values():
        fmu.cleanup()
    _validation_fmus.clear()
    shutil.rmtree(_extract_root, ignore_errors=True)


# ---------------------------------------------------------------------------------------
# Log capture (mechfmu_validate.fmulog)

# Through fmpy's proxy, which now calls fmulog's capture: fmpy's default callbacks (used by a
# plain simulate_fmu) land there too.
CALLBACKS = fmulog.install()
# Without the proxy: the Python function sees the *format* argument, so a test can check
# that messages are passed as ("%s", text), never as the format string itself.
RAW_CALLBACKS = fmulog.raw_callbacks()


# ---------------------------------------------------------------------------------------
# Simulation


@dataclass
class SimResult:
    result: np.ndarray
    log: list[LogRecord] = field(default_factory=list)

    def __getitem__(self, name: str) -> np.ndarray:
        return self.result[name]

    @property
    def time(self) -> np.ndarray:
        return self.result["time"]


def make_input(time: Sequence[float], **signals: Sequence[float]) -> np.ndarray:
    """A structured input array for ``simulate_fmu(input=...)``.

    Repeat a time point to make a jump: ``make_input([0, 2, 2, 20], F=[0, 0, 1, 1])``.
    """
    dtype = [("time", np.float64)] + [(name, np.float64) for name in signals]
    rows = list(zip(time, *signals.values()))
    return np.array(rows, dtype=dtype)


def simulate(
    path: Path,
    *,
    relative_tolerance: float | None = 1e-8,
    output_interval: float | None = None,
    start_values: dict[str, float] | None = None,
    input: np.ndarray | None = None,
    stop_time: float | None = None,
    output: Sequence[str] | None = None,
    debug_logging: bool = False,
    **kwargs: Any,
) -> SimResult:
    """``fmpy.simulate_fmu`` on the FMU, as an importer would call it; log captured."""
    mark = LogMark()
    result = fmpy.simulate_fmu(
        str(path),
        relative_tolerance=relative_tolerance,
        output_interval=output_interval,
        start_values=dict(start_values or {}),
        input=input,
        stop_time=stop_time,
        output=list(output) if output is not None else None,
        debug_logging=debug_logging,
        **kwargs,
    )
    return SimResult(result=result, log=mark.records)


def simulate_refused(path: Path, start_values: dict[str, float]) -> LogMark:
    """``fmpy.simulate_fmu`` from ``start_values`` the FMU refuses: it raises with fmi2Error.
    The mark of what was logged, for the test to find its message in."""
    mark = LogMark()
    with pytest.raises(FMICallException) as info:
        simulate(path, start_values=start_values, stop_time=1.0)
    assert info.value.status == fmi2Error
    return mark


# ---------------------------------------------------------------------------------------
# Low-level API


class Slave:
    """One FMU2Slave instance with raw status codes and a captured log.

    Every ``fmi2*`` call goes through :meth:`call`, which returns the status code instead of
    raising (fmpy raises ``FMICallException`` on Discard, Error and Fatal). The convenience
    methods (``setup``, ``enter``, ``exit``, ``step``, ``get``, ``set``) assert fmi2OK and
    show the log when they do not get it.
    """

    def __init__(
        self,
        path: Path,
        *,
        logging_on: bool = False,
        raw_logger: bool = False,
        instance_name: str | None = None,
        instantiate: bool = True,
    ):
        self.path = Path(path)
        self.unzipdir, self.md = extracted(self.path)
        self.vr = {v.name: v.valueReference for v in self.md.modelVariables}
        self.variables = {v.name: v for v in self.md.modelVariables}
        self.log = LogMark(raw=raw_logger)
        self._callbacks = RAW_CALLBACKS if raw_logger else CALLBACKS
        self.fmu = FMU2Slave(
            guid=self.md.guid,
            unzipDirectory=self.unzipdir,
            modelIdentifier=self.md.coSimulation.modelIdentifier,
            instanceName=instance_name,
        )
        self._freed = False
        if instantiate:
            try:
                self.fmu.instantiate(callbacks=self._callbacks, loggingOn=logging_on)
            except Exception:
                self.fmu.freeLibrary()
                self._freed = True
                raise

    # context manager -------------------------------------------------------------------
    def __enter__(self) -> "Slave":
        return self

    def __exit__(self, *exc) -> None:
        self.free()

    def free(self) -> None:
        if not self._freed:
            self._freed = True
            if self.fmu.component:
                self.fmu.fmi2FreeInstance(self.fmu.component)
            self.fmu.freeLibrary()

    # raw calls -------------------------------------------------------------------------
    def call(self, fname: str, *args: Any) -> int:
        """Call ``fmi2<fname>(component, *args)``; return its status code."""
        f = getattr(self.fmu, fname if fname.startswith("fmi2") else "fmi2" + fname)
        try:
            return int(f(self.fmu.component, *args))
        except FMICallException as e:
            return int(e.status)

    def vrs(self, names_or_refs: Iterable[str | int]):
        refs = [self.vr[n] if isinstance(n, str) else int(n) for n in names_or_refs]
        return (c_uint * len(refs))(*refs), len(refs)

    def get_real_status(self, names_or_refs: Sequence[str | int]) -> tuple[int, list[float]]:
        vr, n = self.vrs(names_or_refs)
        values = (c_double * n)()
        return self.call("fmi2GetReal", vr, n, values), list(values)

    def set_real_status(self, values: dict[str | int, float]) -> int:
        vr, n = self.vrs(values.keys())
        vals = (c_double * n)(*[float(v) for v in values.values()])
        return self.call("fmi2SetReal", vr, n, vals)

    # asserting helpers -----------------------------------------------------------------
    def expect_ok(self, what: str, status: int) -> None:
        assert status in (fmi2OK, fmi2Warning), f"{what} returned {status_name(status)}; log:\n{self.log.text()}"

    def expect_refused_at_initialization(self, name: str, value: float) -> None:
        """Setting parameter ``name`` to ``value`` fails with fmi2Error by the end of
        initialization (at fmi2SetReal, or at entering or leaving initialization mode), with
        an error message naming the parameter."""
        self.setup()
        statuses = [self.set_real_status({name: value})]
        if statuses[-1] < fmi2Error:
            statuses.append(self.call("fmi2EnterInitializationMode"))
        if statuses[-1] < fmi2Error:
            statuses.append(self.call("fmi2ExitInitializationMode"))
        assert max(statuses) == fmi2Error, f"{name} = {value}: statuses {statuses}"
        named = [r for r in self.log.records
                 if r.status >= fmi2Error and re.search(rf"(?<![\w.]){name}(?![\w(])", r.message)]
        assert named, f"no error message naming {name}; log:\n{self.log.text()}"

    def setup(self, tolerance: float | None = 1e-8, start: float = 0.0, stop: float | None = None) -> None:
        self.expect_ok(
            "fmi2SetupExperiment",
            self.call(
                "fmi2SetupExperiment",
                1 if tolerance is not None else 0,
                0.0 if tolerance is None else tolerance,
                start,
                1 if stop is not None else 0,
                0.0 if stop is None else stop,
            ),
        )

    def enter(self) -> None:
        self.expect_ok("fmi2EnterInitializationMode", self.call("fmi2EnterInitializationMode"))

    def exit(self) -> None:
        self.expect_ok("fmi2ExitInitializationMode", self.call("fmi2ExitInitializationMode"))

    def initialize(self, start_values: dict[str, float] | None = None, tolerance: float | None = 1e-8,
                   start: float = 0.0, stop: float | None = None) -> None:
        """setupExperiment, start values, enter and exit initialization mode."""
        self.setup(tolerance=tolerance, start=start, stop=stop)
        if start_values:
            self.set(**start_values)
        self.enter()
        self.exit()

    def step(self, t: float, h: float) -> None:
        self.expect_ok(f"fmi2DoStep(t={t!r}, h={h!r})", self.call("fmi2DoStep", t, h, 1))

    def get(self, *names: str) -> list[float]:
        status, values = self.get_real_status(names)
        self.expect_ok(f"fmi2GetReal({', '.join(names)})", status)
        return values

    def set(self, **values: float) -> None:
        self.expect_ok(f"fmi2SetReal({values})", self.set_real_status(values))

    def expect_refused_on_leaving_initialization(self, name: str, value: float) -> None:
        """Parameter ``name`` set to ``value`` is accepted until fmi2ExitInitializationMode,
        which fails with fmi2Error and an error message ``<name> = ...``."""
        self.setup()
        self.set(**{name: value})
        self.enter()
        status = self.call("fmi2ExitInitializationMode")
        assert status == fmi2Error, status_name(status)
        assert [r for r in self.log.records if r.status == fmi2Error
                and re.search(rf"(?<![\w.]){name} = ", r.message)], self.log.text()

    def expect_steps_without_error(self, start_values: dict[str, float],
                                   inputs: dict[str, float] | None = None) -> None:
        """A legal sequence logs no error: initialization from ``start_values``, ``inputs``
        set, 100 steps of 0.01 s and fmi2Terminate."""
        self.initialize(start_values)
        if inputs:
            self.set(**inputs)
        for i in range(100):
            self.step(i * 0.01, 0.01)
        assert self.call("fmi2Terminate") == fmi2OK
        assert not [r for r in self.log.records if r.status >= fmi2Error], self.log.text()


# ---------------------------------------------------------------------------------------
# Errors and figures


def max_error(got: np.ndarray, want: np.ndarray) -> tuple[float, float, int]:
    """(max |got - want|, range of want, flat index of the max); arrays of any shape."""
    got = np.asarray(got, dtype=float).ravel()
    want = np.asarray(want, dtype=float).ravel()
    assert got.shape == want.shape, f"shape {got.shape} != {want.shape}"
    assert np.all(np.isfinite(got)), "non-finite values in the FMU's output"
    err = np.abs(got - want)
    i = int(np.argmax(err))
    rng = float(np.max(want) - np.min(want))
    return float(err[i]), rng, i


_figures_lock = threading.Lock()
_figures_this_session: list[str] = []


def figures_summary() -> list[str]:
    """Lines for the terminal summary: the worst relative error per figure file and variable."""
    lines = []
    for name in _figures_this_session:
        path = FIGURES_DIR / f"{name}.json"
        try:
            cases = json.loads(path.read_text()).get("cases", {})
        except (OSError, json.JSONDecodeError):
            continue
        worst: dict[str, tuple[float, str]] = {}
        for case, entry in cases.items():
            for row in entry.get("variables", []):
                rel = row.get("relative")
                if isinstance(rel, (int, float)) and rel > worst.get(row["variable"], (-1.0, ""))[0]:
                    worst[row["variable"]] = (float(rel), case)
        lines.append(f"{name}: {len(cases)} cases, table in {path.with_suffix('.md').relative_to(REPO_ROOT)}")
        for var, (rel, case) in sorted(worst.items()):
            lines.append(f"  worst {var:8s} {rel:.2e} of range  ({case})")
    return lines


def record_figures(name: str, case: str, entry: dict[str, Any]) -> None:
    """Merge ``entry`` under ``case`` into ``target/test-figures/<name>.json``
    and re-render ``<name>.md`` (a table the lead can quote)."""
    FIGURES_DIR.mkdir(parents=True, exist_ok=True)
    path = FIGURES_DIR / f"{name}.json"
    with _figures_lock:
        data: dict[str, Any] = {}
        if name not in _figures_this_session:
            # first entry of this run: start afresh so that stale cases do not linger
            _figures_this_session.append(name)
        elif path.exists():
            try:
                data = json.loads(path.read_text())
            except json.JSONDecodeError:
                data = {}
        data.setdefault("cases", {})[case] = entry
        data["fmpy"] = fmpy.__version__
        path.write_text(json.dumps(data, indent=2, sort_keys=True) + "\n")
        _render_markdown(name, data)


def figure_row(var: str, err: float, rng: float, rel: float, limit: float, at_t: float | None = None,
               interval: float | None = None) -> dict[str, Any]:
    """One row of a figures table (plain Python types, for JSON)."""
    return dict(variable=var, output_interval=interval, max_error=float(err), range=float(rng), relative=float(rel),
                limit=limit, at_t=None if at_t is None else float(at_t), **{"pass": bool(rel <= limit)})


def compare_to_reference(figure: str, res: Any, ref: Any, names: list[str], interval: float, case: str,
                         limit: float) -> list[str]:
    """The worst error of each of ``names`` in the FMU's result ``res`` against the reference
    ``ref``, relative to the reference's range: a row per variable recorded under ``case`` in
    the figure file ``figure``, and a line per variable past ``limit`` (none: the case passes)."""
    rows, failures = [], []
    for name in names:
        err, rng, i = max_error(res[name], ref[name])
        rel = err / rng if rng > 0 else err
        rows.append(dict(variable=name, output_interval=interval, max_error=err, range=rng, relative=rel,
                         limit=limit, at_t=float(res.time[i]), **{"pass": bool(rel <= limit)}))
        if not rel <= limit:
            failures.append(f"{name}: max error {err:.3e} = {rel:.3e} of range {rng:.4g} at t = {res.time[i]:.4g}")
    record_figures(figure, case, {"case": case, "variables": rows})
    return failures


def _fmt(v: Any) -> str:
    if isinstance(v, float):
        if v == 0 or (1e-3 <= abs(v) < 1e4):
            return f"{v:.4g}"
        return f"{v:.2e}"
    return str(v)


def _render_markdown(name: str, data: dict[str, Any]) -> None:
    cases = data.get("cases", {})
    cols = ["variable", "output_interval", "max_error", "range", "relative", "limit", "at_t", "pass"]
    lines = [
        f"# {name}: FMU against closed-form references (fmpy {data.get('fmpy')})",
        "",
        "relative = max |FMU - reference| / (max - min of the reference over the run); limit 1e-6.",
        "",
        "| case | " + " | ".join(cols) + " |",
        "|---|" + "---|" * len(cols),
    ]
    for case in sorted(cases):
        entry = cases[case]
        for var in entry.get("variables", []):
            row = [var.get(c, "") for c in cols]
            lines.append(f"| {case} | " + " | ".join(_fmt(v) for v in row) + " |")
    (FIGURES_DIR / f"{name}.md").write_text("\n".join(lines) + "\n")


def isclose_rel(a: float, b: float, rel: float) -> bool:
    return math.isclose(a, b, rel_tol=rel, abs_tol=0.0)

