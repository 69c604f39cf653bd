//! The FMI 2.0 C types and function pointer types, written from the standard's headers
//! (`fmi2FunctionTypes.h`, `fmi2TypesPlatform.h`): this importer trusts nothing of the
//! exporter's own definitions.
#![allow(non_camel_case_types, non_upper_case_globals, non_snake_case)]

use std::os::raw::{c_char, c_double, c_int, c_uint, c_void};

pub type Component = *mut c_void;
pub type Env = *mut c_void;
pub type FmuState = *mut c_void;
pub type Vr = c_uint;
pub type Real = c_double;
pub type Integer = c_int;
pub type Boolean = c_int;
pub type CStr = *const c_char;
pub type Byte = c_char;
pub type Status = c_uint;
pub type StatusKind = c_uint;
pub type FmuType = c_uint;

pub const OK: Status = 0;
pub const WARNING: Status = 1;
pub const DISCARD: Status = 2;
pub const ERROR: Status = 3;
pub const FATAL: Status = 4;
pub const PENDING: Status = 5;

pub const MODEL_EXCHANGE: FmuType = 0;
pub const CO_SIMULATION: FmuType = 1;

pub const DO_STEP_STATUS: StatusKind = 0;
pub const PENDING_STATUS: StatusKind = 1;
pub const LAST_SUCCESSFUL_TIME: StatusKind = 2;
pub const TERMINATED: StatusKind = 3;

pub fn status_name(s: Status) -> String {
    match s {
        OK => "fmi2OK".into(),
        WARNING => "fmi2Warning".into(),
        DISCARD => "fmi2Discard".into(),
        ERROR => "fmi2Error".into(),
        FATAL => "fmi2Fatal".into(),
        PENDING => "fmi2Pending".into(),
        other => format!("status {other} (not a fmi2Status)"),
    }
}

/// The logger as the header declares it: C-variadic.
pub type LoggerFn = unsafe extern "C" fn(Env, CStr, Status, CStr, CStr, ...);
pub type AllocateFn = unsafe extern "C" fn(usize, usize) -> *mut c_void;
pub type FreeFn = unsafe extern "C" fn(*mut c_void);
pub type StepFinishedFn = unsafe extern "C" fn(Env, Status);

#[repr(C)]
#[derive(Clone, Copy)]
pub struct CallbackFunctions {
    pub logger: Option<LoggerFn>,
    pub allocate_memory: Option<AllocateFn>,
    pub free_memory: Option<FreeFn>,
    pub step_finished: Option<StepFinishedFn>,
    pub component_environment: Env,
}

pub type GetTypesPlatformFn = unsafe extern "C" fn() -> CStr;
pub type GetVersionFn = unsafe extern "C" fn() -> CStr;
pub type SetDebugLoggingFn = unsafe extern "C" fn(Component, Boolean, usize, *const CStr) -> Status;
pub type InstantiateFn = unsafe extern "C" fn(
    CStr,
    FmuType,
    CStr,
    CStr,
    *const CallbackFunctions,
    Boolean,
    Boolean,
) -> Component;
pub type FreeInstanceFn = unsafe extern "C" fn(Component);
pub type SetupExperimentFn =
    unsafe extern "C" fn(Component, Boolean, Real, Real, Boolean, Real) -> Status;
