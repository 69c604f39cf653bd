"""The FMI 3.0 FMUs (fmus/fmi3/<Name>.fmu, written by `mechfmu build` beside the FMI 2.0 ones)
as `mechfmu validate` runs them (mechfmu_validate.target, mechfmu_validate.importers):

* which FMI 2.0 variable each element of their arrays is, as their model descriptions name
  it (mechfmu_validate.arrays), is the contract's (docs/mechanisms/README.md, "FMI 3.0, arrays";
  [arrays] in the mechanism's validation/contract.toml);
* every reference case of every mechanism (fmus/*/validation/cases.py) under FMPy's FMI 3.0
  Co-Simulation meets the case's limits, and the fmi crate's FMI 3.0 import agrees with it
  (1e-9); under FMPy's FMI 3.0 Model Exchange (CVode at 1e-10) the case meets its limits, or
  is the LIMIT its FMI 2.0 run is (test_model_exchange.KNOWN_LIMITS);
* the DefaultExperiment under FMPy's Co-Simulation gives the same numbers through both FMUs
  (every variable, 1e-12 relative);
* the crane's trolley reaching the pivot under FMI 3.0 Co-Simulation: with early return, the
  FMU returns early at the crossing and FMPy ends the result there (what FMI 2.0 gives);
  without, the step is fmi3Discard, which FMPy raises.

The fmi crate's FMI 3.0 Model Exchange rows (RK4) are run by test_validate.py's `mechfmu
validate`, and bit for bit against FMI 2.0 by tools/fmi-run/tests/fmi3.rs.
"""

from __future__ import annotations

import re

import numpy as np
import pytest
from fmpy import simulate_fmu
from fmpy.fmi1 import FMICallException

import fmutest
from mechfmu_validate import fmulog
from mechfmu_validate.arrays import MappingError, derive
from mechfmu_validate.case import Case, evaluate, step_input
from mechfmu_validate.agreement import agreement
from mechfmu_validate.fmu import Fmu
from mechfmu_validate.importers.fmi_crate import FMI_CRATE_TOLERANCE as CRATE_TOLERANCE, run_crate3
from mechfmu_validate.importers.fmpy import CVODE, FMI3_CVODE, run_fmpy, run_fmpy3, run_fmpy3_me, run_fmpy_me
from mechfmu_validate.model_exchange import CVODE_FLOOR, cvode_row
from mechfmu_validate.target import AGREEMENT_TOLERANCE, Target as Fmi3, agreement_row
from mechanisms import mechanism
from test_cases import CASES, MODELS
from test_model_exchange import KNOWN_LIMITS, fmi_run  # noqa: F401 (fmi_run: the fixture)

_fmus: dict[str, tuple[Fmu, Fmi3]] = {}


def fmi3_path(model: str):
    path = fmutest.FMU_DIR / "fmi3" / f"{model}.fmu"
    if not path.is_file():
        pytest.fail(f"{path} does not exist: {fmutest.BUILD_HINT}", pytrace=False)
    return path


def both(model: str) -> tuple[Fmu, Fmi3]:
    """The FMI 2.0 FMU and the FMI 3.0 one with its names, once per module."""
    if model not in _fmus:
        fmu2 = Fmu(fmutest.fmu_path(model))
        _fmus[model] = (fmu2, Fmi3.open(fmi3_path(model)))
    return _fmus[model]


@pytest.fixture(scope="module", autouse=True)
def _cleanup():
    yield
    for fmu2, f3 in _fmus.values():
        fmu2.cleanup()
        f3.cleanup()
    _fmus.clear()


def _ids(p):
    return f"{p[0]}-{p[1].name}"


@pytest.mark.parametrize("model", MODELS)
def test_the_arrays_are_the_contracts(model):
    _, f3 = both(model)
    assert f3.problem is None, f3.problem
    contract = mechanism(model).contract
    contract = contract.arrays if contract is not None else {}
    assert {a: " ".join(e) for a, e in f3.mapping.elements.items()} == contract


