//! One function per FMI 2.0 call, generic over the mechanism. The `export_fmu!` macro
//! exports them under their C names. Each one checks its pointers and the instance's state,
//! runs its body under `catch_unwind`, and turns every failure into a status and a logged
//! message: nothing an importer passes can crash the process.

#![allow(clippy::missing_safety_doc, non_upper_case_globals)]

use super::ffi::*;
use super::fmu_state::{FmuState, STATE_MAGIC};
use super::instance::{Instance, MAGIC};
use super::logger::Logger;
use super::state::{self, Function, ModelState};
use crate::model::{Mechanism, SetPhase};
use crate::simulation::StepFailure;
use std::ffi::CStr;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// Largest array length accepted from an importer: beyond it a length is surely garbage.
const MAX_ARRAY: usize = 1 << 24;

/// A failed call: the status to return and the message to log.
pub struct Failure {
    pub status: fmi2Status,
    pub message: String,
}

type Outcome = Result<fmi2Status, Failure>;

fn error(message: impl Into<String>) -> Failure {
    Failure {
        status: fmi2Error,
        message: message.into(),
    }
}

impl From<String> for Failure {
    fn from(message: String) -> Self {
        error(message)
    }
}

/// The instance behind `c`, if it is a live instance of this FMU.
unsafe fn instance<'a, M: Mechanism>(c: fmi2Component) -> Option<&'a mut Instance<M>> {
    let ptr = c as *mut Instance<M>;
    if ptr.is_null() || !ptr.is_aligned() {
        return None;
    }
    // SAFETY: `c` came from fmi2Instantiate (checked by the magic number; a pointer that
    // did not is the importer's bug, which the magic catches in the common cases: a freed
    // instance, a pointer to another FMU's instance type).
    let inst = unsafe { &mut *ptr };
    (inst.magic == MAGIC).then_some(inst)
}

/// The wall every instance function stands behind.
unsafe fn call<M: Mechanism>(
    c: fmi2Component,
    function: Function,
    body: impl FnOnce(&mut Instance<M>) -> Outcome,
) -> fmi2Status {
    let result = catch_unwind(AssertUnwindSafe(|| {
        let Some(inst) = (unsafe { instance::<M>(c) }) else {
            return fmi2Error;
        };
        if !function.allowed.contains(inst.state) {
            inst.logger.log(
                fmi2Error,
                &format!(
                    "{}: illegal call sequence: the instance is {}",
                    function.name,
                    inst.state.name()
                ),
            );
            return fmi2Error;
        }
        match body(inst) {
            Ok(status) => status,
            Err(Failure { status, message }) => {
                inst.logger
                    .log(status, &format!("{}: {message}", function.name));
                status
            }
        }
    }));
    result.unwrap_or_else(|payload| {
        let what = payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_default();
        // The instance may be half-updated: it can only be reset or freed from here on.
        let _ = catch_unwind(AssertUnwindSafe(|| {
            if let Some(inst) = unsafe { instance::<M>(c) } {
                inst.state = ModelState::Error;
                inst.logger.log(
                    fmi2Error,
                    &format!(
                        "{}: internal error ({what}); the instance must be reset",
                        function.name
                    ),
                );
            }
        }));
        fmi2Error
    })
}

/// A slice from an importer's array, refusing NULL (when `n > 0`) and absurd lengths.
unsafe fn slice<'a, T>(ptr: *const T, n: usize, what: &str) -> Result<&'a [T], Failure> {
    if n == 0 {
        return Ok(&[]);
    }
    if ptr.is_null() {
        return Err(error(format!("{what} is NULL but its length is {n}")));
    }
    if n > MAX_ARRAY || !ptr.is_aligned() {
        return Err(error(format!("{what} has an implausible length {n}")));
    }
    // SAFETY: the importer promises `n` elements at `ptr`; NULL and absurd lengths are refused.
    Ok(unsafe { std::slice::from_raw_parts(ptr, n) })
}