pub type ComponentFn = unsafe extern "C" fn(Component) -> Status;
pub type GetRealFn = unsafe extern "C" fn(Component, *const Vr, usize, *mut Real) -> Status;
pub type GetIntegerFn = unsafe extern "C" fn(Component, *const Vr, usize, *mut Integer) -> Status;
pub type GetBooleanFn = unsafe extern "C" fn(Component, *const Vr, usize, *mut Boolean) -> Status;
pub type GetStringFn = unsafe extern "C" fn(Component, *const Vr, usize, *mut CStr) -> Status;
pub type SetRealFn = unsafe extern "C" fn(Component, *const Vr, usize, *const Real) -> Status;
pub type SetIntegerFn = unsafe extern "C" fn(Component, *const Vr, usize, *const Integer) -> Status;
pub type SetBooleanFn = unsafe extern "C" fn(Component, *const Vr, usize, *const Boolean) -> Status;
pub type SetStringFn = unsafe extern "C" fn(Component, *const Vr, usize, *const CStr) -> Status;
pub type GetFmuStateFn = unsafe extern "C" fn(Component, *mut FmuState) -> Status;
pub type SetFmuStateFn = unsafe extern "C" fn(Component, FmuState) -> Status;
pub type FreeFmuStateFn = unsafe extern "C" fn(Component, *mut FmuState) -> Status;
pub type SerializedSizeFn = unsafe extern "C" fn(Component, FmuState, *mut usize) -> Status;
pub type SerializeFn = unsafe extern "C" fn(Component, FmuState, *mut Byte, usize) -> Status;
pub type DeSerializeFn =
    unsafe extern "C" fn(Component, *const Byte, usize, *mut FmuState) -> Status;
pub type DirectionalDerivativeFn = unsafe extern "C" fn(
    Component,
    *const Vr,
    usize,
    *const Vr,
    usize,
    *const Real,
    *mut Real,
) -> Status;
pub type SetInputDerivativesFn =
    unsafe extern "C" fn(Component, *const Vr, usize, *const Integer, *const Real) -> Status;
pub type GetOutputDerivativesFn =
    unsafe extern "C" fn(Component, *const Vr, usize, *const Integer, *mut Real) -> Status;
pub type DoStepFn = unsafe extern "C" fn(Component, Real, Real, Boolean) -> Status;
pub type GetStatusFn = unsafe extern "C" fn(Component, StatusKind, *mut Status) -> Status;
pub type GetRealStatusFn = unsafe extern "C" fn(Component, StatusKind, *mut Real) -> Status;
pub type GetIntegerStatusFn = unsafe extern "C" fn(Component, StatusKind, *mut Integer) -> Status;
pub type GetBooleanStatusFn = unsafe extern "C" fn(Component, StatusKind, *mut Boolean) -> Status;
pub type GetStringStatusFn = unsafe extern "C" fn(Component, StatusKind, *mut CStr) -> Status;

/// What `fmi2NewDiscreteStates` reports (`fmi2EventInfo`; the header packs it with the
/// default alignment of 8, which is `repr(C)`'s here).
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EventInfo {
    pub new_discrete_states_needed: Boolean,
    pub terminate_simulation: Boolean,
    pub nominals_of_continuous_states_changed: Boolean,
    pub values_of_continuous_states_changed: Boolean,
    pub next_event_time_defined: Boolean,
    pub next_event_time: Real,
}

pub type NewDiscreteStatesFn = unsafe extern "C" fn(Component, *mut EventInfo) -> Status;
pub type CompletedIntegratorStepFn =
    unsafe extern "C" fn(Component, Boolean, *mut Boolean, *mut Boolean) -> Status;
pub type SetTimeFn = unsafe extern "C" fn(Component, Real) -> Status;
pub type SetContinuousStatesFn = unsafe extern "C" fn(Component, *const Real, usize) -> Status;
/// fmi2GetDerivatives, fmi2GetEventIndicators, fmi2GetContinuousStates,
/// fmi2GetNominalsOfContinuousStates: `(c, array, n)`.
pub type GetRealArrayFn = unsafe extern "C" fn(Component, *mut Real, usize) -> Status;

