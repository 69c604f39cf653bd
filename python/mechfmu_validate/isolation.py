"""Each FMU's validation in a child process of its own (``multiprocessing``, spawn), so that an
FMU that crashes its importer's process (a segmentation fault in ``fmi2DoStep``), ends it
(``exit()``) or hangs costs one FAIL row, not the whole run: the other FMUs still run, and
the table, the JSON and the JUnit file are still written (as the sweep's native engine
isolates its chunks).

The child sends its rows as they are made (those made before a crash are kept), says what it
runs (:mod:`.progress`), and writes into a buffer shared with the parent, before every FMI
call FMPy makes, the function and its numeric arguments, and counts the calls. The parent
turns a death by a signal, an exit without a result, or :data:`TIME_LIMIT` seconds without
progress (no row, no new run, no FMI call) into one FAIL row (:data:`STOPPED`) naming the
signal or the time limit, the run, and the FMI call it was in (the last one written; a run
whose importer calls the FMU from its own native code, not through FMPy, names the run
only).

Everything the importers and the FMU write to the child's standard output and error (an
importer's loader's messages, FMPy's warnings, an FMU's ``printf``) goes to a
file (its file descriptors 1 and 2), and each row takes what was written while it was made:
``row["output"]``, shown under the row's detail and in the JSON and the JUnit
``<system-out>``. The child's temporary files are in a directory of its own, removed after
it whatever its end; it leads a process group of its own, killed with it.
"""

from __future__ import annotations

import ctypes
import dataclasses
import multiprocessing
import os
import shutil
import signal
import sys
import tempfile
import time
import traceback
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from . import fmulog, progress
from .fmulog import signal_name
from .importer import Selection
from .platforms import WineSession, cleanup_copies
from .rows import Row
from .validation import validate_fmu

__all__ = ["Job", "TIME_LIMIT", "STOPPED", "bounded_text", "stopped_row", "validate_isolated"]

#: seconds without progress (no row, no new run, no FMI call) after which a validation is
#: stopped as hung (``--time-limit``)
TIME_LIMIT = 300.0

#: the case column of the row of a validation that did not finish
STOPPED = "(validation stopped)"

#: the file, in the child's directory, its standard output and error go to
OUTPUT = "output.txt"

#: the size of the buffer the child names its current FMI call in
CALL_BUFFER = 512

#: the most console output a row keeps (its head and its tail, half each)
OUTPUT_LIMIT = 64 * 1024

#: seconds a child that sent its result has to end before it is killed
SHUTDOWN_GRACE = 5.0

#: how many times the time limit one run may last, whatever FMI calls it makes (an event
#: iteration that never ends)
RUN_LIMITS = 10

#: ``prctl``'s option: the signal the kernel sends the child when its parent dies
PR_SET_PDEATHSIG = 1


@dataclass(frozen=True)
class Job:
    """One FMU's validation, as :func:`~.validation.validate_fmu` takes it."""

    path: Path
    #: the model's name in the table (for the row of a validation that did not finish)
    name: str
    cases_file: Path | None
    only: tuple[str, ...]
    #: the importers, interfaces and versions it runs
    selection: Selection


@dataclass
class _Shared:
    """What the child writes and the parent reads: the current FMI call, and how many."""

    call: Any  # multiprocessing.Array of c_char
    calls: Any  # multiprocessing.Value of c_uint64


# ---------------------------------------------------------------------------------------
# The child


class _Output:
    """The child's standard output and error, redirected into ``path``; :meth:`take` returns
    what was written since the last call."""

    def __init__(self, path: str):
        fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_APPEND, 0o600)
        sys.stdout.flush()
        sys.stderr.flush()
        os.dup2(fd, 1)
        os.dup2(fd, 2)
        os.close(fd)
        sys.stdout.reconfigure(line_buffering=True)
        self._libc = ctypes.CDLL(None)
        try:  # C's stdout unbuffered: an FMU's printf before a crash is not lost
            self._libc.setvbuf(ctypes.c_void_p.in_dll(self._libc, "stdout"), None, 2, 0)
        except (AttributeError, ValueError):
            pass
        self._reader = open(path, "rb")
        self.offset = 0

    def take(self) -> str:
        sys.stdout.flush()
        sys.stderr.flush()
        self._libc.fflush(None)
        data = self._reader.read()
        self.offset += len(data)
        return bounded_text(data)


