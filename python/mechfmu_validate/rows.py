"""A row of ``mechfmu validate``'s table (:class:`Row`): a check, a case or a reference under
one importer, or a note, with its verdict and what it measured.

A field a row does not have is :data:`UNSET` (a Model Exchange row judged by its order has
``observed_order``, a Co-Simulation row does not): the JSON file has the fields a row has
(:meth:`Row.to_json`). ``row["passed"]`` and ``row.get("skipped")`` read a row as the JSON
file has it.
"""

from __future__ import annotations

import dataclasses
import enum
from dataclasses import dataclass, field
from typing import Any

__all__ = ["UNSET", "Row"]


class _Unset(enum.Enum):
    UNSET = enum.auto()


#: the value of a field a row does not have (one value across processes: an enum's member)
UNSET = _Unset.UNSET


@dataclass
class Row:
    """One row of the table (see the module's documentation)."""

    #: "check", "case", "reference" or "note"
    kind: str
    fmu: str
    case: str
    importer: str
    max_error: float | None | _Unset = UNSET
    tolerance: float | None | _Unset = UNSET
    passed: bool | _Unset = UNSET
    problems: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    #: the report's anchor of the case's plot
    anchor: str | _Unset = UNSET
    #: the importer cannot run this (not a failure)
    skipped: bool | _Unset = UNSET
    #: the importer's solver did not reach the case's limit (reported, not failed)
    limited: bool | _Unset = UNSET
    #: each compared signal's error, tolerance and verdict
    signals: dict[str, dict[str, Any]] | _Unset = UNSET
    seconds: float | _Unset = UNSET
    #: the FMU's last log messages
    log: list[str] | _Unset = UNSET
    #: a fixed-step method's order, the observed orders it passes with, its step, and what it showed
    order: int | _Unset = UNSET
    order_band: list[float] | _Unset = UNSET
    step: float | _Unset = UNSET
    observed_order: float | _Unset = UNSET
    half_step_error: float | _Unset = UNSET
    #: a co-simulation's order (its coupling error at the step and at half of it), and the
    #: largest communication step that keeps that error under the coupling tolerance (systems)
    coupling_order: float | None | _Unset = UNSET
    largest_step: float | None | _Unset = UNSET
    #: the platforms an FMU has binaries for and which ran (its platforms row)
    platforms: dict[str, Any] | _Unset = UNSET
    #: a foreign binary's run equals this machine's bit for bit
    bit_identical: bool | _Unset = UNSET
    #: the FMU's result in an FMI cross-check tree
    cross_check: dict[str, Any] | _Unset = UNSET
    #: what is wrong with a reference's experiment, by FMPy's criterion
    experiment_problem: Any = UNSET
    #: what the importers and the FMU wrote to the console while the row was made
    output: str | _Unset = UNSET
    #: the FMU file the row is of
    file: str | _Unset = UNSET

    def but(self, **changes: Any) -> Row:
        """A copy with ``changes``."""
        return dataclasses.replace(self, **changes)

    def update(self, **changes: Any) -> None:
        for name, value in changes.items():
            setattr(self, name, value)

    def has(self, name: str) -> bool:
        return getattr(self, name, UNSET) is not UNSET

    def __getitem__(self, name: str) -> Any:
        if not self.has(name):
            raise KeyError(name)
        return getattr(self, name)

    def __setitem__(self, name: str, value: Any) -> None:
        if name not in _FIELDS:
            raise KeyError(f"a row has no field {name!r}")
        setattr(self, name, value)

    def __contains__(self, name: str) -> bool:
        return self.has(name)

    def get(self, name: str, default: Any = None) -> Any:
        return getattr(self, name) if self.has(name) else default

    def to_json(self) -> dict[str, Any]:
        """The fields the row has, by name."""
        return {f.name: getattr(self, f.name) for f in dataclasses.fields(self) if self.has(f.name)}


_FIELDS = {f.name for f in dataclasses.fields(Row)}
