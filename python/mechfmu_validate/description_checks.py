"""The checks of an FMI 2.0 model description beyond FMPy's validation: value references and
their aliases (FMI 2.0 allows variables to share one: one value, so one type, no constant
beside a variable, no two start values that differ), no ``initial`` on inputs and a start
value on each, start within [min, max], every Real variable with a unit and every unit and
display unit used defined. An FMU built by another exporter is held to the standard, not to
mechfmu's own rules (see :mod:`.checks`).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
import zipfile

from .check import Check
from .fmu import Fmu

__all__ = ["check_model_description"]


def _raw_variables(root: ET.Element) -> list[ET.Element]:
    mv = root.find("ModelVariables")
    return list(mv.findall("ScalarVariable")) if mv is not None else []


def _type_element(sv: ET.Element) -> ET.Element | None:
    for tag in ("Real", "Integer", "Boolean", "String", "Enumeration"):
        e = sv.find(tag)
        if e is not None:
            return e
    return None


#: FMI 2.0's base types, by which value references are shared (fmi2GetInteger reads both)
BASE_TYPE = {"Real": "Real", "Integer": "Integer", "Enumeration": "Integer", "Boolean": "Boolean", "String": "String"}

#: the clause of the standard the alias rules are (FMI 2.0.5, section 2.2.7, ScalarVariable)
ALIASES = "FMI 2.0.5 §2.2.7"


def _alias_set_problems(members: list[tuple[ET.Element, ET.Element | None]], types: dict[str, ET.Element],
                        key: tuple[str, str]) -> tuple[list[str], list[str]]:
    """What makes an alias set (the variables of one base type and one value reference) not
    one value: (problems, notes)."""
    problems, notes = [], []
    where = f"the {key[0]} value reference {key[1]} ({', '.join(sv.get('name') for sv, _ in members)})"
    kinds = sorted({e.tag for _, e in members if e is not None})
    if len(kinds) > 1:
        problems.append(f"{ALIASES} valueReference: {where} is one value, of one type, but declared "
                        f"{' and '.join(kinds)}")
    constant = [sv.get("name") for sv, _ in members if sv.get("variability") == "constant"]
    if constant and len(constant) < len(members):
        problems.append(f"{ALIASES} variability: {where} mixes constants ({', '.join(constant)}) with variables "
                        "that change: one value cannot be both")
    starts = {sv.get("name"): e.get("start") for sv, e in members if e is not None and e.get("start") is not None}
    given = {n: v for n, v in starts.items() if n not in constant}
    kind = next((e.tag for _, e in members if e is not None), "")
    values = {n: _start_value(kind, v) for n, v in starts.items()}
    if len({values[n] for n in given}) > 1 or (constant and len(set(values.values())) > 1):
        problems.append(f"{ALIASES} start: {where} has conflicting start values "
                        f"({', '.join(f'{n}={v}' for n, v in starts.items())})")
    elif len(given) > 1:
        notes.append(f"{ALIASES} start: {where}: {len(given)} aliases give the same start value; the standard "
                     "asks for at most one")
    variabilities = {sv.get("variability") or "continuous" for sv, _ in members}
    if len(variabilities) > 1 and not constant:
        notes.append(f"{where}: aliases of variabilities {', '.join(sorted(variabilities))}")

    units = {_unit(e, types) for _, e in members if e is not None} - {None}
    if len(units) > 1:
        notes.append(f"{where}: aliases in units {', '.join(sorted(units))}")
    return problems, notes


def _unit(e: ET.Element, types: dict[str, ET.Element]) -> str | None:
    """A variable's unit, its own or its declared type's."""
    dt = types.get(e.get("declaredType")) if e.get("declaredType") else None
    return e.get("unit") or (dt.get("unit") if dt is not None else None)


def check_value_references(fmu: Fmu, svs: list[ET.Element], types: dict[str, ET.Element]) -> Check:
    """Variables of one base type sharing a value reference are aliases, which FMI 2.0 allows
    (FMI 2.0.5 section 2.2.7, valueReference): one value, so one type, no constant beside a
    variable, no two different start values. Aliases of different variabilities or units
    are notes. mechfmu declares no aliases: in its own FMUs a shared value reference is a
    fault."""
    c = Check("value references and aliases")
    sets: dict[tuple[str, str], list[tuple[ET.Element, ET.Element | None]]] = {}
    for sv in svs:
        e = _type_element(sv)
        key = (BASE_TYPE.get(e.tag, e.tag) if e is not None else "?", sv.get("valueReference"))
        sets.setdefault(key, []).append((sv, e))
    for key, members in sets.items():
        if len(members) < 2:
            continue
        if fmu.by_mechfmu:
            c.problems.append(f"{', '.join(sv.get('name') for sv, _ in members)} share the {key[0]} value reference "
                              f"{key[1]} (mechfmu declares no aliases)")
            continue
        problems, notes = _alias_set_problems(members, types, key)
        c.problems += problems
        c.notes += notes
    aliased = sum(len(m) > 1 for m in sets.values())
    if aliased and not fmu.by_mechfmu:
        c.notes.insert(0, f"{aliased} alias sets (variables sharing a value reference, {ALIASES}: allowed)")
    return c


def check_model_description(fmu: Fmu) -> list[Check]:
    """Value references, initial on inputs, start within bounds, units."""
    with zipfile.ZipFile(fmu.path) as z:
        root = ET.fromstring(z.read("modelDescription.xml"))
    svs = _raw_variables(root)
    types = {}
    td = root.find("TypeDefinitions")
    if td is not None:
        for st in td.findall("SimpleType"):
            e = _type_element(st)
            if e is not None:
                types[st.get("name")] = e
    units = {}
    ud = root.find("UnitDefinitions")
    if ud is not None:
        for u in ud.findall("Unit"):
            units[u.get("name")] = u

    vr = check_value_references(fmu, svs, types)

    inputs = Check("no initial on inputs")
    for sv in svs:
        if sv.get("causality") == "input" and sv.get("initial") is not None:
            inputs.problems.append(f"FMI 2.0.5 §2.2.7 initial: input {sv.get('name')} has "
                                   f"initial=\"{sv.get('initial')}\" (inputs carry no initial attribute)")
        if sv.get("causality") == "input":
            e = _type_element(sv)
            if e is not None and e.get("start") is None:
                inputs.problems.append(f"FMI 2.0.5 §2.2.7 start: input {sv.get('name')} has no start value "
                                       "(an input must have one)")

    bounds = Check("start within [min, max]")
    for sv in svs:
        e = _type_element(sv)
        if e is None or e.get("start") is None or e.tag not in ("Real", "Integer"):
            continue
        dt = types.get(e.get("declaredType")) if e.get("declaredType") else None

        def attr(name):
            v = e.get(name)
            if v is None and dt is not None:
                v = dt.get(name)
            return float(v) if v is not None else None

        start, lo, hi = float(e.get("start")), attr("min"), attr("max")
        if lo is not None and hi is not None and lo > hi:
            bounds.problems.append(f"{sv.get('name')}: min {lo} > max {hi} (no value is within both)")
        # the range an FMU is designed to operate in (FMI 2.0.5 §2.2.7 min, max): mechfmu
        # starts every variable within it; another exporter's start outside it is a note
        outside = bounds.problems if fmu.by_mechfmu else bounds.notes
        if lo is not None and start < lo:
            outside.append(f"{sv.get('name')}: start {start} < min {lo}")
        if hi is not None and start > hi:
            outside.append(f"{sv.get('name')}: start {start} > max {hi}")

    un = Check("units declared and defined")
    # mechfmu's rules, beyond the standard's: problems for its own FMUs, notes for others'
    policy = un.problems if fmu.by_mechfmu else un.notes
    for name, u in units.items():
        if u.find("BaseUnit") is None:
            policy.append(f"unit {name} has no <BaseUnit>")
    for tname, e in types.items():
        if e.tag == "Real" and e.get("unit") is not None and e.get("unit") not in units:
            un.problems.append(f"type {tname} uses unit {e.get('unit')}, not in <UnitDefinitions>")
    for sv in svs:
        e = _type_element(sv)
        if e is None or e.tag != "Real":
            continue
        dt = types.get(e.get("declaredType")) if e.get("declaredType") else None
        if e.get("declaredType") and dt is None:
            un.problems.append(f"{sv.get('name')}: declaredType {e.get('declaredType')} is not defined")
        unit = e.get("unit") or (dt.get("unit") if dt is not None else None)
        display = e.get("displayUnit") or (dt.get("displayUnit") if dt is not None else None)
        if unit is None:
            policy.append(f"{sv.get('name')} declares no unit (use \"1\" for a dimensionless quantity)")
            continue
        if unit not in units:
            un.problems.append(f"{sv.get('name')}: unit {unit} is not in <UnitDefinitions>")
        elif display is not None:
            names = [d.get("name") for d in units[unit].findall("DisplayUnit")]
            if display not in names:
                un.problems.append(f"{sv.get('name')}: display unit {display} is not defined under unit {unit}")
    return [vr, inputs, bounds, un]


def _start_value(kind: str, text: str) -> float | bool | str:
    """A start attribute as the value it writes (``1`` and ``1.0`` are one Real)."""
    try:
        if kind in ("Real", "Integer", "Enumeration"):
            return float(text)
        if kind == "Boolean":
            return text.strip() in ("true", "1")
    except ValueError:
        pass
    return text