def bounded_text(data: bytes) -> str:
    """``data`` as text, its head and tail only when it is over :data:`OUTPUT_LIMIT` bytes,
    saying how much was cut."""
    if len(data) > OUTPUT_LIMIT:
        half = OUTPUT_LIMIT // 2
        cut = len(data) - 2 * half
        data = data[:half] + f"\n[... {cut} bytes of output cut ...]\n".encode() + data[-half:]
    return data.decode("utf-8", errors="replace")


def _call_text(function: str, argnames: list[str], args: tuple) -> bytes:
    """``fmi2DoStep(currentCommunicationPoint=2, communicationStepSize=0.1)``: the function and
    its numeric arguments (the instance and the arrays left out)."""
    numbers = ", ".join(f"{n}={a:g}" for n, a in zip(argnames, args) if isinstance(a, float))
    return f"{function}({numbers})".encode()[: CALL_BUFFER - 1]


def _track_fmi_calls(shared: _Shared) -> None:
    """Every FMI call FMPy makes (its ``_FMU._call``, FMI 2.0 and 3.0 alike) writes itself into
    the shared buffer first, and counts. Best effort: FMPy's ``_FMU._call`` is not its public
    interface, and without it the stopped row names the run only."""
    try:
        from fmpy.fmi1 import _FMU

        original = _FMU._call
    except (ImportError, AttributeError):
        return

    def tracked(fmu, function, *args):
        try:
            shared.call.value = _call_text(function, getattr(fmu._functions.get(function), "argnames", []), args)
            shared.calls.value += 1
        except Exception:  # noqa: BLE001 (the record only: the call itself goes on)
            pass
        return original(fmu, function, *args)

    _FMU._call = tracked


class _Sink(list):
    """The rows of :func:`~.validation.validate_fmu`, each sent to the parent as it is added,
    with the console output written while it was made."""

    def __init__(self, conn, output: _Output):
        super().__init__()
        self._conn, self._output = conn, output

    def append(self, row: Row) -> None:
        text = self._output.take()
        if text.strip():
            row["output"] = row.get("output", "") + text
        super().append(row)
        self._conn.send(("row", row, self._output.offset))

    def extend(self, rows) -> None:
        for row in rows:
            self.append(row)


def _picklable(entry: dict) -> dict:
    """A plot entry without what cannot cross processes (the case's functions)."""
    ev = entry.get("evaluation")
    return dict(entry, evaluation=dataclasses.replace(ev, case=None)) if ev is not None else entry


