//! FMI 3.0's functions and state tables (sections 2.3, 3.2 and 4.2), written out here
//! independently of the runtime's. Step Mode is `StepComplete`; after a step that ended
//! the simulation (`terminateSimulation`), only what FMI 3.0 allows before fmi3Terminate
//! is allowed (`StepFailed`); an error leaves what Terminated allows (`Error`). The states
//! of features the FMU does not offer (Configuration, Reconfiguration, Clock Activation,
//! Intermediate Update Mode) are never entered, so their functions are allowed where an
//! instance is live and refused with a message.

use crate::ffi3::{Status, DISCARD, ERROR, OK, WARNING};
use crate::sequences::machine::{Kind, St};

/// Index of each function in [`FUNCTION_NAMES_FMI3`](crate::ffi3::FUNCTION_NAMES_FMI3).
pub mod f {
    pub const GET_VERSION: usize = 0;
    pub const SET_DEBUG_LOGGING: usize = 1;
    pub const INSTANTIATE_ME: usize = 2;
    pub const INSTANTIATE_CS: usize = 3;
    pub const INSTANTIATE_SE: usize = 4;
    pub const FREE_INSTANCE: usize = 5;
    pub const ENTER_INIT: usize = 6;
    pub const EXIT_INIT: usize = 7;
    pub const ENTER_EVENT_MODE: usize = 8;
    pub const TERMINATE: usize = 9;
    pub const RESET: usize = 10;
    pub const GET_FLOAT32: usize = 11;
    pub const GET_FLOAT64: usize = 12;
    pub const GET_INT8: usize = 13;
    pub const GET_UINT8: usize = 14;
    pub const GET_INT16: usize = 15;
    pub const GET_UINT16: usize = 16;
    pub const GET_INT32: usize = 17;
    pub const GET_UINT32: usize = 18;
    pub const GET_INT64: usize = 19;
    pub const GET_UINT64: usize = 20;
    pub const GET_BOOLEAN: usize = 21;
    pub const GET_STRING: usize = 22;
    pub const GET_BINARY: usize = 23;
    pub const GET_CLOCK: usize = 24;
    pub const SET_FLOAT32: usize = 25;
    pub const SET_FLOAT64: usize = 26;
    pub const SET_INT8: usize = 27;
    pub const SET_UINT8: usize = 28;
    pub const SET_INT16: usize = 29;
    pub const SET_UINT16: usize = 30;
    pub const SET_INT32: usize = 31;
    pub const SET_UINT32: usize = 32;
    pub const SET_INT64: usize = 33;
    pub const SET_UINT64: usize = 34;
    pub const SET_BOOLEAN: usize = 35;
    pub const SET_STRING: usize = 36;
    pub const SET_BINARY: usize = 37;
    pub const SET_CLOCK: usize = 38;
    pub const GET_NUMBER_OF_VARIABLE_DEPENDENCIES: usize = 39;
    pub const GET_VARIABLE_DEPENDENCIES: usize = 40;
    pub const GET_FMU_STATE: usize = 41;
    pub const SET_FMU_STATE: usize = 42;
    pub const FREE_FMU_STATE: usize = 43;
    pub const SERIALIZED_SIZE: usize = 44;
    pub const SERIALIZE: usize = 45;
    pub const DESERIALIZE: usize = 46;
    pub const DIRECTIONAL_DERIVATIVE: usize = 47;
    pub const ADJOINT_DERIVATIVE: usize = 48;
    pub const ENTER_CONFIGURATION_MODE: usize = 49;
    pub const EXIT_CONFIGURATION_MODE: usize = 50;
    /// The interval and shift functions of clocks.
    pub const GET_INTERVAL_DECIMAL: usize = 51;
    pub const GET_INTERVAL_FRACTION: usize = 52;
    pub const GET_SHIFT_DECIMAL: usize = 53;
    pub const GET_SHIFT_FRACTION: usize = 54;
    pub const SET_INTERVAL_DECIMAL: usize = 55;
    pub const SET_INTERVAL_FRACTION: usize = 56;
    pub const SET_SHIFT_DECIMAL: usize = 57;
    pub const SET_SHIFT_FRACTION: usize = 58;
    pub const EVALUATE_DISCRETE_STATES: usize = 59;
    pub const UPDATE_DISCRETE_STATES: usize = 60;
    pub const ENTER_CONTINUOUS_TIME_MODE: usize = 61;
    pub const COMPLETED_INTEGRATOR_STEP: usize = 62;
    pub const SET_TIME: usize = 63;
    pub const SET_CONTINUOUS_STATES: usize = 64;
    pub const GET_DERIVATIVES: usize = 65;
    pub const GET_EVENT_INDICATORS: usize = 66;
    pub const GET_CONTINUOUS_STATES: usize = 67;
    pub const GET_NOMINALS: usize = 68;
    pub const GET_NUMBER_OF_EVENT_INDICATORS: usize = 69;
    pub const GET_NUMBER_OF_CONTINUOUS_STATES: usize = 70;
    pub const ENTER_STEP_MODE: usize = 71;
    pub const GET_OUTPUT_DERIVATIVES: usize = 72;
    pub const DO_STEP: usize = 73;
    pub const ACTIVATE_MODEL_PARTITION: usize = 74;
    /// How many there are.
    pub const COUNT: usize = 75;

