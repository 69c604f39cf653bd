"""What ``mechfmu validate`` is running now (``"Crane: swing_60deg (FMPy ME CVode)"``): shown on a
terminal, and heard by whoever listens, as the child process validating an FMU does
(:mod:`.isolation`) to name the run an FMU crashed or hung in. A run whose importer calls the
FMU from its own native code (not through FMPy) says it is alive with :func:`beat`."""

from __future__ import annotations

import sys
from typing import Callable

__all__ = ["beat", "listen", "report"]

_listeners: list[Callable[[str], None]] = []
_beat_listeners: list[Callable[[], None]] = []


def report(message: str) -> None:
    """Says what runs from now on (``""``: nothing more)."""
    for listener in _listeners:
        listener(message)
    if sys.stderr.isatty():
        sys.stderr.write(f"\r\033[K{message}")
        sys.stderr.flush()


def beat() -> None:
    """Says the current run is still making progress."""
    for listener in _beat_listeners:
        listener()


def listen(listener: Callable[[str], None], on_beat: Callable[[], None] | None = None) -> None:
    """Calls ``listener(message)`` at every :func:`report` of this process, and ``on_beat()``
    at every :func:`beat`."""
    _listeners.append(listener)
    if on_beat is not None:
        _beat_listeners.append(on_beat)
