"""An FMU's binaries for other platforms, run on this (x86-64 Linux) machine: the Windows one
under ``wine64``, the ARM Linux one under ``qemu-aarch64``, each through ``mechfmu-fmi-run``
(the ``fmi`` crate's importer, :mod:`.fmi_crate`) built for that platform, and compared with
the native run.

``scripts/cross-runners`` builds the three runners and writes ``target/cross-runners/
runners.env`` (``KEY='value'`` lines), which :meth:`Runners.load` reads: the runners, a
wrapper executable per platform taking the runner's own arguments (``mechfmu-fmi-run-
x86_64-windows`` runs the ``.exe`` under wine64 with the prefix ``target/wine-prefix``;
``mechfmu-fmi-run-aarch64-linux`` runs the ARM runner under qemu-aarch64 with
``/usr/aarch64-linux-gnu`` as the sysroot).

Platforms are named by FMI 3.0's platform tuples, :data:`PLATFORMS`. FMI 2.0 names the
x86-64 ones ``linux64`` and ``win64`` and, per FMI 2.0.5, any other by its FMI 3.0 tuple:
ARM Linux is ``binaries/aarch64-linux/`` in both versions.

The importer convention this has to work around: the ``fmi`` crate 0.8 (as FMPy) looks for
an FMI 2.0 binary on aarch64 Linux under ``binaries/linux64/``, not ``aarch64-linux``. So
an FMI 2.0 FMU runs under qemu as a temporary copy whose ``linux64`` folder holds the
``aarch64-linux`` binary (:func:`aarch64_fmi2_copy`); FMI 3.0 FMUs run as they are.

* :func:`binary_platforms`: the platforms an FMU has binaries for (from the zip);
* :func:`run_case`: a reference case, the experiment built by :func:`~.fmi_crate.run_fmi_crate`
  itself (pointed at the platform's wrapper), returning its :class:`~.case.Result`;
* :func:`compare`: the largest relative difference from the native result and whether the
  two are bit for bit the same;
* :class:`WineSession`: one persistent wineserver for many runs.

Under wine, the runner gets Linux paths (the experiment, ``--out``, the FMU in the
experiment) as they are: Windows resolves ``/tmp/x`` on the current drive, which wine makes
``Z:`` (``/``) when the working directory is outside the prefix's ``drive_c``.
"""

from __future__ import annotations

import copy
import os
import re
import shlex
import shutil
import subprocess
import tempfile
import threading
import xml.etree.ElementTree as ET
import zipfile
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Mapping, Sequence

import numpy as np

from .case import Case, Result
from .agreement import agreement
from .host import NATIVE
from .importers.fmi_crate import FMI_RUN_ENV, run_fmi_crate

if TYPE_CHECKING:  # pragma: no cover
    from .arrays import ArrayMap
    from .fmu import Fmu

__all__ = ["EMULATED", "FMI2_FOLDERS", "SCRIPT", "ENV_FILE", "NotPrepared", "Runners", "WineSession", "fmi_version",
           "binary_platforms", "aarch64_fmi2_copy", "cleanup_copies", "run_case", "Comparison", "compare"]

#: the other platforms whose binaries run here, emulated, and how (an x86-64 Linux machine
#: runs the Windows and ARM Linux ones; nothing runs a Mac binary but a Mac)
EMULATED = {"x86_64-windows": "under wine64", "aarch64-linux": "under qemu-aarch64"} if NATIVE == "x86_64-linux" else {}
#: FMI 2.0's names of platforms (any other is its FMI 3.0 tuple); mechfmu's ``darwin64`` is a
#: universal binary of both Mac platforms, beside ``aarch64-darwin``'s own
FMI2_FOLDERS = {"linux64": "x86_64-linux", "win64": "x86_64-windows", "darwin64": "x86_64-darwin"}
#: the platforms ``scripts/cross-runners`` prepares a runner for
RUN_HERE = (NATIVE, *EMULATED)


#: what prepares the runners
SCRIPT = "scripts/cross-runners"
#: the environment file it writes (``$MECHFMU_CROSS_RUNNERS_ENV`` overrides)
ENV_FILE = Path(__file__).resolve().parents[2] / "target" / "cross-runners" / "runners.env"


