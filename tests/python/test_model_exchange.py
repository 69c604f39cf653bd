"""The FMUs in Model Exchange: every reference case of `mechfmu validate` (fmus/*/validation/
cases.py) under FMPy's CVode (rtol 1e-10, held to the case's own limits) and Euler, and under
the fmi crate's RK4 (tools/fmi-run, `--interface me`), the fixed-step ones held to their order
(mechfmu_validate.model_exchange); the crane's trolley reaching the pivot ending the
simulation with terminateSimulation where Co-Simulation stops; FMPy's validation of the XML
with its <ModelExchange>.

The rows where the importer's solver does not reach the case's limit are listed, with what
was measured, in the mechanism's validation/expectations.toml (KNOWN_LIMITS here): here they
must be LIMIT (reported, not failed: not a pass, not a failure of the FMU), and so in
`mechfmu validate` (tests/python/test_validate.py). The CVode ones meet the case's limits at
rtol 1e-12.
"""

from __future__ import annotations

import os
import re

import numpy as np
import pytest
from fmpy import read_model_description
from fmpy.fmi2 import fmi2Discard
from fmpy.validation import validate_fmu

import fmutest
from fmutest import LogMark, fmu_path, simulate
from mechfmu_validate import model_exchange
from mechfmu_validate.case import Result, evaluate
from mechfmu_validate.importers.fmi_crate import FMI_RUN_ENV, RK4, rk4
from mechfmu_validate.importers.fmpy import CVODE, EULER, EULER_METHOD, on_grid, run_fmpy_me, simulate_me
from mechfmu_validate.signals import held_input
from mechanisms import known_limits, mechanism
from refs import crane_dynamics as ref_cd
from refs import step_input
from test_cases import CASES, MODELS
from test_crane_dynamics import TAU0

#: the fixed-step methods, by their rows' importer column
METHODS = {EULER: EULER_METHOD, RK4: rk4()}

#: (model, case, importer): why the importer's solver does not reach the case's limit
KNOWN_LIMITS = known_limits()

fmu_of = fmutest.validation_fmu


@pytest.fixture(scope="module")
def fmi_run():
    """mechfmu-fmi-run, built as `mechfmu validate` builds it, named in $MECHFMU_FMI_RUN."""
    exe = fmutest.built_fmi_run()
    before = os.environ.get(FMI_RUN_ENV)
    os.environ[FMI_RUN_ENV] = str(exe)
    yield exe
    if before is None:
        os.environ.pop(FMI_RUN_ENV, None)
    else:
        os.environ[FMI_RUN_ENV] = before


def cases_under(importer: str) -> list:
    """The cases as parameters, with whether the row is a known LIMIT."""
    return [pytest.param(model, case, (model, case.name, importer) in KNOWN_LIMITS, id=f"{model}-{case.name}")
            for model, case in CASES]


@pytest.mark.parametrize("model, case, limit", cases_under(CVODE))
def test_case_under_cvode(model, case, limit):
    _, ev = model_exchange.run_cvode(fmu_of(model), case, run_fmpy_me)
    assert ev.problem is None, ev.problem
    failed = [f"{s.name}: {s.max_error:.3e} of scale {s.scale:.4g} at t = {s.at_time:g} (tolerance {s.tolerance:g})"
              for s in ev.signals if not s.passed]
    if limit:
        assert failed, f"{model} / {case.name} now meets its limits under {CVODE}: no longer a LIMIT"
        assert all(s.passed or s.max_error <= model_exchange.CVODE_FLOOR for s in ev.signals), failed
    else:
        assert not failed, f"{model} / {case.name} under {CVODE}:\n" + "\n".join(failed)


