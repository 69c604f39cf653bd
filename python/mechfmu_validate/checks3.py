"""Static and loading checks of an FMI 3.0 FMU (the rows ``check: FMI 3.0 ...``):

* ``fmpy validate``: FMPy's own validation of the FMI 3.0 archive (the schema, names,
  causality/variability/initial combinations, start values, units, ``ModelStructure``);
* ``identifier = binary``: this machine's ``binaries/<tuple>/<modelIdentifier>.<so|dll|dylib>`` is in the archive
  (and every other platform's binary is named after the model identifier too), loads, exports the FMI 3.0 functions (those FMPy's FMI 3.0 binding
  declares: Co-Simulation, Model Exchange and the common ones), and for a mechfmu binary
  carries exactly the archive's ``modelDescription.xml``;
* ``instantiation token``: ``fmi3InstantiateCoSimulation`` (through FMPy) accepts the
  model description's token and refuses a wrong one;
* ``arrays = FMI 2.0 scalars``: which FMI 2.0 variable each element of the FMU's arrays is,
  as the model description's annotations name it (:func:`~.arrays.derive`; what the
  cases' names need).
"""

from __future__ import annotations

import ctypes
import zipfile
from typing import Iterator

from .checks import Check
from .fmi3 import Fmi3
from .platforms import HOST_EXTENSION, HOST_FOLDER

__all__ = ["run_checks3"]

PLATFORM_DIR = f"binaries/{HOST_FOLDER['3']}"


def _fmi3_functions() -> list[str]:
    import fmpy.fmi3

    return sorted(n for n in dir(fmpy.fmi3._FMU3) if n.startswith("fmi3"))


def check_fmpy(f3: Fmi3) -> Check:
    from fmpy.validation import validate_fmu

    c = Check("FMI 3.0 fmpy validate")
    try:
        c.problems = [str(p) for p in validate_fmu(str(f3.fmu.path))]
    except Exception as e:
        c.problems = [f"validate_fmu raised {type(e).__name__}: {e}"]
    return c


def check_binary(f3: Fmi3) -> Check:
    c = Check("FMI 3.0 identifier = binary")
    cs = f3.fmu.md.coSimulation or f3.fmu.md.modelExchange
    if cs is None:
        c.problems.append("neither <CoSimulation> nor <ModelExchange>")
        return c
    with zipfile.ZipFile(f3.fmu.path) as z:
        names = z.namelist()
        archive_xml = z.read("modelDescription.xml")
    libs = [n for n in names if n.startswith("binaries/") and n.endswith((".so", ".dll", ".dylib"))]
    want = f"{PLATFORM_DIR}/{cs.modelIdentifier}.{HOST_EXTENSION}"
    if want not in names:
        c.problems.append(f"modelIdentifier {cs.modelIdentifier!r} but no {want} in the archive (it has {libs})")
        return c
    # one binary per platform folder, named after the model identifier
    others = [n for n in libs if n != want and n.rsplit("/", 1)[1].rsplit(".", 1)[0] != cs.modelIdentifier]
    if others:
        c.problems.append(f"binaries not named after the model identifier {cs.modelIdentifier!r}: {others}")
    try:
        lib = ctypes.CDLL(str(f3.fmu.directory / want), mode=ctypes.RTLD_LOCAL)
    except OSError as e:
        c.problems.append(f"{want} does not load: {e}")
        return c
    missing = [f for f in _fmi3_functions() if not hasattr(lib, f)]
    if missing:
        c.problems.append(f"{want} does not export {', '.join(missing)}")
    if hasattr(lib, "mechfmu_model_description_fmi3"):
        f = lib.mechfmu_model_description_fmi3
        f.argtypes = [ctypes.c_void_p, ctypes.c_size_t]
        f.restype = ctypes.c_size_t
        n = f(None, 0)
        buf = ctypes.create_string_buffer(n + 1)
        f(buf, n + 1)
        if buf.raw[:n] != archive_xml:
            c.problems.append("the modelDescription.xml in the archive is not the FMI 3.0 one the binary was "
                              "built with")
        else:
            c.notes.append("the binary's own FMI 3.0 modelDescription equals the archive's")
    return c


def check_token(f3: Fmi3) -> Check:
    """fmi3InstantiateCoSimulation accepts the XML's instantiation token and refuses another."""
    from fmpy.fmi3 import FMU3Slave

    from . import fmulog

    c = Check("FMI 3.0 instantiation token accepted, wrong token refused")
    md = f3.fmu.md
    if md.coSimulation is None:
        c.notes.append("no <CoSimulation>: not checked")
        return c

    def instantiate(token: str) -> bool:
        slave = FMU3Slave(guid=token, unzipDirectory=str(f3.fmu.directory),
                          modelIdentifier=md.coSimulation.modelIdentifier, instanceName="mechfmu-validate-token")
        try:
            slave.instantiate(logMessage=fmulog.fmi3_logger())
        except Exception:
            slave.freeLibrary()
            return False
        slave.freeInstance()
        slave.freeLibrary()
        return True

    token = md.guid
    if not instantiate(token):
        c.problems.append(f"fmi3InstantiateCoSimulation refused the modelDescription's instantiationToken {token}")
    wrong = "{00000000-0000-0000-0000-000000000000}"
    if wrong == token:
        wrong = "{11111111-1111-1111-1111-111111111111}"
    if instantiate(wrong):
        said = f"fmi3InstantiateCoSimulation accepted a wrong instantiationToken {wrong}"
        if f3.fmu.by_mechfmu:
            c.problems.append(said)
        else:  # the standard gives the token to check with but does not require the check
            c.notes.append(f"{said} (allowed: FMI 3.0 does not require the check)")
    return c


def check_arrays(f3: Fmi3) -> Check:
    c = Check("FMI 3.0 arrays = FMI 2.0 scalars")
    if f3.mapping is None:
        c.problems.append(f3.problem or "no mapping")
    elif f3.mapping.elements:
        c.notes += f3.mapping.describe()
    else:
        c.notes.append("no arrays: the FMI 2.0 variables, by the same names")
    return c


def run_checks3(f3: Fmi3) -> Iterator[Check]:
    """The checks, each made when it is taken (what the FMU writes while one runs is its own)."""
    yield check_fmpy(f3)
    yield check_binary(f3)
    yield check_token(f3)
    yield check_arrays(f3)
