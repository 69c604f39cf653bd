"""The rows of ``mechfmu validate`` for an FMU's binaries: the platforms it carries, which of
them ran, and each reference case on each binary for another platform (Windows under
wine64, ARM Linux under qemu-aarch64, through :mod:`.platforms`) against this machine's
binary, both through the importer that runs them (:data:`~.importers.PLATFORMS`), to
:data:`PLATFORM_TOLERANCE`.

The foreign binaries run when ``scripts/cross-runners`` has prepared their runners
(``target/cross-runners/runners.env``); otherwise the platform row says they were packaged
and not run, and why."""

from __future__ import annotations

import contextlib
from typing import TYPE_CHECKING, Iterator

from .host import NATIVE, PLATFORMS
from .importer import CS, FMI2, FMI3, Importer, row_name
from .platforms import (EMULATED, FMI2_FOLDERS, NotPrepared, Runners, WineSession,
                        binary_platforms, cleanup_copies, compare, fmi_version, run_case)
from .rows import Row

if TYPE_CHECKING:  # pragma: no cover
    from .case import Case
    from .fmu import Fmu

__all__ = ["PLATFORM_TOLERANCE", "Platforms", "session"]

#: a foreign binary's run must agree with this machine's to this, relative
PLATFORM_TOLERANCE = 1e-12

_runners: Runners | None = None
_why_not: str | None = None


def _load() -> tuple[Runners | None, str | None]:
    global _runners, _why_not
    if _runners is None and _why_not is None:
        try:
            _runners = Runners.load()
        except NotPrepared as e:
            _why_not = f"{e}"
    return _runners, _why_not


@contextlib.contextmanager
def session(enabled: bool = True) -> Iterator[None]:
    """One wine session for a whole validation (when the runners are prepared); the copies of
    FMUs the ARM runs were given are removed at its end."""
    runners, _ = _load() if enabled else (None, None)
    try:
        if runners is None:
            yield
            return
        with WineSession(runners):
            yield
    finally:
        cleanup_copies()


class Platforms:
    """The binaries of the opened ``fmu``, run by ``runner``, the importer that runs them
    (``names``: the FMI 3.0 FMU's array mapping; ``enabled``: whether the runner is used)."""

    def __init__(self, fmu: Fmu, name: str, runner: Importer, names=None, enabled: bool = True):
        self.path, self.name, self.names = fmu.path, name, names
        self.runner = runner.name
        self.version = fmi_version(self.path)
        found = binary_platforms(self.path)
        # in the order of PLATFORMS, then any other
        self.found = {p: found[p] for p in sorted(found, key=lambda p: (p not in PLATFORMS,
                                                                       PLATFORMS.index(p) if p in PLATFORMS else 0, p))}
        #: the importer prefix of its rows: the runner's Co-Simulation rows' importer column
        self.label = row_name(runner.name, FMI3 if self.version.startswith("3.") else FMI2, CS)
        self.runners, why_not = _load() if enabled else (None, f"not asked for (--no-{runner.option})")
        self.why_not = why_not
        self.foreign = [p for p in EMULATED if p in self.found]
        self.by_mechfmu = fmu.by_mechfmu
        # what the platforms row calls each platform: its folder's name in the FMU's own
        # version (FMI 2.0's win64, linux64; FMI 3.0's x86_64-windows), never a mix of both
        fmi2_names = {t: f for f, t in FMI2_FOLDERS.items()} if self.version.startswith("2.") else {}
        self.folders = {p: self.found[p].split("/")[1] if p in self.found else fmi2_names.get(p, p)
                        for p in (*self.found, *PLATFORMS)}

    def summary_row(self) -> Row:
        """The platforms this FMU has binaries for and which of them run here."""
        parts = []
        for platform in self.found:
            if platform == NATIVE:
                parts.append(f"{self.folders[platform]}: run (every importer)")
            elif platform in EMULATED and self.runners is not None:
                parts.append(f"{self.folders[platform]}: run {EMULATED[platform]} ({self.runner})")
            elif platform.endswith("-darwin") and self.by_mechfmu:
                # mechfmu build checked it (exports, libraries, signature) before packaging it
                parts.append(f"{self.folders[platform]}: packaged, checked, not run (only a Mac runs it)")
            else:
                parts.append(f"{self.folders[platform]}: packaged, not run")
        missing = [self.folders[p] for p in PLATFORMS if p not in self.found]
        notes = [f"binaries: {'; '.join(parts) or 'none'}"]
        if missing:
            notes.append(f"no binary for {', '.join(missing)}")
        if self.foreign and self.runners is None:
            notes.append(f"the other platforms' binaries were not run: {self.why_not}")
        return Row(kind="note", fmu=self.name, case=f"(platforms, FMI {self.version})",
                    importer=", ".join(self.folders[p] for p in self.found) or "-", max_error=None, tolerance=None,
                    passed=NATIVE in self.found, problems=[] if NATIVE in self.found
                    else [f"no {self.folders[NATIVE]} binary: nothing to run on this machine"], notes=notes,
                    platforms=dict(found=list(self.found), run=[NATIVE] + (self.foreign if self.runners else []),
                                   names={p: self.folders[p] for p in (*self.found, *PLATFORMS)}))

    def case_rows(self, fmu: Fmu, case: Case) -> Iterator[Row]:
        """The case on each foreign binary against this machine's, a row as each run ends (so
        that what the run printed is its row's)."""
        if self.runners is None or not self.foreign:
            return
        try:
            native = run_case(fmu, case, NATIVE, self.runners, mapping=self.names)
        except Exception as e:  # noqa: BLE001 (a row, not a crash)
            native, native_error = None, f"{type(e).__name__}: {e}"
        for platform in self.foreign:
            row = Row(kind="case", fmu=self.name, case=case.name, importer=f"{self.label} {platform}",
                       tolerance=PLATFORM_TOLERANCE, problems=[], notes=[])
            try:
                if native is None:
                    raise RuntimeError(f"the {NATIVE} run failed: {native_error}")
                other = run_case(fmu, case, platform, self.runners, mapping=self.names)
                c = compare(native, other, [n for n in case.recorded() if n in native.columns])
                row.update(max_error=c.max_relative, passed=bool(c.max_relative <= PLATFORM_TOLERANCE),
                           notes=[f"{platform} binary {EMULATED[platform]} against the {NATIVE} binary: {c}"],
                           bit_identical=c.bit_identical)
            except Exception as e:  # noqa: BLE001 (a row, not a crash)
                row.update(max_error=None, passed=False,
                           problems=[f"{platform} run failed: {type(e).__name__}: {e}"])
            yield row