unsafe fn slice_mut<'a, T>(ptr: *mut T, n: usize, what: &str) -> Result<&'a mut [T], Failure> {
    if n == 0 {
        return Ok(&mut []);
    }
    if ptr.is_null() {
        return Err(error(format!("{what} is NULL but its length is {n}")));
    }
    if n > MAX_ARRAY || !ptr.is_aligned() {
        return Err(error(format!("{what} has an implausible length {n}")));
    }
    // SAFETY: as for `slice`.
    Ok(unsafe { std::slice::from_raw_parts_mut(ptr, n) })
}

unsafe fn out<'a, T>(ptr: *mut T, what: &str) -> Result<&'a mut T, Failure> {
    if ptr.is_null() || !ptr.is_aligned() {
        return Err(error(format!("{what} is NULL")));
    }
    // SAFETY: non-NULL and aligned; the importer promises it points to a T.
    Ok(unsafe { &mut *ptr })
}

unsafe fn c_str<'a>(ptr: fmi2String) -> Option<&'a str> {
    if ptr.is_null() {
        return None;
    }
    // SAFETY: the importer passes a NUL-terminated string.
    unsafe { CStr::from_ptr(ptr) }.to_str().ok()
}

fn no_variables<T>(
    function: &str,
    vr: &[fmi2ValueReference],
    _values: &[T],
    kind: &str,
) -> Outcome {
    match vr.first() {
        None => Ok(fmi2OK),
        Some(vr) => Err(error(format!(
            "value reference {vr} is not a variable of type {kind} (this FMU has only Real variables); called as {function}"
        ))),
    }
}

/// Panics are caught at the wall and reported through the importer's logger; the default
/// hook would also print them to the importer's stderr. The FMU binary has its own copy of
/// std, so the hook installed here (once) affects only this FMU's own code. Called by the
/// exported `fmi2Instantiate` only, never in-process (tests keep their messages).
pub fn silence_panic_messages() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| std::panic::set_hook(Box::new(|_| {})));
}

// ---------------------------------------------------------------------------------------
// Functions without an instance
// ---------------------------------------------------------------------------------------

pub fn get_types_platform() -> fmi2String {
    TYPES_PLATFORM.as_ptr()
}

pub fn get_version() -> fmi2String {
    VERSION.as_ptr()
}

pub unsafe fn instantiate<M: Mechanism>(
    instance_name: fmi2String,
    fmu_type: fmi2Type,
    guid: fmi2String,
    _resource_location: fmi2String,
    functions: *const fmi2CallbackFunctions,
    _visible: fmi2Boolean,
    logging_on: fmi2Boolean,
) -> fmi2Component {
    let result = catch_unwind(AssertUnwindSafe(|| {
        // Without callbacks there is no one to tell what went wrong.
        if functions.is_null() || !functions.is_aligned() {
            return std::ptr::null_mut();
        }
        // SAFETY: non-NULL, aligned; the importer passes its callback table.
        let functions = unsafe { *functions };
        let name = unsafe { c_str(instance_name) }.unwrap_or("");
        let logger = Logger::new(
            functions.logger,
            functions.componentEnvironment,
            name,
            logging_on != 0,
        );
        let fail = |message: String| {
            logger.log(fmi2Error, &format!("fmi2Instantiate: {message}"));
            std::ptr::null_mut()
        };
        if instance_name.is_null() || name.is_empty() {
            return fail("instanceName is NULL or empty (or not UTF-8)".into());
        }
        if fmu_type != fmi2CoSimulation {
            return fail(format!(
                "fmuType = {fmu_type}: {} is a Co-Simulation FMU only (fmi2CoSimulation = 1)",
                M::NAME
            ));
        }
        let expected = crate::guid::guid::<M>();
        match unsafe { c_str(guid) } {
            Some(g) if g == expected => {}
            Some(g) => {
                return fail(format!(
                    "GUID \"{g}\" does not match this binary's \"{expected}\": modelDescription.xml and binary are from different builds"
                ))
            }
            None => return fail("fmuGUID is NULL".into()),
        }
        match crate::model::Layout::new(M::VARIABLES) {
            Ok(layout) => {
                Box::into_raw(Box::new(Instance::<M>::new(logger, layout))) as fmi2Component
            }
            Err(message) => fail(message),
        }
    }));
    result.unwrap_or(std::ptr::null_mut())
}

