"""No event storm in Model Exchange: every FMU that asks for `fmi2CompletedIntegratorStep`
(a monitor of its limits, a projection onto a manifold) run under FMPy's CVode over its
default experiment at tolerances from 1e-4 to 1e-12, given to the FMU
(`fmi2SetupExperiment`, as FMI 2.0 intends and PyFMI does) or not (as FMPy does), enters
event mode a handful of times at most, and reaches the accuracy CVode reaches alone: a
tighter tolerance never gives a worse answer.

The truth is the FMU's own Co-Simulation at tolerance 1e-12 (its Dormand-Prince, whose
agreement with the independent references test_cases.py checks), on the same output grid.
"""

from __future__ import annotations

from xml.etree import ElementTree

import numpy as np
import pytest
from fmpy import extract, read_model_description, simulate_fmu
from fmpy.fmi2 import FMU2Model

import fmutest
from mechanisms import models

TOLERANCES = (1e-4, 1e-6, 1e-8, 1e-10, 1e-12)
#: step events and state events together, over a default experiment
MAX_EVENTS = 3


def asking_for_completed_integrator_step() -> list[str]:
    """The FMUs whose Model Exchange needs `fmi2CompletedIntegratorStep`, as their committed
    model descriptions say (FMPy does not read the attribute)."""
    found = []
    for model in models():
        xml = ElementTree.parse(fmutest.REPO_ROOT / "modelDescription" / f"{model}.xml")
        if xml.find("ModelExchange").get("completedIntegratorStepNotNeeded") != "true":
            found.append(model)
    return found


class FMU2Counted(FMU2Model):
    """An FMI 2.0 Model Exchange instance that counts `fmi2EnterEventMode` and, when
    `tolerance` is given, hands it to `fmi2SetupExperiment`. (FMPy binds the C functions of
    the FMI version its class name begins with.)"""

    def __init__(self, tolerance: float | None, **kwargs):
        self.events = 0
        super().__init__(fmiCallLogger=self._log, **kwargs)
        self._tolerance = tolerance

    def _log(self, line: str) -> None:
        if line.startswith("fmi2EnterEventMode"):
            self.events += 1

    def setupExperiment(self, tolerance=None, startTime=0.0, stopTime=None):
        return super().setupExperiment(tolerance=self._tolerance, startTime=startTime, stopTime=stopTime)


@pytest.fixture(scope="module", params=asking_for_completed_integrator_step())
def fmu(request, tmp_path_factory):
    """(model, model description, unzipped folder, the Co-Simulation truth)."""
    model = request.param
    path = fmutest.fmu_path(model)
    md = read_model_description(str(path))
    unzipped = extract(str(path), unzipdir=str(tmp_path_factory.mktemp(model)))
    truth = simulate_fmu(str(path), fmi_type="CoSimulation", relative_tolerance=1e-12)
    return model, md, unzipped, truth


def _error(md, result, truth) -> float:
    """The largest difference of an output from the truth at the common output points,
    relative to the output's range (at least 1)."""
    outputs = [v.name for v in md.modelVariables if v.causality == "output" and v.type == "Real"]
    assert outputs
    worst = 0.0
    for name in outputs:
        got = np.interp(truth["time"], result["time"], result[name])
        want = truth[name]
        scale = max(1.0, float(np.ptp(want)))
        worst = max(worst, float(np.max(np.abs(got - want))) / scale)
    return worst


@pytest.mark.parametrize("given", [False, True], ids=["tolerance-not-given", "tolerance-given"])
def test_cvode_at_every_tolerance_without_an_event_storm(fmu, given):
    model, md, unzipped, truth = fmu
    errors = {}
    for rtol in TOLERANCES:
        instance = FMU2Counted(rtol if given else None, guid=md.guid, unzipDirectory=unzipped,
                            modelIdentifier=md.modelExchange.modelIdentifier, instanceName=model)
        instance.instantiate()
        try:
            result = simulate_fmu(unzipped, model_description=md, fmu_instance=instance, fmi_type="ModelExchange",
                                  solver="CVode", relative_tolerance=rtol,
                                  output_interval=float(md.defaultExperiment.stepSize))
        finally:
            instance.freeInstance()
        assert instance.events <= MAX_EVENTS, f"{model} at rtol {rtol:g}: {instance.events} events"
        errors[rtol] = _error(md, result, truth)
    # CVode's own accuracy: a tighter tolerance, a smaller error (to within a factor, as
    # CVode's error is not exactly monotone in its tolerance), down to what it reaches
    for looser, tighter in zip(TOLERANCES, TOLERANCES[1:]):
        assert errors[tighter] <= max(3 * errors[looser], 1e-9), (model, errors)
    assert errors[1e-10] <= 1e-6, (model, errors)
