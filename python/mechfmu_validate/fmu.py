"""An FMU file as every importer opens it: extracted once (:class:`Fmu`), with its model
description; and the two ways an importer declines a run that are not the FMU's failure
(:class:`NotSupported`, :class:`NotRead`)."""

from __future__ import annotations

import shutil
import tempfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import fmpy
from fmpy import read_model_description

__all__ = ["Fmu", "NotRead", "NotSupported"]


class NotSupported(RuntimeError):
    """The importer cannot run this kind of experiment (a row to skip, not a failure)."""


class NotRead(RuntimeError):
    """The importer could not load the FMU or one of its variables: a limit of its loader
    when the FMU is legal (an importer's loader may refuse a model description the
    standard allows, or drop variables it judges wrong)."""


@dataclass
class Fmu:
    """An FMU file, extracted once."""

    path: Path
    directory: Path = field(init=False)
    md: Any = field(init=False)

    def __post_init__(self):
        self.path = Path(self.path).resolve()
        self.directory = Path(tempfile.mkdtemp(prefix=f"mechfmu-validate-{self.path.stem}-"))
        try:
            fmpy.extract(str(self.path), str(self.directory))
            self.md = read_model_description(str(self.directory), validate=False)
        except BaseException:
            self.cleanup()
            raise

    @property
    def model(self) -> str:
        cs = self.md.coSimulation
        return cs.modelIdentifier if cs is not None else self.md.modelName

    @property
    def fmi3(self) -> bool:
        """An FMI 3.0 FMU (its arrays need an :class:`~.arrays.ArrayMap` for a case's names)."""
        return self.md.fmiVersion.startswith("3.")

    @property
    def variables(self) -> dict[str, Any]:
        return {v.name: v for v in self.md.modelVariables}

    def inputs(self) -> list[str]:
        return [v.name for v in self.md.modelVariables if v.causality == "input"]

    def outputs(self) -> list[str]:
        return [v.name for v in self.md.modelVariables if v.causality == "output"]

    @property
    def by_mechfmu(self) -> bool:
        """Built by mechfmu (whose own rules the checks then hold it to), not by another exporter."""
        return (self.md.generationTool or "").startswith("mechfmu")

    def cleanup(self) -> None:
        shutil.rmtree(self.directory, ignore_errors=True)

    def __enter__(self) -> Fmu:
        return self

    def __exit__(self, *exc) -> None:
        self.cleanup()
