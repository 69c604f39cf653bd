"""Static and loading checks of an FMU, beyond a simulation.

* ``fmpy validate``: FMPy's own validation (schema, names, causality/variability/initial
  combinations, start values, units, ModelStructure);
* what FMPy does not check: value references unique, no ``initial``
  on inputs, start within [min, max], every Real variable with a unit and every unit and
  display unit used defined, ``modelIdentifier`` = the binary's name in the archive (and the
  binary exports the 34 FMI 2.0 Co-Simulation functions, and the modelDescription it carries
  is the archive's), the GUID in the XML accepted by ``fmi2Instantiate`` and a wrong one
  refused;
* the files every mechfmu FMU carries: ``documentation/index.html``, and the reference
  results of the default experiment in ``extra/org.fmi-standard.fmi-ls-ref/`` in the FMI
  cross-check CSV conventions (checked against the case's reference when there is one).

An FMU built by another exporter is held to the standard, not to mechfmu's own rules: a Real
variable without a unit, a unit without ``<BaseUnit>``, other libraries beside the binary and
a missing ``documentation/index.html`` are notes, and its reference files are read by
:mod:`.embedded_reference` (whose rows say whether they can be).
"""

from __future__ import annotations

import ctypes
import xml.etree.ElementTree as ET
import zipfile
from dataclasses import dataclass, field

import numpy as np

from .case import Case, signal_scale
from .importers import Fmu

__all__ = ["Check", "run_checks", "FMI2_CS_FUNCTIONS", "REFERENCE_DIR", "read_csv"]

REFERENCE_DIR = "extra/org.fmi-standard.fmi-ls-ref"
PLATFORM_DIR = "binaries/linux64"

FMI2_CS_FUNCTIONS = [
    "fmi2GetTypesPlatform", "fmi2GetVersion", "fmi2SetDebugLogging", "fmi2Instantiate",
    "fmi2FreeInstance", "fmi2SetupExperiment", "fmi2EnterInitializationMode",
    "fmi2ExitInitializationMode", "fmi2Terminate", "fmi2Reset", "fmi2GetReal", "fmi2GetInteger",
    "fmi2GetBoolean", "fmi2GetString", "fmi2SetReal", "fmi2SetInteger", "fmi2SetBoolean",
    "fmi2SetString", "fmi2GetFMUstate", "fmi2SetFMUstate", "fmi2FreeFMUstate",
    "fmi2SerializedFMUstateSize", "fmi2SerializeFMUstate", "fmi2DeSerializeFMUstate",
    "fmi2GetDirectionalDerivative", "fmi2SetRealInputDerivatives", "fmi2GetRealOutputDerivatives",
    "fmi2DoStep", "fmi2CancelStep", "fmi2GetStatus", "fmi2GetRealStatus", "fmi2GetIntegerStatus",
    "fmi2GetBooleanStatus", "fmi2GetStringStatus",
]

#: tolerance of the packaged _ref.csv against the case's reference (fraction of range):
#: the CSV stores 13 significant digits
REFERENCE_CSV_TOLERANCE = 1e-9


@dataclass
class Check:
    name: str
    problems: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    #: for the reference CSV check: the largest deviation (fraction of range) and its tolerance
    max_error: float | None = None
    tolerance: float | None = None

    @property
    def passed(self) -> bool:
        return not self.problems


def _raw_variables(root: ET.Element) -> list[ET.Element]:
    mv = root.find("ModelVariables")
    return list(mv.findall("ScalarVariable")) if mv is not None else []


def _type_element(sv: ET.Element) -> ET.Element | None:
    for tag in ("Real", "Integer", "Boolean", "String", "Enumeration"):
        e = sv.find(tag)
        if e is not None:
            return e
    return None


def check_fmpy(fmu: Fmu) -> Check:
    from fmpy.validation import validate_fmu

    c = Check("fmpy validate")
    try:
        c.problems = [str(p) for p in validate_fmu(str(fmu.path))]
    except Exception as e:
        c.problems = [f"validate_fmu raised {type(e).__name__}: {e}"]
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

    vr = Check("value references unique")
    seen: dict[tuple[str, str], str] = {}
    for sv in svs:
        e = _type_element(sv)
        key = (e.tag if e is not None else "?", sv.get("valueReference"))
        if key in seen:
            vr.problems.append(f"{sv.get('name')} and {seen[key]} share the {key[0]} value reference {key[1]}")
        else:
            seen[key] = sv.get("name")

    inputs = Check("no initial on inputs")
    for sv in svs:
        if sv.get("causality") == "input" and sv.get("initial") is not None:
            inputs.problems.append(f"input {sv.get('name')} has initial=\"{sv.get('initial')}\" "
                                   "(FMI 2.0: inputs carry no initial attribute)")
        if sv.get("causality") == "input":
            e = _type_element(sv)
            if e is not None and e.get("start") is None:
                inputs.problems.append(f"input {sv.get('name')} has no start value")

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
            bounds.problems.append(f"{sv.get('name')}: min {lo} > max {hi}")
        if lo is not None and start < lo:
            bounds.problems.append(f"{sv.get('name')}: start {start} < min {lo}")
        if hi is not None and start > hi:
            bounds.problems.append(f"{sv.get('name')}: start {start} > max {hi}")

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


