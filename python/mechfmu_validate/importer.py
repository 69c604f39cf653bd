"""What an importer is to ``mechfmu validate``: a declaration (:class:`Importer`) that one
module of :mod:`.importers` makes, and the registry there lists.

An importer declares its name (its rows' importer column, and the ``--no-<option>`` that
leaves it out), whether it can run here and why not (:class:`Availability`), what it runs
(:class:`Runs`: Co-Simulation and Model Exchange, FMI 2.0 and 3.0, SSP), how it runs a case
(``case_rows``, given a :class:`CaseRun`) and its tolerance. The command line, the order of
the rows, the report's header, curves and legend and the validation tables' columns are read
from the declarations. Beyond its own module and the registry, only :mod:`.platforms` knows
one: it runs other platforms' binaries with the runner of the importer declared with
``platforms=True``.

A case runs first under the reference importer (FMPy in Co-Simulation, against the case's
reference): its result and evaluation are what the others compare with
(:attr:`CaseRun.reference`, :attr:`CaseRun.evaluation`).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Callable, Iterator

from .model_exchange import FixedStep
from .rows import Row

if TYPE_CHECKING:  # pragma: no cover
    from .case import Case, Evaluation, Result
    from .target import Target

__all__ = ["CS", "ME", "FMI2", "FMI3", "Availability", "CaseRun", "Curve", "Importer", "Runs", "Selection", "Words",
           "row_name"]

#: the interfaces, by the letters FMI gives them
CS, ME = "CS", "ME"
#: the FMI versions
FMI2, FMI3 = "2.0", "3.0"


def row_name(name: str, version: str, interface: str, method: str = "") -> str:
    """An importer's rows' importer column: ``FMPy``, ``FMPy ME Euler``, ``FMPy FMI3 CS``,
    ``FMPy FMI3 ME CVode`` (an FMI 2.0 Co-Simulation row by the importer's name alone)."""
    parts = [name] + (["FMI3"] if version == FMI3 else [])
    if interface == ME:
        parts += [ME, method]
    elif version == FMI3:
        parts.append(CS)
    return " ".join(p for p in parts if p)


@dataclass(frozen=True)
class Runs:
    """What an importer runs: its interfaces (``CS``, ``ME``), its FMI versions, and whether
    it runs SSP system structures."""

    interfaces: frozenset[str]
    versions: frozenset[str]
    ssp: bool = False

    def covers(self, interface: str, version: str) -> bool:
        return interface in self.interfaces and version in self.versions


@dataclass(frozen=True)
class Availability:
    """Whether an importer runs here: ``text`` its version when it does, why not when not."""

    ok: bool
    text: str


@dataclass
class CaseRun:
    """One case on one FMU (in its FMI version) as the importers run it, and what the runs
    before give the later ones."""

    target: Target
    case: Case
    #: the report's anchor of the case's plot ("": not plotted)
    anchor: str = ""
    #: "case" (a mechanism's case) or "reference" (a reference an FMU carries or has beside it)
    kind: str = "case"
    #: what fails the reference importer's row whatever its run gives (a reference's problems)
    problems: list[str] = field(default_factory=list)
    #: the case's plot, which the reference importer's run draws (None: this run is not plotted)
    plot: dict[str, Any] | None = None
    #: where the other runs draw their errors, in the case's plot (None: they are not drawn)
    deviations: dict[str, Any] | None = None
    #: the reference importer's result and its evaluation, once it ran
    reference: Result | None = None
    evaluation: Evaluation | None = None
    #: says which run starts (the progress shown, and named when an FMU crashes or hangs)
    progress: Callable[[str], None] = lambda _: None

    @property
    def fmu(self):
        return self.target.fmu

    @property
    def version(self) -> str:
        return self.target.version

    def floors(self) -> dict[str, float]:
        """The case's scale of each signal (the floor of an agreement's scale)."""
        return {s.name: s.scale for s in self.evaluation.signals} if self.evaluation is not None else {}


@dataclass(frozen=True)
class Curve:
    """How the report draws a run's error over time in a case's plot (the error a row of
    its importer holds: ``time``, ``error_over_time``, and ``max_error``, ``tolerance``)."""

    label: str
    color: str
    dashes: tuple
    #: the label of its tolerance's line (None: no line)
    tolerance_label: str | None = None
    #: drawn only where it is not 0 everywhere
    only_nonzero: bool = False
    #: its words in the plot's heading (None: none)
    heading: Callable[[dict[str, Any]], str] | None = None


@dataclass(frozen=True)
class Words:
    """What an importer's rows measure, in the legends of the report and of the validation
    tables (empty: nothing to say)."""

    #: the report's, of its FMI 2.0 Co-Simulation rows' max error ("for a case under FMPy, ...")
    report: str = ""
    #: the report's, of its FMI 3.0 rows
    report3: str = ""
    #: the validation tables', of its FMI 3.0 rows
    tables3: str = ""
    #: who owns its fixed-step Model Exchange methods, in the tables' legend ("FMPy's")
    owner: str = ""


@dataclass(frozen=True)
class Importer:
    """One importer, as its module declares it (see the module's documentation)."""

    #: its rows' importer column in FMI 2.0 Co-Simulation (see :func:`row_name`)
    name: str
    #: ``--no-<option>`` leaves it out; None: it always runs (the reference importer)
    option: str | None
    #: what ``--no-<option>`` leaves out
    left_out: str
    runs: Runs
    #: how far it may be from the reference importer's run (relative); None: it is the
    #: reference importer, held to each case's own tolerance
    tolerance: float | None
    #: whether it runs here (its version), or why not
    available: Callable[[], Availability]
    #: the rows of a case in an interface, each made when it is taken
    case_rows: Callable[[CaseRun, str], Iterator[Row]]
    #: the key of its entry in the JSON header
    header_key: str = ""
    #: its entry in the JSON header and the report's, from its availability (None: not used)
    header: Callable[[Availability | None], str] = lambda a: a.text if a is not None else "-"
    #: what ``mechfmu validate`` says when it is asked for and cannot run (``{why}``: why not)
    unavailable: str = ""
    #: the methods of its Model Exchange rows (``CVode``, ``Euler``), by FMI version
    methods: dict[str, tuple[str, ...]] = field(default_factory=dict)
    #: its fixed-step Model Exchange method (held to its order), as it runs an FMI 2.0 FMU
    fixed_step: FixedStep | None = None
    #: it also runs the FMU's binaries for the other platforms, under emulators (:mod:`.platform_rows`)
    platforms: bool = False
    #: how the report draws its runs' errors, by importer column
    curves: dict[str, Curve] = field(default_factory=dict)
    words: Words = Words()

    @property
    def reference(self) -> bool:
        """The importer every other one is compared with (it always runs)."""
        return self.option is None

    def row_names(self, version: str) -> list[str]:
        """Every importer column of its rows in an FMI version."""
        names = [row_name(self.name, version, CS)] if CS in self.runs.interfaces else []
        if ME in self.runs.interfaces:
            names += [row_name(self.name, version, ME, m) for m in self.methods.get(version, ())]
        return names if version in self.runs.versions else []


@dataclass(frozen=True)
class Selection:
    """What a validation runs: every importer but those left out (by their ``--no-<option>``),
    Model Exchange or not, and the FMI 3.0 FMU beside an FMI 2.0 one or not."""

    left_out: frozenset[str] = frozenset()
    model_exchange: bool = True
    fmi3: bool = True

    def uses(self, importer: Importer) -> bool:
        return importer.option not in self.left_out