@pytest.mark.parametrize("key", [k for k in KNOWN_LIMITS if k[2] == CVODE], ids=lambda k: f"{k[0]}-{k[1]}")
def test_cvode_meets_the_tight_limits_at_a_tighter_tolerance(key):
    """The CVode LIMIT rows are CVode's accuracy at rtol 1e-10, not the FMU's: at 1e-12 the
    same runs meet the cases' own limits."""
    model, name, _ = key
    case = next(c for m, c in CASES if (m, c.name) == (model, name))
    fmu = fmu_of(model)
    run = simulate_me(fmu, stop_time=case.stop_time, output_interval=case.output_interval, relative_tolerance=1e-12,
                      start_values=case.start_values, input=held_input(case, fmu), output=case.recorded())
    assert run.terminated is None, run.terminated
    ev = evaluate(case, Result(on_grid(run.table, case.output_interval, case.steps()), run.log))
    assert ev.problem is None and ev.passed, [(s.name, s.max_error, s.tolerance) for s in ev.signals if not s.passed]


def _fixed_step(model, case, importer, limit):
    ev, checks, _ = model_exchange.run_fixed_step(fmu_of(model), case, METHODS[importer])
    assert ev.problem is None, ev.problem
    failed = [c.describe() for c in checks if not c.passed]
    if limit:
        assert failed, f"{model} / {case.name} now passes under {importer}: no longer a LIMIT"
    else:
        assert not failed, f"{model} / {case.name} under {importer}:\n" + "\n".join(failed)


@pytest.mark.parametrize("model, case, limit", cases_under(EULER))
def test_case_under_euler(model, case, limit):
    _fixed_step(model, case, EULER, limit)


@pytest.mark.parametrize("model, case, limit", cases_under(RK4))
def test_case_under_the_fmi_crates_rk4(model, case, limit, fmi_run):
    _fixed_step(model, case, RK4, limit)


def test_an_fmu_with_a_wrong_derivative_fails_the_order_check():
    """What the order check is for: the free undamped Oscillator with a stiffness 1 % off in
    the FMU (k = 4.04) but not in the reference stands for a wrong derivative. Its phase error
    (10 % of range by t = 20 s) does not shrink with h, and the error (Euler's own: 11 % at
    h = 5 ms) no longer halves with it."""
    from dataclasses import replace

    case = next(c for m, c in CASES if m == "Oscillator" and c.name == "free_undamped")
    wrong = replace(case, start_values={**case.start_values, "k": 4.04})
    _, checks, _ = model_exchange.run_fixed_step(fmu_of("Oscillator"), wrong, METHODS[EULER])
    worst = max(checks, key=lambda c: c.error)
    assert not worst.passed and worst.observed < METHODS[EULER].band[0], worst.describe()


def test_the_rk4_row_is_skipped_when_the_runner_has_no_model_exchange(tmp_path, monkeypatch):
    """A mechfmu-fmi-run from before `--interface` answers with its usage line: the row says
    SKIP and why, it does not fail."""
    old = tmp_path / "mechfmu-fmi-run"
    old.write_text('#!/bin/sh\necho "usage: mechfmu-fmi-run EXPERIMENT.json [--out FILE]" >&2\nexit 2\n')
    old.chmod(0o755)
    monkeypatch.setenv(FMI_RUN_ENV, str(old))
    case = next(c for m, c in CASES if m == "Oscillator" and c.name == "free_critical")
    row = model_exchange.fixed_step_row(fmu_of("Oscillator"), case, METHODS[RK4])
    assert row["skipped"] and row["passed"], row
    assert "does not accept --interface me" in row["problems"][0], row["problems"]


# ---------------------------------------------------------------------------------------
# The trolley reaching the pivot: terminateSimulation where Co-Simulation stops


def termination_time(run) -> float:
    """The time in the FMU's message "terminateSimulation: at t = ...: <reason>" (FMPy stops
    without recording that point)."""
    found = re.search(r"terminateSimulation: at t = ([^:]+): (.*)", run.terminated or "")
    assert found, f"no terminateSimulation in the log: {run.log}"
    assert "the trolley reached the pivot" in found.group(2), found.group(2)
    return float(found.group(1))


