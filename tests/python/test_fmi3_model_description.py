"""The committed FMI 3.0 model descriptions, ``modelDescription/fmi3/<Name>.xml``, as an
importer reads them.

* valid against the official FMI 3.0 schema (the XSD FMPy bundles), with lxml;
* every capability flag of <ModelExchange> and <CoSimulation> is one the schema declares
  (the interface types accept any other attribute, so the XSD alone lets a misspelt flag
  through);
* FMPy reads it with all its checks on (structured variable names, the ModelStructure's
  outputs, derivatives and initial unknowns, start values, units, one independent variable,
  unique value references);
* it shows the FMI 2.0 description's variables: the scalars of the arrays of
  docs/mechanisms/README.md ("FMI 3.0, arrays") grouped into arrays of their shape, start values
  element by element, every other scalar as it is, every variable with its 1-based place in
  the document for value reference (each state before its derivative), and ``time``, listed
  last, with value reference 0;
* ``<ModelStructure>`` as FMI 3.0 section 2.4.8 defines each list's knowns: ``<Output>``,
  ``<ContinuousStateDerivative>`` and ``<EventIndicator>`` depend on inputs, continuous states,
  parameters and the time only, ``<InitialUnknown>`` on inputs, ``initial="exact"`` variables and
  the time only, without the kinds that list does not allow (``fixed``, ``tunable``); every
  ``derivative`` points back, as in FMI 2.0.

Needs no built FMU: it reads the committed XML (regenerate with
``MECHFMU_BLESS=1 cargo test -p <crate> model_description``).
"""

from __future__ import annotations

from math import prod
from pathlib import Path

import pytest
from lxml import etree

import fmpy
from fmpy.model_description import read_model_description

from fmutest import REPO_ROOT

SCHEMA_DIR = Path(fmpy.__file__).parent / "schema" / "fmi3"
FMI2_DIR = REPO_ROOT / "modelDescription"
FMI3_DIR = FMI2_DIR / "fmi3"

#: model -> array -> (shape, the scalars it replaces in row-major order). The arrays of
#: docs/mechanisms/README.md, and the derivatives of its state arrays `w` and `q` (FMI 3.0 wants a
#: state array's derivative to be an array of the same shape).
ARRAYS: dict[str, dict[str, tuple[tuple[int, ...], list[str]]]] = {
    "RigidBody": {
        "I_C": ((3, 3), "I_xx I_xy I_xz I_xy I_yy I_yz I_xz I_yz I_zz".split()),
        "r_C": ((3,), ["r_Cx", "r_Cy", "r_Cz"]),
        "tau": ((3,), ["tau_x", "tau_y", "tau_z"]),
        "w": ((3,), ["w_x", "w_y", "w_z"]),
        "q": ((4,), ["q_w", "q_x", "q_y", "q_z"]),
        "H": ((3,), ["H_X", "H_Y", "H_Z"]),
        "w_dot": ((3,), ["w_x_dot", "w_y_dot", "w_z_dot"]),
        "q_dot": ((4,), ["q_w_dot", "q_x_dot", "q_y_dot", "q_z_dot"]),
        "I_principal": ((3,), ["I_1", "I_2", "I_3"]),
    },
    "TwoMassOscillator": {
        "M": ((2, 2), ["M_11", "M_12", "M_12", "M_22"]),
        "K": ((2, 2), ["K_11", "K_12", "K_12", "K_22"]),
        "C": ((2, 2), ["C_11", "C_12", "C_12", "C_22"]),
        "modes": ((2, 2), ["mode1_x1", "mode2_x1", "mode1_x2", "mode2_x2"]),
    },
}

MODELS = sorted(p.stem for p in FMI2_DIR.glob("*.xml"))


def test_every_fmi2_description_has_its_fmi3_one():
    assert MODELS, f"no model descriptions in {FMI2_DIR}"
    assert sorted(p.stem for p in FMI3_DIR.glob("*.xml")) == MODELS


@pytest.fixture(scope="module")
def schema() -> etree.XMLSchema:
    return etree.XMLSchema(file=str(SCHEMA_DIR / "fmi3ModelDescription.xsd"))


def _declared_attributes(xsd: Path) -> set[str]:
    tree = etree.parse(str(xsd))
    return {a.get("name") for a in tree.iter("{http://www.w3.org/2001/XMLSchema}attribute")}


@pytest.mark.parametrize("model", MODELS)
def test_valid_against_the_fmi3_schema(model, schema):
    root = etree.parse(str(FMI3_DIR / f"{model}.xml"))
    assert schema.validate(root), "\n".join(f"line {e.line}: {e.message}" for e in schema.error_log)
    flags = _declared_attributes(SCHEMA_DIR / "fmi3InterfaceType.xsd")
    for element in ("ModelExchange", "CoSimulation"):
        written = set(root.find(element).attrib)
        assert written <= flags, f"<{element}> attributes the schema does not declare: {written - flags}"


def _read(model: str):
    fmi3 = read_model_description(str(FMI3_DIR / f"{model}.xml"), validate=True,
                                  validate_variable_names=True, validate_model_structure=True)
    fmi2 = read_model_description(str(FMI2_DIR / f"{model}.xml"), validate=False)
    return fmi3, fmi2