class NotPrepared(RuntimeError):
    """The runners (or wine64, qemu-aarch64) are missing: run ``scripts/cross-runners``."""


# ---------------------------------------------------------------------------------------
# The runners


def _key(platform: str) -> str:
    return platform.upper().replace("-", "_")


@dataclass(frozen=True)
class Runners:
    """What ``scripts/cross-runners`` prepared (its environment file's settings)."""

    settings: Mapping[str, str]
    source: Path

    @classmethod
    def load(cls, path: str | Path | None = None) -> Runners:
        """Reads the environment file; raises :class:`NotPrepared` naming the script when it
        or any executable it names is missing."""
        path = Path(path or os.environ.get("MECHFMU_CROSS_RUNNERS_ENV") or ENV_FILE)
        if not path.is_file():
            raise NotPrepared(f"{path} does not exist: run `{SCRIPT}` (it builds mechfmu-fmi-run for "
                              f"{', '.join(RUN_HERE)} and prepares wine64 and qemu-aarch64)")
        settings = {}
        for line in path.read_text().splitlines():
            if line.strip() and not line.lstrip().startswith("#") and "=" in line:
                key, value = line.split("=", 1)
                settings[key.strip()] = shlex.split(value)[0] if value.strip() else ""
        runners = cls(settings, path)
        missing = [f"{k}={v}" for k, v in settings.items()
                   if k.startswith(("MECHFMU_RUNNER_", "MECHFMU_WRAPPER_", "MECHFMU_WINE", "MECHFMU_QEMU"))
                   and not (os.path.isfile(v) and os.access(v, os.X_OK))]
        missing += [f"{k} (not in the file)" for k in (f"MECHFMU_WRAPPER_{_key(p)}" for p in RUN_HERE)
                    if k not in settings]
        if missing:
            raise NotPrepared(f"{path} names what is not there: {', '.join(missing)}: run `{SCRIPT}` again "
                              "(see its header for the apt packages and rustup targets it needs)")
        return runners

    def wrapper(self, platform: str) -> str:
        """The executable running ``mechfmu-fmi-run`` for the platform (its arguments)."""
        if platform not in RUN_HERE:
            raise ValueError(f"no runner for {platform!r} here: only for {', '.join(RUN_HERE)}")
        return self.settings[f"MECHFMU_WRAPPER_{_key(platform)}"]

    def wine_env(self) -> dict[str, str]:
        session = {"TMPDIR": WineSession.tmpdir} if WineSession.tmpdir else {}
        return {**os.environ, "WINEPREFIX": self.settings["WINEPREFIX"], "WINEARCH": "win64", "WINEDEBUG": "-all",
                "WINEDLLOVERRIDES": "mscoree,mshtml=;winemenubuilder.exe=d", **session}


class WineSession:
    """A persistent wineserver (and the wine services, started once) for many runs under
    wine: without it every run starts and stops them, and a caller reading the run's output
    through a pipe (``subprocess.run(capture_output=True)``) waits until they exit, 3 s after
    the run (they inherit its standard handles). Started with the handles on /dev/null.

        with WineSession(runners):
            ... run_case(..., "x86_64-windows") ...

    On exit, ``wineserver -k`` ends that server (of this prefix only) and its processes.

    wine keeps its server's socket in ``$TMPDIR/wine-*/``, and leaves that folder behind: the
    session gives wine a temporary directory of its own (every run under wine meanwhile, as
    :func:`run_case` passes ``$TMPDIR`` on), and removes it."""

    #: the temporary directory of the open session's wine, if one is open
    tmpdir: str | None = None

    def __init__(self, runners: Runners):
        self.runners = runners

    def __enter__(self) -> WineSession:
        WineSession.tmpdir = tempfile.mkdtemp(prefix="mechfmu-wine-")
        try:
            env, s = self.runners.wine_env(), self.runners.settings
            quiet = dict(stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, cwd="/")
            subprocess.run([s["MECHFMU_WINESERVER"], "-p"], env=env, check=True, timeout=60, **quiet)
            # the runner without arguments prints its usage: starts the services, off any pipe
            subprocess.run([s["MECHFMU_WINE64"], s["MECHFMU_RUNNER_X86_64_WINDOWS"]], env=env, timeout=120, **quiet)
        except BaseException:
            self.__exit__()
            raise
        return self

    def __exit__(self, *exc) -> None:
        try:
            quiet = dict(stdin=subprocess.DEVNULL, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, timeout=60)
            server, env = self.runners.settings["MECHFMU_WINESERVER"], self.runners.wine_env()
            subprocess.run([server, "-k"], env=env, **quiet)
            subprocess.run([server, "-w"], env=env, **quiet)  # until it has exited
        finally:
            shutil.rmtree(WineSession.tmpdir or "", ignore_errors=True)
            WineSession.tmpdir = None


