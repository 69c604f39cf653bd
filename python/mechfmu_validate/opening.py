"""Opening an FMU for validation, or saying in words why it cannot be opened.

:func:`open_fmu` checks, in this order, what every later check and run takes for granted:
the file is a zip archive that reads to its end, extracts inside its folder and names each
file once; it has a well-formed ``modelDescription.xml``
of FMI 2.0 or 3.0 with a ``<CoSimulation>`` interface; it has a binary for this machine,
named after the model identifier; FMPy loads that binary; and it instantiates with the
model description's GUID (instantiation token). The first of these that fails raises
:class:`BrokenFmu`, whose message is the one FAIL row ``mechfmu validate`` shows for the FMU
(``not an FMU: the file is not a zip archive``). Nothing is left in the temporary directory.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
import zipfile
import zlib
from pathlib import Path

from . import fmulog
from .fmu import Fmu
from .host import HOST_EXTENSION, HOST_FOLDER

__all__ = ["BrokenFmu", "escaping_entry", "open_fmu", "OPENS"]

#: the check column of the row of an FMU that cannot be opened
OPENS = "check: the FMU opens and instantiates"


class BrokenFmu(Exception):
    """The FMU cannot be validated; the message says why, in words."""


def _describe_archive(path: Path) -> None:
    """Raises :class:`BrokenFmu` unless ``path`` is a zip archive whose members all read."""
    try:
        with path.open("rb") as f:
            head = f.read(4)
    except OSError as e:
        raise BrokenFmu(f"cannot read the file: {e.strerror or e}") from None
    if not zipfile.is_zipfile(path):
        if head == b"PK\x03\x04":
            raise BrokenFmu("the zip archive is truncated or damaged (its central directory is missing)")
        raise BrokenFmu("not an FMU: the file is not a zip archive")
    try:
        with zipfile.ZipFile(path) as z:
            bad = z.testzip()
            names = z.namelist()
    except (zipfile.BadZipFile, EOFError, zlib.error, OSError) as e:
        raise BrokenFmu(f"the zip archive is truncated or damaged ({e})") from None
    if bad is not None:
        raise BrokenFmu(f"the zip archive is damaged: {bad} fails its CRC check")
    escaping = escaping_entry(names)
    if escaping is not None:
        raise BrokenFmu(f"the zip archive has an entry outside the FMU's folder: {escaping!r} "
                        "(an importer that extracts it would write there)")
    seen: set[str] = set()
    twice = next((n for n in names if n in seen or seen.add(n)), None)
    if twice is not None:
        raise BrokenFmu(f"the zip archive has two entries named {twice!r} (importers may read either)")


def escaping_entry(names: list[str]) -> str | None:
    """The first archive entry of ``names`` that lands outside the folder the archive is
    extracted into, if any."""
    return next((n for n in names if _escapes(n)), None)


def _escapes(name: str) -> bool:
    """Whether the archive entry ``name`` lands outside the folder it is extracted into: an
    absolute path (``/x``, ``\\x``, ``C:x``) or one with a ``..`` part (either separator, as
    Windows reads both)."""
    parts = name.replace("\\", "/").split("/")
    return name.startswith(("/", "\\")) or (len(name) > 1 and name[1] == ":") or ".." in parts


def _model_description(path: Path) -> ET.Element:
    with zipfile.ZipFile(path) as z:
        if "modelDescription.xml" not in z.namelist():
            raise BrokenFmu("not an FMU: the archive has no modelDescription.xml")
        text = z.read("modelDescription.xml")
    try:
        root = ET.fromstring(text)
    except ET.ParseError as e:
        raise BrokenFmu(f"modelDescription.xml is not well-formed XML ({e})") from None
    if root.tag != "fmiModelDescription":
        raise BrokenFmu(f"modelDescription.xml is not an FMI model description (its root is <{root.tag}>)")
    version = root.get("fmiVersion", "")
    if version.split(".")[0] not in HOST_FOLDER:
        raise BrokenFmu(f"FMI version {version or '(none given)'} is not validated here (FMI 2.0 and 3.0 are)")
    if root.find("CoSimulation") is None:
        raise BrokenFmu("the FMU offers no Co-Simulation (modelDescription.xml has no <CoSimulation>): "
                        "mechfmu validate runs Co-Simulation")
    return root


def _binary(path: Path, root: ET.Element) -> str:
    """The archive's name of this machine's binary; :class:`BrokenFmu` when it is missing."""
    identifier = root.find("CoSimulation").get("modelIdentifier", "")
    folder = HOST_FOLDER[root.get("fmiVersion", "").split(".")[0]]
    with zipfile.ZipFile(path) as z:
        names = [n for n in z.namelist() if not n.endswith("/")]
    want = f"binaries/{folder}/{identifier}.{HOST_EXTENSION}"
    if want in names:
        return want
    here = sorted(n.rsplit("/", 1)[1] for n in names if n.startswith(f"binaries/{folder}/"))
    if here:
        raise BrokenFmu(f"binaries/{folder}/ has {', '.join(here)}, not {identifier}.{HOST_EXTENSION} "
                        "(the modelIdentifier)")
    platforms = sorted({n.split("/")[1] for n in names if n.startswith("binaries/") and n.count("/") >= 2})
    raise BrokenFmu(f"no binary for {folder} in the archive (it has: {', '.join(platforms) or 'none'})")


def _instantiate(fmu: Fmu, binary: str) -> None:
    """FMPy loads the binary and the model description's GUID instantiates it."""
    version = fmu.md.fmiVersion.split(".")[0]
    identifier = fmu.md.coSimulation.modelIdentifier
    call = "fmi2Instantiate" if version == "2" else "fmi3InstantiateCoSimulation"
    if version == "2":
        from fmpy.fmi2 import FMU2Slave as Slave
    else:
        from fmpy.fmi3 import FMU3Slave as Slave
    try:
        slave = Slave(guid=fmu.md.guid, unzipDirectory=str(fmu.directory), modelIdentifier=identifier,
                      instanceName="mechfmu-validate")
    except Exception as e:  # noqa: BLE001 (FMPy raises plain Exception, OSError, AttributeError)
        raise BrokenFmu(f"FMPy cannot load {binary}: {str(e).replace(str(fmu.directory) + '/', '')}") from None
    mark = fmulog.LogMark()
    try:
        if version == "2":
            slave.instantiate()
        else:
            slave.instantiate(logMessage=fmulog.fmi3_logger())
    except Exception:  # noqa: BLE001 (FMPy: "Failed to instantiate model")
        said = "; ".join(r.message for r in mark.records[-3:])
        raise BrokenFmu(f"{call} returned NULL for the modelDescription's "
                        f"{'GUID' if version == '2' else 'instantiationToken'} {fmu.md.guid}"
                        + (f" (the FMU said: {said})" if said else "")) from None
    finally:
        if slave.component and version == "2":
            slave.fmi2FreeInstance(slave.component)
        elif slave.component:
            slave.freeInstance()
        slave.freeLibrary()


def open_fmu(path: str | Path) -> Fmu:
    """The FMU at ``path``, extracted, its binary loaded and instantiated once; raises
    :class:`BrokenFmu` (and leaves no temporary directory) when it cannot be."""
    path = Path(path)
    _describe_archive(path)
    root = _model_description(path)
    binary = _binary(path, root)
    try:
        fmu = Fmu(path)
    except Exception as e:  # noqa: BLE001 (FMPy's reading of what passed the checks above)
        raise BrokenFmu(f"modelDescription.xml cannot be read: {e}") from None
    try:
        _instantiate(fmu, binary)
    except BaseException:
        fmu.cleanup()
        raise
    return fmu
