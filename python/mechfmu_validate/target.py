"""The FMU under validation in its FMI version, the version a value (:class:`Target`): an
FMI 2.0 FMU, or the FMI 3.0 FMU of a mechanism (``fmus/fmi3/<Name>.fmu``, Co-Simulation and
Model Exchange in one archive) run under the same reference cases as its FMI 2.0 FMU and held
to the same limits; and, per mechanism, ``check: FMI 3.0 CS = FMI 2.0 CS``
(:func:`agreement_row`): the DefaultExperiment under FMPy through both FMUs (the same step
sequence), every FMI 2.0 variable against its FMI 3.0 scalar or array element(s), to 1e-12
relative.

A case names FMI 2.0 variables: they reach an FMI 3.0 FMU through the mechanism's
:class:`~.arrays.ArrayMap` (read from the FMU's annotations: :func:`~.arrays.derive`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

import fmpy

from . import fmulog
from .arrays import ArrayMap, MappingError, derive, fmi2_sibling, fmi3_sibling
from .fmu import Fmu
from .opening import open_fmu
from .rows import Row

__all__ = ["AGREEMENT", "AGREEMENT_TOLERANCE", "Target", "agreement_row"]

#: the check row of the FMI 3.0 and FMI 2.0 Co-Simulation runs of the DefaultExperiment
AGREEMENT = "check: FMI 3.0 CS = FMI 2.0 CS"
AGREEMENT_TOLERANCE = 1e-12


@dataclass
class Target:
    """An FMU in its FMI version; an FMI 3.0 one with the FMI 2.0 names of its variables (or
    why there are none)."""

    fmu: Fmu
    mapping: ArrayMap | None = None
    problem: str | None = None

    @classmethod
    def open(cls, path: Path) -> Target:
        """The FMU at ``path`` (an FMI 3.0 one with the FMI 2.0 names of its variables); raises
        :class:`~.opening.BrokenFmu` when it cannot be opened."""
        fmu = open_fmu(path)
        if not fmu.fmi3:
            return cls(fmu)
        try:
            return cls(fmu, derive(fmu))
        except MappingError as e:
            return cls(fmu, None, str(e))

    @property
    def version(self) -> str:
        """``"2.0"`` or ``"3.0"``."""
        return "3.0" if self.fmu.fmi3 else "2.0"

    def sibling(self) -> Path | None:
        """The same mechanism's FMU in the other version, where ``mechfmu build`` puts it
        (``<dir>/fmi3/<Name>.fmu`` beside ``<dir>/<Name>.fmu``), if it was built."""
        return fmi2_sibling(self.fmu.path) if self.fmu.fmi3 else fmi3_sibling(self.fmu.path)

    @property
    def names(self):
        """What names the variables a case names: the FMU itself (FMI 2.0), or its
        :class:`~.arrays.ArrayMap` (FMI 3.0; raises :class:`~.arrays.MappingError` without one)."""
        if not self.fmu.fmi3:
            return self.fmu
        if self.mapping is None:
            raise MappingError(self.problem or "no mapping")
        return self.mapping

    def cleanup(self) -> None:
        self.fmu.cleanup()


def agreement_row(f3: Target, fmu2: Fmu) -> Row:
    """The DefaultExperiment under FMPy's Co-Simulation through both FMUs: every FMI 2.0
    variable against its FMI 3.0 counterpart (each place of an array element)."""
    row = Row(kind="check", fmu=fmu2.model, case=AGREEMENT, importer="FMPy", tolerance=AGREEMENT_TOLERANCE,
               problems=[], notes=[])
    mark = fmulog.LogMark()
    try:
        names = f3.names
        fmi2 = [v.name for v in fmu2.md.modelVariables if v.type == "Real"]
        cs2 = fmpy.simulate_fmu(str(fmu2.directory), output=fmi2, validate=False)
        cs3 = fmpy.simulate_fmu(str(f3.fmu.directory), output=names.fmi3_record(fmi2), validate=False,
                                logger=fmulog.fmi3_logger())
        if not np.array_equal(cs2["time"], cs3["time"]):
            raise RuntimeError(f"the two runs have different times ({len(cs2)} and {len(cs3)} points)")
        worst, where = 0.0, ""
        for name in fmi2:
            for a, k in names.places(name):
                col = np.asarray(cs3[a], dtype=float)
                got = col if k < 0 else col.reshape(len(col), -1)[:, k]
                want = np.asarray(cs2[name], dtype=float)
                err = float(np.max(np.abs(got - want))) / (float(np.max(np.abs(want))) or 1.0)
                err = err if math.isfinite(err) else math.inf
                if err > worst or not where:
                    worst, where = err, name if k < 0 else f"{name} = {names.element_names_of(name)[0]}"
    except Exception as e:
        return row.but(max_error=None, passed=False, problems=[f"{type(e).__name__}: {mark.explain(e)}"])
    row.update(max_error=worst, passed=worst <= AGREEMENT_TOLERANCE,
               notes=[f"{len(fmi2)} variables over {len(cs2)} points of the DefaultExperiment; worst: {where}"])
    if not row["passed"]:
        row["problems"] = [f"{where} differs by {worst:.2e} (relative) between the FMI 3.0 and FMI 2.0 runs"]
    return row