# ---------------------------------------------------------------------------------------
# An FMU's platforms


def fmi_version(fmu_path: str | Path) -> str:
    """The ``fmiVersion`` of the FMU's model description."""
    with zipfile.ZipFile(fmu_path) as z:
        return ET.fromstring(z.read("modelDescription.xml")).get("fmiVersion", "")


def binary_platforms(fmu_path: str | Path) -> dict[str, str]:
    """The platforms the FMU has a binary for, as FMI 3.0 tuples (``win64`` is
    ``x86_64-windows`` in an FMI 2.0 FMU), each with the binary's name in the zip
    (``binaries/win64/Oscillator.dll``). Only binaries named after a model identifier count."""
    with zipfile.ZipFile(fmu_path) as z:
        md = ET.fromstring(z.read("modelDescription.xml"))
        ids = {e.get("modelIdentifier") for e in md if e.get("modelIdentifier")}
        fmi2 = md.get("fmiVersion", "").startswith("2.")
        found = {}
        for name in z.namelist():
            m = re.fullmatch(r"binaries/([^/]+)/([^/]+)\.(so|dll|dylib)", name)
            if m and m.group(2) in ids:
                folder = m.group(1)
                found.setdefault(FMI2_FOLDERS.get(folder, folder) if fmi2 else folder, name)
        return found


_copies_lock = threading.Lock()
_copies: dict[tuple[str, float], Path] = {}
_copies_dir: str | None = None


def aarch64_fmi2_copy(fmu_path: str | Path) -> Path:
    """A copy of an FMI 2.0 FMU whose ``binaries/linux64/`` holds its ``aarch64-linux``
    binary (in place of the x86-64 one): where the ``fmi`` crate (and FMPy) look for an FMI
    2.0 binary on aarch64 Linux. Made once per process and FMU (a temporary directory)."""
    global _copies_dir
    fmu_path = Path(fmu_path).resolve()
    key = (str(fmu_path), fmu_path.stat().st_mtime)
    with _copies_lock:
        if key in _copies:
            return _copies[key]
        arm = {k: v for k, v in binary_platforms(fmu_path).items() if k == "aarch64-linux"}
        if not arm:
            raise FileNotFoundError(f"{fmu_path} has no binaries/aarch64-linux/ binary")
        if _copies_dir is None:
            _copies_dir = tempfile.mkdtemp(prefix="mechfmu-platforms-")
        target = Path(_copies_dir) / str(len(_copies)) / fmu_path.name
        target.parent.mkdir(parents=True)
        binary = arm["aarch64-linux"]
        with zipfile.ZipFile(fmu_path) as src, zipfile.ZipFile(target, "w", zipfile.ZIP_DEFLATED) as dst:
            for info in src.infolist():
                if not info.filename.startswith("binaries/linux64/"):
                    # a copy: writestr sets the ZipInfo's offset to the new archive's
                    dst.writestr(copy.copy(info), src.read(info.filename))
            dst.writestr("binaries/linux64/" + binary.rsplit("/", 1)[1], src.read(binary))
        _copies[key] = target
        return target


def cleanup_copies() -> None:
    """Removes this process's :func:`aarch64_fmi2_copy` copies."""
    global _copies_dir
    with _copies_lock:
        if _copies_dir is not None:
            shutil.rmtree(_copies_dir, ignore_errors=True)
        _copies_dir = None
        _copies.clear()