/// All 44 functions of the FMI 2.0 API (`fmi2Functions.h`: the common ones, Co-Simulation's,
/// then Model Exchange's), resolved from one binary.
#[derive(Clone, Copy)]
pub struct Api {
    pub get_types_platform: GetTypesPlatformFn,
    pub get_version: GetVersionFn,
    pub set_debug_logging: SetDebugLoggingFn,
    pub instantiate: InstantiateFn,
    pub free_instance: FreeInstanceFn,
    pub setup_experiment: SetupExperimentFn,
    pub enter_initialization_mode: ComponentFn,
    pub exit_initialization_mode: ComponentFn,
    pub terminate: ComponentFn,
    pub reset: ComponentFn,
    pub get_real: GetRealFn,
    pub get_integer: GetIntegerFn,
    pub get_boolean: GetBooleanFn,
    pub get_string: GetStringFn,
    pub set_real: SetRealFn,
    pub set_integer: SetIntegerFn,
    pub set_boolean: SetBooleanFn,
    pub set_string: SetStringFn,
    pub get_fmu_state: GetFmuStateFn,
    pub set_fmu_state: SetFmuStateFn,
    pub free_fmu_state: FreeFmuStateFn,
    pub serialized_fmu_state_size: SerializedSizeFn,
    pub serialize_fmu_state: SerializeFn,
    pub deserialize_fmu_state: DeSerializeFn,
    pub get_directional_derivative: DirectionalDerivativeFn,
    pub set_real_input_derivatives: SetInputDerivativesFn,
    pub get_real_output_derivatives: GetOutputDerivativesFn,
    pub do_step: DoStepFn,
    pub cancel_step: ComponentFn,
    pub get_status: GetStatusFn,
    pub get_real_status: GetRealStatusFn,
    pub get_integer_status: GetIntegerStatusFn,
    pub get_boolean_status: GetBooleanStatusFn,
    pub get_string_status: GetStringStatusFn,
    pub enter_event_mode: ComponentFn,
    pub new_discrete_states: NewDiscreteStatesFn,
    pub enter_continuous_time_mode: ComponentFn,
    pub completed_integrator_step: CompletedIntegratorStepFn,
    pub set_time: SetTimeFn,
    pub set_continuous_states: SetContinuousStatesFn,
    pub get_derivatives: GetRealArrayFn,
    pub get_event_indicators: GetRealArrayFn,
    pub get_continuous_states: GetRealArrayFn,
    pub get_nominals_of_continuous_states: GetRealArrayFn,
}

/// The names of the 44 functions, in the order of [`Api`]'s fields (the common and
/// Co-Simulation ones, then Model Exchange's; `tests/exports.rs` checks the set against the
/// header's).
pub const FUNCTION_NAMES: [&str; 44] = [
    "fmi2GetTypesPlatform",
    "fmi2GetVersion",
    "fmi2SetDebugLogging",
    "fmi2Instantiate",
    "fmi2FreeInstance",
    "fmi2SetupExperiment",
    "fmi2EnterInitializationMode",
    "fmi2ExitInitializationMode",
    "fmi2Terminate",
    "fmi2Reset",
    "fmi2GetReal",
    "fmi2GetInteger",
    "fmi2GetBoolean",
    "fmi2GetString",
    "fmi2SetReal",
    "fmi2SetInteger",
    "fmi2SetBoolean",
    "fmi2SetString",
    "fmi2GetFMUstate",
    "fmi2SetFMUstate",
    "fmi2FreeFMUstate",
    "fmi2SerializedFMUstateSize",
    "fmi2SerializeFMUstate",
    "fmi2DeSerializeFMUstate",
    "fmi2GetDirectionalDerivative",
    "fmi2SetRealInputDerivatives",
    "fmi2GetRealOutputDerivatives",
    "fmi2DoStep",
    "fmi2CancelStep",
    "fmi2GetStatus",
    "fmi2GetRealStatus",
    "fmi2GetIntegerStatus",
    "fmi2GetBooleanStatus",
    "fmi2GetStringStatus",
    "fmi2EnterEventMode",
    "fmi2NewDiscreteStates",
    "fmi2EnterContinuousTimeMode",
    "fmi2CompletedIntegratorStep",
    "fmi2SetTime",
    "fmi2SetContinuousStates",
    "fmi2GetDerivatives",
    "fmi2GetEventIndicators",
    "fmi2GetContinuousStates",
    "fmi2GetNominalsOfContinuousStates",
];