pub unsafe fn free_instance<M: Mechanism>(c: fmi2Component) {
    let _ = catch_unwind(AssertUnwindSafe(|| {
        let Some(inst) = (unsafe { instance::<M>(c) }) else {
            return;
        };
        if !state::FREE_INSTANCE.allowed.contains(inst.state) {
            inst.logger.log(
                fmi2Error,
                &format!(
                    "fmi2FreeInstance: illegal call sequence: the instance is {}",
                    inst.state.name()
                ),
            );
            return;
        }
        inst.magic = 0;
        // SAFETY: created by Box::into_raw in instantiate, and live (magic checked, then
        // cleared so a second free is refused).
        drop(unsafe { Box::from_raw(c as *mut Instance<M>) });
    }));
}

// ---------------------------------------------------------------------------------------
// Instance life cycle
// ---------------------------------------------------------------------------------------

pub unsafe fn set_debug_logging<M: Mechanism>(
    c: fmi2Component,
    logging_on: fmi2Boolean,
    n_categories: usize,
    categories: *const fmi2String,
) -> fmi2Status {
    unsafe {
        call::<M>(c, state::SET_DEBUG_LOGGING, |inst| {
            let categories = slice(categories, n_categories, "categories[]")?;
            let mut names = Vec::with_capacity(categories.len());
            for &p in categories {
                names.push(c_str(p).ok_or_else(|| error("a category is NULL or not UTF-8"))?);
            }
            inst.logger.set_categories(logging_on != 0, &names)?;
            Ok(fmi2OK)
        })
    }
}

pub unsafe fn setup_experiment<M: Mechanism>(
    c: fmi2Component,
    tolerance_defined: fmi2Boolean,
    tolerance: fmi2Real,
    start_time: fmi2Real,
    stop_time_defined: fmi2Boolean,
    stop_time: fmi2Real,
) -> fmi2Status {
    unsafe {
        call::<M>(c, state::SETUP_EXPERIMENT, |inst| {
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
        })
    }
}

pub unsafe fn enter_initialization_mode<M: Mechanism>(c: fmi2Component) -> fmi2Status {
    unsafe {
        call::<M>(c, state::ENTER_INITIALIZATION_MODE, |inst| {
            inst.state = ModelState::InitializationMode;
            Ok(fmi2OK)
        })
    }
}

pub unsafe fn exit_initialization_mode<M: Mechanism>(c: fmi2Component) -> fmi2Status {
    unsafe {
        call::<M>(c, state::EXIT_INITIALIZATION_MODE, |inst| {
            if let Err(message) = inst.sim.update() {
                inst.state = ModelState::Error;
                return Err(error(format!("initialization failed: {message}")));
            }
            inst.last_successful_time = inst.sim.time();
            inst.state = ModelState::StepComplete;
            inst.logger
                .log(fmi2OK, &format!("initialized at t = {}", inst.sim.time()));
            Ok(fmi2OK)
        })
    }
}

pub unsafe fn terminate<M: Mechanism>(c: fmi2Component) -> fmi2Status {
    unsafe {
        call::<M>(c, state::TERMINATE, |inst| {
            inst.state = ModelState::Terminated;
            Ok(fmi2OK)
        })
    }
}

pub unsafe fn reset<M: Mechanism>(c: fmi2Component) -> fmi2Status {
    unsafe {
        call::<M>(c, state::RESET, |inst| {
            inst.reset();
            Ok(fmi2OK)
        })
    }
}

// ---------------------------------------------------------------------------------------
// Getting and setting values
// ---------------------------------------------------------------------------------------

pub unsafe fn get_real<M: Mechanism>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *mut fmi2Real,
) -> fmi2Status {
    unsafe {
        call::<M>(c, state::GET_REAL, |inst| {
            let vr = slice(vr, nvr, "vr[]")?;
            let value = slice_mut(value, nvr, "value[]")?;
            if let Err(message) = inst.sim.get_real(vr, value) {
                return Err(error(message));
            }
            Ok(fmi2OK)
        })
    }
}

