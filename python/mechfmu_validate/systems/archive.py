"""An SSP as ``mechfmu build`` writes it and any SSP 1.0 tool reads it: the components and
their FMUs, the connections, the parameter sets (the one ``SystemStructure.ssd`` binds, and
each variant ``<set>.ssd``'s), the default experiment's stop time and communication step."""

from __future__ import annotations

import zipfile
from dataclasses import dataclass, field
from pathlib import Path

from lxml import etree

from ..opening import escaping_entry

SSD = "{http://ssp-standard.org/SSP1/SystemStructureDescription}"
SSV = "{http://ssp-standard.org/SSP1/SystemStructureParameterValues}"
OSP = "{http://opensimulationplatform.com/SSP/OSPAnnotations}"
OMS = "{https://raw.githubusercontent.com/OpenModelica/OMSimulator/master/schema/oms.xsd}"
DEFAULT_SSD = "SystemStructure.ssd"


@dataclass
class Component:
    name: str
    #: the FMU's path inside the SSP (``resources/Oscillator.fmu``)
    source: str


@dataclass
class Ssp:
    path: Path
    #: the folder it is extracted to
    folder: Path
    name: str
    components: list[Component]
    #: ``((component, output), (component, input))``
    connections: list[tuple[tuple[str, str], tuple[str, str]]]
    #: each parameter set by name: ``{(component, variable): value}``, ``default`` first
    sets: dict[str, dict[tuple[str, str], float]] = field(default_factory=dict)
    #: the ``.ssd`` file (inside :attr:`folder`) that binds each set
    set_files: dict[str, str] = field(default_factory=dict)
    start: float = 0.0
    stop: float = 1.0
    step: float | None = None

    def fmu(self, component: str) -> Path:
        source = next(c.source for c in self.components if c.name == component)
        return self.folder / source


def read(path: Path, folder: Path) -> Ssp:
    """The SSP at ``path``, extracted to ``folder``."""
    with zipfile.ZipFile(path) as z:
        outside = escaping_entry(z.namelist())
        if outside is not None:
            raise ValueError(f"the SSP has an entry outside its folder: {outside!r}")
        z.extractall(folder)
    root = etree.parse(str(folder / DEFAULT_SSD)).getroot()
    system = root.find(f"{SSD}System")
    components = [Component(c.get("name"), c.get("source"))
                  for c in system.iterfind(f"{SSD}Elements/{SSD}Component")]
    connections = [((c.get("startElement"), c.get("startConnector")), (c.get("endElement"), c.get("endConnector")))
                   for c in system.iterfind(f"{SSD}Connections/{SSD}Connection")]
    for c in components:
        # An importer extracts each component's FMU: none may write outside its folder.
        with zipfile.ZipFile(folder / c.source) as z:
            outside = escaping_entry(z.namelist())
        if outside is not None:
            raise ValueError(f"{c.source} has an entry outside the FMU's folder: {outside!r} "
                             "(an importer that extracts it would write there)")
    ssp = Ssp(path, folder, system.get("name"), components, connections)
    experiment = root.find(f"{SSD}DefaultExperiment")
    if experiment is not None:
        ssp.start = float(experiment.get("startTime", 0.0))
        ssp.stop = float(experiment.get("stopTime", 1.0))
        algorithm = experiment.find(f".//{OSP}FixedStepAlgorithm")
        if algorithm is not None:
            ssp.step = float(algorithm.get("baseStepSize"))
    if ssp.step is None:
        master = system.find(f".//{OMS}FixedStepMaster")
        if master is not None:
            ssp.step = float(master.get("stepSize"))
    ssds = [DEFAULT_SSD] + sorted(p.name for p in folder.glob("*.ssd") if p.name != DEFAULT_SSD)
    for ssd in ssds:
        name, values = _bound_set(folder, ssd)
        name = "default" if ssd == DEFAULT_SSD and name is None else name or Path(ssd).stem
        ssp.sets[name] = values
        ssp.set_files[name] = ssd
    return ssp


def _bound_set(folder: Path, ssd: str) -> tuple[str | None, dict[tuple[str, str], float]]:
    """The values the components' bindings of ``ssd`` give, and their set's name."""
    root = etree.parse(str(folder / ssd)).getroot()
    values: dict[tuple[str, str], float] = {}
    name = None
    for component in root.iterfind(f"{SSD}System/{SSD}Elements/{SSD}Component"):
        for binding in component.iterfind(f"{SSD}ParameterBindings/{SSD}ParameterBinding"):
            # a file of its own, or the values inline
            source = binding.get("source")
            ssv = (etree.parse(str(folder / source)).getroot() if source
                   else binding.find(f"{SSD}ParameterValues/{SSV}ParameterSet"))
            if ssv is None:
                continue
            name = ssv.get("name", name)
            for p in ssv.iterfind(f"{SSV}Parameters/{SSV}Parameter"):
                real = p.find(f"{SSV}Real")
                if real is not None:
                    values[(component.get("name"), p.get("name"))] = float(real.get("value"))
    return name, values
