//! The FMI 3.0 C types and the 75 functions of `fmi3Functions.h`, written from the
//! standard's headers (`fmi3PlatformTypes.h`, `fmi3FunctionTypes.h`): this importer trusts
//! nothing of the exporter's own definitions.
//!
//! `fmi3Boolean` is C's `bool`, which has no value but 0 and 1: arguments passed by value
//! are `bool` here, so a hostile call cannot hand the FMU a byte its compiler assumes
//! impossible. Where the FMU writes booleans (out arguments, `fmi3GetBoolean`) or reads an
//! array of them, this importer passes bytes (`u8`, the same size and alignment), so it
//! can check every byte written is 0 or 1 and hand arrays holding other bytes.
#![allow(non_camel_case_types, non_upper_case_globals, non_snake_case)]

use std::os::raw::{c_char, c_uint, c_void};

pub type Instance = *mut c_void;
pub type Env = *mut c_void;
pub type FmuState = *mut c_void;
pub type Vr = u32;
pub type CStr = *const c_char;
pub type Status = c_uint;

pub const OK: Status = 0;
pub const WARNING: Status = 1;
pub const DISCARD: Status = 2;
pub const ERROR: Status = 3;
pub const FATAL: Status = 4;

pub fn status_name(s: Status) -> String {
    match s {
        OK => "fmi3OK".into(),
        WARNING => "fmi3Warning".into(),
        DISCARD => "fmi3Discard".into(),
        ERROR => "fmi3Error".into(),
        FATAL => "fmi3Fatal".into(),
        other => format!("status {other} (not a fmi3Status)"),
    }
}

/// `fmi3LogMessageCallback`: environment, status, category, message.
pub type LogMessageFn = unsafe extern "C" fn(Env, Status, CStr, CStr);
pub type LogMessage = Option<LogMessageFn>;
/// `fmi3IntermediateUpdateCallback`.
pub type IntermediateUpdate =
    Option<unsafe extern "C" fn(Env, f64, bool, bool, bool, bool, *mut bool, *mut f64)>;
pub type ClockUpdate = Option<unsafe extern "C" fn(Env)>;
pub type Preemption = Option<unsafe extern "C" fn()>;

/// Declares [`Api3`] (one field per function, typed from the header), the names in the
/// same order ([`FUNCTION_NAMES_FMI3`]) and [`Api3::load`].
macro_rules! api3 {
    ($($field:ident $name:literal ($($arg:ty),*) $(-> $ret:ty)?;)*) => {
        /// All 75 functions of the FMI 3.0 API, resolved from one binary.
        #[derive(Clone, Copy)]
        pub struct Api3 {
            $(pub $field: unsafe extern "C" fn($($arg),*) $(-> $ret)?,)*
        }

        /// The names of the 75 functions, in the order of [`Api3`]'s fields (the header's).
        pub const FUNCTION_NAMES_FMI3: [&str; 75] = [$($name),*];

        impl Api3 {
            /// Resolves every function; a missing symbol is an error.
            ///
            /// # Safety
            /// `lib` must be an FMI 3.0 binary whose symbols have the standard's signatures.
            pub unsafe fn load(lib: &libloading::Library) -> Result<Api3, String> {
                Ok(Api3 {
                    $(
                        // SAFETY: the symbol is the standard's function of that name; its
                        // type is the field's, written from the header.
                        $field: *unsafe { lib.get(concat!($name, "\0").as_bytes()) }
                            .map_err(|e| format!("{}: {e}", $name))?,
                    )*
                })
            }
        }
    };
}

type I = Instance;
type VrP = *const Vr;