@pytest.mark.parametrize("model", MODELS)
def test_fmpy_reads_it_with_its_checks(model):
    fmi3, fmi2 = _read(model)  # raises fmpy's ValidationError with the problems it finds
    assert fmi3.fmiVersion == "3.0"
    assert fmi3.modelName == model == fmi2.modelName
    assert fmi3.variableNamingConvention == "structured"
    assert fmi3.modelExchange.modelIdentifier == fmi3.coSimulation.modelIdentifier == model
    assert fmi3.instantiationToken and fmi3.instantiationToken != fmi2.guid
    assert fmi3.defaultExperiment.stopTime == fmi2.defaultExperiment.stopTime


@pytest.mark.parametrize("model", MODELS)
def test_the_fmi2_variables_grouped_into_arrays(model):
    fmi3, fmi2 = _read(model)
    arrays = ARRAYS.get(model, {})
    scalars = {v.name: v for v in fmi2.modelVariables}
    variables = {v.name: v for v in fmi3.modelVariables}
    replaced = {name for _, elements in arrays.values() for name in elements}

    # time: the independent variable, with value reference 0 (as the Reference-FMUs number it),
    # listed last
    time = variables["time"]
    assert (time.causality, time.variability, time.start) == ("independent", "continuous", None)
    assert time.valueReference == 0
    assert fmi3.modelVariables[-1] is time

    # as many variables as the scalars less those grouped, plus the arrays and the time;
    # each one's value reference is its 1-based place in the document (an importer that reads
    # FMI 3.0's `derivative` as a 1-based place, FMI 2.0's meaning, finds the state)
    assert len(fmi3.modelVariables) == len(scalars) - len(replaced) + len(arrays) + 1
    assert [v.valueReference for v in fmi3.modelVariables] == [*range(1, len(fmi3.modelVariables)), 0]
    for name, (shape, elements) in arrays.items():
        v = variables[name]
        first = scalars[elements[0]]
        assert v.shape == shape and prod(shape) == len(elements), name
        assert (v.causality, v.variability) == (first.causality, first.variability), name
        assert v.unit == (first.unit or first.declaredType.unit), name
        if first.start is None:
            assert v.start is None, name
        else:
            assert [float(x) for x in v.start.split()] == [float(scalars[e].start) for e in elements], name
    for name, s in scalars.items():
        if name in replaced:
            assert name not in variables or name in arrays, name
            continue
        v = variables[name]
        assert v.shape == (), name
        assert (v.causality, v.variability, v.initial) == (s.causality, s.variability, s.initial), name
        assert v.start == s.start, name
        assert v.unit == (s.unit or s.declaredType.unit), name

    # as many continuous states, in declaration order
    assert fmi3.numberOfContinuousStates == len(fmi2.derivatives)
    states = [d.variable.derivative.valueReference for d in fmi3.derivatives]
    assert states == sorted(states)


@pytest.mark.parametrize("model", MODELS)
def test_dependencies_are_the_knowns_of_each_list(model):
    fmi3, _ = _read(model)
    variables = fmi3.modelVariables
    states = {id(d.variable.derivative) for d in fmi3.derivatives}
    independent = {id(v) for v in variables if v.causality == "independent"}
    inputs = {id(v) for v in variables if v.causality == "input"}
    parameters = {id(v) for v in variables if v.causality == "parameter"}
    exact = {id(v) for v in variables if v.initial == "exact" or v.causality == "parameter"}
    continuous_time = inputs | states | parameters | independent
    every_kind = {"dependent", "constant", "fixed", "tunable"}
    for name, unknowns, knowns, kinds in [
        ("Output", fmi3.outputs, continuous_time, every_kind),
        ("ContinuousStateDerivative", fmi3.derivatives, continuous_time, every_kind),
        ("EventIndicator", fmi3.eventIndicators, continuous_time, every_kind),
        ("InitialUnknown", fmi3.initialUnknowns, inputs | exact | independent, {"dependent", "constant"}),
    ]:
        for u in unknowns:
            if u.dependencies is None:
                # "depends on all knowns" (section 2.4.8): how we write a list of every known
                assert u.dependenciesKind is None, f"{name} {u.variable.name}: kinds without dependencies"
                continue
            assert len(u.dependenciesKind) == len(u.dependencies)
            assert {id(d) for d in u.dependencies} != knowns, (
                f"{name} {u.variable.name} lists every known: written without dependencies instead"
            )
            others = [d.name for d in u.dependencies if id(d) not in knowns]
            assert not others, f"{name} {u.variable.name} depends on {others}, which are no knowns there"
            assert set(u.dependenciesKind) <= kinds, f"{name} {u.variable.name}: {u.dependenciesKind}"
            references = [d.valueReference for d in u.dependencies]
            assert references == sorted(references)


@pytest.mark.parametrize("model", MODELS)
def test_every_derivative_points_back(model):
    variables = list(etree.parse(str(FMI3_DIR / f"{model}.xml")).getroot().find("ModelVariables"))
    seen: set[str] = set()
    for v in variables:
        state = v.get("derivative")
        assert state is None or state in seen, f"{v.get('name')} is the derivative of {state}, written after it"
        seen.add(v.get("valueReference"))
