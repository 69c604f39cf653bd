"""The mechanisms of a workspace and what the test suite expects of each, read from their crates.

The list is cargo's: every package of the workspace whose Cargo.toml names its model in
``[package.metadata.mechfmu] model = "Name"`` (as ``mechfmu build`` finds them), and every
system that is compiled into one FMU (``system = "Name"`` and the feature ``fmu``). What a test
expects of one mechanism lives in its crate's ``validation/`` folder, next to its reference
cases (``cases.py``):

* ``contract.toml``: its interface contract (contracts.py reads it; test_contract.py checks the
  FMU against it, and the FMI 3.0 arrays and the number of event indicators are read from it
  too), where the mechanism has one;
* ``expectations.toml``: the rows where an importer's solver does not reach a case's limit
  (``[[limit]]``: case, importer, why) and a parameter sweep run by both engines of
  ``mechfmu sweep`` (``[sweep] parameters``); a mechanism without the file expects neither.

Adding a mechanism is adding its crate: every test that runs on every mechanism finds it here.
"""

from __future__ import annotations

import json
import shutil
import subprocess
import tempfile
import tomllib
from dataclasses import dataclass
from functools import cache
from pathlib import Path

from contracts import Contract, Variable, read_contract
from fmutest import FMU_DIR
from mechfmu_validate.systems import archive
from mechfmu_validate.importers.fmi_crate import RK4
from mechfmu_validate.importers.fmpy import CVODE, EULER

REPO_ROOT = Path(__file__).resolve().parents[2]

#: the importers whose rows may be a known LIMIT: the Model Exchange ones with a solver of the importer's
LIMIT_IMPORTERS = (CVODE, EULER, RK4)


@dataclass(frozen=True)
class Limit:
    """A (case, importer) row reported as LIMIT: the importer's solver, not the FMU, misses the case's limit."""

    case: str
    importer: str
    why: str


@dataclass(frozen=True)
class Expectations:
    """A mechanism's ``validation/expectations.toml``."""

    limits: tuple[Limit, ...] = ()
    sweep_parameters: tuple[str, ...] = ()


@dataclass(frozen=True)
class Mechanism:
    """One mechanism crate of the workspace (or a system crate compiled into one FMU)."""

    model: str
    package: str
    crate: Path
    #: a system: its FMU's contract is its components', connected as its SSP says
    system: bool = False

    @property
    def validation(self) -> Path:
        return self.crate / "validation"

    @property
    def cases_file(self) -> Path:
        return self.validation / "cases.py"

    @property
    def contract(self) -> Contract | None:
        """``validation/contract.toml``, or None; a system's, from its components' (see
        :func:`system_contract`)."""
        if self.system:
            return system_contract(self.model)
        return _contract(self.validation / "contract.toml", self.model)

    @property
    def expectations(self) -> Expectations:
        return read_expectations(self.validation / "expectations.toml")


def mechanisms(manifest: Path | None = None) -> list[Mechanism]:
    """The mechanism crates of the workspace at ``manifest`` (the repository's, read once), by
    model name."""
    return list(_repository() if manifest is None else _read(Path(manifest).resolve()))


@cache
def _repository() -> tuple[Mechanism, ...]:
    return _read(REPO_ROOT / "Cargo.toml")


def _read(manifest: Path) -> tuple[Mechanism, ...]:
    done = subprocess.run(["cargo", "metadata", "--format-version", "1", "--no-deps", "--manifest-path",
                           str(manifest)], cwd=manifest.parent, capture_output=True, text=True, check=False)
    if done.returncode != 0:
        raise RuntimeError(f"cargo metadata failed for {manifest}:\n{done.stderr}")
    found = []
    for package in json.loads(done.stdout)["packages"]:
        declared = (package.get("metadata") or {}).get("mechfmu") or {}
        # a system compiled into one FMU (its feature `fmu`) is an FMU like a mechanism's
        one_fmu = "system" in declared and "fmu" in package.get("features", {})
        model = declared.get("model") or (declared["system"] if one_fmu else None)
        if model:
            found.append(Mechanism(model, package["name"], Path(package["manifest_path"]).parent, one_fmu))
    return tuple(sorted(found, key=lambda m: m.model))


