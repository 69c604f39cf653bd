"""Static and loading checks of an FMU, beyond a simulation, in its FMI version (an FMI 3.0
FMU's rows are ``check: FMI 3.0 ...``).

* ``fmpy validate``: FMPy's own validation (schema, names, causality/variability/initial
  combinations, start values, units, ModelStructure);
* what FMPy does not check: the model description's value references, aliases, inputs,
  bounds and units (:mod:`.description_checks`), ``modelIdentifier`` = the binary's name in
  the archive (and the binary exports the 34 FMI 2.0 Co-Simulation functions, and the
  modelDescription it carries is the archive's), the GUID in the XML accepted by
  ``fmi2Instantiate`` and a wrong one refused;
* the files every mechfmu FMU carries: ``documentation/index.html``, and the reference
  results in ``extra/org.fmi-standard.fmi-ls-ref/`` in the FMI cross-check CSV conventions
  (checked against the reference case's reference when there is one).

An FMI 3.0 FMU: ``fmpy validate``; ``identifier = binary``, this machine's
``binaries/<tuple>/<modelIdentifier>.<so|dll|dylib>`` is in the archive (and every other
platform's binary is named after the model identifier too), loads, exports the FMI 3.0
functions (those FMPy's FMI 3.0 binding declares: Co-Simulation, Model Exchange and the
common ones), and for a mechfmu binary carries exactly the archive's
``modelDescription.xml``; ``fmi3InstantiateCoSimulation`` accepts the model description's
instantiation token and refuses a wrong one; and ``arrays = FMI 2.0 scalars``: which FMI 2.0
variable each element of its arrays is (:func:`check_arrays`).

An FMU built by another exporter is held to the standard, not to mechfmu's own rules: a
problem names the clause of the standard it breaks (``FMI 2.0.5 §2.2.7 start: ...``); aliases
(which mechfmu never declares), a Real variable without a unit, a unit without
``<BaseUnit>``, a start outside [min, max], other libraries beside the binary and a missing
``documentation/index.html`` are notes, and its reference files are read by
:mod:`.embedded_reference` (whose rows say whether they can be).
"""

from __future__ import annotations

import ctypes
import zipfile
from dataclasses import dataclass
from typing import Iterator

import numpy as np

from . import fmulog
from .case import Case, signal_scale
from .check import Check
from .description_checks import check_model_description
from .fmu import Fmu
from .host import HOST_EXTENSION, HOST_FOLDER
from .target import Target

__all__ = ["run_checks", "FMI2_CS_FUNCTIONS", "REFERENCE_DIR", "read_csv"]

REFERENCE_DIR = "extra/org.fmi-standard.fmi-ls-ref"

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


def check_fmpy(target: Target) -> Check:
    """FMPy's own validation of the archive."""
    from fmpy.validation import validate_fmu

    c = Check(f"{VERSIONS[target.version].prefix}fmpy validate")
    try:
        c.problems = [str(p) for p in validate_fmu(str(target.fmu.path))]
    except Exception as e:
        c.problems = [f"validate_fmu raised {type(e).__name__}: {e}"]
    return c


@dataclass(frozen=True)
class _Version:
    """What the binary and instantiation checks look for in an FMU of one FMI version."""

    #: the check names' prefix
    prefix: str
    #: this machine's binaries' folder in the archive
    folder: str
    #: the interface elements, one of which names the model identifier, and the words if none does
    interfaces: tuple[str, ...]
    no_interface: str
    #: mechfmu's export of the model description it was built with, and its words for it
    own_description: str
    described: str
    #: the instantiation's words: the function, the model description's attribute, the clause
    instantiate: str
    token: str
    standard: str


