"""The committed FMI 2.0 model descriptions, ``modelDescription/<Name>.xml``, as importers
read them.

* valid against the official FMI 2.0 schema (the XSD FMPy bundles), with lxml, and read by
  FMPy with all its checks on;
* every ``derivative`` points back: a state's ``ScalarVariable`` comes before its
  derivative's (importers that resolve the attribute while reading, OMSimulator's Python
  API, need it), while every variable keeps its value reference, the declaration's order;
* every ``<Real>`` has its ``unit`` (and ``displayUnit``, where its type has one) as well as
  its ``declaredType`` (OMSimulator reads ``unit`` on ``<Real>`` only);
* ``<ModelStructure>``: ``InitialUnknowns`` ordered by index, dependencies ordered by index
  (FMI 2.0.5 section 2.2.8), the knowns of each list only (Outputs and Derivatives: inputs
  and states; InitialUnknowns: inputs and ``initial="exact"``), and the kinds each list
  allows (no ``fixed`` or ``tunable`` among the InitialUnknowns).

Needs no built FMU: it reads the committed XML (regenerate with
``MECHFMU_BLESS=1 cargo test -p <crate> model_description``).
"""

from __future__ import annotations

from pathlib import Path

import pytest
from lxml import etree

import fmpy
from fmpy.model_description import read_model_description

from fmutest import REPO_ROOT

SCHEMA = Path(fmpy.__file__).parent / "schema" / "fmi2" / "fmi2ModelDescription.xsd"
FMI2_DIR = REPO_ROOT / "modelDescription"
MODELS = sorted(p.stem for p in FMI2_DIR.glob("*.xml"))


@pytest.fixture(scope="module")
def schema() -> etree.XMLSchema:
    return etree.XMLSchema(file=str(SCHEMA))


def _root(model: str) -> etree._Element:
    return etree.parse(str(FMI2_DIR / f"{model}.xml")).getroot()


def test_there_are_descriptions():
    assert MODELS, f"no model descriptions in {FMI2_DIR}"


@pytest.mark.parametrize("model", MODELS)
def test_valid_against_the_fmi2_schema_and_read_by_fmpy(model, schema):
    root = etree.parse(str(FMI2_DIR / f"{model}.xml"))
    assert schema.validate(root), "\n".join(f"line {e.line}: {e.message}" for e in schema.error_log)
    md = read_model_description(str(FMI2_DIR / f"{model}.xml"), validate=True,
                                validate_variable_names=True, validate_model_structure=True)
    assert md.fmiVersion == "2.0" and md.modelName == model


@pytest.mark.parametrize("model", MODELS)
def test_every_derivative_points_back_and_value_references_are_the_declarations(model):
    variables = _root(model).find("ModelVariables").findall("ScalarVariable")
    for index, sv in enumerate(variables, start=1):
        state = sv.find("Real").get("derivative")
        if state is not None:
            assert int(state) < index, (
                f"{sv.get('name')} (index {index}) is the derivative of index {state}, written after it")
    references = sorted(int(sv.get("valueReference")) for sv in variables)
    assert references == list(range(len(variables)))


@pytest.mark.parametrize("model", MODELS)
def test_every_real_carries_the_unit_of_its_type(model):
    root = _root(model)
    types = {t.get("name"): t.find("Real") for t in root.iter("SimpleType")}
    for sv in root.find("ModelVariables").findall("ScalarVariable"):
        real = sv.find("Real")
        declared = types.get(real.get("declaredType"))
        assert declared is not None, f"{sv.get('name')} has no declared type"
        assert real.get("unit") == declared.get("unit") is not None, sv.get("name")
        assert real.get("displayUnit") == declared.get("displayUnit"), sv.get("name")


@pytest.mark.parametrize("model", MODELS)
def test_model_structure_lists_the_knowns_of_each_list_in_index_order(model):
    md = read_model_description(str(FMI2_DIR / f"{model}.xml"), validate=False)
    variables = md.modelVariables
    index = {id(v): i for i, v in enumerate(variables, start=1)}
    states = {id(d.variable.derivative) for d in md.derivatives}
    inputs = {id(v) for v in variables if v.causality == "input"}
    exact = {id(v) for v in variables if v.initial == "exact"}
    for name, unknowns, knowns, kinds in [
        ("Outputs", md.outputs, inputs | states, {"dependent", "constant", "fixed", "tunable"}),
        ("Derivatives", md.derivatives, inputs | states, {"dependent", "constant", "fixed", "tunable"}),
        ("InitialUnknowns", md.initialUnknowns, inputs | exact, {"dependent", "constant"}),
    ]:
        for u in unknowns:
            assert u.dependencies is not None and len(u.dependenciesKind) == len(u.dependencies)
            positions = [index[id(d)] for d in u.dependencies]
            assert positions == sorted(positions), f"{name} {u.variable.name}: {positions}"
            others = [d.name for d in u.dependencies if id(d) not in knowns]
            assert not others, f"{name} {u.variable.name} depends on {others}, which are no knowns there"
            assert set(u.dependenciesKind) <= kinds, f"{name} {u.variable.name}: {u.dependenciesKind}"
    order = [index[id(u.variable)] for u in md.initialUnknowns]
    assert order == sorted(order)