api3! {
    get_version "fmi3GetVersion" () -> CStr;
    set_debug_logging "fmi3SetDebugLogging" (I, bool, usize, *const CStr) -> Status;
    instantiate_model_exchange "fmi3InstantiateModelExchange"
        (CStr, CStr, CStr, bool, bool, Env, LogMessage) -> I;
    instantiate_co_simulation "fmi3InstantiateCoSimulation"
        (CStr, CStr, CStr, bool, bool, bool, bool, VrP, usize, Env, LogMessage, IntermediateUpdate) -> I;
    instantiate_scheduled_execution "fmi3InstantiateScheduledExecution"
        (CStr, CStr, CStr, bool, bool, Env, LogMessage, ClockUpdate, Preemption, Preemption) -> I;
    free_instance "fmi3FreeInstance" (I);
    enter_initialization_mode "fmi3EnterInitializationMode" (I, bool, f64, f64, bool, f64) -> Status;
    exit_initialization_mode "fmi3ExitInitializationMode" (I) -> Status;
    enter_event_mode "fmi3EnterEventMode" (I) -> Status;
    terminate "fmi3Terminate" (I) -> Status;
    reset "fmi3Reset" (I) -> Status;
    get_float32 "fmi3GetFloat32" (I, VrP, usize, *mut f32, usize) -> Status;
    get_float64 "fmi3GetFloat64" (I, VrP, usize, *mut f64, usize) -> Status;
    get_int8 "fmi3GetInt8" (I, VrP, usize, *mut i8, usize) -> Status;
    get_uint8 "fmi3GetUInt8" (I, VrP, usize, *mut u8, usize) -> Status;
    get_int16 "fmi3GetInt16" (I, VrP, usize, *mut i16, usize) -> Status;
    get_uint16 "fmi3GetUInt16" (I, VrP, usize, *mut u16, usize) -> Status;
    get_int32 "fmi3GetInt32" (I, VrP, usize, *mut i32, usize) -> Status;
    get_uint32 "fmi3GetUInt32" (I, VrP, usize, *mut u32, usize) -> Status;
    get_int64 "fmi3GetInt64" (I, VrP, usize, *mut i64, usize) -> Status;
    get_uint64 "fmi3GetUInt64" (I, VrP, usize, *mut u64, usize) -> Status;
    get_boolean "fmi3GetBoolean" (I, VrP, usize, *mut u8, usize) -> Status;
    get_string "fmi3GetString" (I, VrP, usize, *mut CStr, usize) -> Status;
    get_binary "fmi3GetBinary" (I, VrP, usize, *mut usize, *mut *const u8, usize) -> Status;
    get_clock "fmi3GetClock" (I, VrP, usize, *mut u8) -> Status;
    set_float32 "fmi3SetFloat32" (I, VrP, usize, *const f32, usize) -> Status;
    set_float64 "fmi3SetFloat64" (I, VrP, usize, *const f64, usize) -> Status;
    set_int8 "fmi3SetInt8" (I, VrP, usize, *const i8, usize) -> Status;
    set_uint8 "fmi3SetUInt8" (I, VrP, usize, *const u8, usize) -> Status;
    set_int16 "fmi3SetInt16" (I, VrP, usize, *const i16, usize) -> Status;
    set_uint16 "fmi3SetUInt16" (I, VrP, usize, *const u16, usize) -> Status;
    set_int32 "fmi3SetInt32" (I, VrP, usize, *const i32, usize) -> Status;
    set_uint32 "fmi3SetUInt32" (I, VrP, usize, *const u32, usize) -> Status;
    set_int64 "fmi3SetInt64" (I, VrP, usize, *const i64, usize) -> Status;
    set_uint64 "fmi3SetUInt64" (I, VrP, usize, *const u64, usize) -> Status;
    set_boolean "fmi3SetBoolean" (I, VrP, usize, *const u8, usize) -> Status;
    set_string "fmi3SetString" (I, VrP, usize, *const CStr, usize) -> Status;
    set_binary "fmi3SetBinary" (I, VrP, usize, *const usize, *const *const u8, usize) -> Status;
    set_clock "fmi3SetClock" (I, VrP, usize, *const u8) -> Status;
    get_number_of_variable_dependencies "fmi3GetNumberOfVariableDependencies" (I, Vr, *mut usize) -> Status;
    get_variable_dependencies "fmi3GetVariableDependencies"
        (I, Vr, *mut usize, *mut Vr, *mut usize, *mut c_uint, usize) -> Status;
    get_fmu_state "fmi3GetFMUState" (I, *mut FmuState) -> Status;
    set_fmu_state "fmi3SetFMUState" (I, FmuState) -> Status;
    free_fmu_state "fmi3FreeFMUState" (I, *mut FmuState) -> Status;
    serialized_fmu_state_size "fmi3SerializedFMUStateSize" (I, FmuState, *mut usize) -> Status;
    serialize_fmu_state "fmi3SerializeFMUState" (I, FmuState, *mut u8, usize) -> Status;
    deserialize_fmu_state "fmi3DeserializeFMUState" (I, *const u8, usize, *mut FmuState) -> Status;
    get_directional_derivative "fmi3GetDirectionalDerivative"
        (I, VrP, usize, VrP, usize, *const f64, usize, *mut f64, usize) -> Status;
    get_adjoint_derivative "fmi3GetAdjointDerivative"
        (I, VrP, usize, VrP, usize, *const f64, usize, *mut f64, usize) -> Status;
    enter_configuration_mode "fmi3EnterConfigurationMode" (I) -> Status;
    exit_configuration_mode "fmi3ExitConfigurationMode" (I) -> Status;
    get_interval_decimal "fmi3GetIntervalDecimal" (I, VrP, usize, *mut f64, *mut c_uint) -> Status;
    get_interval_fraction "fmi3GetIntervalFraction"
        (I, VrP, usize, *mut u64, *mut u64, *mut c_uint) -> Status;
    get_shift_decimal "fmi3GetShiftDecimal" (I, VrP, usize, *mut f64) -> Status;
    get_shift_fraction "fmi3GetShiftFraction" (I, VrP, usize, *mut u64, *mut u64) -> Status;
    set_interval_decimal "fmi3SetIntervalDecimal" (I, VrP, usize, *const f64) -> Status;
    set_interval_fraction "fmi3SetIntervalFraction" (I, VrP, usize, *const u64, *const u64) -> Status;
    set_shift_decimal "fmi3SetShiftDecimal" (I, VrP, usize, *const f64) -> Status;
    set_shift_fraction "fmi3SetShiftFraction" (I, VrP, usize, *const u64, *const u64) -> Status;
    evaluate_discrete_states "fmi3EvaluateDiscreteStates" (I) -> Status;
    update_discrete_states "fmi3UpdateDiscreteStates"
        (I, *mut u8, *mut u8, *mut u8, *mut u8, *mut u8, *mut f64) -> Status;
    enter_continuous_time_mode "fmi3EnterContinuousTimeMode" (I) -> Status;
    completed_integrator_step "fmi3CompletedIntegratorStep" (I, bool, *mut u8, *mut u8) -> Status;
    set_time "fmi3SetTime" (I, f64) -> Status;
    set_continuous_states "fmi3SetContinuousStates" (I, *const f64, usize) -> Status;
    get_continuous_state_derivatives "fmi3GetContinuousStateDerivatives" (I, *mut f64, usize) -> Status;
    get_event_indicators "fmi3GetEventIndicators" (I, *mut f64, usize) -> Status;
    get_continuous_states "fmi3GetContinuousStates" (I, *mut f64, usize) -> Status;
    get_nominals_of_continuous_states "fmi3GetNominalsOfContinuousStates" (I, *mut f64, usize) -> Status;
    get_number_of_event_indicators "fmi3GetNumberOfEventIndicators" (I, *mut usize) -> Status;
    get_number_of_continuous_states "fmi3GetNumberOfContinuousStates" (I, *mut usize) -> Status;
    enter_step_mode "fmi3EnterStepMode" (I) -> Status;
    get_output_derivatives "fmi3GetOutputDerivatives" (I, VrP, usize, *const i32, *mut f64, usize) -> Status;
    do_step "fmi3DoStep" (I, f64, f64, bool, *mut u8, *mut u8, *mut u8, *mut f64) -> Status;
    activate_model_partition "fmi3ActivateModelPartition" (I, Vr, f64) -> Status;
}

/// What `fmi3UpdateDiscreteStates` reports, each boolean as the byte the FMU wrote.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DiscreteStates {
    pub discrete_states_need_update: u8,
    pub terminate_simulation: u8,
    pub nominals_changed: u8,
    pub values_changed: u8,
    pub next_event_time_defined: u8,
    pub next_event_time: f64,
}

/// What `fmi3DoStep` reports, each boolean as the byte the FMU wrote.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Step {
    pub status: Status,
    pub event_handling_needed: u8,
    pub terminate_simulation: u8,
    pub early_return: u8,
    pub last_successful_time: f64,
}

#[cfg(test)]
mod tests {
    use super::FUNCTION_NAMES_FMI3;

    #[test]
    fn the_names_are_75_distinct_fmi3_functions() {
        let names: std::collections::BTreeSet<&str> = FUNCTION_NAMES_FMI3.into_iter().collect();
        assert_eq!(names.len(), 75);
        assert!(names.iter().all(|n| n.starts_with("fmi3")));
    }
}
