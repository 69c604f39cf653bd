"""The FMUs' log messages under FMPy, captured: the one implementation, used by
``mechfmu validate`` (:func:`mechfmu_validate.importers.fmpy.run_fmpy`) and by the test suite
(``tests/python/fmutest.py``: ``LogMark``, ``Slave.log``).

FMI 2.0 loggers are variadic, which ctypes cannot receive, so fmpy routes messages through a
native proxy (``fmpy.logging.addLoggerProxy``) that formats them and calls ONE process-wide
Python callback (a static pointer in the proxy library). :func:`install` puts this module's
capturing callback there, once, and keeps it alive for the life of the process; fmpy's
default callbacks (used by a plain ``fmpy.simulate_fmu``) then land here too. Never pass
``logger=`` to ``fmpy.simulate_fmu`` in a process that uses this: fmpy would repoint the
proxy at a temporary callback that is freed after the call, and the next FMU message would
jump to freed memory. Whoever repoints the proxy on purpose (an in-process sweep does) calls
:func:`repoint` afterwards.

FMI 3.0's log callback is not variadic: ctypes receives it directly, without the proxy, and
FMPy keeps the callback it is given alive with the instance. Pass :func:`fmi3_logger` as
``logger=`` to ``fmpy.simulate_fmu`` (or ``logMessage=`` to an instance's ``instantiate``)
of an FMI 3.0 FMU, and its messages land here too (FMPy's default prints them to stdout).

Every message becomes a :class:`LogRecord`; a :class:`LogMark` collects those logged after
its creation::

    callbacks = install()                 # FMU2Slave.instantiate(callbacks=callbacks)
    mark = LogMark()
    fmpy.simulate_fmu(...)
    mark.records, mark.text(), mark.find("must be > 0", status=3)

:func:`raw_callbacks` are callbacks without the proxy: the Python function sees the *format*
argument, so a test can check that messages are passed as ("%s", text), never as the format
string itself (their records are collected by ``LogMark(raw=True)``).
"""

from __future__ import annotations

import re
import signal
import threading
from ctypes import byref
from dataclasses import dataclass
from typing import Any

__all__ = ["LogRecord", "LogMark", "install", "raw_callbacks", "repoint", "fmi3_logger", "signal_name", "status_name",
           "STATUS_NAMES"]

#: fmi2Status values and their names
STATUS_NAMES = {
    0: "fmi2OK",
    1: "fmi2Warning",
    2: "fmi2Discard",
    3: "fmi2Error",
    4: "fmi2Fatal",
    5: "fmi2Pending",
}


def signal_name(number: int) -> str:
    """``SIGSEGV (signal 11)``: the signal a run died of."""
    try:
        return f"{signal.Signals(number).name} (signal {number})"
    except ValueError:
        return f"signal {number}"


def status_name(status: int, fmi: int = 2) -> str:
    """``fmi2Warning`` (``fmi3Warning`` for ``fmi=3``: the statuses have the same values)."""
    name = STATUS_NAMES.get(status)
    return f"fmi{fmi}{name.removeprefix('fmi2')}" if name else f"status {status}"


@dataclass(frozen=True)
class LogRecord:
    instance: str
    status: int
    category: str
    message: str
    #: the FMI version of the FMU that logged it (FMI 3.0's callback names no instance)
    fmi: int = 2

    def __str__(self) -> str:
        return f"[{status_name(self.status, self.fmi)}|{self.category}] {self.instance}: {self.message}"

    def brief(self) -> str:
        """``[Warning] message``: the form of the report's log lines."""
        return f"[{status_name(self.status, self.fmi).removeprefix(f'fmi{self.fmi}')}] {self.message}"


_records: list[LogRecord] = []
_raw_records: list[LogRecord] = []


def _decode(b: bytes | None) -> str:
    return "" if b is None else b.decode("utf-8", errors="replace")


def _capture(env, instance_name, status, category, message):  # called from C through fmpy's proxy
    _records.append(LogRecord(_decode(instance_name), int(status), _decode(category), _decode(message)))


