//! FMI 2.0's functions and state tables (sections 3.2.3 and 4.2.4), written out here
//! independently of the runtime's.

use crate::ffi::{Status, DISCARD, ERROR, OK, WARNING};
use crate::sequences::machine::{Kind, St};

/// Index of each function in [`FUNCTION_NAMES`](crate::ffi::FUNCTION_NAMES).
pub mod f {
    pub const GET_TYPES_PLATFORM: usize = 0;
    pub const GET_VERSION: usize = 1;
    pub const SET_DEBUG_LOGGING: usize = 2;
    pub const INSTANTIATE: usize = 3;
    pub const FREE_INSTANCE: usize = 4;
    pub const SETUP_EXPERIMENT: usize = 5;
    pub const ENTER_INIT: usize = 6;
    pub const EXIT_INIT: usize = 7;
    pub const TERMINATE: usize = 8;
    pub const RESET: usize = 9;
    pub const GET_REAL: usize = 10;
    pub const GET_INTEGER: usize = 11;
    pub const GET_BOOLEAN: usize = 12;
    pub const GET_STRING: usize = 13;
    pub const SET_REAL: usize = 14;
    pub const SET_INTEGER: usize = 15;
    pub const SET_BOOLEAN: usize = 16;
    pub const SET_STRING: usize = 17;
    pub const GET_FMU_STATE: usize = 18;
    pub const SET_FMU_STATE: usize = 19;
    pub const FREE_FMU_STATE: usize = 20;
    pub const SERIALIZED_SIZE: usize = 21;
    pub const SERIALIZE: usize = 22;
    pub const DESERIALIZE: usize = 23;
    pub const DIRECTIONAL_DERIVATIVE: usize = 24;
    pub const SET_INPUT_DERIVATIVES: usize = 25;
    pub const GET_OUTPUT_DERIVATIVES: usize = 26;
    pub const DO_STEP: usize = 27;
    pub const CANCEL_STEP: usize = 28;
    pub const GET_STATUS: usize = 29;
    pub const GET_REAL_STATUS: usize = 30;
    pub const GET_INTEGER_STATUS: usize = 31;
    pub const GET_BOOLEAN_STATUS: usize = 32;
    pub const GET_STRING_STATUS: usize = 33;
    pub const ENTER_EVENT_MODE: usize = 34;
    pub const NEW_DISCRETE_STATES: usize = 35;
    pub const ENTER_CONTINUOUS_TIME_MODE: usize = 36;
    pub const COMPLETED_INTEGRATOR_STEP: usize = 37;
    pub const SET_TIME: usize = 38;
    pub const SET_CONTINUOUS_STATES: usize = 39;
    pub const GET_DERIVATIVES: usize = 40;
    pub const GET_EVENT_INDICATORS: usize = 41;
    pub const GET_CONTINUOUS_STATES: usize = 42;
    pub const GET_NOMINALS: usize = 43;
    /// How many there are.
    pub const COUNT: usize = 44;

    /// Whether `function` is one of Co-Simulation only.
    pub(crate) fn co_simulation_only(function: usize) -> bool {
        matches!(
            function,
            SET_INPUT_DERIVATIVES
                | GET_OUTPUT_DERIVATIVES
                | DO_STEP
                | CANCEL_STEP
                | GET_STATUS
                | GET_REAL_STATUS
                | GET_INTEGER_STATUS
                | GET_BOOLEAN_STATUS
                | GET_STRING_STATUS
        )
    }

    /// Whether `function` is one of Model Exchange only.
    pub(crate) fn model_exchange_only(function: usize) -> bool {
        (ENTER_EVENT_MODE..COUNT).contains(&function)
    }
}