def test_crane_trolley_reaching_the_pivot_terminates_where_co_simulation_stops():
    """x = 1 - 1.05 t reaches the pivot at t* = 1/1.05 (test_crane.py runs it in
    Co-Simulation). CVode locates the zero of the event indicator x, and the FMU asks for
    terminateSimulation there: t* to rounding, x being linear in t. Co-Simulation ends with
    fmi2Discard at its last valid time t_CS, the start of the communication step (H) its
    solver crossed the pivot in: t_CS <= t* < t_CS + H. Euler notices the crossing at the end
    of the step that made it: t* <= t < t* + h."""
    t_star = 1.0 / 1.05
    start = {"x": 1.0, "x_dot": -1.05}
    mark = LogMark()
    H = 0.1
    cs = simulate(fmu_path("Crane"), relative_tolerance=1e-8, output_interval=H, stop_time=5.0, start_values=start)
    assert mark.find(r"trolley reached the pivot", status=fmi2Discard), mark.text()
    t_cs = float(cs.time[-1])
    fmu = fmu_of("Crane")
    cvode = simulate_me(fmu, stop_time=5.0, output_interval=H, start_values=start, output=["x"])
    t_me = termination_time(cvode)
    assert t_me == pytest.approx(t_star, abs=1e-12)
    assert t_cs <= t_me < t_cs + H, (t_cs, t_me)
    assert cvode.end_time < t_me and np.all(cvode.table["x"] > 0)
    h = 0.01
    euler = simulate_me(fmu, stop_time=5.0, output_interval=h, solver="Euler", start_values=start, output=["x"])
    assert t_star <= termination_time(euler) < t_star + h


def test_crane_dynamics_trolley_reaching_the_pivot_terminates_at_the_references_time():
    """The trolley drive pulling inwards (test_crane_dynamics.py): the reference (DOP853, rtol
    1e-12) reaches the pivot at t = 0.946018128. CVode's error on the cases is at most 2e-7 of
    a signal's range; for x (10 m, crossing at 9 m/s) that is 2e-7 s of crossing time.
    Co-Simulation stops at its last valid time, within the communication step before it."""
    inp = step_input(["F", "tau"], [0.0], [[-1e4, 0.5 * TAU0]], t_end=5.0)
    with pytest.raises(RuntimeError, match=r"t = (\S+):") as stopped:
        ref_cd.simulate(None, None, np.linspace(0.0, 5.0, 11), inp)
    t_ref = float(re.search(r"t = (\S+):", str(stopped.value)).group(1))
    H = 0.01
    cs = simulate(fmu_path("CraneDynamics"), relative_tolerance=1e-8, output_interval=H, stop_time=5.0, input=inp)
    run = simulate_me(fmu_of("CraneDynamics"), stop_time=5.0, output_interval=H, input=inp, output=["x", "T"])
    t_me = termination_time(run)
    assert t_me == pytest.approx(t_ref, abs=2e-7)
    assert cs.time[-1] <= t_me < cs.time[-1] + H, (cs.time[-1], t_me)
    # the slack cable (T < 0 at the start), warned as in Co-Simulation
    assert any("the cable is slack" in line for line in run.log), run.log


# ---------------------------------------------------------------------------------------
# The model description


@pytest.mark.parametrize("model", MODELS)
def test_fmpy_validates_the_model_exchange_description(model):
    """FMPy's validate_fmu over the XML with both interfaces: <ModelExchange> beside
    <CoSimulation>, the derivatives of every state in <ModelStructure> (the states its
    contract lists: none for a coupling element), and the event indicators its contract
    counts (event_indicators; none without)."""
    path = str(fmu_path(model))
    md = read_model_description(path)
    me, cs = md.modelExchange, md.coSimulation
    assert me is not None and cs is not None and me.modelIdentifier == cs.modelIdentifier
    assert me.providesDirectionalDerivative and me.canGetAndSetFMUstate and me.canSerializeFMUstate
    assert md.numberOfContinuousStates == len(md.derivatives)
    contract = mechanism(model).contract
    if contract is not None and contract.derivatives is not None:
        assert md.numberOfContinuousStates == len(contract.derivatives)  # 0 for a coupling element
    else:
        assert md.numberOfContinuousStates > 0
    assert md.numberOfEventIndicators == (contract.event_indicators if contract is not None else 0)
    assert validate_fmu(path) == [], "\n".join(validate_fmu(path))