def check_binary(fmu: Fmu) -> Check:
    """modelIdentifier = the binary's name; the 34 functions; the XML the binary carries."""
    c = Check("identifier = binary")
    cs = fmu.md.coSimulation
    if cs is None:
        c.problems.append("no <CoSimulation> element")
        return c
    ident = cs.modelIdentifier
    with zipfile.ZipFile(fmu.path) as z:
        names = z.namelist()
        archive_xml = z.read("modelDescription.xml")
    libs = [n for n in names if n.startswith(PLATFORM_DIR + "/") and n.endswith(".so")]
    want = f"{PLATFORM_DIR}/{ident}.so"
    if want not in names:
        c.problems.append(f"modelIdentifier {ident!r} but no {want} in the archive (it has {libs})")
        return c
    others = [n for n in libs if n != want]
    if others:
        (c.problems if fmu.by_mechfmu else c.notes).append(f"other binaries beside {want}: {others}")
    try:
        lib = ctypes.CDLL(str(fmu.directory / want), mode=ctypes.RTLD_LOCAL)
    except OSError as e:
        c.problems.append(f"{want} does not load: {e}")
        return c
    missing = [f for f in FMI2_CS_FUNCTIONS if not hasattr(lib, f)]
    if missing:
        c.problems.append(f"{want} does not export {', '.join(missing)}")
    if hasattr(lib, "mechfmu_model_description"):
        f = lib.mechfmu_model_description
        f.argtypes = [ctypes.c_void_p, ctypes.c_size_t]
        f.restype = ctypes.c_size_t
        n = f(None, 0)
        buf = ctypes.create_string_buffer(n + 1)
        f(buf, n + 1)
        if buf.raw[:n] != archive_xml:
            c.problems.append("the modelDescription.xml in the archive is not the one the binary was built with")
        else:
            c.notes.append("the binary's own modelDescription equals the archive's")
    return c


def check_guid(fmu: Fmu) -> Check:
    """fmi2Instantiate accepts the XML's GUID and refuses another."""
    from fmpy.fmi2 import FMU2Slave

    c = Check("GUID accepted, wrong GUID refused")
    cs = fmu.md.coSimulation
    if cs is None:
        c.problems.append("no <CoSimulation> element")
        return c

    def instantiate(guid: str) -> bool:
        slave = FMU2Slave(guid=guid, unzipDirectory=str(fmu.directory), modelIdentifier=cs.modelIdentifier,
                          instanceName="mechfmu-validate-guid")
        try:
            slave.instantiate()
        except Exception:
            slave.freeLibrary()
            return False
        slave.fmi2FreeInstance(slave.component)
        slave.freeLibrary()
        return True

    guid = fmu.md.guid
    if not instantiate(guid):
        c.problems.append(f"fmi2Instantiate refused the modelDescription's GUID {guid}")
    wrong = "{00000000-0000-0000-0000-000000000000}"
    if wrong == guid:
        wrong = "{11111111-1111-1111-1111-111111111111}"
    if instantiate(wrong):
        c.problems.append(f"fmi2Instantiate accepted a wrong GUID {wrong}: it does not check the GUID")
    return c


def read_csv(text: str) -> tuple[list[str], np.ndarray]:
    """A CSV in the cross-check conventions: quoted names on line 1, numbers after."""
    lines = [l for l in text.splitlines() if l.strip()]
    if not lines:
        raise ValueError("empty file")
    header = [h.strip() for h in lines[0].split(",")]
    if not all(len(h) >= 2 and h[0] == '"' and h[-1] == '"' for h in header):
        raise ValueError(f"the names on line 1 must be quoted with \": {lines[0]!r}")
    names = [h[1:-1] for h in header]
    rows = []
    for i, line in enumerate(lines[1:], start=2):
        cells = line.split(",")
        if len(cells) != len(names):
            raise ValueError(f"line {i} has {len(cells)} cells, the header {len(names)}")
        try:
            rows.append([float(x) for x in cells])
        except ValueError as e:
            raise ValueError(f"line {i}: {e}") from None
    return names, np.array(rows, dtype=float).reshape(len(rows), len(names))