def _die_with_parent(parent: int) -> None:
    """The kernel kills this process when its parent dies (a parent killed outright cannot
    end it), and it ends now if the parent is already gone."""
    try:
        ctypes.CDLL(None, use_errno=True).prctl(PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
    except (AttributeError, OSError):  # not Linux: the parent's own handlers end it
        pass
    if os.getppid() != parent:
        os._exit(1)


def _send_result(conn, rows: list[Row], plots: list[dict], details: list[dict]) -> None:
    """The final message; the rows alone (plain data) when the plots or details cannot be sent."""
    try:
        conn.send(("done", rows, plots, details))
    except Exception:  # noqa: BLE001 (pickling: an object of a cases.py the parent cannot build)
        conn.send(("done", rows, [], []))


def _child(conn, shared: _Shared, workdir: str, job: Job, wine_tmpdir: str | None, parent: int) -> None:
    """The child process: ``job``'s rows, plots and details, sent to the parent."""
    os.setsid()  # a process group of its own: the parent ends the FMU's helpers with it
    _die_with_parent(parent)
    os.environ["TMPDIR"] = tempfile.tempdir = workdir
    output = _Output(os.path.join(workdir, OUTPUT))
    WineSession.tmpdir = wine_tmpdir
    fmulog.install()
    _track_fmi_calls(shared)

    def said(message: str) -> None:
        shared.call.value = b""
        conn.send(("progress", message))

    def alive() -> None:
        shared.calls.value += 1

    progress.listen(said, alive)
    rows, plots, details = _Sink(conn, output), [], []
    try:
        validate_fmu(job.path, job.cases_file, list(job.only), job.selection, rows, plots, details)
    except Exception as e:  # noqa: BLE001 (a bug of ours on this FMU: its row, and on to the next)
        where = traceback.extract_tb(e.__traceback__)[-1]
        rows.append(stopped_row(job, f"mechfmu validate failed on {job.path}: {type(e).__name__}: {e} "
                                     f"(at {Path(where.filename).name}:{where.lineno}: a bug of mechfmu's)"))
    finally:
        cleanup_copies()
    rest = output.take()  # written after the last row (an importer's cleanup): the last row's
    if rest.strip() and rows:
        rows[-1]["output"] = rows[-1].get("output", "") + rest
    _send_result(conn, list(rows), [_picklable(p) for p in plots], details)


# ---------------------------------------------------------------------------------------
# The parent


def stopped_row(job: Job, problem: str, output: str = "") -> Row:
    """The FAIL row of a validation that did not finish, saying why."""
    return Row(kind="check", fmu=job.name, case=STOPPED, importer="-", max_error=None, tolerance=None,
                passed=False, notes=[], problems=[problem], **({"output": output} if output.strip() else {}))


def _where_stopped(running: str, call: str, calls: int) -> str:
    """``in fmi2DoStep(...), while running X``: the FMI call (the last one FMPy recorded) and
    the run; the run only when the FMI function is not known."""
    run = f"while running {running or 'its opening'}"
    if call:
        return f"in {call}, {run}"
    if calls == 0:
        return f"before any FMI call, {run}"
    return f"{run} (in a call the FMI function of which is not known: an importer's native code)"


def _read_output(workdir: str, offset: int) -> str:
    """What the child wrote after ``offset`` (nothing when it died before writing any)."""
    try:
        with open(os.path.join(workdir, OUTPUT), "rb") as f:
            f.seek(offset)
            return bounded_text(f.read())
    except OSError:
        return ""


def _end(proc) -> None:
    """Ends the child and its process group (an FMU's helpers, a runner it started)."""
    if proc.pid is None:  # never started
        return
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):  # not yet a group of its own, or gone
        pass
    if proc.is_alive():
        proc.kill()
    proc.join()


def _install_exit_on_termination() -> None:
    """SIGTERM and SIGHUP end this process through ``SystemExit``, so that a validation's
    ``finally`` ends its child and removes its directory (the main thread only)."""
    def leave(number, _frame):
        # once: a second signal (the parent-death signal after a SIGTERM) would cut the
        # clean-up short
        for other in (signal.SIGTERM, signal.SIGHUP, signal.SIGINT):
            signal.signal(other, signal.SIG_IGN)
        raise SystemExit(128 + number)

    try:
        for number in (signal.SIGTERM, signal.SIGHUP):
            if signal.getsignal(number) is signal.SIG_DFL:
                signal.signal(number, leave)
    except ValueError:  # not the main thread: the default actions stay
        pass


@dataclass
class _Watch:
    """What the parent knows of the child: the run it said, the console output it took, and
    when it last made progress (a message, an FMI call) and started its run."""

    running: str = ""
    offset: int = 0
    calls: int = 0
    last: float = dataclasses.field(default_factory=time.monotonic)
    run_started: float = dataclasses.field(default_factory=time.monotonic)


