"""The native engine: cases run by ``mechfmu sweep-worker``, a compiled runner that loads the
FMU once and drives it without a Python call per step.

``NativeRuntime`` has the interface of ``runner.Runtime`` (``run(cases)``, ``close()``) and
gives the same rows: the worker makes FMPy's calls in FMPy's order (``Runtime._simulate``),
interpolates inputs with ``FastInput``'s arithmetic and computes the summaries as numpy does,
so every number is the FMPy engine's to the bit; the rows' statuses and messages are composed
here, by the code the FMPy engine uses. One worker process serves one Dask worker; if the FMU
crashes it (someone else's FMU can), the cases of that chunk fail with a message saying so and
the next chunk starts a new worker.

The protocol (every message framed as a little-endian u32 length and a payload) is the
worker's, ``crates/sweep-worker``: a JSON setup, then binary chunks of cases.
"""

from __future__ import annotations

import json
import math
import os
import shutil
import signal
import socket
import struct
import subprocess
import tempfile
from pathlib import Path
from typing import Any, Sequence

import numpy as np

from .runner import STATUS, CaseSetup, extract, log_message

# the variable in which `mechfmu sweep` names its own executable, which runs the worker
EXE_ENV = "MECHFMU_EXE"


class NativeUnavailable(Exception):
    """The native engine cannot run this sweep (the reason says why); the FMPy engine can."""


def find_worker() -> str | None:
    """The `mechfmu` executable whose `sweep-worker` runs the cases, if there is one."""
    exe = os.environ.get(EXE_ENV)
    if exe and os.path.isfile(exe):
        return exe
    return None


def _settable_phase(variable) -> bool | None:
    """Where FMPy's ``apply_start_values`` sets a start value: False before
    fmi2EnterInitializationMode, True in initialization mode, None: it cannot."""
    from fmpy.simulation import settable_in_initialization_mode, settable_in_instantiated

    if settable_in_instantiated(variable):
        return False
    if settable_in_initialization_mode(variable):
        return True
    return None


class Layout:
    """What the worker is told once: the FMU, the experiment, the order of every value a
    case sends and of every summary it returns."""

    def __init__(self, md, unzipdir: str, setup: CaseSetup):
        import fmpy

        self.setup = setup
        identifier = md.coSimulation.modelIdentifier
        library = Path(unzipdir) / "binaries" / fmpy.platform / (identifier + fmpy.sharedLibraryExtension)
        if not library.is_file():
            raise NativeUnavailable(f"the FMU has no binary for {fmpy.platform}")
        names = set(setup.fixed_start_values) | set(setup.start_columns.values())
        self.starts: list[tuple[str, str]] = []  # (variable, type), in the order they are set
        starts_json = []
        unsettable = []
        for v in md.modelVariables:  # FMPy's order: the model description's
            if v.name not in names:
                continue
            phase = _settable_phase(v)
            if phase is None:
                unsettable.append(v.name)
                continue
            kind = "Integer" if v.type == "Enumeration" else v.type
            if kind not in ("Real", "Integer", "Boolean") or v.shape:
                raise NativeUnavailable(f"`{v.name}` is a {v.type} start value")
            self.starts.append((v.name, kind))
            starts_json.append({"vr": v.valueReference, "type": kind, "initialization": phase})
        # FMPy sets what it can, then fails every case naming the rest
        self.unsettable = sorted(unsettable, key=lambda n: [v.name for v in md.modelVariables].index(n))
        by_name = {v.name: v for v in md.modelVariables}
        input_names = self._input_names()
        for name in input_names:
            v = by_name.get(name)
            if v is None or v.type != "Real" or v.causality != "input" or v.variability != "continuous":
                raise NativeUnavailable(f"input column `{name}` is not a continuous Real input")
        self.input_names = input_names
        trajectory = sorted({s.var for s in setup.summaries if s.func != "final"})
        finals = sorted({s.var for s in setup.summaries if s.func == "final"} - set(trajectory))
        summaries = []
        for s in setup.summaries:
            if s.var in finals and s.func == "final":
                summaries.append({"func": "final", "source": "final", "index": finals.index(s.var)})
            else:
                summaries.append({"func": s.func, "source": "trajectory", "index": trajectory.index(s.var)})
        self.columns = [s.column for s in setup.summaries]
        self.json = {
            "library": str(library),
            "model_identifier": identifier,
            "guid": md.guid,
            "resource_location": Path(unzipdir, "resources").as_uri(),
            "instance_name": f"sweep-{os.getpid()}",
            "start_time": setup.start_time,
            "stop_time": setup.stop_time,
            "output_interval": setup.output_interval,
            "tolerance": setup.tolerance,
            "set_stop_time": setup.set_stop_time,
            "can_vary_step": bool(md.coSimulation.canHandleVariableCommunicationStepSize),
            "starts": starts_json,
            "inputs": [by_name[n].valueReference for n in input_names],
            "trajectory": [by_name[n].valueReference for n in trajectory],
            "finals": [by_name[n].valueReference for n in finals],
            "summaries": summaries,
        }

    def _input_names(self) -> list[str]:
        """The columns of every case's input table (the same for all cases)."""
        setup = self.setup
        names = list(setup.base_input.dtype.names[1:]) if setup.base_input is not None else []
        return names + [n for n in setup.schedules if n not in names]

    def case_bytes(self, index: int, values: Sequence[float]) -> bytes:
        """One case of a chunk request."""
        setup = self.setup
        case = dict(zip(setup.columns, (float(v) for v in values)))
        start_values = setup.case_start_values(case)
        starts = np.empty(len(self.starts))
        for k, (name, kind) in enumerate(self.starts):
            value = start_values[name]
            # FMPy's conversions: int() truncates, bool() is "not zero"
            starts[k] = float(int(value)) if kind == "Integer" else (1.0 if kind == "Boolean" and value else value)
        table = setup.case_input(case) if self.input_names else None
        if table is None:
            rows = np.empty((0, 0))
        else:
            cols = [table.dtype.names[0]] + self.input_names
            rows = np.column_stack([np.asarray(table[c], dtype=float) for c in cols])
        return (struct.pack("<Q", index) + starts.astype("<f8").tobytes() + struct.pack("<I", len(rows))
                + np.ascontiguousarray(rows, dtype="<f8").tobytes())


