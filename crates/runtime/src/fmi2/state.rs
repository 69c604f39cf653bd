//! The state machines of FMI 2.0: section 3.2.3 (Model Exchange) and section 4.2.4
//! (Co-Simulation) of FMI 2.0.5, the tables of which function may be called in which
//! state, one row per function (see [`machine`](crate::fmi::machine)).

use crate::fmi::machine::{
    all_but, mask, row_constructors, STATES_READABLE, WRITABLE, WRITABLE_DISCRETE,
};
pub use crate::fmi::machine::{Function, Interface, ModelState, StateMask};
use crate::fmi::Version::Fmi2;
use ModelState as S;

row_constructors!(Fmi2);

// The rows of the tables. "Any state with an instance but fatal" recurs:
const LIVE: StateMask = all_but(&[S::Fatal]);
const FREEABLE: StateMask = all_but(&[S::Fatal, S::StepInProgress]);
const READABLE: StateMask = all_but(&[S::Fatal, S::StepInProgress, S::Instantiated]);
const STATUS: StateMask = mask(&[
    S::StepComplete,
    S::StepInProgress,
    S::StepFailed,
    S::StepCanceled,
    S::Terminated,
]);
/// Model Exchange, once initialized and not yet terminated.
const RUNNING_ME: StateMask = mask(&[S::EventMode, S::ContinuousTimeMode]);

pub const SET_DEBUG_LOGGING: Function = f("fmi2SetDebugLogging", LIVE);
pub const FREE_INSTANCE: Function = f("fmi2FreeInstance", FREEABLE);
pub const SETUP_EXPERIMENT: Function = f("fmi2SetupExperiment", mask(&[S::Instantiated]));
pub const ENTER_INITIALIZATION_MODE: Function =
    f("fmi2EnterInitializationMode", mask(&[S::Instantiated]));
pub const EXIT_INITIALIZATION_MODE: Function =
    f("fmi2ExitInitializationMode", mask(&[S::InitializationMode]));
pub const TERMINATE: Function = f(
    "fmi2Terminate",
    mask(&[
        S::EventMode,
        S::ContinuousTimeMode,
        S::StepComplete,
        S::StepFailed,
        S::StepCanceled,
    ]),
);
pub const RESET: Function = f("fmi2Reset", FREEABLE);
pub const GET_REAL: Function = f("fmi2GetReal", READABLE);
pub const GET_INTEGER: Function = f("fmi2GetInteger", READABLE);
pub const GET_BOOLEAN: Function = f("fmi2GetBoolean", READABLE);
pub const GET_STRING: Function = f("fmi2GetString", READABLE);
pub const SET_REAL: Function = f("fmi2SetReal", WRITABLE);
pub const SET_INTEGER: Function = f("fmi2SetInteger", WRITABLE_DISCRETE);
pub const SET_BOOLEAN: Function = f("fmi2SetBoolean", WRITABLE_DISCRETE);
pub const SET_STRING: Function = f("fmi2SetString", WRITABLE_DISCRETE);
pub const GET_FMU_STATE: Function = f("fmi2GetFMUstate", FREEABLE);
pub const SET_FMU_STATE: Function = f("fmi2SetFMUstate", FREEABLE);
pub const FREE_FMU_STATE: Function = f("fmi2FreeFMUstate", FREEABLE);
pub const SERIALIZED_FMU_STATE_SIZE: Function = f("fmi2SerializedFMUstateSize", FREEABLE);
pub const SERIALIZE_FMU_STATE: Function = f("fmi2SerializeFMUstate", FREEABLE);
pub const DESERIALIZE_FMU_STATE: Function = f("fmi2DeSerializeFMUstate", FREEABLE);
pub const GET_DIRECTIONAL_DERIVATIVE: Function = f("fmi2GetDirectionalDerivative", READABLE);

// Model Exchange only (section 3.2.3).
pub const ENTER_EVENT_MODE: Function = me("fmi2EnterEventMode", RUNNING_ME);
pub const NEW_DISCRETE_STATES: Function = me("fmi2NewDiscreteStates", mask(&[S::EventMode]));
pub const ENTER_CONTINUOUS_TIME_MODE: Function =
    me("fmi2EnterContinuousTimeMode", mask(&[S::EventMode]));
pub const COMPLETED_INTEGRATOR_STEP: Function = me(
    "fmi2CompletedIntegratorStep",
    mask(&[S::ContinuousTimeMode]),
);
pub const SET_TIME: Function = me("fmi2SetTime", RUNNING_ME);
pub const SET_CONTINUOUS_STATES: Function =
    me("fmi2SetContinuousStates", mask(&[S::ContinuousTimeMode]));
pub const GET_EVENT_INDICATORS: Function = me("fmi2GetEventIndicators", STATES_READABLE);
pub const GET_CONTINUOUS_STATES: Function = me("fmi2GetContinuousStates", STATES_READABLE);
pub const GET_DERIVATIVES: Function = me(
    "fmi2GetDerivatives",
    mask(&[S::EventMode, S::ContinuousTimeMode, S::Terminated, S::Error]),
);
pub const GET_NOMINALS_OF_CONTINUOUS_STATES: Function = me(
    "fmi2GetNominalsOfContinuousStates",
    mask(&[
        S::Instantiated,
        S::EventMode,
        S::ContinuousTimeMode,
        S::Terminated,
        S::Error,
    ]),
);

// Co-Simulation only (section 4.2.4).
pub const SET_REAL_INPUT_DERIVATIVES: Function = cs(
    "fmi2SetRealInputDerivatives",
    mask(&[S::Instantiated, S::InitializationMode, S::StepComplete]),
);
pub const GET_REAL_OUTPUT_DERIVATIVES: Function = cs(
    "fmi2GetRealOutputDerivatives",
    mask(&[
        S::StepComplete,
        S::StepFailed,
        S::StepCanceled,
        S::Terminated,
        S::Error,
    ]),
);
pub const DO_STEP: Function = cs("fmi2DoStep", mask(&[S::StepComplete]));
pub const CANCEL_STEP: Function = cs("fmi2CancelStep", mask(&[S::StepInProgress]));
pub const GET_STATUS: Function = cs("fmi2GetStatus", STATUS);
pub const GET_REAL_STATUS: Function = cs("fmi2GetRealStatus", STATUS);
pub const GET_INTEGER_STATUS: Function = cs("fmi2GetIntegerStatus", STATUS);
pub const GET_BOOLEAN_STATUS: Function = cs("fmi2GetBooleanStatus", STATUS);
pub const GET_STRING_STATUS: Function = cs("fmi2GetStringStatus", STATUS);
