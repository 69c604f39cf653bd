//! What the Model Exchange calls of both standards do (FMI 2.0.5 chapter 3, FMI 3.0
//! chapter 3), in safe Rust over checked arguments; each layer converts its own out
//! arguments (`fmi2EventInfo`, FMI 3.0's booleans).
//!
//! Events: the importer's solver locates the sign changes of the mechanism's event
//! indicators and enters event mode there; at every event (`fmi2NewDiscreteStates`) and
//! every completed integrator step the mechanism's monitor is asked. A warning is logged
//! once per episode (a Warning status); a point where the model no longer holds ends the
//! simulation (`terminateSimulation`, the reason logged). A mechanism that projects its
//! states onto a manifold asks for a step event when they have drifted off it by more than
//! the tolerance, and projects them there (`valuesOfContinuousStatesChanged`).

use super::boundary::{discard, error, Failure, Outcome};
use super::instance::Instance;
use super::machine::ModelState;
use super::{Status, Version, OK, WARNING};
use crate::model::Mechanism;

/// What an importer's array of Model Exchange has one element per.
#[derive(Clone, Copy)]
enum Count {
    States,
    EventIndicators,
}

/// The importer's `n` is the number the FMU has, `expected`.
#[inline(always)]
fn check_count(version: Version, count: Count, n: usize, expected: usize) -> Result<(), Failure> {
    if n == expected {
        return Ok(());
    }
    Err(count_mismatch(version, count, n, expected))
}

/// The mismatch, naming the length argument as `version`'s functions do.
#[cold]
#[inline(never)]
fn count_mismatch(version: Version, count: Count, n: usize, expected: usize) -> Failure {
    let (what, of) = match (version, count) {
        (Version::Fmi2, Count::States) => ("nx", "continuous states"),
        (Version::Fmi2, Count::EventIndicators) => ("ni", "event indicators"),
        (Version::Fmi3, Count::States) => ("nContinuousStates", "continuous states"),
        (Version::Fmi3, Count::EventIndicators) => ("nEventIndicators", "event indicators"),
    };
    error(format!("{what} = {n}, but the FMU has {expected} {of}"))
}

pub fn enter_event_mode<M: Mechanism>(inst: &mut Instance<M>) -> Outcome {
    inst.state = ModelState::EventMode;
    Ok(OK)
}

pub fn enter_continuous_time_mode<M: Mechanism>(inst: &mut Instance<M>) -> Outcome {
    inst.state = ModelState::ContinuousTimeMode;
    Ok(OK)
}

/// What an event iteration found.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EventUpdate {
    /// The model no longer holds: the importer must stop.
    pub terminate: bool,
    /// The projection moved the states.
    pub states_changed: bool,
}

/// The event iteration (`fmi2NewDiscreteStates`, `fmi3UpdateDiscreteStates`): the
/// projection, if due, and the monitor's verdict. Nothing is discrete, so one iteration
/// always suffices and no time event is ever announced.
pub fn update_discrete_states<M: Mechanism>(
    inst: &mut Instance<M>,
    function: &str,
) -> Result<(Status, EventUpdate), Failure> {
    let states_changed = inst.sim.projection_due() && inst.sim.project();
    let (status, terminate) = judge(inst, function)?;
    Ok((
        status,
        EventUpdate {
            terminate,
            states_changed,
        },
    ))
}

/// `fmi2CompletedIntegratorStep`, `fmi3CompletedIntegratorStep`: the status, whether to
/// enter event mode (a projection is due) and whether to terminate.
pub fn completed_integrator_step<M: Mechanism>(
    inst: &mut Instance<M>,
    function: &str,
) -> Result<(Status, bool, bool), Failure> {
    let (status, terminate) = judge(inst, function)?;
    let enter_event_mode = !terminate && inst.sim.projection_due();
    Ok((status, enter_event_mode, terminate))
}

/// The monitor's verdict at the current point, logged: the status to return, and whether
/// the simulation must stop.
fn judge<M: Mechanism>(inst: &mut Instance<M>, function: &str) -> Result<(Status, bool), Failure> {
    match inst.sim.check_point()? {
        Some(reason) => {
            inst.terminated = true;
            inst.logger.log(
                WARNING,
                &format!("{function}: terminateSimulation: {reason}"),
            );
            Ok((WARNING, true))
        }
        None if inst.sim.warnings().is_empty() => Ok((OK, false)),
        None => {
            for warning in inst.sim.warnings() {
                inst.logger.log(WARNING, &format!("{function}: {warning}"));
            }
            Ok((WARNING, false))
        }
    }
}

// Inlined into both standards' exported functions: the path of every derivative an
// importer's solver asks for.
#[inline(always)]
pub fn set_time<M: Mechanism>(inst: &mut Instance<M>, time: f64) -> Outcome {
    inst.sim.set_time(time)?;
    Ok(OK)
}

// Inlined into both standards' exported functions: the path of every derivative an
// importer's solver asks for.
#[inline(always)]
pub fn set_continuous_states<M: Mechanism>(inst: &mut Instance<M>, x: &[f64]) -> Outcome {
    check_count(inst.version, Count::States, x.len(), inst.sim.state_count())?;
    inst.sim.set_states(x)?;
    Ok(OK)
}

pub fn get_continuous_states<M: Mechanism>(inst: &mut Instance<M>, x: &mut [f64]) -> Outcome {
    check_count(inst.version, Count::States, x.len(), inst.sim.state_count())?;
    inst.sim.states(x);
    Ok(OK)
}

/// A derivative that is not a number is `fmi2Discard` (the standard's advice for a point
/// outside the equations' domain: the solver retries with a smaller step).
// Inlined into both standards' exported functions: the path of every derivative an
// importer's solver asks for.
#[inline(always)]
pub fn get_derivatives<M: Mechanism>(inst: &mut Instance<M>, dx: &mut [f64]) -> Outcome {
    check_count(
        inst.version,
        Count::States,
        dx.len(),
        inst.sim.state_count(),
    )?;
    inst.sim.derivatives(dx).map_err(discard)?;
    Ok(OK)
}

pub fn get_event_indicators<M: Mechanism>(inst: &mut Instance<M>, z: &mut [f64]) -> Outcome {
    check_count(
        inst.version,
        Count::EventIndicators,
        z.len(),
        inst.sim.event_indicator_count(),
    )?;
    inst.sim.event_indicators(z).map_err(discard)?;
    Ok(OK)
}

/// The states declare no `nominal`, so each is 1 (the standard's default).
pub fn get_nominals_of_continuous_states<M: Mechanism>(
    inst: &mut Instance<M>,
    x_nominal: &mut [f64],
) -> Outcome {
    check_count(
        inst.version,
        Count::States,
        x_nominal.len(),
        inst.sim.state_count(),
    )?;
    x_nominal.fill(1.0);
    Ok(OK)
}
