"""The registry of importers: every importer ``mechfmu validate`` runs a case under, one
module each, in the order their rows come (the reference importer first). Each module
declares its :class:`~mechfmu_validate.importer.Importer` as ``IMPORTER``; the command line's
``--no-<option>``, the rows, the report's header, curves and legend and the validation tables'
columns are read from this list.

Adding an importer: a module beside these declaring ``IMPORTER``, and its line here.
"""

from __future__ import annotations

from ..importer import Importer
from . import fmi_crate, fmpy, libcosim

__all__ = ["IMPORTERS", "PLATFORMS", "REFERENCE"]

IMPORTERS: tuple[Importer, ...] = (
    fmpy.IMPORTER,
    libcosim.IMPORTER,
    fmi_crate.IMPORTER,
)

#: the importer every other one is compared with
REFERENCE: Importer = next(i for i in IMPORTERS if i.reference)

#: the importer that runs an FMU's binaries for the other platforms (:mod:`.platform_rows`)
PLATFORMS: Importer = next(i for i in IMPORTERS if i.platforms)