def _capture_fmi3(env, status, category, message):  # FMI 3.0's fmi3LogMessageCallback
    _records.append(LogRecord("", int(status), _decode(category), _decode(message), fmi=3))


def fmi3_logger():
    """The log callback for an FMI 3.0 FMU under FMPy (``simulate_fmu(logger=...)``): its
    messages become :class:`LogRecord` s that a :class:`LogMark` sees."""
    return _capture_fmi3


def _capture_raw(env, instance_name, status, category, message):  # called from C, no proxy
    _raw_records.append(LogRecord(_decode(instance_name), int(status), _decode(category), _decode(message)))


_lock = threading.Lock()
# Kept alive for the life of the process (see the module docstring).
_keep: dict[str, Any] = {}


def _callbacks(capture) -> tuple[Any, Any]:
    """(fmi2CallbackFunctions, its logger: the CFUNCTYPE of ``capture``), kept alive."""
    import fmpy
    from fmpy.fmi2 import (
        fmi2CallbackAllocateMemoryTYPE,
        fmi2CallbackFreeMemoryTYPE,
        fmi2CallbackFunctions,
        fmi2CallbackLoggerTYPE,
    )

    if "allocate" not in _keep:
        _keep["allocate"] = fmi2CallbackAllocateMemoryTYPE(fmpy.calloc)
        _keep["free"] = fmi2CallbackFreeMemoryTYPE(fmpy.free)
    logger = fmi2CallbackLoggerTYPE(capture)
    _keep.setdefault("loggers", []).append(logger)
    cb = fmi2CallbackFunctions()
    cb.logger = logger
    cb.allocateMemory = _keep["allocate"]
    cb.freeMemory = _keep["free"]
    cb.componentEnvironment = None
    return cb, logger


def install():
    """Points fmpy's logger proxy at this module's capture (once per process) and returns
    the callbacks to instantiate FMUs with (``fmi2CallbackFunctions``; their logger is the
    proxy)."""
    with _lock:
        if "callbacks" not in _keep:
            from fmpy.logging import addLoggerProxy

            cb, _keep["logger"] = _callbacks(_capture)
            addLoggerProxy(byref(cb))  # cb.logger becomes the proxy, which calls _capture
            _keep["callbacks"] = cb
        return _keep["callbacks"]


def repoint() -> None:
    """Points fmpy's logger proxy at this module's capture again, after something else in
    this process pointed it elsewhere. (``addLoggerProxy`` only re-points it when given
    callbacks whose logger is not the proxy already, hence the fresh struct.)"""
    install()
    from fmpy.fmi2 import fmi2CallbackFunctions
    from fmpy.logging import addLoggerProxy

    tmp = fmi2CallbackFunctions()
    tmp.logger = _keep["logger"]
    addLoggerProxy(byref(tmp))


def raw_callbacks():
    """Callbacks without the proxy (see the module docstring)."""
    with _lock:
        if "raw" not in _keep:
            _keep["raw"], _ = _callbacks(_capture_raw)
        return _keep["raw"]


class LogMark:
    """Collects the records logged after its creation (through the proxy, or with
    ``raw=True`` through :func:`raw_callbacks`)."""

    def __init__(self, raw: bool = False):
        self._list = _raw_records if raw else _records
        self._start = len(self._list)

    @property
    def records(self) -> list[LogRecord]:
        return list(self._list[self._start :])

    def text(self) -> str:
        return "\n".join(str(r) for r in self.records) or "(nothing logged)"

    def find(self, pattern: str, *, status: int | None = None, flags: int = re.IGNORECASE) -> list[LogRecord]:
        rx = re.compile(pattern, flags)
        return [r for r in self.records if rx.search(r.message) and (status is None or r.status == status)]

    def explain(self, error: Exception) -> Exception:
        """``error`` (an importer's exception for an FMI call that failed) with the reason the
        FMU logged for it: its last messages of status Discard or worse since the mark,
        appended to the exception's text. The importer says only which call failed; the FMU
        says why."""
        reasons = [r.message for r in self.records if r.status >= 2]
        if reasons:
            error.args = (f"{str(error).rstrip('.')}; the FMU logged: {' | '.join(reasons[-3:])}",)
        return error
