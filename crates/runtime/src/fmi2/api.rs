//! What each FMI 2.0 call does, in safe Rust over checked arguments: the instance, slices,
//! references and strings that [`wall`](super::wall) made of the importer's pointers.
//! [`functions`](super::functions) wires each C function to its body here; a body's
//! failure is a [`Failure`], which the wall logs and returns as the call's status.

#![allow(non_upper_case_globals)]

use super::ffi::*;
use super::fmu_state::FmuState;
use super::instance::Instance;
use super::logger::Logger;
use super::state::{Interface, ModelState};
use super::wall::{discard, error, Buffer, Outcome, StateSlot};
use crate::model::{event_indicator_references, Layout, Mechanism, SetPhase};
use crate::simulation::StepFailure;

// ---------------------------------------------------------------------------------------
// Functions without an instance
// ---------------------------------------------------------------------------------------

pub fn get_types_platform() -> fmi2String {
    TYPES_PLATFORM.as_ptr()
}

pub fn get_version() -> fmi2String {
    VERSION.as_ptr()
}

/// Panics are caught at the wall and reported through the importer's logger; the default
/// hook would also print them to the importer's stderr. The FMU binary has its own copy of
/// std, so the hook installed here (once) affects only this FMU's own code. Called by the
/// exported `fmi2Instantiate` only, never in-process (tests keep their messages).
pub fn silence_panic_messages() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| std::panic::set_hook(Box::new(|_| {})));
}

/// `fmi2Instantiate` once the callbacks are known: `instance_name` is `None` when NULL or not
/// UTF-8, as is what `guid` gives (asked only once the name and the type are accepted).
/// `Err` is logged through `logger` and gives NULL.
pub fn instantiate<'a, M: Mechanism>(
    logger: Logger,
    instance_name: Option<&str>,
    fmu_type: fmi2Type,
    guid: impl FnOnce() -> Option<&'a str>,
) -> Result<Box<Instance<M>>, (Logger, String)> {
    if instance_name.is_none_or(str::is_empty) {
        return Err((
            logger,
            "instanceName is NULL or empty (or not UTF-8)".into(),
        ));
    }
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
    let expected = crate::contract::guid::<M>();
    match guid() {
        Some(g) if g == expected => {}
        Some(g) => {
            return Err((
                logger,
                format!(
                    "GUID \"{g}\" does not match this binary's \"{expected}\": modelDescription.xml and binary are from different builds"
                ),
            ))
        }
        None => return Err((logger, "fmuGUID is NULL".into())),
    }
    let layout = Layout::new(M::VARIABLES).and_then(|layout| {
        event_indicator_references(M::VARIABLES, M::EVENT_INDICATORS).map(|_| layout)
    });
    match layout {
        Ok(layout) => Ok(Box::new(Instance::<M>::new(logger, layout, interface))),
        Err(message) => Err((logger, message)),
    }
}

// ---------------------------------------------------------------------------------------
// Instance life cycle
// ---------------------------------------------------------------------------------------

pub fn set_debug_logging<M: Mechanism>(
    inst: &mut Instance<M>,
    logging_on: fmi2Boolean,
    categories: &[&str],
) -> Outcome {
    inst.logger.set_categories(logging_on != 0, categories)?;
    Ok(fmi2OK)
}

pub fn setup_experiment<M: Mechanism>(
    inst: &mut Instance<M>,
    tolerance_defined: fmi2Boolean,
    tolerance: fmi2Real,
    start_time: fmi2Real,
    stop_time_defined: fmi2Boolean,
    stop_time: fmi2Real,
) -> Outcome {
    let stop = (stop_time_defined != 0).then_some(stop_time);
    if let Some(stop) = stop {
        if !(stop.is_finite() && stop >= start_time) {
            return Err(error(format!(
                "stopTime = {stop} must be finite and ≥ startTime = {start_time}"
            )));
        }
    }
    inst.sim
        .setup((tolerance_defined != 0).then_some(tolerance), start_time)?;
    inst.stop_time = stop;
    inst.last_successful_time = start_time;
    Ok(fmi2OK)
}

pub fn enter_initialization_mode<M: Mechanism>(inst: &mut Instance<M>) -> Outcome {
    inst.state = ModelState::InitializationMode;
    Ok(fmi2OK)
}

pub fn exit_initialization_mode<M: Mechanism>(inst: &mut Instance<M>) -> Outcome {
    if let Err(message) = inst.sim.update() {
        inst.state = ModelState::Error;
        return Err(error(format!("initialization failed: {message}")));
    }
    inst.last_successful_time = inst.sim.time();
    inst.state = inst.interface.initialized();
    inst.logger
        .log(fmi2OK, &format!("initialized at t = {}", inst.sim.time()));
    Ok(fmi2OK)
}

pub fn terminate<M: Mechanism>(inst: &mut Instance<M>) -> Outcome {
    inst.state = ModelState::Terminated;
    Ok(fmi2OK)
}

pub fn reset<M: Mechanism>(inst: &mut Instance<M>) -> Outcome {
    inst.reset();
    Ok(fmi2OK)
}

// ---------------------------------------------------------------------------------------
// Getting and setting values
// ---------------------------------------------------------------------------------------

