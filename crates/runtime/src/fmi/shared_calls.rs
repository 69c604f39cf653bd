//! What the calls both standards share do, in safe Rust over checked arguments: creating an
//! instance, the experiment and initialization, values by (scalar) value reference, FMU
//! states, derivatives and the communication step. Each layer's `calls` adapts its own
//! signatures (FMI 3.0's arrays, out arguments, names) to these.

use super::boundary::{discard, error, Buffer, Failure, Outcome, StateSlot};
use super::fmu_state::FmuState;
use super::instance::Instance;
use super::logger::Logger;
use super::machine::{Interface, ModelState};
use super::{Status, Version, DISCARD, OK, WARNING};
use crate::model::{event_indicator_references, Layout, Mechanism, SetPhase};
use crate::simulation::{Simulation, StepFailure};

/// Panics are caught at the boundary and reported through the importer's logger; the default
/// hook would also print them to the importer's stderr. The FMU binary has its own copy of
/// std, so the hook installed here (once) affects only this FMU's own code. Called by the
/// exported instantiation functions only, never in-process (tests keep their messages).
pub fn silence_panic_messages() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| std::panic::set_hook(Box::new(|_| {})));
}

/// A new instance of `M` for `version`: `instance_name` is `None` when NULL or not UTF-8,
/// as is what `token` gives (asked only once the name is accepted), the GUID or
/// instantiation token of the model description the importer read. `Err` is logged through
/// the logger and gives NULL.
pub fn instantiate<'a, M: Mechanism>(
    version: Version,
    logger: Logger,
    instance_name: Option<&str>,
    interface: Interface,
    token: impl FnOnce() -> Option<&'a str>,
) -> Result<Box<Instance<M>>, (Logger, String)> {
    if instance_name.is_none_or(|name| name.trim().is_empty()) {
        return Err((
            logger,
            "instanceName is NULL or empty (or not UTF-8)".into(),
        ));
    }
    let (what, argument) = match version {
        Version::Fmi2 => ("GUID", "fmuGUID"),
        Version::Fmi3 => ("instantiation token", "instantiationToken"),
    };
    let expected = version.token::<M>();
    match token() {
        Some(t) if t == expected => {}
        Some(t) => {
            return Err((
                logger,
                format!(
                    "{what} \"{t}\" does not match this binary's \"{expected}\": modelDescription.xml and binary are from different builds (or FMI versions)"
                ),
            ))
        }
        None => {
            return Err((
                logger,
                format!("{argument} is NULL or not UTF-8 (expected \"{expected}\")"),
            ))
        }
    }
    let layout = Layout::new(M::VARIABLES).and_then(|layout| {
        event_indicator_references(M::VARIABLES, M::EVENT_INDICATORS).map(|_| layout)
    });
    match layout {
        Ok(layout) => Ok(Box::new(Instance::<M>::new(
            version, logger, layout, interface,
        ))),
        Err(message) => Err((logger, message)),
    }
}

pub fn set_debug_logging<M: Mechanism>(
    inst: &mut Instance<M>,
    logging_on: bool,
    categories: &[&str],
) -> Outcome {
    inst.logger.set_categories(logging_on, categories)?;
    Ok(OK)
}

/// The experiment: the relative tolerance (None: the DefaultExperiment's), the start and
/// the stop time (`fmi2SetupExperiment`, FMI 3.0's `fmi3EnterInitializationMode`).
pub fn setup<M: Mechanism>(
    inst: &mut Instance<M>,
    tolerance: Option<f64>,
    start_time: f64,
    stop_time: Option<f64>,
) -> Outcome {
    if let Some(stop) = stop_time {
        if !(stop.is_finite() && stop >= start_time) {
            return Err(error(format!(
                "stopTime = {stop} must be finite and ≥ startTime = {start_time}"
            )));
        }
    }
    inst.sim.setup(tolerance, start_time)?;
    inst.stop_time = stop_time;
    inst.last_successful_time = start_time;
    Ok(OK)
}

pub fn enter_initialization_mode<M: Mechanism>(inst: &mut Instance<M>) -> Outcome {
    inst.state = ModelState::InitializationMode;
    Ok(OK)
}

