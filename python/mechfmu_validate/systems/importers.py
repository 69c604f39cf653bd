"""The SSP importers: each runs one parameter set of an SSP at a communication step and
returns the connected outputs at the times it reached them, or says why it cannot.

- FMPy (``fmpy.ssp.simulate_ssp``) applies no binding of the SSP: the set is passed as its
  ``parameter_set``, with the components' names before the variables'. It labels each row
  with the time the step started, so its rows are moved one step on. Its master passes each
  output once per step, as read after the step, and starts every input at 0.
- libcosim (``libcosimpy``) loads the ``.ssd`` that binds the set (a variant for a set other
  than the default) and applies a set only to parameters and inputs: a start value of a state
  it leaves at the FMU's own (logged as "Non-input causality"). Its master passes each output
  once per step, as read after the step.
- Ecos (``ecospy``, which needs Debian's ``libtbb12``) applies the set ``init`` names among
  those ``SystemStructure.ssd`` binds, the default set alone (it loads no variant).
- OMSimulator's Python API (no wheel: it builds from source; used when ``OMSimulator`` can
  be imported) runs the variant of the set, and writes two rows per step (the last is kept).
  Its command line (``MECHFMU_OMSIMULATOR``, or ``OMSimulator`` on the PATH) runs
  ``SystemStructure.ssd``, the default set, at the SSD's own step whatever ``--stepSize`` says.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from types import SimpleNamespace
from typing import Callable

import fmpy
import numpy as np

from .archive import DEFAULT_SSD, Ssp

Series = tuple[np.ndarray, dict[tuple[str, str], np.ndarray]]


@dataclass(frozen=True)
class SspImporter:
    name: str
    #: ``(available, version or why not)``
    available: Callable[[], tuple[bool, str]]
    run: Callable[[Ssp, str, float, list[tuple[str, str]]], Series]
    #: the master it runs (:func:`.jacobi.run`'s ``resolved`` and ``zero_start``)
    scheme: tuple[bool, bool] = (True, False)
    #: the causalities a set's values reach in this importer (None: every variable)
    applies_to: frozenset[str] | None = None
    #: it runs the default set only (it loads no variant)
    default_only: bool = False
    #: it runs at the SSP's own step only (a command line that takes no other)
    own_step_only: bool = False


def _fmpy_available() -> tuple[bool, str]:
    return True, f"FMPy {fmpy.__version__}"


def _fmpy_run(ssp: Ssp, set_name: str, step: float, signals) -> Series:
    from fmpy.ssp.simulation import simulate_ssp

    parameters = [SimpleNamespace(name=f"{c}.{v}", value=x) for (c, v), x in ssp.sets[set_name].items()]
    result = simulate_ssp(str(ssp.path), start_time=ssp.start, stop_time=ssp.stop, step_size=step,
                          parameter_set=SimpleNamespace(parameters=parameters))
    # a row holds the values at the end of the step that starts at its time
    times = np.asarray(result["time"]) + step
    return times, {s: np.asarray(result[f"{s[0]}.{s[1]}"]) for s in signals}


def _libcosim_available() -> tuple[bool, str]:
    try:
        import libcosimpy  # noqa: F401
        from importlib.metadata import version
        return True, f"libcosimpy {version('libcosimpy')}"
    except Exception as e:  # noqa: BLE001
        return False, f"libcosimpy cannot be imported: {e}"


def _libcosim_run(ssp: Ssp, set_name: str, step: float, signals) -> Series:
    from libcosimpy.CosimEnums import CosimVariableType
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver

    log_output_level(CosimLogLevel.ERROR)
    ssd = ssp.folder / ssp.set_files[set_name]
    # always a step, in integer nanoseconds (libcosimpy's unit): libcosim fails without one,
    # and an SSP may give its step to OMSimulator alone
    execution = CosimExecution.from_ssp_file(str(ssd), step_size=int(round(step * 1e9)))
    slaves = {info.name.decode(): info.index for info in execution.slave_infos()}
    refs = {}
    for name, index in slaves.items():
        for v in execution.slave_variables(index):
            refs[(name, v.name.decode())] = v.reference
    n = int(round((ssp.stop - ssp.start) / step))
    series = CosimObserver.create_time_series(buffer_size=n + 16)
    execution.add_observer(observer=series)
    for s in signals:
        series.start_time_series(slaves[s[0]], refs[s], CosimVariableType.REAL)
    # libcosimpy's times are integer nanoseconds
    if not execution.simulate_until(target_time=int(round(n * step * 1e9))):
        raise RuntimeError(f"libcosim stopped before {ssp.stop:g} s: {execution.status()}")
    out, times = {}, None
    for s in signals:
        at, _, values = series.time_series_real_samples(slaves[s[0]], refs[s], from_step=0, sample_count=n + 8)
        out[s] = np.asarray(values, dtype=float)
        times = np.asarray(at, dtype=float) * 1e-9 if times is None else times
    return times, out


def _ecos_available() -> tuple[bool, str]:
    try:
        import ecospy  # noqa: F401
        from importlib.metadata import version
        return True, f"ecospy {version('ecospy')}"
    except Exception as e:  # noqa: BLE001 (its library missing, libtbb12 say)
        return False, f"ecospy cannot be imported: {e}"


def _ecos_run(ssp: Ssp, set_name: str, step: float, signals) -> Series:
    from ecospy import EcosSimulation

    simulation = EcosSimulation(step_size=step, ssp_path=str(ssp.path))
    try:
        simulation.init(start_time=ssp.start, parameter_set=set_name)
        n = int(round((ssp.stop - ssp.start) / step))
        times = np.empty(n + 1)
        out = {s: np.empty(n + 1) for s in signals}
        names = {s: f"{s[0]}::{s[1]}" for s in signals}
        for k in range(n + 1):
            if k:
                simulation.step(1)
            times[k] = simulation.get_time()
            for s in signals:
                out[s][k] = simulation.get_real(names[s])
        simulation.terminate()
        return times, out
    finally:
        simulation.free()


def _oms_available() -> tuple[bool, str]:
    try:
        import OMSimulator  # noqa: F401
        return True, "OMSimulator (Python API)"
    except Exception as e:  # noqa: BLE001 (not installed: it has no wheel)
        return False, f"OMSimulator cannot be imported (it builds from source; put its lib/ on PYTHONPATH): {e}"


def _oms_run(ssp: Ssp, set_name: str, step: float, signals) -> Series:
    import tempfile

    from OMSimulator import SSP

    model = SSP(str(ssp.path))
    if ssp.set_files[set_name] != DEFAULT_SSD:
        model.activeVariantName = set_name
    instance = model.instantiate()
    with tempfile.TemporaryDirectory(prefix="mechfmu-oms-") as tmp:
        result = f"{tmp}/result.csv"
        instance.setResultFile(result)
        instance.setFixedStepSize(step)
        instance.setStopTime(ssp.stop)
        instance.initialize()
        instance.simulate()
        instance.terminate()
        instance.delete()
        return _oms_result(result, ssp.name, signals)


def _oms_executable() -> str | None:
    import os
    import shutil

    return os.environ.get("MECHFMU_OMSIMULATOR") or shutil.which("OMSimulator")


def _oms_cli_available() -> tuple[bool, str]:
    executable = _oms_executable()
    if executable is None:
        return False, "no OMSimulator executable (MECHFMU_OMSIMULATOR, or OMSimulator on PATH)"
    return True, f"OMSimulator command line ({executable})"


def _oms_cli_run(ssp: Ssp, set_name: str, step: float, signals) -> Series:
    import subprocess
    import tempfile

    with tempfile.TemporaryDirectory(prefix="mechfmu-oms-cli-") as tmp:
        result = f"{tmp}/result.csv"
        done = subprocess.run([_oms_executable(), f"--resultFile={result}", f"--stopTime={ssp.stop!r}",
                               f"--tempDir={tmp}", str(Path(ssp.path).resolve())], capture_output=True,
                              text=True, cwd=tmp,
                              timeout=1800)
        if done.returncode != 0:
            raise RuntimeError(f"OMSimulator exited with {done.returncode}: {done.stdout[-2000:]}")
        times, out = _oms_result(result, f"{ssp.name}.{ssp.name}", signals)
    return times, out


def _oms_result(path: str, prefix: str, signals) -> Series:
    """OMSimulator's result file: its columns ``<prefix>.<component>.<variable>``, two rows
    per step (before and after the exchange), of which the last of each time is kept."""
    import csv

    with open(path, newline="") as f:
        rows = list(csv.reader(f, skipinitialspace=True))
    columns = {name: i for i, name in enumerate(rows[0])}
    last: dict[float, list[str]] = {}
    for row in rows[1:]:
        last[float(row[0])] = row
    times = np.array(sorted(last))
    return times, {s: np.array([float(last[t][columns[f"{prefix}.{s[0]}.{s[1]}"]]) for t in times])
                   for s in signals}


IMPORTERS = (
    SspImporter("FMPy SSP", _fmpy_available, _fmpy_run, scheme=(False, True)),
    SspImporter("libcosim SSP", _libcosim_available, _libcosim_run, scheme=(False, False),
                applies_to=frozenset({"parameter", "input"})),
    SspImporter("Ecos SSP", _ecos_available, _ecos_run, scheme=(False, False), default_only=True),
    SspImporter("OMSimulator SSP", _oms_available, _oms_run, scheme=(True, False)),
    SspImporter("OMSimulator CLI", _oms_cli_available, _oms_cli_run, scheme=(True, False), default_only=True,
                own_step_only=True),
)