pub unsafe fn set_real<M: Mechanism>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    value: *const fmi2Real,
) -> fmi2Status {
    unsafe {
        call::<M>(c, state::SET_REAL, |inst| {
            let vr = slice(vr, nvr, "vr[]")?;
            let value = slice(value, nvr, "value[]")?;
            let phase = match inst.state {
                ModelState::Instantiated => SetPhase::Instantiated,
                ModelState::InitializationMode => SetPhase::Initialization,
                _ => SetPhase::Running,
            };
            inst.sim.set_real(vr, value, phase)?;
            Ok(fmi2OK)
        })
    }
}

macro_rules! non_real_accessors {
    ($get:ident, $set:ident, $ty:ty, $kind:literal, $getf:ident, $setf:ident) => {
        pub unsafe fn $get<M: Mechanism>(
            c: fmi2Component,
            vr: *const fmi2ValueReference,
            nvr: usize,
            value: *mut $ty,
        ) -> fmi2Status {
            unsafe {
                call::<M>(c, state::$getf, |_| {
                    let vr = slice(vr, nvr, "vr[]")?;
                    let value = slice_mut(value, nvr, "value[]")?;
                    no_variables(state::$getf.name, vr, value, $kind)
                })
            }
        }

        pub unsafe fn $set<M: Mechanism>(
            c: fmi2Component,
            vr: *const fmi2ValueReference,
            nvr: usize,
            value: *const $ty,
        ) -> fmi2Status {
            unsafe {
                call::<M>(c, state::$setf, |_| {
                    let vr = slice(vr, nvr, "vr[]")?;
                    let value = slice(value, nvr, "value[]")?;
                    no_variables(state::$setf.name, vr, value, $kind)
                })
            }
        }
    };
}

non_real_accessors!(
    get_integer,
    set_integer,
    fmi2Integer,
    "Integer",
    GET_INTEGER,
    SET_INTEGER
);
non_real_accessors!(
    get_boolean,
    set_boolean,
    fmi2Boolean,
    "Boolean",
    GET_BOOLEAN,
    SET_BOOLEAN
);
non_real_accessors!(get_string, set_string, fmi2String, "String", GET_STRING, SET_STRING);

// ---------------------------------------------------------------------------------------
// FMU state
// ---------------------------------------------------------------------------------------

/// The live FMU state behind an importer's handle.
unsafe fn fmu_state<'a>(s: fmi2FMUstate) -> Result<&'a mut FmuState, Failure> {
    let ptr = s as *mut FmuState;
    if ptr.is_null() || !ptr.is_aligned() {
        return Err(error("the FMU state is NULL"));
    }
    // SAFETY: a handle from fmi2GetFMUstate/fmi2DeSerializeFMUstate (checked by its magic
    // number, cleared when freed).
    let state = unsafe { &mut *ptr };
    if state.magic != STATE_MAGIC {
        return Err(error(
            "the FMU state is not a live state of this FMU (freed, or not from fmi2GetFMUstate)",
        ));
    }
    Ok(state)
}

/// Hands a state to the importer through `*slot`, reusing the state already there if any.
unsafe fn store_state(slot: *mut fmi2FMUstate, state: FmuState) -> Outcome {
    let slot = unsafe { out(slot, "FMUstate")? };
    if slot.is_null() {
        *slot = Box::into_raw(Box::new(state)) as fmi2FMUstate;
    } else {
        *unsafe { fmu_state(*slot)? } = state;
    }
    Ok(fmi2OK)
}

pub unsafe fn get_fmu_state<M: Mechanism>(c: fmi2Component, s: *mut fmi2FMUstate) -> fmi2Status {
    unsafe { call::<M>(c, state::GET_FMU_STATE, |inst| store_state(s, inst.save())) }
}

pub unsafe fn set_fmu_state<M: Mechanism>(c: fmi2Component, s: fmi2FMUstate) -> fmi2Status {
    unsafe {
        call::<M>(c, state::SET_FMU_STATE, |inst| {
            let saved = fmu_state(s)?;
            inst.restore(saved)?;
            Ok(fmi2OK)
        })
    }
}

