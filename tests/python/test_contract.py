"""Every FMU against its interface contract (docs/mechanisms/README.md), as FMPy reads it.

The contract of each mechanism is data, next to the mechanism: ``fmus/<crate>/validation/
contract.py`` (``MODEL``, ``DEFAULT_EXPERIMENT``, ``VARIABLES``, ``MIN_ZERO`` and, where the
structure is part of it, ``DERIVATIVES``). The Rust side does not read it. One test checks
every FMU against its file, the same way:

* identity: FMI 2.0, modelName and modelIdentifier, Model Exchange and Co-Simulation
  with the same model identifier, variable communication steps, a GUID;
* the DefaultExperiment's start, stop and step;
* every variable of the contract: present, Real, its causality and variability, its
  `initial` attribute as written (none on an input; "exact" with the contract's start value;
  "calculated" without a start value), a description, its unit by name and by the SI base
  unit exponents of its <UnitDefinitions> entry (written out below for each unit name);
* min="0" on the variables that must be > 0, and the <Derivatives> where the contract has them.

And FMPy's own ``validate_fmu`` finds no problem in any of them.

A contract's ``VARIABLES`` maps a name to (causality, variability, initial, start, unit). A
variability is a value or a tuple of the values allowed; initial is None for an input (no
`initial` attribute), "exact" with the start value given, or "calculated" (no start value);
unit is the name of a <UnitDefinitions> unit ("1": dimensionless).
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path
from types import ModuleType

import pytest

import fmpy
from fmpy.validation import validate_fmu

from fmutest import REPO_ROOT, fmu_path
from mechanisms import mechanisms, models

MECHANISMS = models()

#: the mechanisms the interface contract (docs/mechanisms/README.md) has a section for, `## N. `Name``:
#: each must have its contract file
IN_THE_CONTRACT = re.findall(r"^## \d+\. `(\w+)`", (REPO_ROOT / "docs/mechanisms/README.md").read_text(), re.M)

#: SI base unit exponents (kg, m, s, rad) of each unit name a contract uses; the other base
#: units (A, K, mol, cd) are 0, factor 1, offset 0. None: dimensionless ("1"), which may
#: also come without a <BaseUnit>.
UNIT_DIMS = {
    "kg": (1, 0, 0, 0),
    "m": (0, 1, 0, 0),
    "m/s": (0, 1, -1, 0),
    "m/s2": (0, 1, -2, 0),
    "rad": (0, 0, 0, 1),
    "rad/s": (0, 0, -1, 1),
    "rad/s2": (0, 0, -2, 1),
    "N": (1, 1, -2, 0),
    "N.m": (1, 2, -2, 0),
    "J": (1, 2, -2, 0),
    "N/m": (1, 0, -2, 0),
    "N.s/m": (1, 0, -1, 0),
    "N.s": (1, 1, -1, 0),
    "N.m.s/rad": (1, 2, -1, -1),
    "kg.m2": (1, 2, 0, 0),
    "kg.m2/s": (1, 2, -1, 0),
    "1": None,
}

GUID = re.compile(r"\{?[0-9a-fA-F]{8}-[0-9a-fA-F]{4}-[0-9a-fA-F]{4}-[0-9a-fA-F]{4}-[0-9a-fA-F]{12}\}?")


#: model -> its crate's validation/contract.py
CONTRACTS = {m.model: m.contract for m in mechanisms() if m.contract is not None}


def test_every_mechanism_has_its_contract():
    assert IN_THE_CONTRACT, "no `## N. `Name`` section in docs/mechanisms/README.md"
    missing = [m for m in IN_THE_CONTRACT if m not in CONTRACTS]
    assert not missing, f"no fmus/<crate>/validation/contract.py for {missing}"


def _raw_variables(path: Path) -> dict[str, dict[str, str]]:
    """The <ScalarVariable> attributes exactly as written (fmpy fills in defaults)."""
    with zipfile.ZipFile(path) as z:
        root = ET.fromstring(z.read("modelDescription.xml"))
    return {sv.get("name"): dict(sv.attrib) for sv in root.iter("ScalarVariable")}


def contract_problems(path: Path, contract: ModuleType) -> list[str]:
    """What the FMU at ``path`` declares differently from ``contract`` (empty: it follows it)."""
    model = contract.MODEL
    md = fmpy.read_model_description(str(path), validate=False)
    raw = _raw_variables(path)
    problems: list[str] = []

    def check(ok, what: str) -> None:
        if not ok:
            problems.append(what)

    # identity
    check(md.fmiVersion == "2.0", f"fmiVersion {md.fmiVersion!r}")
    check(md.modelName == model, f"modelName {md.modelName!r}")
    cs = md.coSimulation
    check(cs is not None, "no <CoSimulation> element")
    if cs is not None:
        check(cs.modelIdentifier == model, f"modelIdentifier {cs.modelIdentifier!r}")
        check(cs.canHandleVariableCommunicationStepSize,
              "canHandleVariableCommunicationStepSize must be true (variable communication steps are supported)")
    me = md.modelExchange
    check(me is not None, "no <ModelExchange> element")
    if me is not None:
        check(me.modelIdentifier == model, f"Model Exchange modelIdentifier {me.modelIdentifier!r}")
    check(GUID.fullmatch(md.guid or ""), f"guid {md.guid!r} is not a GUID")

    # the default experiment
    ex = md.defaultExperiment
    check(ex is not None, "no <DefaultExperiment>")
    if ex is not None:
        got = tuple(None if v is None else float(v) for v in (ex.startTime, ex.stopTime, ex.stepSize))
        check(got == tuple(contract.DEFAULT_EXPERIMENT),
              f"DefaultExperiment (startTime, stopTime, stepSize) = {got}, the contract says {contract.DEFAULT_EXPERIMENT}")

    # the variables
    variables = {v.name: v for v in md.modelVariables}
    units = {u.name: u for u in md.unitDefinitions}
    for name, (causality, variability, initial, start, unit) in contract.VARIABLES.items():
        v = variables.get(name)
        if v is None:
            problems.append(f"{name}: missing (has {sorted(variables)})")
            continue
        check(v.type == "Real", f"{name}: type {v.type}")
        check(v.causality == causality, f"{name}: causality {v.causality}, the contract says {causality}")
        allowed = variability if isinstance(variability, tuple) else (variability,)
        check(v.variability in allowed, f"{name}: variability {v.variability}, the contract says {variability}")
        raw_initial = raw[name].get("initial")
        if initial is None:
            check(raw_initial is None, f"{name}: an input must not carry an `initial` attribute (has {raw_initial!r})")
        elif initial == "calculated":
            check(raw_initial in (None, "calculated") and v.initial == "calculated",
                  f"{name}: initial={raw_initial!r} (read as {v.initial!r}), the contract says calculated")
            check(v.start is None, f"{name}: a calculated variable must not have a start value (has {v.start})")
        else:
            check(raw_initial == initial and v.initial == initial,
                  f"{name}: initial={raw_initial!r}, the contract says {initial!r}")
        if start is not None:
            check(v.start is not None and float(v.start) == start, f"{name}: start {v.start}, the contract says {start!r}")
        check(bool(v.description), f"{name} has no description")
        declared = v.unit or (v.declaredType.unit if v.declaredType is not None else None)
        check(declared == unit, f"{name}: unit {declared!r}, the contract says {unit!r}")
        if declared is None:
            continue
        if declared not in units:
            problems.append(f"{name}: unit {declared!r} is not in <UnitDefinitions>")
            continue
        if unit not in UNIT_DIMS:
            problems.append(f"{name}: unit {unit!r} has no SI exponents in test_contract.UNIT_DIMS: add them")
            continue
        bu = units[declared].baseUnit
        if UNIT_DIMS[unit] is None:
            check(bu is None or ((bu.kg, bu.m, bu.s, bu.rad, bu.A, bu.K, bu.mol, bu.cd) == (0,) * 8
                                 and bu.factor == 1.0 and bu.offset == 0.0),
                  f"{name}: unit {declared!r} is not dimensionless")
        elif bu is None:
            problems.append(f"{name}: unit {declared!r} has no <BaseUnit>")
        else:
            check((bu.kg, bu.m, bu.s, bu.rad) == UNIT_DIMS[unit],
                  f"{name}: unit {declared!r}: (kg, m, s, rad) exponents {(bu.kg, bu.m, bu.s, bu.rad)}, "
                  f"expected {UNIT_DIMS[unit]}")
            check((bu.A, bu.K, bu.mol, bu.cd) == (0, 0, 0, 0), f"{name}: unit {declared!r}: A, K, mol, cd exponents")
            check(bu.factor == 1.0 and bu.offset == 0.0, f"{name}: unit {declared!r}: factor {bu.factor}, offset {bu.offset}")

    # bounds and structure
    for name in getattr(contract, "MIN_ZERO", []):
        v = variables.get(name)
        check(v is not None and v.min is not None and float(v.min) == 0.0,
              f"{name} must declare min 0 (has {None if v is None else v.min})")
    derivatives = getattr(contract, "DERIVATIVES", None)
    if derivatives is not None:
        got = {d.variable.derivative.name: d.variable.name for d in md.derivatives}
        check(got == derivatives, f"<Derivatives> (state: derivative) {got}, the contract says {derivatives}")
    return problems


@pytest.mark.parametrize("model", list(CONTRACTS))
def test_fmu_follows_its_contract(model):
    contract = CONTRACTS[model]
    problems = contract_problems(fmu_path(model), contract)
    assert not problems, f"{model} differs from {Path(contract.__file__).relative_to(REPO_ROOT)}:\n" + "\n".join(
        problems)


@pytest.mark.parametrize("model", MECHANISMS)
def test_validate_fmu_reports_no_problems(model):
    problems = validate_fmu(str(fmu_path(model)))
    assert problems == [], "fmpy.validation.validate_fmu found problems:\n" + "\n".join(problems)
