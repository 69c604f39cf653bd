//! What each FMI 3.0 call does, in safe Rust over checked arguments, where it differs from
//! FMI 2.0's: the instantiation flags, initialization, event and step mode, out
//! arguments, early return, the features not offered. Variables and derivatives by FMI 3.0
//! value reference are in [`variables`](super::variables); what both standards do alike
//! is in [`shared_calls`](crate::fmi::shared_calls) and [`model_exchange`](crate::fmi::model_exchange).

use super::ffi::*;
use crate::contract::might_return_early_from_do_step;
use crate::fmi::boundary::{discard, error, Outcome};
use crate::fmi::instance::Instance;
use crate::fmi::logger::Logger;
use crate::fmi::machine::{Interface, ModelState};
use crate::fmi::model_exchange as me;
use crate::fmi::shared_calls::{self, Stepped};
use crate::fmi::{Version, OK, WARNING};
use crate::model::{Mechanism, Shapes};

pub fn get_version() -> fmi3String {
    VERSION.as_ptr()
}

/// `fmi3InstantiateModelExchange` and `fmi3InstantiateCoSimulation` once the callback is
/// known (see [`shared_calls::instantiate`]), with the Co-Simulation flags and the number of
/// required intermediate variables (none may be: there is no intermediate update).
pub fn instantiate<'a, M: Mechanism>(
    logger: Logger,
    instance_name: Option<&str>,
    interface: Interface,
    token: impl FnOnce() -> Option<&'a str>,
    event_mode_used: bool,
    early_return_allowed: bool,
    required_intermediate_variables: usize,
) -> Result<Box<Instance<M>>, (Logger, String)> {
    if required_intermediate_variables > 0 {
        return Err((
            logger,
            format!(
                "nRequiredIntermediateVariables = {required_intermediate_variables}, but this FMU provides no intermediate update"
            ),
        ));
    }
    let shapes = match Shapes::new(M::VARIABLES, M::ARRAYS) {
        Ok(shapes) => shapes,
        Err(message) => return Err((logger, message)),
    };
    let mut inst =
        shared_calls::instantiate(Version::Fmi3, logger, instance_name, interface, token)?;
    inst.shapes = Some(Box::new(shapes));
    inst.event_mode_used = event_mode_used;
    inst.early_return_allowed = early_return_allowed;
    Ok(inst)
}

pub fn enter_initialization_mode<M: Mechanism>(
    inst: &mut Instance<M>,
    tolerance_defined: fmi3Boolean,
    tolerance: fmi3Float64,
    start_time: fmi3Float64,
    stop_time_defined: fmi3Boolean,
    stop_time: fmi3Float64,
) -> Outcome {
    shared_calls::setup(
        inst,
        tolerance_defined.then_some(tolerance),
        start_time,
        stop_time_defined.then_some(stop_time),
    )?;
    shared_calls::enter_initialization_mode(inst)
}

/// Model Exchange always; Co-Simulation if the importer said it uses event mode.
pub fn enter_event_mode<M: Mechanism>(inst: &mut Instance<M>) -> Outcome {
    if inst.interface == Interface::CoSimulation && !inst.event_mode_used {
        return Err(error(
            "the instance was instantiated with eventModeUsed = false, so it has no event mode",
        ));
    }
    me::enter_event_mode(inst)
}

pub fn enter_step_mode<M: Mechanism>(inst: &mut Instance<M>) -> Outcome {
    inst.state = ModelState::StepComplete;
    Ok(OK)
}

// ---------------------------------------------------------------------------------------
// Events and steps
// ---------------------------------------------------------------------------------------

/// Writes `value` where the importer asked for it (FMI 3.0 lets an importer pass NULL for
/// an out argument of `fmi3UpdateDiscreteStates` it does not want).
fn put<T>(slot: Option<&mut T>, value: T) {
    if let Some(slot) = slot {
        *slot = value;
    }
}