def _fmu_for(fmu_path: str | Path, platform: str) -> Path:
    """The file the platform's runner is given: the FMU, or its aarch64 FMI 2.0 copy."""
    found = binary_platforms(fmu_path)
    if platform not in found:
        raise FileNotFoundError(f"{fmu_path} has no {platform} binary (it has: {', '.join(found) or 'none'})")
    if platform == "aarch64-linux" and fmi_version(fmu_path).startswith("2."):
        return aarch64_fmi2_copy(fmu_path)
    return Path(fmu_path)


# ---------------------------------------------------------------------------------------
# Running


_env_lock = threading.Lock()


def run_case(fmu: Fmu, case: Case, platform: str, runners: Runners | None = None, mapping: ArrayMap | None = None,
             interface: str = "cs", step: float | None = None) -> Result:
    """A reference case on the FMU's binary for ``platform``: exactly what
    :func:`~.fmi_crate.run_fmi_crate` runs (it builds the experiment; ``mapping``: the FMI 3.0
    FMU's names, as :func:`~.fmi3.run_crate3` passes them), with ``$MECHFMU_FMI_RUN`` pointed
    at the platform's wrapper for the call.

    As ``$MECHFMU_FMI_RUN`` is the process's, runs in one process are serialized (a lock):
    run cases in parallel in several processes (each loads its FMUs). Under wine, have a
    :class:`WineSession` open."""
    runners = runners or Runners.load()
    path = _fmu_for(fmu.path, platform)
    if path != fmu.path:
        fmu = copy.copy(fmu)  # the same extracted model description, another file for the runner
        fmu.path = path
    settings = {FMI_RUN_ENV: runners.wrapper(platform)}
    if platform == "x86_64-windows" and WineSession.tmpdir:
        settings["TMPDIR"] = WineSession.tmpdir  # where the session's wineserver is
    with _env_lock:
        before = {k: os.environ.get(k) for k in settings}
        os.environ.update(settings)
        try:
            return run_fmi_crate(fmu, case, interface=interface, step=step, mapping=mapping)
        finally:
            for k, v in before.items():
                if v is None:
                    os.environ.pop(k, None)
                else:
                    os.environ[k] = v


# ---------------------------------------------------------------------------------------
# Comparing


@dataclass
class Comparison:
    """A platform's result against the native one.

    ``max_relative``: the largest ``|x - y| / scale`` over the compared columns and times,
    ``y`` native, ``scale`` the native column's largest magnitude, or 1 for a column that is
    zero throughout (then an absolute difference): :func:`~.agreement.agreement`'s
    definition, the one every importer comparison of ``mechfmu validate`` uses.
    ``bit_identical``: every compared value has the same 64 bits (so ``-0.0`` differs
    from ``0.0``); ``differing``: the columns that are not."""

    max_relative: float
    signal: str
    time: float
    bit_identical: bool
    differing: list[str] = field(default_factory=list)

    def __str__(self) -> str:
        if self.bit_identical:
            return "bit-identical"
        return (f"max rel diff {self.max_relative:.3e} in {self.signal} at t = {self.time:g} "
                f"({len(self.differing)} column(s) differ)")


def compare(native: Result | Mapping[str, np.ndarray], other: Result | Mapping[str, np.ndarray],
            names: Sequence[str] | None = None) -> Comparison:
    """``other`` against ``native`` over ``names`` (default: every native column but
    ``time``, which must be equal too for the results to be bit-identical)."""
    a = other if isinstance(other, Result) else Result(dict(other))
    b = native if isinstance(native, Result) else Result(dict(native))
    names = list(names) if names is not None else [n for n in b.columns if n != "time"]
    worst, signal, when, _ = agreement(a, b, names, None)
    differing = [n for n in ["time", *names] if n not in a.columns or a[n].shape != b[n].shape
                 or a[n].astype(np.float64).tobytes() != b[n].astype(np.float64).tobytes()]
    return Comparison(worst, signal, when, not differing, differing)
