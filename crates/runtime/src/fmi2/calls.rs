//! What each FMI 2.0 call does, in safe Rust over checked arguments: the instance, slices,
//! references and strings that [`boundary`](crate::fmi::boundary) made of the importer's pointers.
//! [`functions`](super::functions) wires each C function to its body here or, for what
//! both standards do alike, in [`shared_calls`](crate::fmi::shared_calls) and
//! [`model_exchange`](crate::fmi::model_exchange); a body's failure is a
//! [`Failure`](crate::fmi::boundary::Failure), which the boundary logs and returns as the call's
//! status.

#![allow(non_upper_case_globals)]

use super::ffi::*;
use super::state::Interface;
use crate::fmi::boundary::{discard, Outcome};
use crate::fmi::instance::Instance;
use crate::fmi::logger::Logger;
use crate::fmi::model_exchange as me;
use crate::fmi::{shared_calls, Version};
use crate::model::Mechanism;

// ---------------------------------------------------------------------------------------
// Functions without an instance
// ---------------------------------------------------------------------------------------

pub fn get_types_platform() -> fmi2String {
    TYPES_PLATFORM.as_ptr()
}

pub fn get_version() -> fmi2String {
    VERSION.as_ptr()
}

/// `fmi2Instantiate` once the callbacks are known (see [`shared_calls::instantiate`]), for
/// `fmu_type`.
pub fn instantiate<'a, M: Mechanism>(
    logger: Logger,
    instance_name: Option<&str>,
    fmu_type: fmi2Type,
    guid: impl FnOnce() -> Option<&'a str>,
) -> Result<Box<Instance<M>>, (Logger, String)> {
    let interface = match fmu_type {
        fmi2ModelExchange => Interface::ModelExchange,
        fmi2CoSimulation => Interface::CoSimulation,
        _ => {
            return Err((
                logger,
                format!(
                    "fmuType = {fmu_type} is neither fmi2ModelExchange (0) nor fmi2CoSimulation (1)"
                ),
            ))
        }
    };
    shared_calls::instantiate(Version::Fmi2, logger, instance_name, interface, guid)
}

pub fn setup_experiment<M: Mechanism>(
    inst: &mut Instance<M>,
    tolerance_defined: fmi2Boolean,
    tolerance: fmi2Real,
    start_time: fmi2Real,
    stop_time_defined: fmi2Boolean,
    stop_time: fmi2Real,
) -> Outcome {
    shared_calls::setup(
        inst,
        (tolerance_defined != 0).then_some(tolerance),
        start_time,
        (stop_time_defined != 0).then_some(stop_time),
    )
}

// ---------------------------------------------------------------------------------------
// Model Exchange: FMI 2.0's out arguments of the shared calls
// ---------------------------------------------------------------------------------------

fn boolean(b: bool) -> fmi2Boolean {
    if b {
        fmi2True
    } else {
        fmi2False
    }
}

pub fn new_discrete_states<M: Mechanism>(
    inst: &mut Instance<M>,
    event_info: &mut fmi2EventInfo,
) -> Outcome {
    let (status, update) = me::update_discrete_states(inst, "fmi2NewDiscreteStates")?;
    *event_info = fmi2EventInfo {
        newDiscreteStatesNeeded: fmi2False,
        terminateSimulation: boolean(update.terminate),
        nominalsOfContinuousStatesChanged: fmi2False,
        valuesOfContinuousStatesChanged: boolean(update.states_changed),
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
    let (status, enter, terminate) =
        me::completed_integrator_step(inst, "fmi2CompletedIntegratorStep")?;
    *enter_event_mode = boolean(enter);
    *terminate_simulation = boolean(terminate);
    Ok(status)
}

// ---------------------------------------------------------------------------------------
// Co-simulation
// ---------------------------------------------------------------------------------------

pub fn set_real_input_derivatives<M: Mechanism>(
    inst: &mut Instance<M>,
    vr: &[fmi2ValueReference],
    order: &[fmi2Integer],
    value: &[fmi2Real],
) -> Outcome {
    inst.sim.set_input_derivatives(vr, order, value)?;
    Ok(fmi2OK)
}

pub fn get_real_output_derivatives<M: Mechanism>(
    inst: &mut Instance<M>,
    vr: &[fmi2ValueReference],
    order: &[fmi2Integer],
    value: &mut [fmi2Real],
) -> Outcome {
    shared_calls::output_derivatives(inst, vr, order, value)
}

pub fn do_step<M: Mechanism>(
    inst: &mut Instance<M>,
    current_communication_point: fmi2Real,
    communication_step_size: fmi2Real,
) -> Outcome {
    let stepped = shared_calls::step(
        inst,
        current_communication_point,
        communication_step_size,
        "fmi2DoStep",
    )?;
    shared_calls::discarded(stepped)
}

/// Steps run synchronously, so the instance is never in StepInProgress and the state
/// check always refuses this call, as the standard's table says.
pub fn cancel_step<M: Mechanism>(_inst: &mut Instance<M>) -> Outcome {
    Ok(fmi2OK)
}

pub fn get_status<M: Mechanism>(
    inst: &mut Instance<M>,
    kind: fmi2StatusKind,
    value: &mut fmi2Status,
) -> Outcome {
    match kind {
        fmi2DoStepStatus => {
            *value = inst.last_step_status;
            Ok(fmi2OK)
        }
        fmi2PendingStatus => Err(discard(
            "fmi2PendingStatus: no step is pending (steps run synchronously)",
        )),
        _ => Err(discard(format!(
            "status kind {kind} is not a fmi2Status kind"
        ))),
    }
}

pub fn get_real_status<M: Mechanism>(
    inst: &mut Instance<M>,
    kind: fmi2StatusKind,
    value: &mut fmi2Real,
) -> Outcome {
    match kind {
        fmi2LastSuccessfulTime => {
            *value = inst.last_successful_time;
            Ok(fmi2OK)
        }
        _ => Err(discard(format!(
            "status kind {kind} is not a real status (fmi2LastSuccessfulTime = 2 is)"
        ))),
    }
}

pub fn get_integer_status<M: Mechanism>(_inst: &mut Instance<M>, kind: fmi2StatusKind) -> Outcome {
    Err(discard(format!(
        "status kind {kind}: there is no integer status"
    )))
}

pub fn get_boolean_status<M: Mechanism>(
    inst: &mut Instance<M>,
    kind: fmi2StatusKind,
    value: &mut fmi2Boolean,
) -> Outcome {
    match kind {
        fmi2Terminated => {
            *value = if inst.terminated { fmi2True } else { fmi2False };
            Ok(fmi2OK)
        }
        _ => Err(discard(format!(
            "status kind {kind} is not a boolean status (fmi2Terminated = 3 is)"
        ))),
    }
}

pub fn get_string_status<M: Mechanism>(
    _inst: &mut Instance<M>,
    kind: fmi2StatusKind,
    value: &mut fmi2String,
) -> Outcome {
    *value = c"".as_ptr();
    Err(discard(format!(
        "status kind {kind}: there is no string status (no step is pending)"
    )))
}
