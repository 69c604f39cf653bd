//! The co-simulation instance's state machine: FMI 2.0.5, section 4.2.4, the table of which
//! function may be called in which state.

/// A state of the co-simulation state machine.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u16)]
pub enum ModelState {
    Instantiated = 1 << 0,
    InitializationMode = 1 << 1,
    StepComplete = 1 << 2,
    StepInProgress = 1 << 3,
    StepFailed = 1 << 4,
    StepCanceled = 1 << 5,
    Terminated = 1 << 6,
    Error = 1 << 7,
    Fatal = 1 << 8,
}

impl ModelState {
    pub fn name(self) -> &'static str {
        match self {
            ModelState::Instantiated => "instantiated",
            ModelState::InitializationMode => "in initialization mode",
            ModelState::StepComplete => "step complete",
            ModelState::StepInProgress => "step in progress",
            ModelState::StepFailed => "step failed",
            ModelState::StepCanceled => "step canceled",
            ModelState::Terminated => "terminated",
            ModelState::Error => "in the error state",
            ModelState::Fatal => "in the fatal state",
        }
    }
}

/// The set of states in which a function may be called.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct StateMask(u16);

use ModelState as S;

const fn mask(states: &[ModelState]) -> StateMask {
    let mut bits = 0;
    let mut i = 0;
    while i < states.len() {
        bits |= states[i] as u16;
        i += 1;
    }
    StateMask(bits)
}

impl StateMask {
    pub fn contains(self, state: ModelState) -> bool {
        self.0 & state as u16 != 0
    }
}

/// One FMI function: its name (for messages) and the states it may be called in.
#[derive(Clone, Copy, Debug)]
pub struct Function {
    pub name: &'static str,
    pub allowed: StateMask,
}

const fn f(name: &'static str, allowed: StateMask) -> Function {
    Function { name, allowed }
}

// The rows of the table. "Any state with an instance but fatal" recurs:
const LIVE: StateMask = mask(&[
    S::Instantiated,
    S::InitializationMode,
    S::StepComplete,
    S::StepInProgress,
    S::StepFailed,
    S::StepCanceled,
    S::Terminated,
    S::Error,
]);
const FREEABLE: StateMask = mask(&[
    S::Instantiated,
    S::InitializationMode,
    S::StepComplete,
    S::StepFailed,
    S::StepCanceled,
    S::Terminated,
    S::Error,
]);
const READABLE: StateMask = mask(&[
    S::InitializationMode,
    S::StepComplete,
    S::StepFailed,
    S::StepCanceled,
    S::Terminated,
    S::Error,
]);
const WRITABLE: StateMask = mask(&[S::Instantiated, S::InitializationMode, S::StepComplete]);
const STATUS: StateMask = mask(&[
    S::StepComplete,
    S::StepInProgress,
    S::StepFailed,
    S::StepCanceled,
    S::Terminated,
]);

pub const SET_DEBUG_LOGGING: Function = f("fmi2SetDebugLogging", LIVE);
pub const FREE_INSTANCE: Function = f("fmi2FreeInstance", FREEABLE);
pub const SETUP_EXPERIMENT: Function = f("fmi2SetupExperiment", mask(&[S::Instantiated]));
pub const ENTER_INITIALIZATION_MODE: Function =
    f("fmi2EnterInitializationMode", mask(&[S::Instantiated]));
pub const EXIT_INITIALIZATION_MODE: Function =
    f("fmi2ExitInitializationMode", mask(&[S::InitializationMode]));
pub const TERMINATE: Function = f(
    "fmi2Terminate",
    mask(&[S::StepComplete, S::StepFailed, S::StepCanceled]),
);
pub const RESET: Function = f("fmi2Reset", FREEABLE);
pub const GET_REAL: Function = f("fmi2GetReal", READABLE);
pub const GET_INTEGER: Function = f("fmi2GetInteger", READABLE);
pub const GET_BOOLEAN: Function = f("fmi2GetBoolean", READABLE);
pub const GET_STRING: Function = f("fmi2GetString", READABLE);
pub const SET_REAL: Function = f("fmi2SetReal", WRITABLE);
pub const SET_INTEGER: Function = f("fmi2SetInteger", WRITABLE);
pub const SET_BOOLEAN: Function = f("fmi2SetBoolean", WRITABLE);
pub const SET_STRING: Function = f("fmi2SetString", WRITABLE);
pub const GET_FMU_STATE: Function = f("fmi2GetFMUstate", FREEABLE);
pub const SET_FMU_STATE: Function = f("fmi2SetFMUstate", FREEABLE);
pub const FREE_FMU_STATE: Function = f("fmi2FreeFMUstate", FREEABLE);
pub const SERIALIZED_FMU_STATE_SIZE: Function = f("fmi2SerializedFMUstateSize", FREEABLE);
pub const SERIALIZE_FMU_STATE: Function = f("fmi2SerializeFMUstate", FREEABLE);
pub const DESERIALIZE_FMU_STATE: Function = f("fmi2DeSerializeFMUstate", FREEABLE);
pub const GET_DIRECTIONAL_DERIVATIVE: Function = f("fmi2GetDirectionalDerivative", READABLE);
pub const SET_REAL_INPUT_DERIVATIVES: Function = f("fmi2SetRealInputDerivatives", WRITABLE);
pub const GET_REAL_OUTPUT_DERIVATIVES: Function = f(
    "fmi2GetRealOutputDerivatives",
    mask(&[
        S::StepComplete,
        S::StepFailed,
        S::StepCanceled,
        S::Terminated,
        S::Error,
    ]),
);
pub const DO_STEP: Function = f("fmi2DoStep", mask(&[S::StepComplete]));
pub const CANCEL_STEP: Function = f("fmi2CancelStep", mask(&[S::StepInProgress]));
pub const GET_STATUS: Function = f("fmi2GetStatus", STATUS);
pub const GET_REAL_STATUS: Function = f("fmi2GetRealStatus", STATUS);
pub const GET_INTEGER_STATUS: Function = f("fmi2GetIntegerStatus", STATUS);
pub const GET_BOOLEAN_STATUS: Function = f("fmi2GetBooleanStatus", STATUS);
pub const GET_STRING_STATUS: Function = f("fmi2GetStringStatus", STATUS);
