"""A mechanism's interface contract as data: ``fmus/<crate>/validation/contract.toml``, what its
modelDescription.xml must declare (test_contract.py checks every FMU against its file; the
Rust side does not read it).

The file's keys, each refused when misspelt or of the wrong shape:

* ``model``: the model name (the crate's, as ``[package.metadata.mechfmu] model`` says);
* ``default_experiment``: the <DefaultExperiment>'s ``[startTime, stopTime, stepSize]``;
* ``min_zero``: the variables declared with min="0";
* ``event_indicators``: Model Exchange's number of event indicators (0 when left out);
* the variables, a table by kind, each row ``name = ...``:

  ====================== ============================= ====================================
  table                  kind                          a row
  ====================== ============================= ====================================
  [parameters]           parameter, initial exact      ``[variability, start, unit]``
  [inputs]               input, continuous, no initial ``[start, unit]``
  [outputs]              output, continuous, exact     ``[start, unit]``
  [calculated]           output, continuous, no start  ``unit``
  [calculated_parameters] calculatedParameter, fixed   ``unit``
                         or tunable, no start
  ====================== ============================= ====================================

  a unit is the name of a <UnitDefinitions> unit ("1": dimensionless);
* ``[derivatives]``: the <Derivatives>, ``state = "its derivative"`` (unchecked when left out);
* ``[arrays]``: the FMI 3.0 arrays (docs/mechanisms/README.md, "FMI 3.0, arrays"), each the
  FMI 2.0 scalars at its elements, row-major, separated by spaces (test_fmi3.py).
"""

from __future__ import annotations

import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import NamedTuple

#: the variabilities a calculatedParameter may have
CALCULATED = ("fixed", "tunable")


class Variable(NamedTuple):
    """A variable of the contract: a variability is a value or a tuple of the values allowed;
    initial is None for an input (no `initial` attribute), "exact" with the start value given, or
    "calculated" (no start value)."""

    causality: str
    variability: str | tuple[str, ...]
    initial: str | None
    start: float | None
    unit: str


@dataclass(frozen=True)
class Contract:
    """A mechanism's ``validation/contract.toml``."""

    path: Path
    model: str
    default_experiment: tuple[float, float, float]
    variables: dict[str, Variable]
    min_zero: tuple[str, ...] = ()
    derivatives: dict[str, str] | None = None
    arrays: dict[str, str] = field(default_factory=dict)
    event_indicators: int = 0


def read_contract(path: Path, model: str) -> Contract | None:
    """The contract in ``path`` (None when there is no file); a key it does not know, a row of
    the wrong shape or a model other than ``model`` is an error naming the file."""
    if not path.is_file():
        return None
    def fail(what: str) -> ValueError:
        return ValueError(f"{path}: {what}")

    try:
        data = tomllib.loads(path.read_text())
    except tomllib.TOMLDecodeError as e:
        raise fail(f"not TOML: {e}") from None

    def number(x) -> bool:
        return isinstance(x, (int, float)) and not isinstance(x, bool)

    def strings(table: str) -> dict[str, str]:
        rows = data.get(table, {})
        if not isinstance(rows, dict) or not all(isinstance(v, str) for v in rows.values()):
            raise fail(f"[{table}] maps a name to a string")
        return rows

    def rows(table: str, shape: str, ok) -> dict:
        found = data.get(table, {})
        if not isinstance(found, dict):
            raise fail(f"[{table}] is a table")
        for name, row in found.items():
            if not (isinstance(row, list) and ok(row)):
                raise fail(f"[{table}] {name} = {row!r}: a row is {shape}")
        return found

    known = {"model", "default_experiment", "min_zero", "event_indicators", "parameters", "inputs", "outputs",
             "calculated", "calculated_parameters", "derivatives", "arrays"}
    if set(data) - known:
        raise fail(f"unknown keys {sorted(set(data) - known)} (known: {', '.join(sorted(known))})")
    if data.get("model") != model:
        raise fail(f"model = {data.get('model')!r}, the crate's model is {model!r}")
    experiment = data.get("default_experiment")
    if not (isinstance(experiment, list) and len(experiment) == 3 and all(map(number, experiment))):
        raise fail("default_experiment is [startTime, stopTime, stepSize]")
    min_zero = data.get("min_zero", [])
    if not (isinstance(min_zero, list) and all(isinstance(n, str) for n in min_zero)):
        raise fail("min_zero is a list of variable names")
    indicators = data.get("event_indicators", 0)
    if not (isinstance(indicators, int) and not isinstance(indicators, bool) and indicators >= 0):
        raise fail("event_indicators is a count")

    variables = {}
    for name, (variability, start, unit) in rows(
            "parameters", "[variability, start, unit]",
            lambda r: len(r) == 3 and r[0] in CALCULATED and number(r[1]) and isinstance(r[2], str)).items():
        variables[name] = Variable("parameter", variability, "exact", float(start), unit)
    started = lambda r: len(r) == 2 and number(r[0]) and isinstance(r[1], str)  # noqa: E731
    for name, (start, unit) in rows("inputs", "[start, unit]", started).items():
        variables[name] = Variable("input", "continuous", None, float(start), unit)
    for name, (start, unit) in rows("outputs", "[start, unit]", started).items():
        variables[name] = Variable("output", "continuous", "exact", float(start), unit)
    for name, unit in strings("calculated").items():
        variables[name] = Variable("output", "continuous", "calculated", None, unit)
    for name, unit in strings("calculated_parameters").items():
        variables[name] = Variable("calculatedParameter", CALCULATED, "calculated", None, unit)
    twice = [n for n in variables if sum(n in data.get(t, {}) for t in
                                         ("parameters", "inputs", "outputs", "calculated", "calculated_parameters")) > 1]
    if twice:
        raise fail(f"{twice} stand in more than one table")
    return Contract(path, model, tuple(map(float, experiment)), variables, tuple(min_zero),
                    strings("derivatives") if "derivatives" in data else None, strings("arrays"), indicators)