pub unsafe fn free_fmu_state<M: Mechanism>(c: fmi2Component, s: *mut fmi2FMUstate) -> fmi2Status {
    unsafe {
        call::<M>(c, state::FREE_FMU_STATE, |_| {
            let slot = out(s, "FMUstate")?;
            if slot.is_null() {
                return Ok(fmi2OK);
            }
            fmu_state(*slot)?.magic = 0;
            // SAFETY: a live state created by Box::into_raw (magic checked, then cleared).
            drop(Box::from_raw(*slot as *mut FmuState));
            *slot = std::ptr::null_mut();
            Ok(fmi2OK)
        })
    }
}

pub unsafe fn serialized_fmu_state_size<M: Mechanism>(
    c: fmi2Component,
    s: fmi2FMUstate,
    size: *mut usize,
) -> fmi2Status {
    unsafe {
        call::<M>(c, state::SERIALIZED_FMU_STATE_SIZE, |_| {
            let bytes = fmu_state(s)?.to_bytes::<M>();
            *out(size, "size")? = bytes.len();
            Ok(fmi2OK)
        })
    }
}

pub unsafe fn serialize_fmu_state<M: Mechanism>(
    c: fmi2Component,
    s: fmi2FMUstate,
    buffer: *mut fmi2Byte,
    size: usize,
) -> fmi2Status {
    unsafe {
        call::<M>(c, state::SERIALIZE_FMU_STATE, |_| {
            let bytes = fmu_state(s)?.to_bytes::<M>();
            if size != bytes.len() {
                return Err(error(format!(
                    "size = {size}, but the serialized state has {} bytes (ask fmi2SerializedFMUstateSize)",
                    bytes.len()
                )));
            }
            let buffer = slice_mut(buffer as *mut u8, size, "serializedState[]")?;
            buffer.copy_from_slice(&bytes);
            Ok(fmi2OK)
        })
    }
}

pub unsafe fn deserialize_fmu_state<M: Mechanism>(
    c: fmi2Component,
    bytes: *const fmi2Byte,
    size: usize,
    s: *mut fmi2FMUstate,
) -> fmi2Status {
    unsafe {
        call::<M>(c, state::DESERIALIZE_FMU_STATE, |_| {
            let bytes = slice(bytes as *const u8, size, "serializedState[]")?;
            let state = FmuState::from_bytes::<M>(bytes)?;
            store_state(s, state)
        })
    }
}

pub unsafe fn get_directional_derivative<M: Mechanism>(
    c: fmi2Component,
    unknowns: *const fmi2ValueReference,
    n_unknowns: usize,
    knowns: *const fmi2ValueReference,
    n_knowns: usize,
    dv_known: *const fmi2Real,
    dv_unknown: *mut fmi2Real,
) -> fmi2Status {
    unsafe {
        call::<M>(c, state::GET_DIRECTIONAL_DERIVATIVE, |inst| {
            let unknowns = slice(unknowns, n_unknowns, "vUnknown_ref[]")?;
            let knowns = slice(knowns, n_knowns, "vKnown_ref[]")?;
            let dv_known = slice(dv_known, n_knowns, "dvKnown[]")?;
            let dv_unknown = slice_mut(dv_unknown, n_unknowns, "dvUnknown[]")?;
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
        })
    }
}

// ---------------------------------------------------------------------------------------
// Co-simulation
// ---------------------------------------------------------------------------------------

pub unsafe fn set_real_input_derivatives<M: Mechanism>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    order: *const fmi2Integer,
    value: *const fmi2Real,
) -> fmi2Status {
    unsafe {
        call::<M>(c, state::SET_REAL_INPUT_DERIVATIVES, |inst| {
            let vr = slice(vr, nvr, "vr[]")?;
            let order = slice(order, nvr, "order[]")?;
            let value = slice(value, nvr, "value[]")?;
            inst.sim.set_input_derivatives(vr, order, value)?;
            Ok(fmi2OK)
        })
    }
}