/// Initialization ends: Model Exchange goes to event mode, Co-Simulation to step mode (to
/// event mode in FMI 3.0 when the importer uses it).
pub fn exit_initialization_mode<M: Mechanism>(inst: &mut Instance<M>) -> Outcome {
    if let Err(message) = inst.sim.update() {
        inst.state = ModelState::Error;
        return Err(error(format!("initialization failed: {message}")));
    }
    inst.last_successful_time = inst.sim.time();
    inst.state = if inst.event_mode_used {
        ModelState::EventMode
    } else {
        inst.interface.initialized()
    };
    inst.logger
        .log(OK, &format!("initialized at t = {}", inst.sim.time()));
    Ok(OK)
}

pub fn terminate<M: Mechanism>(inst: &mut Instance<M>) -> Outcome {
    inst.state = ModelState::Terminated;
    Ok(OK)
}

pub fn reset<M: Mechanism>(inst: &mut Instance<M>) -> Outcome {
    inst.reset();
    Ok(OK)
}

/// Reads scalars by value reference.
pub fn get_real<M: Mechanism>(inst: &mut Instance<M>, vr: &[u32], value: &mut [f64]) -> Outcome {
    inst.sim.get_real(vr, value)?;
    Ok(OK)
}

/// Sets scalars by value reference, as the instance's state allows.
pub fn set_real<M: Mechanism>(inst: &mut Instance<M>, vr: &[u32], value: &[f64]) -> Outcome {
    inst.sim.set_real(vr, value, set_phase(inst))?;
    Ok(OK)
}

/// Why `set_real` would refuse these values, without setting any.
pub fn check_set_real<M: Mechanism>(inst: &Instance<M>, vr: &[u32], value: &[f64]) -> Outcome {
    Simulation::<M>::check_set(vr, value, set_phase(inst))?;
    Ok(OK)
}

fn set_phase<M: Mechanism>(inst: &Instance<M>) -> SetPhase {
    match inst.state {
        ModelState::Instantiated => SetPhase::Instantiated,
        ModelState::InitializationMode => SetPhase::Initialization,
        ModelState::ContinuousTimeMode => SetPhase::ContinuousTime,
        _ => SetPhase::Running,
    }
}

/// A get or set of a type this FMU has no variables of: only the empty call succeeds.
pub fn no_variables(function: &str, vr: &[u32], kind: &str) -> Outcome {
    match vr.first() {
        None => Ok(OK),
        Some(vr) => Err(error(format!(
            "value reference {vr} is not a variable of type {kind} (this FMU has only real (Float64) variables); called as {function}"
        ))),
    }
}

pub fn get_fmu_state<M: Mechanism>(inst: &mut Instance<M>, slot: StateSlot) -> Outcome {
    slot.store(inst.save())
}

pub fn set_fmu_state<M: Mechanism>(inst: &mut Instance<M>, saved: &FmuState) -> Outcome {
    inst.restore(saved)?;
    Ok(OK)
}

pub fn serialized_fmu_state_size<M: Mechanism>(state: &FmuState, size: &mut usize) -> Outcome {
    *size = state.to_bytes::<M>().len();
    Ok(OK)
}

pub fn serialize_fmu_state<M: Mechanism>(state: &FmuState, buffer: Buffer) -> Outcome {
    let bytes = state.to_bytes::<M>();
    if buffer.size() != bytes.len() {
        return Err(error(format!(
            "size = {}, but the serialized state has {} bytes (ask {}SerializedFMU{}Size)",
            buffer.size(),
            bytes.len(),
            state.version.prefix(),
            match state.version {
                Version::Fmi2 => "state",
                Version::Fmi3 => "State",
            }
        )));
    }
    buffer.fill(&bytes, "serializedState[]")?;
    Ok(OK)
}

pub fn deserialize_fmu_state<M: Mechanism>(
    version: Version,
    bytes: &[u8],
    slot: StateSlot,
) -> Outcome {
    slot.store(FmuState::from_bytes::<M>(bytes, version)?)
}

