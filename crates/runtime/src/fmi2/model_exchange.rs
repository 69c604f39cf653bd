//! What each Model Exchange call does (FMI 2.0.5, chapter 3), in safe Rust over checked
//! arguments, as [`api`](super::api) for the calls both interface types share.
//!
//! Events: the importer's solver locates the sign changes of the mechanism's event
//! indicators and enters event mode there; at every event (`fmi2NewDiscreteStates`) and
//! every completed integrator step the mechanism's monitor is asked. A warning is logged
//! once per episode (`fmi2Warning`); a point where the model no longer holds ends the
//! simulation (`terminateSimulation`, the reason logged). A mechanism that projects its
//! states onto a manifold asks for a step event when they have drifted off it by more than
//! the tolerance, and projects them there (`valuesOfContinuousStatesChanged`).

#![allow(non_upper_case_globals)]

use super::ffi::*;
use super::instance::Instance;
use super::state::ModelState;
use super::wall::{discard, error, Outcome};
use crate::model::Mechanism;

fn boolean(b: bool) -> fmi2Boolean {
    if b {
        fmi2True
    } else {
        fmi2False
    }
}

/// `n` (named `what`) is the number the FMU has, `expected`.
#[inline(always)]
fn check_count(
    what: &str,
    n: usize,
    expected: usize,
    of: &str,
) -> Result<(), super::wall::Failure> {
    if n == expected {
        return Ok(());
    }
    Err(count_mismatch(what, n, expected, of))
}

#[cold]
#[inline(never)]
fn count_mismatch(what: &str, n: usize, expected: usize, of: &str) -> super::wall::Failure {
    error(format!("{what} = {n}, but the FMU has {expected} {of}"))
}

pub fn enter_event_mode<M: Mechanism>(inst: &mut Instance<M>) -> Outcome {
    inst.state = ModelState::EventMode;
    Ok(fmi2OK)
}

pub fn enter_continuous_time_mode<M: Mechanism>(inst: &mut Instance<M>) -> Outcome {
    inst.state = ModelState::ContinuousTimeMode;
    Ok(fmi2OK)
}

/// The event iteration: the projection, if due, and the monitor's verdict. Nothing is
/// discrete, so one iteration always suffices and no time event is ever announced.
pub fn new_discrete_states<M: Mechanism>(
    inst: &mut Instance<M>,
    event_info: &mut fmi2EventInfo,
) -> Outcome {
    let projected = inst.sim.projection_due() && inst.sim.project();
    let (status, terminate) = judge(inst, "fmi2NewDiscreteStates")?;
    *event_info = fmi2EventInfo {
        newDiscreteStatesNeeded: fmi2False,
        terminateSimulation: boolean(terminate),
        nominalsOfContinuousStatesChanged: fmi2False,
        valuesOfContinuousStatesChanged: boolean(projected),
        nextEventTimeDefined: fmi2False,
        nextEventTime: 0.0,
    };
    Ok(status)
}

pub fn completed_integrator_step<M: Mechanism>(
    inst: &mut Instance<M>,
    enter_event_mode: &mut fmi2Boolean,
    terminate_simulation: &mut fmi2Boolean,
) -> Outcome {
    let (status, terminate) = judge(inst, "fmi2CompletedIntegratorStep")?;
    *enter_event_mode = boolean(!terminate && inst.sim.projection_due());
    *terminate_simulation = boolean(terminate);
    Ok(status)
}

/// The monitor's verdict at the current point, logged: the status to return, and whether
/// the simulation must stop.
fn judge<M: Mechanism>(
    inst: &mut Instance<M>,
    function: &str,
) -> Result<(fmi2Status, bool), super::wall::Failure> {
    match inst.sim.check_point()? {
        Some(reason) => {
            inst.terminated = true;
            inst.logger.log(
                fmi2Warning,
                &format!("{function}: terminateSimulation: {reason}"),
            );
            Ok((fmi2Warning, true))
        }
        None if inst.sim.warnings().is_empty() => Ok((fmi2OK, false)),
        None => {
            for warning in inst.sim.warnings() {
                inst.logger
                    .log(fmi2Warning, &format!("{function}: {warning}"));
            }
            Ok((fmi2Warning, false))
        }
    }
}

pub fn set_time<M: Mechanism>(inst: &mut Instance<M>, time: fmi2Real) -> Outcome {
    inst.sim.set_time(time)?;
    Ok(fmi2OK)
}

pub fn set_continuous_states<M: Mechanism>(inst: &mut Instance<M>, x: &[fmi2Real]) -> Outcome {
    check_count("nx", x.len(), inst.sim.state_count(), "continuous states")?;
    inst.sim.set_states(x)?;
    Ok(fmi2OK)
}

pub fn get_continuous_states<M: Mechanism>(inst: &mut Instance<M>, x: &mut [fmi2Real]) -> Outcome {
    check_count("nx", x.len(), inst.sim.state_count(), "continuous states")?;
    inst.sim.states(x);
    Ok(fmi2OK)
}

/// A derivative that is not a number is `fmi2Discard` (the standard's advice for a point
/// outside the equations' domain: the solver retries with a smaller step).
pub fn get_derivatives<M: Mechanism>(inst: &mut Instance<M>, dx: &mut [fmi2Real]) -> Outcome {
    check_count("nx", dx.len(), inst.sim.state_count(), "continuous states")?;
    inst.sim.derivatives(dx).map_err(discard)?;
    Ok(fmi2OK)
}

pub fn get_event_indicators<M: Mechanism>(inst: &mut Instance<M>, z: &mut [fmi2Real]) -> Outcome {
    check_count(
        "ni",
        z.len(),
        inst.sim.event_indicator_count(),
        "event indicators",
    )?;
    inst.sim.event_indicators(z).map_err(discard)?;
    Ok(fmi2OK)
}

/// The states declare no `nominal`, so each is 1 (the standard's default).
pub fn get_nominals_of_continuous_states<M: Mechanism>(
    inst: &mut Instance<M>,
    x_nominal: &mut [fmi2Real],
) -> Outcome {
    check_count(
        "nx",
        x_nominal.len(),
        inst.sim.state_count(),
        "continuous states",
    )?;
    x_nominal.fill(1.0);
    Ok(fmi2OK)
}