class Reply:
    """Reads one chunk reply."""

    def __init__(self, payload: bytes):
        self.view = memoryview(payload)
        self.at = 0

    def take(self, fmt: str):
        values = struct.unpack_from(fmt, self.view, self.at)
        self.at += struct.calcsize(fmt)
        return values

    def text(self) -> str:
        (n,) = self.take("<I")
        s = bytes(self.view[self.at:self.at + n]).decode("utf-8", "replace")
        self.at += n
        return s


def compose_row(index: int, status: int, function: str, discard: tuple[float, float],
                log: list[tuple[int, str, str]], summaries: dict[str, float]) -> dict[str, Any]:
    """The row the FMPy engine (``Runtime.run_case``) gives for the same outcome."""
    row: dict[str, Any] = {"case": index, "status": "ok", "message": ""}
    if status == 0:
        row.update(summaries)
        warn = log_message(log, 1)
        if warn:
            row["status"], row["message"] = "warning", warn
        return row
    if function == "fmi2Instantiate":
        row["status"], row["message"] = "error", "Exception: Failed to instantiate model"
    else:
        time, last = discard
        if not math.isnan(time):
            log = log + [(2, "", f"fmi2DoStep discarded the step from t = {time:g} "
                                 f"(last successful time {last:g})")]
        name = STATUS.get(status, f"status {status}")
        row["status"] = name
        row["message"] = log_message(log, 2) or log_message(log, 0) or f"{function} returned fmi2{name.title()}"
    for column in summaries:
        row[column] = math.nan
    return row