def _why_stopped(watch: _Watch, shared: _Shared, time_limit: float) -> str | None:
    """Why a child that is still at work is stopped (no progress for ``time_limit`` seconds, or
    one run longer than :data:`RUN_LIMITS` times it whatever its calls); None: it goes on."""
    now = time.monotonic()
    if shared.calls.value != watch.calls:
        watch.calls, watch.last = shared.calls.value, now
    if now - watch.last > time_limit:
        return f"made no progress for {time_limit:g} s (the time limit, --time-limit): stopped"
    if now - watch.run_started > RUN_LIMITS * time_limit:
        return (f"ran one run for more than {RUN_LIMITS * time_limit:g} s ({RUN_LIMITS} times the time limit, "
                "--time-limit), its FMI calls never ending: stopped")
    return None


def _receive(receive, proc, shared: _Shared, watch: _Watch, rows: list[Row], time_limit: float):
    """The child's messages until its result (returned as ``("done", rows, plots, details)``)
    or its end: then ``("stopped", why)``, ``why`` None when it ended or died by itself."""
    while True:
        if receive.poll(0.2):
            try:
                message = receive.recv()
            except EOFError:
                return "stopped", None
            except Exception as e:  # noqa: BLE001 (a message the parent cannot rebuild)
                return "stopped", f"sent a result that cannot be read ({type(e).__name__}: {e})"
            watch.last = time.monotonic()
            if message[0] == "done":
                return message
            if message[0] == "progress":
                watch.running, watch.run_started = message[1], watch.last
                progress.report(watch.running)
            elif message[0] == "row":
                rows.append(message[1])
                watch.offset = message[2]
        elif not proc.is_alive() and not receive.poll(0):
            return "stopped", None
        else:
            why = _why_stopped(watch, shared, time_limit)
            if why is not None:
                return "stopped", why


def validate_isolated(job: Job, time_limit: float = TIME_LIMIT, child=None
                      ) -> tuple[list[Row], list[dict], list[dict]]:
    """``job`` run in a child process: (rows, plots, details). A child that dies, exits without
    a result or makes no progress for ``time_limit`` seconds leaves the rows it sent and one
    FAIL row saying so. ``child`` is the function the child runs (default: the validation;
    its arguments are those of ``_child``)."""
    _install_exit_on_termination()
    context = multiprocessing.get_context("spawn")
    shared = _Shared(context.Array(ctypes.c_char, CALL_BUFFER, lock=False),
                     context.Value(ctypes.c_uint64, lock=False))
    workdir = tempfile.mkdtemp(prefix="mechfmu-validate-run-")
    Path(workdir, OUTPUT).touch(mode=0o600)  # there even when the child dies before it opens it
    receive, send = context.Pipe(duplex=False)
    proc = context.Process(target=child or _child, daemon=True,
                           args=(send, shared, workdir, job, WineSession.tmpdir, os.getpid()))
    rows: list[Row] = []
    watch = _Watch()
    try:
        proc.start()
        send.close()
        message = _receive(receive, proc, shared, watch, rows, time_limit)
        if message[0] == "done":
            proc.join(SHUTDOWN_GRACE)  # a child hanging at its exit is killed below, its helpers too
            return message[1], message[2], message[3]
        why = message[1]
        call = shared.call.value.decode("utf-8", errors="replace")
        _end(proc)
        if why is None:
            code = proc.exitcode
            why = (f"the process validating it died of {signal_name(-code)}" if code is not None and code < 0
                   else f"the process validating it ended (exit status {code}) with its validation unfinished")
        where = _where_stopped(watch.running, call, shared.calls.value)
        rows.append(stopped_row(job, f"{job.path}: {why} {where}", _read_output(workdir, watch.offset)))
        return rows, [], []
    finally:
        _end(proc)
        receive.close()
        shutil.rmtree(workdir, ignore_errors=True)
        progress.report("")