def test_an_fmu_alone_names_its_elements_and_a_foreign_one_says_it_cannot(tmp_path):
    """The FMI 3.0 FMU alone names its arrays' FMI 2.0 scalars (its annotations); one whose
    arrays lack them (as another exporter's would) gets an error that says so."""
    rigid_body, oscillator = Fmu(fmi3_path("RigidBody")), Fmu(fmi3_path("Oscillator"))
    try:
        assert " ".join(derive(rigid_body).elements["q"]) == "q_w q_x q_y q_z"
        assert derive(oscillator).scalars >= {"x", "x_dot", "k"}  # no arrays: the FMI 2.0 names
        xml = rigid_body.directory / "modelDescription.xml"
        text = xml.read_text()
        xml.write_text(text.replace('type="org.mechfmu.scalars"', 'type="org.example.other"'))
        with pytest.raises(MappingError, match=r"no org\.mechfmu\.scalars annotation"):
            derive(rigid_body)
        xml.write_text(text)
    finally:
        rigid_body.cleanup()
        oscillator.cleanup()


@pytest.mark.parametrize("model, case", CASES, ids=[_ids(p) for p in CASES])
def test_case_under_fmi3_co_simulation(model, case, fmi_run):
    """FMPy's FMI 3.0 Co-Simulation against the case's reference; the fmi crate's FMI 3.0
    import against FMPy's run."""
    _, f3 = both(model)
    result = run_fmpy3(f3, case)
    ev = evaluate(case, result)
    assert ev.problem is None, ev.problem
    failed = [f"{s.name}: {s.max_error:.3e} of scale {s.scale:.4g} at t = {s.at_time:g} (tolerance {s.tolerance:g})"
              for s in ev.signals if not s.passed]
    assert not failed, f"{model} / {case.name} under FMI 3.0:\n" + "\n".join(failed)
    floors = {s.name: s.scale for s in ev.signals}
    worst, name, t, _ = agreement(run_crate3(f3, case), result, case.recorded(), floors)
    assert worst <= CRATE_TOLERANCE, \
        f"the fmi crate's FMI 3.0 run differs from FMPy's by {worst:.2e} in {name} at t = {t:g}"


@pytest.mark.parametrize("model, case", CASES, ids=[_ids(p) for p in CASES])
def test_case_under_fmi3_model_exchange(model, case):
    """FMPy's FMI 3.0 Model Exchange (CVode at 1e-10), judged as the FMI 2.0 row is."""
    _, f3 = both(model)
    row = cvode_row(f3.fmu, case, importer=FMI3_CVODE, run=lambda _, c: run_fmpy3_me(f3, c, "CVode"))
    assert row["passed"] and not row["problems"], row["problems"] or row["signals"]
    if (model, case.name, CVODE) in KNOWN_LIMITS:
        assert row["limited"] and row["max_error"] <= CVODE_FLOOR, row
    else:
        assert not row["limited"], f"{model} / {case.name}: LIMIT under FMI 3.0 only: {row['notes']}"


def test_array_elements_as_start_values_inputs_and_outputs_give_the_fmi2_numbers(fmi_run):
    """What no reference case does: an input that is an array element (tau_y = tau[2]), a
    repeated element set once (I_xy: I_C[1,2] and I_C[2,1]), outputs from three arrays. FMPy's
    FMI 3.0 runs (an input table with an array column) and the fmi crate's give the FMI 2.0
    FMU's numbers, bit for bit, in both interfaces."""
    case = Case("torque_step", stop_time=2.0, output_interval=0.01, relative_tolerance=1e-8,
                start_values={"I_xy": 0.001, "q_w": np.cos(0.2), "q_y": np.sin(0.2), "r_Cz": 0.02},
                input=step_input(["tau_y"], [0.0, 0.5, 1.2], [[0.0], [0.02], [-0.01]], 2.0),
                outputs=["q_x", "w_z", "H_Z", "w_y_dot", "I_Bxy"], reference=lambda t: {})
    fmu2, f3 = both("RigidBody")
    pairs = [(run_fmpy3(f3, case), run_fmpy(fmu2, case)), (run_crate3(f3, case), run_fmpy(fmu2, case)),
             (run_fmpy3_me(f3, case), run_fmpy_me(fmu2, case))]
    for a, b in pairs:
        for name in ["time", *case.outputs]:
            assert np.array_equal(a[name], b[name]), name
    assert np.ptp(pairs[0][0]["w_y_dot"]) > 0.01  # the torque acted