pub unsafe fn get_real_output_derivatives<M: Mechanism>(
    c: fmi2Component,
    vr: *const fmi2ValueReference,
    nvr: usize,
    order: *const fmi2Integer,
    value: *mut fmi2Real,
) -> fmi2Status {
    unsafe {
        call::<M>(c, state::GET_REAL_OUTPUT_DERIVATIVES, |inst| {
            let vr = slice(vr, nvr, "vr[]")?;
            let order = slice(order, nvr, "order[]")?;
            let value = slice_mut(value, nvr, "value[]")?;
            inst.sim.output_derivatives(vr, order, value)?;
            // Input derivatives near the overflow limit give inf - inf: refuse, not NaN.
            if let Some(i) = value.iter().position(|x| x.is_nan()) {
                return Err(error(format!(
                    "the derivative of value reference {} is not a number (input derivatives too large?)",
                    vr[i]
                )));
            }
            Ok(fmi2OK)
        })
    }
}

pub unsafe fn do_step<M: Mechanism>(
    c: fmi2Component,
    current_communication_point: fmi2Real,
    communication_step_size: fmi2Real,
    _no_set_fmu_state_prior: fmi2Boolean,
) -> fmi2Status {
    unsafe {
        call::<M>(c, state::DO_STEP, |inst| {
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
                    Err(Failure {
                        status: fmi2Discard,
                        message: format!("step from t = {t} stopped at t = {time}: {message}"),
                    })
                }
            }
        })
    }
}

pub unsafe fn cancel_step<M: Mechanism>(c: fmi2Component) -> fmi2Status {
    // Steps run synchronously, so the instance is never in StepInProgress and the state
    // check always refuses this call, as the standard's table says.
    unsafe { call::<M>(c, state::CANCEL_STEP, |_| Ok(fmi2OK)) }
}

pub unsafe fn get_status<M: Mechanism>(
    c: fmi2Component,
    kind: fmi2StatusKind,
    value: *mut fmi2Status,
) -> fmi2Status {
    unsafe {
        call::<M>(c, state::GET_STATUS, |inst| {
            let value = out(value, "value")?;
            match kind {
                fmi2DoStepStatus => {
                    *value = inst.last_step_status;
                    Ok(fmi2OK)
                }
                fmi2PendingStatus => Err(Failure {
                    status: fmi2Discard,
                    message: "fmi2PendingStatus: no step is pending (steps run synchronously)"
                        .into(),
                }),
                _ => Err(Failure {
                    status: fmi2Discard,
                    message: format!("status kind {kind} is not a fmi2Status kind"),
                }),
            }
        })
    }
}

pub unsafe fn get_real_status<M: Mechanism>(
    c: fmi2Component,
    kind: fmi2StatusKind,
    value: *mut fmi2Real,
) -> fmi2Status {
    unsafe {
        call::<M>(c, state::GET_REAL_STATUS, |inst| {
            let value = out(value, "value")?;
            match kind {
                fmi2LastSuccessfulTime => {
                    *value = inst.last_successful_time;
                    Ok(fmi2OK)
                }
                _ => Err(Failure {
                    status: fmi2Discard,
                    message: format!(
                        "status kind {kind} is not a real status (fmi2LastSuccessfulTime = 2 is)"
                    ),
                }),
            }
        })
    }
}

pub unsafe fn get_integer_status<M: Mechanism>(
    c: fmi2Component,
    kind: fmi2StatusKind,
    _value: *mut fmi2Integer,
) -> fmi2Status {
    unsafe {
        call::<M>(c, state::GET_INTEGER_STATUS, |_| {
            Err(Failure {
                status: fmi2Discard,
                message: format!("status kind {kind}: there is no integer status"),
            })
        })
    }
}