def check_files(fmu: Fmu, default_case: Case | None) -> Check:
    """documentation/index.html, and the reference results in the cross-check conventions."""
    c = Check("documentation and reference files")
    ident = fmu.model
    with zipfile.ZipFile(fmu.path) as z:
        names = set(z.namelist())
        if not fmu.by_mechfmu:
            c.notes.append("documentation/index.html: " + ("there" if "documentation/index.html" in names else "none"))
            carried = sorted(n for n in names if n.startswith(REFERENCE_DIR + "/") and not n.endswith("/"))
            c.notes.append(f"{REFERENCE_DIR}/: {', '.join(n.rsplit('/', 1)[1] for n in carried) or 'none'}")
            return c

        def read(n):
            return z.read(n).decode("utf-8")

        if "documentation/index.html" not in names:
            c.problems.append("no documentation/index.html")
        else:
            html = read("documentation/index.html")
            if "<html" not in html or ident not in html:
                c.problems.append("documentation/index.html does not look like this FMU's documentation")
        ref_name = f"{REFERENCE_DIR}/{ident}_ref.csv"
        opt_name = f"{REFERENCE_DIR}/{ident}_ref.opt"
        in_name = f"{REFERENCE_DIR}/{ident}_in.csv"
        if ref_name not in names:
            if default_case is not None:
                c.problems.append(f"no {ref_name}, but the mechanism has a default-experiment case "
                                  "(write it with `mechfmu validate --write-references`, then rebuild)")
            else:
                c.notes.append(f"no {ref_name}")
            return c
        variables = fmu.variables
        for name, data in [(ref_name, names), (in_name, names)]:
            if name not in data:
                continue
            raw = z.getinfo(name).file_size
            if raw > 1_000_000:
                c.problems.append(f"{name} is {raw} bytes: the cross-check rules allow 1 MB")
            try:
                cols, table = read_csv(read(name))
            except ValueError as e:
                c.problems.append(f"{name}: {e}")
                continue
            if cols[0] != "time":
                c.problems.append(f"{name}: the first column is {cols[0]!r}, not \"time\"")
            unknown = [n for n in cols[1:] if n not in variables]
            if unknown:
                c.problems.append(f"{name}: {unknown} are not variables of the modelDescription")
            if table.size and np.any(np.diff(table[:, 0]) < 0):
                c.problems.append(f"{name}: time decreases")
            if name == in_name:
                not_inputs = [n for n in cols[1:] if n in variables and variables[n].causality != "input"]
                if not_inputs:
                    c.problems.append(f"{name}: {not_inputs} are not inputs")
            elif default_case is not None and not unknown and table.size:
                t = table[:, 0]
                try:
                    ref = default_case.reference(t)
                    worst, where = 0.0, ""
                    for j, n in enumerate(cols[1:], start=1):
                        want = np.broadcast_to(np.asarray(ref[n], dtype=float), t.shape)
                        err = float(np.max(np.abs(table[:, j] - want))) / signal_scale(want)
                        if err > worst or not where:
                            worst, where = err, n
                    c.max_error, c.tolerance = worst, REFERENCE_CSV_TOLERANCE
                    if not worst <= REFERENCE_CSV_TOLERANCE:
                        c.problems.append(
                            f"{name} differs from the case {default_case.name!r}'s reference by {worst:.2e} of "
                            f"range ({where}): stale? regenerate with `mechfmu validate --write-references`")
                except Exception as e:
                    c.problems.append(f"{name}: cannot compare with the reference: {type(e).__name__}: {e}")
        if opt_name not in names:
            c.problems.append(f"no {opt_name}")
        else:
            opts = {}
            for line in read(opt_name).splitlines():
                if "," in line:
                    k, v = line.split(",", 1)
                    opts[k.strip()] = v.strip()
            for k in ("StartTime", "StopTime", "StepSize", "RelTol"):
                if k not in opts:
                    c.problems.append(f"{opt_name} has no {k}")
    return c


def run_checks(fmu: Fmu, default_case: Case | None = None) -> list[Check]:
    return [check_fmpy(fmu), *check_model_description(fmu), check_binary(fmu), check_guid(fmu),
            check_files(fmu, default_case)]