pub fn get_real<M: Mechanism>(
    inst: &mut Instance<M>,
    vr: &[fmi2ValueReference],
    value: &mut [fmi2Real],
) -> Outcome {
    inst.sim.get_real(vr, value)?;
    Ok(fmi2OK)
}

pub fn set_real<M: Mechanism>(
    inst: &mut Instance<M>,
    vr: &[fmi2ValueReference],
    value: &[fmi2Real],
) -> Outcome {
    let phase = match inst.state {
        ModelState::Instantiated => SetPhase::Instantiated,
        ModelState::InitializationMode => SetPhase::Initialization,
        ModelState::ContinuousTimeMode => SetPhase::ContinuousTime,
        _ => SetPhase::Running,
    };
    inst.sim.set_real(vr, value, phase)?;
    Ok(fmi2OK)
}

/// `fmi2Get`/`fmi2Set` of a type this FMU has no variables of (Integer, Boolean, String):
/// only the empty call succeeds.
pub fn no_variables(function: &str, vr: &[fmi2ValueReference], kind: &str) -> Outcome {
    match vr.first() {
        None => Ok(fmi2OK),
        Some(vr) => Err(error(format!(
            "value reference {vr} is not a variable of type {kind} (this FMU has only Real variables); called as {function}"
        ))),
    }
}

// ---------------------------------------------------------------------------------------
// FMU state
// ---------------------------------------------------------------------------------------

pub fn get_fmu_state<M: Mechanism>(inst: &mut Instance<M>, slot: StateSlot) -> Outcome {
    slot.store(inst.save())
}

pub fn set_fmu_state<M: Mechanism>(inst: &mut Instance<M>, saved: &FmuState) -> Outcome {
    inst.restore(saved)?;
    Ok(fmi2OK)
}

pub fn serialized_fmu_state_size<M: Mechanism>(state: &FmuState, size: &mut usize) -> Outcome {
    *size = state.to_bytes::<M>().len();
    Ok(fmi2OK)
}

pub fn serialize_fmu_state<M: Mechanism>(state: &FmuState, buffer: Buffer) -> Outcome {
    let bytes = state.to_bytes::<M>();
    if buffer.size() != bytes.len() {
        return Err(error(format!(
            "size = {}, but the serialized state has {} bytes (ask fmi2SerializedFMUstateSize)",
            buffer.size(),
            bytes.len()
        )));
    }
    buffer.fill(&bytes, "serializedState[]")?;
    Ok(fmi2OK)
}

pub fn deserialize_fmu_state<M: Mechanism>(bytes: &[u8], slot: StateSlot) -> Outcome {
    slot.store(FmuState::from_bytes::<M>(bytes)?)
}

pub fn get_directional_derivative<M: Mechanism>(
    inst: &mut Instance<M>,
    unknowns: &[fmi2ValueReference],
    knowns: &[fmi2ValueReference],
    dv_known: &[fmi2Real],
    dv_unknown: &mut [fmi2Real],
) -> Outcome {
    if let Some(x) = dv_known.iter().find(|x| !x.is_finite()) {
        return Err(error(format!(
            "dvKnown contains {x}: every seed must be finite"
        )));
    }
    inst.sim
        .directional_derivative(unknowns, knowns, dv_known, dv_unknown)?;
    // Seeds near the overflow limit give inf - inf: refuse, rather than return NaN.
    if let Some(i) = dv_unknown.iter().position(|x| x.is_nan()) {
        return Err(error(format!(
            "the derivative of value reference {} is not a number (a seed too large to multiply?)",
            unknowns[i]
        )));
    }
    Ok(fmi2OK)
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
    inst.sim.output_derivatives(vr, order, value)?;
    // Input derivatives near the overflow limit give inf - inf: refuse, not NaN.
    if let Some(i) = value.iter().position(|x| x.is_nan()) {
        return Err(error(format!(
            "the derivative of value reference {} is not a number (input derivatives too large?)",
            vr[i]
        )));
    }
    Ok(fmi2OK)
}

pub fn do_step<M: Mechanism>(
    inst: &mut Instance<M>,
    current_communication_point: fmi2Real,
    communication_step_size: fmi2Real,
) -> Outcome {
    let t = current_communication_point;
    let h = communication_step_size;
    if let Some(stop) = inst.stop_time {
        let end = t + h;
        if end > stop + 1e-9 * stop.abs().max(h) {
            return Err(error(format!(
                "the step [{t}, {end}] goes beyond stopTime = {stop} given to fmi2SetupExperiment"
            )));
        }
    }
    match inst.sim.step(t, h) {
        Ok(_) => {
            for warning in inst.sim.warnings() {
                inst.logger
                    .log(fmi2Warning, &format!("fmi2DoStep: {warning}"));
            }
            inst.last_successful_time = inst.sim.time();
            inst.last_step_status = fmi2OK;
            Ok(if inst.sim.warnings().is_empty() {
                fmi2OK
            } else {
                fmi2Warning
            })
        }
        Err(StepFailure::Rejected(message)) => Err(error(message)),
        Err(StepFailure::Stopped { time, message }) => {
            inst.last_successful_time = time;
            inst.last_step_status = fmi2Discard;
            inst.terminated = true;
            inst.state = ModelState::StepFailed;
            Err(discard(format!(
                "step from t = {t} stopped at t = {time}: {message}"
            )))
        }
    }
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