/// The event iteration, in Model Exchange and in Co-Simulation's event mode.
pub fn update_discrete_states<M: Mechanism>(
    inst: &mut Instance<M>,
    discrete_states_need_update: Option<&mut fmi3Boolean>,
    terminate_simulation: Option<&mut fmi3Boolean>,
    nominals_changed: Option<&mut fmi3Boolean>,
    values_changed: Option<&mut fmi3Boolean>,
    next_event_time_defined: Option<&mut fmi3Boolean>,
    next_event_time: Option<&mut fmi3Float64>,
) -> Outcome {
    let (status, update) = me::update_discrete_states(inst, "fmi3UpdateDiscreteStates")?;
    put(discrete_states_need_update, false);
    put(terminate_simulation, update.terminate);
    put(nominals_changed, false);
    put(values_changed, update.states_changed);
    put(next_event_time_defined, false);
    put(next_event_time, 0.0);
    Ok(status)
}

pub fn completed_integrator_step<M: Mechanism>(
    inst: &mut Instance<M>,
    enter_event_mode: &mut fmi3Boolean,
    terminate_simulation: &mut fmi3Boolean,
) -> Outcome {
    let (status, enter, terminate) =
        me::completed_integrator_step(inst, "fmi3CompletedIntegratorStep")?;
    *enter_event_mode = enter;
    *terminate_simulation = terminate;
    Ok(status)
}

/// A communication step. Where the model stops holding inside it (the crane's trolley at
/// the pivot), the importer learns when: with early return allowed, the step returns
/// early there (`earlyReturn`, `lastSuccessfulTime`, `terminateSimulation`, a warning
/// saying why); without, it is discarded with `lastSuccessfulTime` and
/// `terminateSimulation` set.
#[allow(clippy::too_many_arguments)]
pub fn do_step<M: Mechanism>(
    inst: &mut Instance<M>,
    current_communication_point: fmi3Float64,
    communication_step_size: fmi3Float64,
    event_handling_needed: &mut fmi3Boolean,
    terminate_simulation: &mut fmi3Boolean,
    early_return: &mut fmi3Boolean,
    last_successful_time: &mut fmi3Float64,
) -> Outcome {
    let stepped = shared_calls::step(
        inst,
        current_communication_point,
        communication_step_size,
        "fmi3DoStep",
    );
    // Every outcome tells the importer where the instance is and whether to go on. Only a
    // limit of the model returns early, as the model description says
    // (`mightReturnEarlyFromDoStep`: a mechanism with event indicators); a step the solver
    // cannot complete is discarded.
    let (stopped, early) = match &stepped {
        Ok(Stepped::Stopped { limit, .. }) => (
            true,
            *limit && inst.early_return_allowed && might_return_early_from_do_step::<M>(),
        ),
        _ => (false, false),
    };
    *event_handling_needed = false;
    *terminate_simulation = stopped;
    *early_return = early;
    *last_successful_time = inst.last_successful_time;
    match stepped? {
        Stepped::Completed(status) => Ok(status),
        Stepped::Stopped { message, .. } if early => {
            inst.logger
                .log(WARNING, &format!("fmi3DoStep: returned early: {message}"));
            Ok(WARNING)
        }
        Stepped::Stopped { message, .. } => Err(discard(message)),
    }
}

pub fn get_number_of_continuous_states<M: Mechanism>(
    inst: &mut Instance<M>,
    n: &mut usize,
) -> Outcome {
    *n = inst.sim.state_count();
    Ok(OK)
}

pub fn get_number_of_event_indicators<M: Mechanism>(
    inst: &mut Instance<M>,
    n: &mut usize,
) -> Outcome {
    *n = inst.sim.event_indicator_count();
    Ok(OK)
}

/// Clocks, intervals, shifts, configuration mode, Scheduled Execution.
pub fn unsupported(what: &str) -> Outcome {
    Err(error(format!("this FMU has {what}")))
}

/// Per-element dependencies are not provided (`providesPerElementDependencies` is false):
/// the model description's `<ModelStructure>` lists the dependencies.
pub fn variable_dependencies() -> Outcome {
    Err(error(
        "this FMU does not provide per-element dependencies (providesPerElementDependencies = false): read them from <ModelStructure>",
    ))
}