VERSIONS = {
    "2.0": _Version("", f"binaries/{HOST_FOLDER['2']}", ("coSimulation",), "no <CoSimulation> element",
                    "mechfmu_model_description", "", "fmi2Instantiate", "GUID", "FMI 2.0"),
    "3.0": _Version("FMI 3.0 ", f"binaries/{HOST_FOLDER['3']}", ("coSimulation", "modelExchange"),
                    "neither <CoSimulation> nor <ModelExchange>", "mechfmu_model_description_fmi3", "FMI 3.0 ",
                    "fmi3InstantiateCoSimulation", "instantiationToken", "FMI 3.0"),
}


def _functions(version: str) -> list[str]:
    """The functions the binary must export: FMI 2.0's Co-Simulation ones, or every FMI 3.0 one
    FMPy's binding declares (Co-Simulation, Model Exchange and the common ones)."""
    if version == "2.0":
        return FMI2_CS_FUNCTIONS
    import fmpy.fmi3

    return sorted(n for n in dir(fmpy.fmi3._FMU3) if n.startswith("fmi3"))


def check_binary(target: Target) -> Check:
    """modelIdentifier = the binary's name (every platform's binary so named); the FMI
    functions exported; the XML the binary carries."""
    fmu, v = target.fmu, VERSIONS[target.version]
    c = Check(f"{v.prefix}identifier = binary")
    interface = next((getattr(fmu.md, i) for i in v.interfaces if getattr(fmu.md, i) is not None), None)
    if interface is None:
        c.problems.append(v.no_interface)
        return c
    ident = interface.modelIdentifier
    with zipfile.ZipFile(fmu.path) as z:
        names = z.namelist()
        archive_xml = z.read("modelDescription.xml")
    want = f"{v.folder}/{ident}.{HOST_EXTENSION}"
    if target.version == "2.0":
        libs = [n for n in names if n.startswith(v.folder + "/") and n.endswith("." + HOST_EXTENSION)]
    else:
        libs = [n for n in names if n.startswith("binaries/") and n.endswith((".so", ".dll", ".dylib"))]
    if want not in names:
        c.problems.append(f"modelIdentifier {ident!r} but no {want} in the archive (it has {libs})")
        return c
    if target.version == "2.0":
        others = [n for n in libs if n != want]
        if others:
            (c.problems if fmu.by_mechfmu else c.notes).append(f"other binaries beside {want}: {others}")
    else:  # one binary per platform folder, named after the model identifier
        others = [n for n in libs if n != want and n.rsplit("/", 1)[1].rsplit(".", 1)[0] != ident]
        if others:
            c.problems.append(f"binaries not named after the model identifier {ident!r}: {others}")
    try:
        lib = ctypes.CDLL(str(fmu.directory / want), mode=ctypes.RTLD_LOCAL)
    except OSError as e:
        c.problems.append(f"{want} does not load: {e}")
        return c
    missing = [f for f in _functions(target.version) if not hasattr(lib, f)]
    if missing:
        c.problems.append(f"{want} does not export {', '.join(missing)}")
    if hasattr(lib, v.own_description):
        f = getattr(lib, v.own_description)
        f.argtypes = [ctypes.c_void_p, ctypes.c_size_t]
        f.restype = ctypes.c_size_t
        n = f(None, 0)
        buf = ctypes.create_string_buffer(n + 1)
        f(buf, n + 1)
        if buf.raw[:n] != archive_xml:
            c.problems.append(f"the modelDescription.xml in the archive is not the {v.described}one the binary "
                              "was built with")
        else:
            c.notes.append(f"the binary's own {v.described}modelDescription equals the archive's")
    return c


