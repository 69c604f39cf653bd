"""A check's outcome (:class:`Check`): its name, its problems (which fail it) and its notes;
what :mod:`.checks` and :mod:`.description_checks` make."""

from __future__ import annotations

from dataclasses import dataclass, field

__all__ = ["Check"]


@dataclass
class Check:
    name: str
    problems: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    #: for the reference CSV check: the largest deviation (fraction of range) and its tolerance
    max_error: float | None = None
    tolerance: float | None = None

    @property
    def passed(self) -> bool:
        return not self.problems
