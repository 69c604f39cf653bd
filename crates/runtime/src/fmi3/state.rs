//! The state machines of FMI 3.0 (section 2.3, and sections 3.2 and 4.2 for Model Exchange
//! and Co-Simulation), one row per function: which function may be called in which state
//! (see [`machine`](crate::fmi::machine)). FMI 3.0's Step Mode is the shared
//! `StepComplete`, the state after a discarded step `StepFailed`; an error leaves the
//! instance where only what Terminated allows is allowed (the shared `Error`). The states
//! of features this runtime does not offer (Configuration, Reconfiguration, Clock
//! Activation and Intermediate Update Mode) are never entered: their functions are refused
//! with a message.

use crate::fmi::machine::{
    all_but, mask, row_constructors, STATES_READABLE, WRITABLE, WRITABLE_DISCRETE,
};
pub use crate::fmi::machine::{Function, Interface, ModelState, StateMask};
use crate::fmi::Version::Fmi3;
use ModelState as S;

row_constructors!(Fmi3);

/// Any state an instance can be in, but Fatal (FMI 3.0 has no step in progress or
/// canceled step).
const LIVE: StateMask = all_but(&[S::Fatal, S::StepInProgress, S::StepCanceled]);
/// Where variables may be read: start values from instantiation on, so in every state.
const READABLE: StateMask = LIVE;
/// Where derivatives may be asked for: from initialization on.
const DERIVATIVES: StateMask = all_but(&[
    S::Fatal,
    S::StepInProgress,
    S::StepCanceled,
    S::Instantiated,
]);

pub const SET_DEBUG_LOGGING: Function = f("fmi3SetDebugLogging", LIVE);
pub const FREE_INSTANCE: Function = f("fmi3FreeInstance", LIVE);
pub const ENTER_INITIALIZATION_MODE: Function =
    f("fmi3EnterInitializationMode", mask(&[S::Instantiated]));
pub const EXIT_INITIALIZATION_MODE: Function =
    f("fmi3ExitInitializationMode", mask(&[S::InitializationMode]));
pub const ENTER_EVENT_MODE: Function = f(
    "fmi3EnterEventMode",
    mask(&[S::ContinuousTimeMode, S::StepComplete]),
);
pub const TERMINATE: Function = f(
    "fmi3Terminate",
    mask(&[
        S::EventMode,
        S::ContinuousTimeMode,
        S::StepComplete,
        S::StepFailed,
    ]),
);
pub const RESET: Function = f("fmi3Reset", LIVE);

/// Rows of the same mask, one per function.
macro_rules! rows {
    ($mask:expr => $($row:ident $name:literal),* $(,)?) => {
        $( pub const $row: Function = f($name, $mask); )*
    };
}

rows!(READABLE =>
    GET_FLOAT32 "fmi3GetFloat32", GET_FLOAT64 "fmi3GetFloat64", GET_INT8 "fmi3GetInt8",
    GET_UINT8 "fmi3GetUInt8", GET_INT16 "fmi3GetInt16", GET_UINT16 "fmi3GetUInt16",
    GET_INT32 "fmi3GetInt32", GET_UINT32 "fmi3GetUInt32", GET_INT64 "fmi3GetInt64",
    GET_UINT64 "fmi3GetUInt64", GET_BOOLEAN "fmi3GetBoolean", GET_STRING "fmi3GetString",
    GET_BINARY "fmi3GetBinary",
);
rows!(WRITABLE => SET_FLOAT32 "fmi3SetFloat32", SET_FLOAT64 "fmi3SetFloat64");
rows!(WRITABLE_DISCRETE =>
    SET_INT8 "fmi3SetInt8", SET_UINT8 "fmi3SetUInt8", SET_INT16 "fmi3SetInt16",
    SET_UINT16 "fmi3SetUInt16", SET_INT32 "fmi3SetInt32", SET_UINT32 "fmi3SetUInt32",
    SET_INT64 "fmi3SetInt64", SET_UINT64 "fmi3SetUInt64", SET_BOOLEAN "fmi3SetBoolean",
    SET_STRING "fmi3SetString", SET_BINARY "fmi3SetBinary",
);
// Clocks, configuration mode: refused in every state with a message (see `calls`).
rows!(LIVE =>
    GET_CLOCK "fmi3GetClock", SET_CLOCK "fmi3SetClock",
    GET_INTERVAL_DECIMAL "fmi3GetIntervalDecimal", GET_INTERVAL_FRACTION "fmi3GetIntervalFraction",
    GET_SHIFT_DECIMAL "fmi3GetShiftDecimal", GET_SHIFT_FRACTION "fmi3GetShiftFraction",
    SET_INTERVAL_DECIMAL "fmi3SetIntervalDecimal", SET_INTERVAL_FRACTION "fmi3SetIntervalFraction",
    SET_SHIFT_DECIMAL "fmi3SetShiftDecimal", SET_SHIFT_FRACTION "fmi3SetShiftFraction",
    ENTER_CONFIGURATION_MODE "fmi3EnterConfigurationMode",
    EXIT_CONFIGURATION_MODE "fmi3ExitConfigurationMode",
);