/// The change of each unknown along the direction `seed` of the knowns (states and
/// inputs) and `time_seed` of the time (FMI 3.0's independent variable; FMI 2.0 gives 0),
/// at the current point, by scalar value reference.
pub fn directional_derivative<M: Mechanism>(
    inst: &mut Instance<M>,
    unknowns: &[u32],
    knowns: &[u32],
    seed: &[f64],
    time_seed: f64,
    sensitivity: &mut [f64],
) -> Outcome {
    if let Some(x) = seed.iter().chain([&time_seed]).find(|x| !x.is_finite()) {
        return Err(error(format!(
            "the seed contains {x}: every seed must be finite"
        )));
    }
    inst.sim
        .directional_derivative(unknowns, knowns, seed, time_seed, sensitivity)?;
    // Seeds near the overflow limit give an infinity, or inf - inf: refuse, rather than
    // return a number that is none.
    if let Some(i) = sensitivity.iter().position(|x| !x.is_finite()) {
        return Err(error(format!(
            "the derivative of `{}` is not a finite number (a seed too large to multiply?)",
            M::VARIABLES[unknowns[i] as usize].name
        )));
    }
    Ok(OK)
}

/// First time derivatives of outputs, by scalar value reference.
pub fn output_derivatives<M: Mechanism>(
    inst: &mut Instance<M>,
    vr: &[u32],
    order: &[i32],
    value: &mut [f64],
) -> Outcome {
    inst.sim.output_derivatives(vr, order, value)?;
    // Input derivatives near the overflow limit give an infinity, or inf - inf: refuse.
    if let Some(i) = value.iter().position(|x| !x.is_finite()) {
        return Err(error(format!(
            "the derivative of `{}` is not a finite number (input derivatives too large?)",
            M::VARIABLES[vr[i] as usize].name
        )));
    }
    Ok(OK)
}

/// How a communication step ended that did not fail.
#[derive(Clone, Debug, PartialEq)]
pub enum Stepped {
    /// At the end of the step; the status is OK or Warning (a warning logged).
    Completed(Status),
    /// The model stopped holding inside the step, at `time`: the instance is terminated
    /// there, and `message` says why (the caller logs it with the status it returns).
    Stopped {
        time: f64,
        message: String,
        /// A limit of the model (its monitor), not a failure of the solver.
        limit: bool,
    },
}

/// A communication step from `t` of size `h` (`fmi2DoStep`, `fmi3DoStep`), as `function`
/// (which prefixes the warnings logged).
pub fn step<M: Mechanism>(
    inst: &mut Instance<M>,
    t: f64,
    h: f64,
    function: &str,
) -> Result<Stepped, Failure> {
    if let Some(stop) = inst.stop_time {
        let end = t + h;
        if end > stop + 1e-9 * stop.abs().max(h) {
            return Err(error(format!(
                "the step [{t}, {end}] goes beyond stopTime = {stop} of the experiment"
            )));
        }
    }
    match inst.sim.step(t, h) {
        Ok(_) => {
            for warning in inst.sim.warnings() {
                inst.logger.log(WARNING, &format!("{function}: {warning}"));
            }
            inst.last_successful_time = inst.sim.time();
            inst.last_step_status = OK;
            Ok(Stepped::Completed(if inst.sim.warnings().is_empty() {
                OK
            } else {
                WARNING
            }))
        }
        Err(StepFailure::Rejected(message)) => Err(error(message)),
        Err(StepFailure::Stopped {
            time,
            message,
            limit,
        }) => {
            inst.last_successful_time = time;
            inst.last_step_status = DISCARD;
            inst.terminated = true;
            inst.state = ModelState::StepFailed;
            Ok(Stepped::Stopped {
                time,
                limit,
                message: format!("step from t = {t} stopped at t = {time}: {message}"),
            })
        }
    }
}

/// [`step`] for a caller that reports a stop as a Discard with its message.
pub fn discarded(stepped: Stepped) -> Outcome {
    match stepped {
        Stepped::Completed(status) => Ok(status),
        Stepped::Stopped { message, .. } => Err(discard(message)),
    }
}