/// The standard's state tables, written out here independently of the runtime's: whether
/// an instance of `kind` in state `st` may call `function`.
pub fn allowed(function: usize, kind: Kind, st: St) -> bool {
    use St::*;
    if (kind == Kind::ModelExchange && f::co_simulation_only(function))
        || (kind == Kind::CoSimulation && f::model_exchange_only(function))
    {
        return false;
    }
    let any_but_fatal = st != Fatal;
    let freeable = !matches!(st, StepInProgress | Fatal);
    let readable = matches!(
        st,
        Init | EventMode
            | ContinuousTimeMode
            | StepComplete
            | StepFailed
            | StepCanceled
            | Terminated
            | Error
    );
    let writable = matches!(
        st,
        Instantiated | Init | EventMode | ContinuousTimeMode | StepComplete
    );
    // Integer, Boolean and String variables are discrete: not in continuous-time mode.
    let writable_discrete = writable && st != ContinuousTimeMode;
    let me_states_readable = matches!(
        st,
        Init | EventMode | ContinuousTimeMode | Terminated | Error
    );
    let status = matches!(
        st,
        StepComplete | StepInProgress | StepFailed | StepCanceled | Terminated
    );
    match function {
        f::GET_TYPES_PLATFORM | f::GET_VERSION => true,
        f::SET_DEBUG_LOGGING => any_but_fatal,
        f::INSTANTIATE => false,
        f::FREE_INSTANCE | f::RESET => freeable,
        f::SETUP_EXPERIMENT | f::ENTER_INIT => st == Instantiated,
        f::EXIT_INIT => st == Init,
        f::TERMINATE => matches!(
            st,
            EventMode | ContinuousTimeMode | StepComplete | StepFailed | StepCanceled
        ),
        f::GET_REAL | f::GET_INTEGER | f::GET_BOOLEAN | f::GET_STRING => readable,
        f::SET_REAL => writable,
        f::SET_INTEGER | f::SET_BOOLEAN | f::SET_STRING => writable_discrete,
        f::GET_FMU_STATE
        | f::SET_FMU_STATE
        | f::FREE_FMU_STATE
        | f::SERIALIZED_SIZE
        | f::SERIALIZE
        | f::DESERIALIZE => freeable,
        f::DIRECTIONAL_DERIVATIVE => readable,
        f::SET_INPUT_DERIVATIVES => writable,
        f::GET_OUTPUT_DERIVATIVES => {
            matches!(
                st,
                StepComplete | StepFailed | StepCanceled | Terminated | Error
            )
        }
        f::DO_STEP => st == StepComplete,
        f::CANCEL_STEP => st == StepInProgress,
        f::GET_STATUS
        | f::GET_REAL_STATUS
        | f::GET_INTEGER_STATUS
        | f::GET_BOOLEAN_STATUS
        | f::GET_STRING_STATUS => status,
        f::ENTER_EVENT_MODE | f::SET_TIME => matches!(st, EventMode | ContinuousTimeMode),
        f::NEW_DISCRETE_STATES | f::ENTER_CONTINUOUS_TIME_MODE => st == EventMode,
        f::COMPLETED_INTEGRATOR_STEP | f::SET_CONTINUOUS_STATES => st == ContinuousTimeMode,
        f::GET_EVENT_INDICATORS | f::GET_CONTINUOUS_STATES => me_states_readable,
        f::GET_DERIVATIVES => matches!(st, EventMode | ContinuousTimeMode | Terminated | Error),
        f::GET_NOMINALS => matches!(
            st,
            Instantiated | EventMode | ContinuousTimeMode | Terminated | Error
        ),
        _ => false,
    }
}

/// Statuses a function may return here (a synchronous CS FMU; in Model Exchange, a point
/// outside the equations' domain is fmi2Discard from the functions that evaluate them).
pub fn status_allowed(function: usize, s: Status) -> bool {
    match s {
        OK | WARNING | ERROR => true,
        DISCARD => matches!(
            function,
            f::DO_STEP
                | f::GET_DERIVATIVES
                | f::GET_EVENT_INDICATORS
                | f::GET_STATUS
                | f::GET_REAL_STATUS
                | f::GET_INTEGER_STATUS
                | f::GET_BOOLEAN_STATUS
                | f::GET_STRING_STATUS
        ),
        _ => false,
    }
}
