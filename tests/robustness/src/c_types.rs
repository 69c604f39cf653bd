//! The standards' C types and function tables, from `mechfmu_host` (written from the
//! headers there, as the FMU's importer sees them), under the short names this suite writes
//! its calls with; and the statuses' names for its messages.
//!
//! `fmi3Boolean` is C's `bool`, which has no value but 0 and 1: arguments passed by value
//! are `bool`, so a hostile call cannot hand the FMU a byte its compiler assumes impossible.
//! Where the FMU writes booleans (out arguments, `fmi3GetBoolean`) or reads an array of
//! them, this suite passes bytes (`u8`, the same size and alignment) through the header's
//! `*mut bool`, so it can check every byte written is 0 or 1 and hand arrays holding other
//! bytes.

/// FMI 2.0.
pub mod ffi {
    /// The signature of `fmi2GetDerivatives`, `fmi2GetEventIndicators`,
    /// `fmi2GetContinuousStates` and `fmi2GetNominalsOfContinuousStates`: `(c, array, n)`.
    pub use mechfmu_host::fmi2::api::fmi2GetDerivativesTYPE as GetRealArrayFn;
    pub use mechfmu_host::fmi2::api::{Api, FUNCTION_NAMES};
    pub use mechfmu_host::fmi2::ffi::{
        fmi2Boolean as Boolean, fmi2Byte as Byte, fmi2CallbackFunctions as CallbackFunctions,
        fmi2CallbackLogger as Logger, fmi2Component as Component, fmi2ComponentEnvironment as Env,
        fmi2EventInfo as EventInfo, fmi2FMUstate as FmuState, fmi2Integer as Integer,
        fmi2Real as Real, fmi2Status as Status, fmi2StatusKind as StatusKind, fmi2String as CStr,
        fmi2Type as FmuType, fmi2ValueReference as Vr,
    };
    pub use mechfmu_host::fmi2::ffi::{
        fmi2CoSimulation as CO_SIMULATION, fmi2Discard as DISCARD,
        fmi2DoStepStatus as DO_STEP_STATUS, fmi2Error as ERROR, fmi2Fatal as FATAL,
        fmi2LastSuccessfulTime as LAST_SUCCESSFUL_TIME, fmi2ModelExchange as MODEL_EXCHANGE,
        fmi2OK as OK, fmi2Pending as PENDING, fmi2PendingStatus as PENDING_STATUS,
        fmi2Terminated as TERMINATED, fmi2Warning as WARNING,
    };

    /// An `fmi2EventInfo` holding what no FMU writes (-1, NaN), so that a field the FMU
    /// leaves unwritten shows.
    pub fn unwritten_event_info() -> EventInfo {
        EventInfo {
            newDiscreteStatesNeeded: -1,
            terminateSimulation: -1,
            nominalsOfContinuousStatesChanged: -1,
            valuesOfContinuousStatesChanged: -1,
            nextEventTimeDefined: -1,
            nextEventTime: f64::NAN,
        }
    }

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
}

/// FMI 3.0.
pub mod ffi3 {
    pub use mechfmu_host::fmi3::api::{Api as Api3, FUNCTION_NAMES as FUNCTION_NAMES_FMI3};
    pub use mechfmu_host::fmi3::ffi::{
        fmi3Discard as DISCARD, fmi3Error as ERROR, fmi3Fatal as FATAL, fmi3OK as OK,
        fmi3Warning as WARNING,
    };
    pub use mechfmu_host::fmi3::ffi::{
        fmi3FMUState as FmuState, fmi3Instance as Instance, fmi3InstanceEnvironment as Env,
        fmi3LogMessageCallback as LogMessage, fmi3Status as Status, fmi3String as CStr,
        fmi3ValueReference as Vr,
    };

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

    /// A byte the FMU writes an `fmi3Boolean` into, as the header's `fmi3Boolean*`.
    pub fn boolean_out(byte: &mut u8) -> *mut bool {
        (byte as *mut u8).cast()
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
}