def systems() -> list[tuple[str, Path]]:
    """The repository's systems: ``(name, crate folder)`` for every package whose Cargo.toml
    names a system (``[package.metadata.mechfmu] system = "Name"``)."""
    done = subprocess.run(["cargo", "metadata", "--format-version", "1", "--no-deps", "--manifest-path",
                           str(REPO_ROOT / "Cargo.toml")], capture_output=True, text=True, check=True)
    found = []
    for package in json.loads(done.stdout)["packages"]:
        name = ((package.get("metadata") or {}).get("mechfmu") or {}).get("system")
        if name:
            found.append((name, Path(package["manifest_path"]).parent))
    return sorted(found)


def models() -> list[str]:
    """The model names of the repository's mechanisms."""
    return [m.model for m in mechanisms()]


def mechanism(model: str) -> Mechanism:
    """The repository's mechanism named ``model``."""
    return next(m for m in mechanisms() if m.model == model)


def known_limits() -> dict[tuple[str, str, str], str]:
    """(model, case, importer) -> why, over every mechanism of the repository."""
    return {(m.model, limit.case, limit.importer): limit.why for m in mechanisms() for limit in m.expectations.limits}


def read_expectations(path: Path) -> Expectations:
    """The expectations in ``path`` (none when it does not exist); a key or importer it does not
    know is an error naming the file."""
    if not path.is_file():
        return Expectations()
    data = tomllib.loads(path.read_text())

    def fail(what: str) -> ValueError:
        return ValueError(f"{path}: {what}")

    unknown = set(data) - {"limit", "sweep"}
    if unknown:
        raise fail(f"unknown keys {sorted(unknown)} (known: limit, sweep)")
    limits = []
    for row in data.get("limit", []):
        if set(row) != {"case", "importer", "why"} or not all(isinstance(v, str) for v in row.values()):
            raise fail(f"a [[limit]] has exactly case, importer and why, as strings: {row}")
        if row["importer"] not in LIMIT_IMPORTERS:
            raise fail(f"importer {row['importer']!r} is not one of {list(LIMIT_IMPORTERS)}")
        limits.append(Limit(row["case"], row["importer"], row["why"]))
    sweep = data.get("sweep", {})
    if set(sweep) - {"parameters"}:
        raise fail(f"unknown keys in [sweep]: {sorted(set(sweep) - {'parameters'})} (known: parameters)")
    parameters = sweep.get("parameters", [])
    if not isinstance(parameters, list) or not all(isinstance(p, str) for p in parameters):
        raise fail("[sweep] parameters is a list of `--param` values (strings)")
    return Expectations(tuple(limits), tuple(parameters))


@cache
def _contract(path: Path, model: str) -> Contract | None:
    return read_contract(path, model)


@cache
def system_contract(model: str) -> Contract:
    """The contract of the system ``model`` compiled into one FMU (docs/mechanisms/README.md,
    section 10), from what its SSP (``fmus/<model>.ssp``) says of it and its components'
    contracts: each component's variables named ``component.variable``, an input a connection
    feeds a local variable without start value, the ``default`` set's values as start values,
    the states' derivatives and the event indicators the components'. A component's FMI 3.0
    arrays are scalars there (a system has none)."""
    folder = Path(tempfile.mkdtemp(prefix="mechfmu-contract-"))
    try:
        ssp = archive.read(FMU_DIR / f"{model}.ssp", folder)
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    fed = {to for _, to in ssp.connections}
    default = ssp.sets.get("default", {})
    variables, min_zero, derivatives, indicators = {}, [], {}, 0
    unchecked = False  # a component's contract leaves its derivatives unchecked
    for component in ssp.components:
        part = mechanism(Path(component.source).stem).contract
        assert part is not None, f"{model}: component {component.name} ({component.source}) has no contract"
        name = lambda n: f"{component.name}.{n}"  # noqa: E731
        for n, v in part.variables.items():
            if (component.name, n) in fed:
                v = Variable("local", "continuous", "calculated", None, v.unit)
            elif v.start is not None and (component.name, n) in default:
                v = v._replace(start=default[(component.name, n)])
            variables[name(n)] = v
        min_zero += [name(n) for n in part.min_zero]
        unchecked |= part.derivatives is None
        derivatives.update({name(s): name(d) for s, d in (part.derivatives or {}).items()})
        indicators += part.event_indicators
    return Contract(FMU_DIR / f"{model}.ssp", model, (ssp.start, ssp.stop, ssp.step), variables, tuple(min_zero),
                    None if unchecked else derivatives, {}, indicators)
