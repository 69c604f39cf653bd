"""A plain Jacobi co-simulation of an SSP's FMUs (FMI 2.0 Co-Simulation, through FMPy's
``FMU2Slave``): at each communication point the outputs are passed to the inputs they feed,
repeated until every output that follows its inputs at once has seen them (as many passes as
there are components), then every FMU steps over the communication step with its inputs held.
"""

from __future__ import annotations

from collections import defaultdict

import fmpy
import numpy as np
from fmpy.fmi2 import FMU2Slave

from .archive import Ssp


def run(ssp: Ssp, values: dict[tuple[str, str], float], step: float, stop: float,
        signals: list[tuple[str, str]], workdir, resolved: bool = True, zero_start: bool = False,
        ) -> tuple[np.ndarray, dict[tuple[str, str], np.ndarray]]:
    """The signals at every communication point from ``ssp.start`` to ``stop`` in steps of
    ``step``, the set ``values`` applied before initialization. Not ``resolved``: each
    output passed once per step, as read after the step (libcosim's, FMPy's and Ecos'
    schemes: an output that follows its inputs at once reaches the inputs it feeds a step
    late). ``zero_start``: every connected input 0 over the first step (FMPy's start)."""
    slaves: dict[str, FMU2Slave] = {}
    refs: dict[tuple[str, str], int] = {}
    try:
        for c in ssp.components:
            fmu = ssp.fmu(c.name)
            md = fmpy.read_model_description(str(fmu), validate=False)
            unzipped = fmpy.extract(str(fmu), str(workdir / f"jacobi-{c.name}"))
            slave = FMU2Slave(guid=md.guid, unzipDirectory=unzipped,
                              modelIdentifier=md.coSimulation.modelIdentifier, instanceName=c.name)
            slaves[c.name] = slave
            for v in md.modelVariables:
                refs[(c.name, v.name)] = v.valueReference
            slave.instantiate()
            slave.setupExperiment(startTime=ssp.start)
            own = [(refs[(c.name, v)], x) for (name, v), x in values.items() if name == c.name]
            if own:
                slave.setReal([r for r, _ in own], [x for _, x in own])
            slave.enterInitializationMode()
            slave.exitInitializationMode()
        # the connections grouped by the component they read from and the one they write to
        by_source: dict[str, list[tuple[int, tuple[str, int]]]] = defaultdict(list)
        for (fc, fv), (tc, tv) in ssp.connections:
            by_source[fc].append((refs[(fc, fv)], (tc, refs[(tc, tv)])))
        passes = len(slaves) if resolved else 1

        def exchange():
            for _ in range(passes):
                incoming: dict[str, tuple[list[int], list[float]]] = defaultdict(lambda: ([], []))
                for source, links in by_source.items():
                    read = slaves[source].getReal([r for r, _ in links])
                    for (_, (target, vr)), x in zip(links, read):
                        incoming[target][0].append(vr)
                        incoming[target][1].append(x)
                for target, (vrs, xs) in incoming.items():
                    slaves[target].setReal(vrs, xs)

        n = int(round((stop - ssp.start) / step))
        times = ssp.start + step * np.arange(n + 1)
        out = {s: np.empty(n + 1) for s in signals}
        by_component: dict[str, list[tuple[str, str]]] = defaultdict(list)
        for s in signals:
            by_component[s[0]].append(s)

        def record(k):
            for name, wanted in by_component.items():
                for s, x in zip(wanted, slaves[name].getReal([refs[s] for s in wanted])):
                    out[s][k] = x

        if zero_start:
            for (_, _), (tc, tv) in ssp.connections:
                slaves[tc].setReal([refs[(tc, tv)]], [0.0])
        else:
            exchange()
        record(0)
        for k in range(n):
            if k > 0 or not zero_start:
                exchange()
            for slave in slaves.values():
                slave.doStep(currentCommunicationPoint=times[k], communicationStepSize=step)
            record(k + 1)
        return times, out
    finally:
        for slave in slaves.values():
            try:
                slave.terminate()
                slave.freeInstance()
            except Exception:  # noqa: BLE001 (an instance that failed is freed as far as it goes)
                pass


def solution(ssp: Ssp, values, stop: float, signals, workdir, refinement: int = 8):
    """The system's solution at the SSP's communication points: the plain Jacobi scheme at
    ``step / refinement`` and at half of that, extrapolated to a step of zero (its error is
    first order in the step)."""
    fine = ssp.step / refinement
    _, coarse_run = run(ssp, values, fine, stop, signals, workdir)
    _, finer_run = run(ssp, values, fine / 2, stop, signals, workdir)
    n = int(round((stop - ssp.start) / ssp.step))
    times = ssp.start + ssp.step * np.arange(n + 1)
    solved = {}
    for s in signals:
        coarse = coarse_run[s][::refinement][: n + 1]
        finer = finer_run[s][:: 2 * refinement][: n + 1]
        solved[s] = 2.0 * finer - coarse
    return times, solved