@pytest.mark.parametrize("model", MODELS)
def test_fmi3_co_simulation_equals_fmi2(model):
    """The DefaultExperiment through both FMUs, FMPy's Co-Simulation: every FMI 2.0 variable
    and its FMI 3.0 scalar or element (each place of it) agree to 1e-12 (one binary, the same
    steps: they are the same numbers)."""
    fmu2, f3 = both(model)
    row = agreement_row(f3, fmu2)
    assert row["passed"] and row["max_error"] <= AGREEMENT_TOLERANCE, row["problems"] or row["notes"]


# ---------------------------------------------------------------------------------------
# Early return: the trolley reaching the pivot (test_crane.py, test_model_exchange.py)

START = {"x": 1.0, "x_dot": -1.05}  # x = 1 - 1.05 t: the pivot at t* = 1/1.05
H = 0.1


def _crane3(**options):
    calls: list[str] = []
    mark = fmulog.LogMark()
    table = simulate_fmu(str(both("Crane")[1].fmu.directory), relative_tolerance=1e-8, output_interval=H,
                         stop_time=5.0, start_values=START, output=["x"], logger=fmulog.fmi3_logger(),
                         fmi_call_logger=calls.append, **options)
    return table, [c for c in calls if c.startswith("fmi3DoStep")], mark


@pytest.mark.parametrize("event_mode", [False, True], ids=["step-mode", "event-mode"])
def test_crane_early_return_stops_at_the_pivot(event_mode):
    """With early return allowed, the step in which the trolley reaches the pivot returns
    fmi3Warning with earlyReturn and terminateSimulation, lastSuccessfulTime the crossing
    (the FMU logs why). FMPy 0.3.32 records that point and stops: the result ends at t* with
    x = 0 to rounding, after the communication points before it, and is the FMI 2.0 FMU's
    result (which FMPy ends at fmi2Discard's last successful time) to the bit. In event mode
    it is the same (no event is signalled: the run just ends)."""
    t_star = 1.0 / 1.05
    table, steps, mark = _crane3(early_return_allowed=True, use_event_mode=event_mode)
    last = steps[-1]
    assert "terminateSimulation=True, earlyReturn=True" in last and last.endswith("-> WARNING"), last
    assert float(re.search(r"lastSuccessfulTime=([^)]+)\)", last).group(1)) == table["time"][-1]
    assert mark.find(r"returned early.*the trolley reached the pivot", status=1), mark.text()
    t = table["time"]
    assert t[-1] == pytest.approx(t_star, abs=1e-9)
    assert np.allclose(t[:-1], np.arange(len(t) - 1) * H, rtol=0, atol=1e-12) and t[-2] < t_star
    assert abs(table["x"][-1]) < 1e-9 and np.all(table["x"][:-1] > 0)
    fmi2 = fmutest.simulate(fmutest.fmu_path("Crane"), relative_tolerance=1e-8, output_interval=H, stop_time=5.0,
                            start_values=START)
    assert np.array_equal(fmi2.time, t) and np.array_equal(fmi2["x"], table["x"])


def test_crane_without_early_return_is_a_discard_fmpy_raises():
    """The same step without early return: fmi3Discard with terminateSimulation, at the same
    last successful time. FMPy 0.3.32's FMI 3.0 Co-Simulation does not handle a discard (its
    FMI 2.0 one does): simulate_fmu raises, and the user gets no result, only the FMU's reason."""
    mark = fmulog.LogMark()
    with pytest.raises(FMICallException, match="fmi3DoStep failed with status 2"):
        _crane3()
    assert any("trolley reached the pivot" in r.message and r.status == 2 for r in mark.records), mark.text()