pub const GET_NUMBER_OF_VARIABLE_DEPENDENCIES: Function =
    f("fmi3GetNumberOfVariableDependencies", LIVE);
pub const GET_VARIABLE_DEPENDENCIES: Function = f("fmi3GetVariableDependencies", LIVE);

pub const GET_FMU_STATE: Function = f("fmi3GetFMUState", LIVE);
pub const SET_FMU_STATE: Function = f("fmi3SetFMUState", LIVE);
pub const FREE_FMU_STATE: Function = f("fmi3FreeFMUState", LIVE);
pub const SERIALIZED_FMU_STATE_SIZE: Function = f("fmi3SerializedFMUStateSize", LIVE);
pub const SERIALIZE_FMU_STATE: Function = f("fmi3SerializeFMUState", LIVE);
pub const DESERIALIZE_FMU_STATE: Function = f("fmi3DeserializeFMUState", LIVE);

pub const GET_DIRECTIONAL_DERIVATIVE: Function = f("fmi3GetDirectionalDerivative", DERIVATIVES);
pub const GET_ADJOINT_DERIVATIVE: Function = f("fmi3GetAdjointDerivative", DERIVATIVES);

pub const EVALUATE_DISCRETE_STATES: Function =
    f("fmi3EvaluateDiscreteStates", mask(&[S::EventMode]));
pub const UPDATE_DISCRETE_STATES: Function = f("fmi3UpdateDiscreteStates", mask(&[S::EventMode]));

// Model Exchange only (section 3.2).
pub const ENTER_CONTINUOUS_TIME_MODE: Function =
    me("fmi3EnterContinuousTimeMode", mask(&[S::EventMode]));
pub const COMPLETED_INTEGRATOR_STEP: Function = me(
    "fmi3CompletedIntegratorStep",
    mask(&[S::ContinuousTimeMode]),
);
pub const SET_TIME: Function = me("fmi3SetTime", mask(&[S::EventMode, S::ContinuousTimeMode]));
pub const SET_CONTINUOUS_STATES: Function =
    me("fmi3SetContinuousStates", mask(&[S::ContinuousTimeMode]));
pub const GET_CONTINUOUS_STATE_DERIVATIVES: Function =
    me("fmi3GetContinuousStateDerivatives", STATES_READABLE);
pub const GET_EVENT_INDICATORS: Function = me("fmi3GetEventIndicators", STATES_READABLE);
pub const GET_CONTINUOUS_STATES: Function = me("fmi3GetContinuousStates", STATES_READABLE);
pub const GET_NOMINALS_OF_CONTINUOUS_STATES: Function =
    me("fmi3GetNominalsOfContinuousStates", STATES_READABLE);
pub const GET_NUMBER_OF_EVENT_INDICATORS: Function = me("fmi3GetNumberOfEventIndicators", LIVE);
pub const GET_NUMBER_OF_CONTINUOUS_STATES: Function = me("fmi3GetNumberOfContinuousStates", LIVE);

// Co-Simulation only (section 4.2).
pub const ENTER_STEP_MODE: Function = cs("fmi3EnterStepMode", mask(&[S::EventMode]));
pub const GET_OUTPUT_DERIVATIVES: Function = cs(
    "fmi3GetOutputDerivatives",
    mask(&[S::StepComplete, S::StepFailed, S::Terminated, S::Error]),
);
pub const DO_STEP: Function = cs("fmi3DoStep", mask(&[S::StepComplete]));

// Scheduled Execution (chapter 5): never instantiated here.
pub const ACTIVATE_MODEL_PARTITION: Function = f("fmi3ActivateModelPartition", LIVE);