impl Api {
    /// Resolves every function; a missing symbol is an error (FMPy refuses such an FMU).
    ///
    /// # Safety
    /// `lib` must be an FMI 2.0 binary whose symbols have the standard's signatures.
    pub unsafe fn load(lib: &libloading::Library) -> Result<Api, String> {
        macro_rules! sym {
            ($name:literal) => {
                // SAFETY: the symbol is the standard's function of that name; its type is
                // the field's, written from the header.
                *unsafe { lib.get(concat!($name, "\0").as_bytes()) }
                    .map_err(|e| format!("{}: {e}", $name))?
            };
        }
        Ok(Api {
            get_types_platform: sym!("fmi2GetTypesPlatform"),
            get_version: sym!("fmi2GetVersion"),
            set_debug_logging: sym!("fmi2SetDebugLogging"),
            instantiate: sym!("fmi2Instantiate"),
            free_instance: sym!("fmi2FreeInstance"),
            setup_experiment: sym!("fmi2SetupExperiment"),
            enter_initialization_mode: sym!("fmi2EnterInitializationMode"),
            exit_initialization_mode: sym!("fmi2ExitInitializationMode"),
            terminate: sym!("fmi2Terminate"),
            reset: sym!("fmi2Reset"),
            get_real: sym!("fmi2GetReal"),
            get_integer: sym!("fmi2GetInteger"),
            get_boolean: sym!("fmi2GetBoolean"),
            get_string: sym!("fmi2GetString"),
            set_real: sym!("fmi2SetReal"),
            set_integer: sym!("fmi2SetInteger"),
            set_boolean: sym!("fmi2SetBoolean"),
            set_string: sym!("fmi2SetString"),
            get_fmu_state: sym!("fmi2GetFMUstate"),
            set_fmu_state: sym!("fmi2SetFMUstate"),
            free_fmu_state: sym!("fmi2FreeFMUstate"),
            serialized_fmu_state_size: sym!("fmi2SerializedFMUstateSize"),
            serialize_fmu_state: sym!("fmi2SerializeFMUstate"),
            deserialize_fmu_state: sym!("fmi2DeSerializeFMUstate"),
            get_directional_derivative: sym!("fmi2GetDirectionalDerivative"),
            set_real_input_derivatives: sym!("fmi2SetRealInputDerivatives"),
            get_real_output_derivatives: sym!("fmi2GetRealOutputDerivatives"),
            do_step: sym!("fmi2DoStep"),
            cancel_step: sym!("fmi2CancelStep"),
            get_status: sym!("fmi2GetStatus"),
            get_real_status: sym!("fmi2GetRealStatus"),
            get_integer_status: sym!("fmi2GetIntegerStatus"),
            get_boolean_status: sym!("fmi2GetBooleanStatus"),
            get_string_status: sym!("fmi2GetStringStatus"),
            enter_event_mode: sym!("fmi2EnterEventMode"),
            new_discrete_states: sym!("fmi2NewDiscreteStates"),
            enter_continuous_time_mode: sym!("fmi2EnterContinuousTimeMode"),
            completed_integrator_step: sym!("fmi2CompletedIntegratorStep"),
            set_time: sym!("fmi2SetTime"),
            set_continuous_states: sym!("fmi2SetContinuousStates"),
            get_derivatives: sym!("fmi2GetDerivatives"),
            get_event_indicators: sym!("fmi2GetEventIndicators"),
            get_continuous_states: sym!("fmi2GetContinuousStates"),
            get_nominals_of_continuous_states: sym!("fmi2GetNominalsOfContinuousStates"),
        })
    }
}