    /// The functions of features the FMU does not offer: clocks, per-element dependencies,
    /// configuration mode, Scheduled Execution's model partitions.
    pub(crate) fn unsupported(function: usize) -> bool {
        matches!(
            function,
            GET_CLOCK
                | SET_CLOCK
                | GET_NUMBER_OF_VARIABLE_DEPENDENCIES
                | GET_VARIABLE_DEPENDENCIES
                | ENTER_CONFIGURATION_MODE
                | EXIT_CONFIGURATION_MODE
                | ACTIVATE_MODEL_PARTITION
        ) || (GET_INTERVAL_DECIMAL..=SET_SHIFT_FRACTION).contains(&function)
    }
}

/// The interface type `function` belongs to (`None`: both).
pub fn interface_of(function: usize) -> Option<Kind> {
    match function {
        f::ENTER_CONTINUOUS_TIME_MODE..=f::GET_NUMBER_OF_CONTINUOUS_STATES => {
            Some(Kind::ModelExchange)
        }
        f::ENTER_STEP_MODE..=f::DO_STEP => Some(Kind::CoSimulation),
        _ => None,
    }
}

/// Whether an instance of `kind` in state `st` may call `function`.
pub fn allowed(function: usize, kind: Kind, st: St) -> bool {
    use St::*;
    if interface_of(function).is_some_and(|k| k != kind) {
        return false;
    }
    // The states an FMI 3.0 instance can be in; Fatal is never left.
    let live = matches!(
        st,
        Instantiated
            | Init
            | EventMode
            | ContinuousTimeMode
            | StepComplete
            | StepFailed
            | Terminated
            | Error
    );
    let writable = matches!(
        st,
        Instantiated | Init | EventMode | ContinuousTimeMode | StepComplete
    );
    let states_readable = matches!(
        st,
        Init | EventMode | ContinuousTimeMode | Terminated | Error
    );
    match function {
        f::GET_VERSION => true,
        f::INSTANTIATE_ME | f::INSTANTIATE_CS | f::INSTANTIATE_SE => false,
        f::SET_DEBUG_LOGGING | f::FREE_INSTANCE | f::RESET => live,
        f::ENTER_INIT => st == Instantiated,
        f::EXIT_INIT => st == Init,
        // Co-Simulation's only with eventModeUsed: that is checked by the call, which
        // refuses it with a message of its own.
        f::ENTER_EVENT_MODE => matches!(st, ContinuousTimeMode | StepComplete),
        f::TERMINATE => matches!(
            st,
            EventMode | ContinuousTimeMode | StepComplete | StepFailed
        ),
        // Variables are readable from instantiation on (start values).
        f::GET_FLOAT32..=f::GET_BINARY => live,
        f::SET_FLOAT32 | f::SET_FLOAT64 => writable,
        // The other types are discrete: not in continuous-time mode.
        f::SET_FLOAT32..=f::SET_BINARY => writable && st != ContinuousTimeMode,
        f::GET_FMU_STATE..=f::DESERIALIZE => live,
        f::DIRECTIONAL_DERIVATIVE | f::ADJOINT_DERIVATIVE => {
            matches!(
                st,
                Init | EventMode
                    | ContinuousTimeMode
                    | StepComplete
                    | StepFailed
                    | Terminated
                    | Error
            )
        }
        f::EVALUATE_DISCRETE_STATES | f::UPDATE_DISCRETE_STATES => st == EventMode,
        f::ENTER_CONTINUOUS_TIME_MODE => st == EventMode,
        f::COMPLETED_INTEGRATOR_STEP | f::SET_CONTINUOUS_STATES => st == ContinuousTimeMode,
        f::SET_TIME => matches!(st, EventMode | ContinuousTimeMode),
        f::GET_DERIVATIVES..=f::GET_NOMINALS => states_readable,
        f::GET_NUMBER_OF_EVENT_INDICATORS | f::GET_NUMBER_OF_CONTINUOUS_STATES => live,
        f::ENTER_STEP_MODE => st == EventMode,
        f::GET_OUTPUT_DERIVATIVES => matches!(st, StepComplete | StepFailed | Terminated | Error),
        f::DO_STEP => st == StepComplete,
        _ if f::unsupported(function) => live,
        _ => false,
    }
}

/// Statuses a function may return here (a synchronous FMU; in Model Exchange, a point
/// outside the equations' domain is fmi3Discard from the functions that evaluate them).
pub fn status_allowed(function: usize, s: Status) -> bool {
    match s {
        OK | WARNING | ERROR => true,
        DISCARD => matches!(
            function,
            f::DO_STEP | f::GET_DERIVATIVES | f::GET_EVENT_INDICATORS
        ),
        _ => false,
    }
}

/// What may change the continuous states other than fmi3SetContinuousStates.
pub fn moves_states(function: usize) -> bool {
    matches!(
        function,
        f::ENTER_INIT
            | f::EXIT_INIT
            | f::RESET
            | f::SET_FLOAT64
            | f::SET_FMU_STATE
            | f::UPDATE_DISCRETE_STATES
    )
}
