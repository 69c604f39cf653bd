"""Every FMU against its interface contract (docs/mechanisms/README.md), as FMPy reads it.

The contract of each mechanism is data, next to the mechanism: ``fmus/<crate>/validation/
contract.toml`` (its format: contracts.py). The Rust side does not read it. One test checks
every FMU against its file, the same way:

* identity: FMI 2.0, modelName and modelIdentifier, Model Exchange and Co-Simulation
  with the same model identifier, variable communication steps, a GUID;
* the DefaultExperiment's start, stop and step;
* every variable of the contract: present, Real, its causality and variability, its
  `initial` attribute as written (none on an input; "exact" with the contract's start value;
  "calculated" without a start value), a description, its unit by name and by the SI base
  unit exponents of its <UnitDefinitions> entry (written out below for each unit name);
* min="0" on the variables that must be > 0, and the <Derivatives> where the contract has them.

And FMPy's own ``validate_fmu`` finds no problem in any of them; and a contract file with a
misspelt key or a row of the wrong shape is refused, naming it.
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
import zipfile
from pathlib import Path

import pytest

import fmpy
from fmpy.validation import validate_fmu

from contracts import Contract, read_contract
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
    "N.m/rad": (1, 2, -2, -1),
    "N.s/rad": (1, 1, -1, -1),
    "kg.m2": (1, 2, 0, 0),
    "kg.m2/s": (1, 2, -1, 0),
    "1": None,
}

GUID = re.compile(r"\{?[0-9a-fA-F]{8}-[0-9a-fA-F]{4}-[0-9a-fA-F]{4}-[0-9a-fA-F]{4}-[0-9a-fA-F]{12}\}?")


#: model -> its crate's validation/contract.toml
CONTRACTS = {m.model: m.contract for m in mechanisms() if m.contract is not None}


def test_every_mechanism_has_its_contract():
    assert IN_THE_CONTRACT, "no `## N. `Name`` section in docs/mechanisms/README.md"
    missing = [m for m in IN_THE_CONTRACT if m not in CONTRACTS]
    assert not missing, f"no fmus/<crate>/validation/contract.toml for {missing}"


def _raw_variables(path: Path) -> dict[str, dict[str, str]]:
    """The <ScalarVariable> attributes exactly as written (fmpy fills in defaults)."""
    with zipfile.ZipFile(path) as z:
        root = ET.fromstring(z.read("modelDescription.xml"))
    return {sv.get("name"): dict(sv.attrib) for sv in root.iter("ScalarVariable")}


def contract_problems(path: Path, contract: Contract) -> list[str]:
    """What the FMU at ``path`` declares differently from ``contract`` (empty: it follows it)."""
    model = contract.model
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
        check(got == contract.default_experiment,
              f"DefaultExperiment (startTime, stopTime, stepSize) = {got}, the contract says {contract.default_experiment}")

    # the variables
    variables = {v.name: v for v in md.modelVariables}
    units = {u.name: u for u in md.unitDefinitions}
    for name, (causality, variability, initial, start, unit) in contract.variables.items():
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
    for name in contract.min_zero:
        v = variables.get(name)
        check(v is not None and v.min is not None and float(v.min) == 0.0,
              f"{name} must declare min 0 (has {None if v is None else v.min})")
    derivatives = contract.derivatives
    if derivatives is not None:
        got = {d.variable.derivative.name: d.variable.name for d in md.derivatives}
        check(got == derivatives, f"<Derivatives> (state: derivative) {got}, the contract says {derivatives}")
    return problems


@pytest.mark.parametrize("model", list(CONTRACTS))
def test_fmu_follows_its_contract(model):
    contract = CONTRACTS[model]
    problems = contract_problems(fmu_path(model), contract)
    assert not problems, f"{model} differs from {contract.path.relative_to(REPO_ROOT)}:\n" + "\n".join(
        problems)


@pytest.mark.parametrize("model", MECHANISMS)
def test_validate_fmu_reports_no_problems(model):
    problems = validate_fmu(str(fmu_path(model)))
    assert problems == [], "fmpy.validation.validate_fmu found problems:\n" + "\n".join(problems)


def test_a_contract_file_with_a_mistake_is_refused_naming_it(tmp_path):
    """A misspelt key would drop a check silently, and a row of the wrong shape would check the
    wrong thing: both are refused, naming the file and what is wrong."""
    path = tmp_path / "contract.toml"
    good = 'model = "Cart"\ndefault_experiment = [0.0, 1.0, 0.1]\n[parameters]\nm = ["fixed", 1.0, "kg"]\n'
    path.write_text(good)
    contract = read_contract(path, "Cart")
    assert contract.variables["m"] == ("parameter", "fixed", "exact", 1.0, "kg") and contract.event_indicators == 0
    for text, said in [("min_zer0 = ['m']\n" + good, "unknown keys ['min_zer0']"),
                       (good.replace('"fixed", 1.0', '"fixed", "1.0"'), "[parameters] m = ['fixed', '1.0', 'kg']"),
                       (good + '[calculated]\nm = "kg"\n', "['m'] stand in more than one table"),
                       (good.replace('"Cart"', '"Cat"'), "model = 'Cat', the crate's model is 'Cart'"),
                       (good.replace("[0.0, 1.0, 0.1]", "[0.0, 1.0]"), "default_experiment is"),
                       (good.replace("= [", "= [[", 1), "not TOML")]:
        path.write_text(text)
        with pytest.raises(ValueError) as refused:
            read_contract(path, "Cart")
        assert str(refused.value).startswith(f"{path}: ") and said in str(refused.value), str(refused.value)
    assert read_contract(tmp_path / "none.toml", "Cart") is None