class NativeRuntime:
    """An extracted FMU and the worker process that runs its cases, on one Dask worker."""

    def __init__(self, fmu: bytes | str | Path, setup: CaseSetup, exe: str | None = None, bare: bool = False):
        """``bare``: the worker only steps each case (fmi2Reset, the setup, fmi2DoStep; no
        inputs, samples or summaries): the FMU's own cost, for the benchmark."""
        self.exe = exe or find_worker()
        if self.exe is None:
            raise NativeUnavailable(f"no `mechfmu` executable to run the worker (${EXE_ENV} is not set)")
        self.setup = setup
        self.tmpdir, self.unzipdir, md = extract(fmu)
        try:
            self.layout = Layout(md, self.unzipdir, setup)
            self.layout.json["bare"] = bare
        except BaseException:
            shutil.rmtree(self.tmpdir, ignore_errors=True)
            raise
        self.host = f"{socket.gethostname()}:{os.getpid()}"
        self.process: subprocess.Popen | None = None
        self.stderr = None

    # the worker process ----------------------------------------------------------------
    def _start(self) -> subprocess.Popen:
        self.stderr = tempfile.TemporaryFile(dir=self.tmpdir)
        process = subprocess.Popen([self.exe, "sweep-worker"], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                   stderr=self.stderr)
        self.process = process
        self._send(json.dumps(self.layout.json).encode())
        answer = json.loads(self._receive() or b'{"ok": false, "error": "no answer"}')
        if not answer.get("ok"):
            self._stop()
            raise RuntimeError(f"the native runner cannot run {self.layout.json['library']}: {answer.get('error')}")
        return process

    def _send(self, payload: bytes) -> None:
        assert self.process is not None and self.process.stdin is not None
        self.process.stdin.write(struct.pack("<I", len(payload)) + payload)
        self.process.stdin.flush()

    def _receive(self) -> bytes | None:
        """One reply, or None when the worker has gone."""
        assert self.process is not None and self.process.stdout is not None
        head = self.process.stdout.read(4)
        if len(head) < 4:
            return None
        (n,) = struct.unpack("<I", head)
        payload = self.process.stdout.read(n)
        return payload if len(payload) == n else None

    def _stop(self) -> None:
        process, self.process = self.process, None
        if process is None:
            return
        for stream in (process.stdin, process.stdout):
            try:
                stream.close()
            except OSError:
                pass
        try:
            process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait()

    def _death(self) -> str:
        """Why the worker ended, in words, with the end of what it wrote on stderr."""
        process = self.process
        code = process.wait() if process is not None else None
        if code is not None and code < 0:
            try:
                how = f"killed by {signal.Signals(-code).name}"
            except ValueError:
                how = f"killed by signal {-code}"
        else:
            how = f"exit status {code}"
        said = ""
        if self.stderr is not None:
            self.stderr.seek(0)
            tail = self.stderr.read().decode("utf-8", "replace").strip().splitlines()[-3:]
            said = f": {' | '.join(tail)}" if tail else ""
        return f"the FMU crashed the native runner while it ran this chunk ({how}{said})"

    def close(self) -> None:
        self._stop()
        shutil.rmtree(self.tmpdir, ignore_errors=True)

    # cases -----------------------------------------------------------------------------
    def run(self, cases: Sequence[tuple[int, Sequence[float]]]) -> list[dict[str, Any]]:
        if not cases:
            return []
        layout = self.layout
        if layout.unsettable:
            message = "these variables could not be set: " + ", ".join(layout.unsettable)
            return [self._stamp(dict({"case": i, "status": "error", "message": message},
                                     **{c: math.nan for c in layout.columns}), 0.0, 0.0) for i, _ in cases]
        if self.process is None or self.process.poll() is not None:
            self._start()
        request = b"".join([struct.pack("<I", len(cases))] + [layout.case_bytes(i, v) for i, v in cases])
        try:
            self._send(request)
            payload = self._receive()
        except (BrokenPipeError, OSError):
            payload = None
        if payload is None:
            message = self._death()
            self._stop()
            return [self._stamp(dict({"case": i, "status": "crashed", "message": message},
                                     **{c: math.nan for c in layout.columns}), math.nan, math.nan)
                    for i, _ in cases]
        return self._rows(payload)

    def _rows(self, payload: bytes) -> list[dict[str, Any]]:
        reply = Reply(payload)
        (n,) = reply.take("<I")
        columns = self.layout.columns
        summary_format = f"<{len(columns)}d"
        rows = []
        for _ in range(n):
            index, status = reply.take("<QB")
            function = reply.text()
            discard = reply.take("<2d")
            (n_log,) = reply.take("<I")
            log = []
            for _ in range(n_log):
                (level,) = reply.take("<B")
                category = reply.text()
                log.append((level, category, reply.text()))
            summaries = dict(zip(columns, reply.take(summary_format)))
            elapsed, cpu = reply.take("<2d")
            rows.append(self._stamp(compose_row(index, status, function, discard, log, summaries), elapsed, cpu))
        return rows

    def _stamp(self, row: dict[str, Any], elapsed: float, cpu: float) -> dict[str, Any]:
        row["elapsed_s"], row["cpu_s"], row["worker"] = elapsed, cpu, self.host
        return row


def unavailable(fmu: Path, setup: CaseSetup) -> str | None:
    """Why the native engine cannot run this sweep on this machine, or None when it can."""
    import fmpy
    from fmpy import read_model_description

    if find_worker() is None:
        return f"no `mechfmu` executable to run it (${EXE_ENV} is not set)"
    with tempfile.TemporaryDirectory(prefix="mechfmu-sweep-") as tmp:
        try:
            fmpy.extract(str(fmu), tmp)
            Layout(read_model_description(tmp, validate=False), tmp, setup)
        except NativeUnavailable as e:
            return str(e)
    return None