def _instantiates(target: Target, token: str) -> bool:
    """Whether the FMU instantiates (in Co-Simulation, through FMPy) with ``token``."""
    fmu = target.fmu
    if target.version == "2.0":
        from fmpy.fmi2 import FMU2Slave

        slave = FMU2Slave(guid=token, unzipDirectory=str(fmu.directory),
                          modelIdentifier=fmu.md.coSimulation.modelIdentifier, instanceName="mechfmu-validate-guid")
        try:
            slave.instantiate()
        except Exception:
            slave.freeLibrary()
            return False
        slave.fmi2FreeInstance(slave.component)
        slave.freeLibrary()
        return True
    from fmpy.fmi3 import FMU3Slave

    slave = FMU3Slave(guid=token, unzipDirectory=str(fmu.directory),
                      modelIdentifier=fmu.md.coSimulation.modelIdentifier, instanceName="mechfmu-validate-token")
    try:
        slave.instantiate(logMessage=fmulog.fmi3_logger())
    except Exception:
        slave.freeLibrary()
        return False
    slave.freeInstance()
    slave.freeLibrary()
    return True


def check_instantiation(target: Target) -> Check:
    """The FMU's Co-Simulation instantiation accepts the XML's GUID (instantiation token) and
    refuses another."""
    v = VERSIONS[target.version]
    fmi3 = target.version == "3.0"
    c = Check(f"{v.prefix}instantiation token accepted, wrong token refused" if fmi3
              else "GUID accepted, wrong GUID refused")
    if target.fmu.md.coSimulation is None:
        if fmi3:
            c.notes.append("no <CoSimulation>: not checked")
        else:
            c.problems.append("no <CoSimulation> element")
        return c
    token = target.fmu.md.guid
    if not _instantiates(target, token):
        c.problems.append(f"{v.instantiate} refused the modelDescription's {v.token} {token}")
    wrong = "{00000000-0000-0000-0000-000000000000}"
    if wrong == token:
        wrong = "{11111111-1111-1111-1111-111111111111}"
    if _instantiates(target, wrong):
        said = f"{v.instantiate} accepted a wrong {v.token} {wrong}" + ("" if fmi3 else ": it does not check the GUID")
        if target.fmu.by_mechfmu:
            c.problems.append(said)
        else:  # the standard gives the token to check with but does not require the check
            c.notes.append(f"{said} (allowed: {v.standard} does not require the check)")
    return c


def check_arrays(target: Target) -> Check:
    """Which FMI 2.0 variable each element of an FMI 3.0 FMU's arrays is, as its model
    description's annotations name it (:func:`~.arrays.derive`; what the cases' names need)."""
    c = Check("FMI 3.0 arrays = FMI 2.0 scalars")
    if target.mapping is None:
        c.problems.append(target.problem or "no mapping")
    elif target.mapping.elements:
        c.notes += target.mapping.describe()
    else:
        c.notes.append("no arrays: the FMI 2.0 variables, by the same names")
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


def check_files(fmu: Fmu, reference_case: Case | None) -> Check:
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
            if reference_case is not None:
                c.problems.append(f"no {ref_name}, but the mechanism has a reference case "
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
            elif reference_case is not None and not unknown and table.size:
                t = table[:, 0]
                try:
                    ref = reference_case.reference(t)
                    worst, where = 0.0, ""
                    for j, n in enumerate(cols[1:], start=1):
                        want = np.broadcast_to(np.asarray(ref[n], dtype=float), t.shape)
                        err = float(np.max(np.abs(table[:, j] - want))) / signal_scale(want)
                        if err > worst or not where:
                            worst, where = err, n
                    c.max_error, c.tolerance = worst, REFERENCE_CSV_TOLERANCE
                    if not worst <= REFERENCE_CSV_TOLERANCE:
                        c.problems.append(
                            f"{name} differs from the case {reference_case.name!r}'s reference by {worst:.2e} of "
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


def run_checks(target: Target, reference_case: Case | None = None) -> Iterator[Check]:
    """The checks of the FMU in its FMI version, each made when it is taken (what the FMU
    writes while one runs is its own)."""
    yield check_fmpy(target)
    if target.version == "2.0":
        yield from check_model_description(target.fmu)
    yield check_binary(target)
    yield check_instantiation(target)
    if target.version == "2.0":
        yield check_files(target.fmu, reference_case)
    else:
        yield check_arrays(target)