pub unsafe fn get_boolean_status<M: Mechanism>(
    c: fmi2Component,
    kind: fmi2StatusKind,
    value: *mut fmi2Boolean,
) -> fmi2Status {
    unsafe {
        call::<M>(c, state::GET_BOOLEAN_STATUS, |inst| {
            let value = out(value, "value")?;
            match kind {
                fmi2Terminated => {
                    *value = if inst.terminated { fmi2True } else { fmi2False };
                    Ok(fmi2OK)
                }
                _ => Err(Failure {
                    status: fmi2Discard,
                    message: format!(
                        "status kind {kind} is not a boolean status (fmi2Terminated = 3 is)"
                    ),
                }),
            }
        })
    }
}

pub unsafe fn get_string_status<M: Mechanism>(
    c: fmi2Component,
    kind: fmi2StatusKind,
    value: *mut fmi2String,
) -> fmi2Status {
    unsafe {
        call::<M>(c, state::GET_STRING_STATUS, |_| {
            let value = out(value, "value")?;
            *value = c"".as_ptr();
            Err(Failure {
                status: fmi2Discard,
                message: format!(
                    "status kind {kind}: there is no string status (no step is pending)"
                ),
            })
        })
    }
}

/// Copies this FMU's modelDescription.xml into `buffer` when it fits (with a NUL);
/// returns its length. Never fails: a NULL buffer just asks for the length.
pub unsafe fn model_description<M: Mechanism>(buffer: *mut u8, capacity: usize) -> usize {
    catch_unwind(|| {
        // A declaration the generator refuses (e.g. an unknown unit) yields the message
        // instead, which `mechfmu build` reports.
        let xml = crate::xml::model_description::<M>().unwrap_or_else(|e| format!("error: {e}"));
        let bytes = xml.as_bytes();
        if !buffer.is_null() && capacity > bytes.len() {
            // SAFETY: the caller gives `capacity` writable bytes at `buffer`.
            unsafe {
                std::ptr::copy_nonoverlapping(bytes.as_ptr(), buffer, bytes.len());
                *buffer.add(bytes.len()) = 0;
            }
        }
        bytes.len()
    })
    .unwrap_or(0)
}

// ---------------------------------------------------------------------------------------
// Not FMI: work counters and the parts of a step alone, for `mechfmu bench`
// ---------------------------------------------------------------------------------------

/// Number of counters [`counters`] reports.
pub const COUNTERS: usize = 4;

/// Copies the instance's cumulative work counters into `out` (at most `n` of them, in the
/// order: communication steps, accepted solver steps, rejected solver steps, model
/// evaluations) and returns how many there are ([`COUNTERS`]); 0 if `c` is not a live
/// instance. Any state; not an FMI function, logs nothing.
pub unsafe fn counters<M: Mechanism>(c: fmi2Component, out: *mut u64, n: usize) -> usize {
    catch_unwind(AssertUnwindSafe(|| {
        let Some(inst) = (unsafe { instance::<M>(c) }) else {
            return 0;
        };
        let k = inst.sim.counters();
        let all = [k.steps, k.accepted, k.rejected, k.evaluations];
        if let Ok(out) = unsafe { slice_mut(out, n.min(COUNTERS), "out") } {
            out.copy_from_slice(&all[..out.len()]);
        }
        COUNTERS
    }))
    .unwrap_or(0)
}

/// Repeats one part of a communication step `n` times on a copy of the instance's
/// simulation (part 0: the model equations alone, 1: the solver's right-hand-side callback,
/// 2: whole steps of size `h` without the FMI layer; see
/// [`Simulation::bench`](crate::simulation::Simulation::bench)), so a benchmark can time
/// the parts from outside, in the FMU's own compiled code. Changes nothing. Not an FMI
/// function; logs nothing.
pub unsafe fn bench<M: Mechanism>(c: fmi2Component, part: u32, n: u64, h: f64) -> fmi2Status {
    catch_unwind(AssertUnwindSafe(|| {
        let Some(inst) = (unsafe { instance::<M>(c) }) else {
            return fmi2Error;
        };
        let Some(part) = crate::simulation::Part::from_code(part) else {
            return fmi2Error;
        };
        match inst.sim.bench(part, n, h) {
            Ok(sum) => {
                std::hint::black_box(sum);
                fmi2OK
            }
            Err(_) => fmi2Error,
        }
    }))
    .unwrap_or(fmi2Error)
}
