"""A mechanism's FMI 2.0 scalars in its FMI 3.0 FMU: which FMI 3.0 array element each is.

A reference case names FMI 2.0 variables (``q_x``, ``I_xy``). The FMI 3.0 FMU of the same
mechanism has the same scalar variables (same names; value references of their own, their
places in its model description), and arrays that group the others (``q`` = ``q_w q_x q_y q_z``; ``I_C`` a symmetric 3x3 whose ``I_xy``
stands at [1,2] and [2,1]). An :class:`ArrayMap` translates a case into FMI 3.0 terms (start
values and inputs as whole arrays, recorded arrays) and the results back.

Which scalar each element is comes from the FMI 3.0 model description itself: mechfmu
annotates every array with the FMI 2.0 variables of its elements, row-major
(``<Annotation type="org.mechfmu.scalars">I_xx I_xy I_xz I_xy ...</Annotation>``). An FMI
3.0 FMU with arrays and without the annotation (not mechfmu's) has no FMI 2.0 names: its
case rows say so (a :class:`MappingError`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from math import prod
from pathlib import Path
from typing import Any, Iterable, Mapping
from xml.etree import ElementTree

import numpy as np

__all__ = ["ArrayMap", "MappingError", "derive", "element_name", "fmi2_sibling", "fmi3_sibling"]


class MappingError(RuntimeError):
    """The FMI 3.0 arrays cannot be matched with the FMI 2.0 scalars."""


def element_name(array: str, shape: tuple[int, ...], k: int) -> str:
    """``I_C[1,2]``: element ``k`` (row-major, 0-based) of an array, 1-based as FMI 3.0 writes it."""
    return f"{array}[{','.join(str(i + 1) for i in np.unravel_index(k, shape))}]"


def fmi3_sibling(path: Path) -> Path | None:
    """``<dir>/fmi3/<Name>.fmu`` beside an FMI 2.0 ``<dir>/<Name>.fmu`` (``mechfmu build``'s layout)."""
    p = Path(path).parent / "fmi3" / Path(path).name
    return p if p.is_file() else None


def fmi2_sibling(path: Path) -> Path | None:
    """``<dir>/<Name>.fmu`` for an FMI 3.0 ``<dir>/fmi3/<Name>.fmu``."""
    p = Path(path)
    if p.parent.name != "fmi3":
        return None
    q = p.parent.parent / p.name
    return q if q.is_file() else None


@dataclass
class ArrayMap:
    """The FMI 2.0 names of a mechanism in its FMI 3.0 FMU."""

    #: variables of both (same name)
    scalars: set[str]
    #: FMI 3.0 array -> its shape
    shapes: dict[str, tuple[int, ...]] = field(default_factory=dict)
    #: FMI 3.0 array -> the FMI 2.0 scalar at each element, row-major
    elements: dict[str, list[str]] = field(default_factory=dict)
    #: FMI 3.0 array -> its start values (the model description's), where it has them
    starts: dict[str, list[float]] = field(default_factory=dict)

    @property
    def variables(self) -> dict[str, None]:
        """The FMI 2.0 names it knows (as ``Fmu.variables`` has its names: for the input helpers)."""
        return {**dict.fromkeys(self.scalars), **{s: None for e in self.elements.values() for s in e}}

    def places(self, name: str) -> list[tuple[str, int]]:
        """Where an FMI 2.0 variable is: ``[(name, -1)]`` for a scalar, ``[(array, k), ...]``."""
        if name in self.scalars:
            return [(name, -1)]
        found = [(a, k) for a, e in self.elements.items() for k, s in enumerate(e) if s == name]
        if not found:
            raise KeyError(f"{name} is not a variable of the FMI 3.0 FMU, nor an element of one of its arrays")
        return found

    def element_names_of(self, name: str) -> list[str]:
        """``["I_C[1,2]", "I_C[2,1]"]`` for ``I_xy``; ``[name]`` for a scalar."""
        return [a if k < 0 else element_name(a, self.shapes[a], k) for a, k in self.places(name)]

    def fmi3_elements(self, values: Mapping[str, float]) -> dict[str, float]:
        """FMI 2.0 values by FMI 3.0 element name (each place of a scalar), for a runner that sets elements by name."""
        return {e: float(v) for n, v in values.items() for e in self.element_names_of(n)}

    def fmi3_start_values(self, values: Mapping[str, float]) -> dict[str, Any]:
        """FMI 2.0 start values as FMPy sets FMI 3.0 ones: scalars, and whole arrays (their
        start values with the named elements replaced)."""
        out: dict[str, Any] = {}
        for name, value in values.items():
            for a, k in self.places(name):
                if k < 0:
                    out[a] = value
                    continue
                if a not in self.starts:
                    raise MappingError(f"{name} is an element of {a}, which has no start values to set")
                out.setdefault(a, list(self.starts[a]))[k] = float(value)
        return out

    def fmi3_record(self, names: Iterable[str]) -> list[str]:
        """The FMI 3.0 variables holding these FMI 2.0 ones."""
        out: list[str] = []
        for name in names:
            for a, _ in self.places(name)[:1]:
                if a not in out:
                    out.append(a)
        return out

    def fmi2_columns(self, table: np.ndarray, names: Iterable[str]) -> dict[str, np.ndarray]:
        """FMPy's FMI 3.0 result as columns of the FMI 2.0 names (an element: its first place)."""
        out = {"time": np.asarray(table["time"], dtype=float)}
        for name in names:
            a, k = self.places(name)[0]
            col = np.asarray(table[a], dtype=float)
            out[name] = col if k < 0 else col.reshape(len(col), -1)[:, k]
        return out

    def fmi3_input(self, table: np.ndarray | None) -> np.ndarray | None:
        """An FMPy input table of FMI 2.0 names as one of FMI 3.0 variables: an input array
        is a column of its shape, its start values where the table names no element."""
        if table is None:
            return None
        names = [n for n in table.dtype.names[1:] if n in self.variables]
        columns: dict[str, np.ndarray] = {}
        for name in names:
            for a, k in self.places(name):
                if k < 0:
                    columns[a] = np.asarray(table[name], dtype=float)
                    continue
                if a not in columns:
                    columns[a] = np.tile(np.asarray(self.starts[a], dtype=float), (len(table), 1))
                columns[a][:, k] = table[name]
        dtype = [(table.dtype.names[0], np.float64)] + [
            (a, np.float64, self.shapes[a]) if a in self.shapes else (a, np.float64) for a in columns]
        out = np.zeros(len(table), dtype=dtype)
        out[table.dtype.names[0]] = table[table.dtype.names[0]]
        for a, col in columns.items():
            out[a] = col.reshape((len(table), *self.shapes[a])) if a in self.shapes else col
        return out

    def describe(self) -> list[str]:
        """One line per array: ``q (4) = q_w q_x q_y q_z``."""
        return [f"{a} {'x'.join(map(str, self.shapes[a]))} = {' '.join(e)}" for a, e in self.elements.items()]


SCALARS_ANNOTATION = "org.mechfmu.scalars"


def _listed_scalars(fmu3) -> dict[str, list[str]]:
    """Array -> the FMI 2.0 scalars of its elements, as its model description's annotation
    (``<Annotation type="org.mechfmu.scalars">``) lists them, row-major."""
    root = ElementTree.parse(Path(fmu3.directory) / "modelDescription.xml").getroot()
    listed = {}
    for variable in root.iter("Float64"):
        for annotation in variable.iter("Annotation"):
            if annotation.get("type") == SCALARS_ANNOTATION:
                listed[variable.get("name")] = (annotation.text or "").split()
    return listed


def derive(fmu3) -> ArrayMap:
    """The FMI 2.0 names of the FMI 3.0 FMU ``fmu3`` (an :class:`~.fmu.Fmu`): its
    scalars are FMI 2.0's, and each array's annotation ``org.mechfmu.scalars`` names the FMI
    2.0 variable of every element. An FMU without arrays needs none; another exporter's
    without annotations has its elements named as FMI 3.0 writes them (``y[2]``)."""
    variables = fmu3.md.modelVariables
    arrays = [v for v in variables if v.shape]
    scalars = {v.name for v in variables if v.causality != "independent" and not v.shape}
    if not arrays:
        return ArrayMap(scalars)
    listed = _listed_scalars(fmu3)
    if not listed and not fmu3.by_mechfmu:
        listed = {v.name: [element_name(v.name, tuple(v.shape), k) for k in range(prod(v.shape))] for v in arrays}
    problems = []
    for v in arrays:
        names = listed.get(v.name)
        if names is None:
            problems.append(f"{v.name} has no {SCALARS_ANNOTATION} annotation naming its elements' FMI 2.0 variables")
        elif len(names) != prod(v.shape):
            problems.append(f"{v.name} of shape {tuple(v.shape)} names {len(names)} FMI 2.0 variables")
    if problems:
        raise MappingError(f"{fmu3.model}: " + "; ".join(problems))
    return ArrayMap(
        scalars,
        {v.name: tuple(v.shape) for v in arrays},
        {v.name: listed[v.name] for v in arrays},
        {v.name: [float(x) for x in v.start.split()] for v in arrays if v.start},
    )
