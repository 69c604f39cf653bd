//! The state machines of an instance: FMI 2.0.5, section 3.2.3 (Model Exchange) and section
//! 4.2.4 (Co-Simulation), the tables of which function may be called in which state.
//!
//! Both machines share the states before initialization ends and after it (Instantiated,
//! InitializationMode, Terminated, Error, Fatal); the states between are Model Exchange's
//! (EventMode, ContinuousTimeMode) or Co-Simulation's (StepComplete, ...), never both. So
//! one mask per function serves both tables, and a function of one interface type only
//! says so ([`Function::interface`]): an instance of the other type is refused it in every
//! state.

/// A state of either state machine.
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
    EventMode = 1 << 9,
    ContinuousTimeMode = 1 << 10,
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
            ModelState::EventMode => "in event mode",
            ModelState::ContinuousTimeMode => "in continuous-time mode",
        }
    }

    /// The interface type whose own state this is (`None`: a state both machines have).
    pub fn interface(self) -> Option<Interface> {
        match self {
            S::EventMode | S::ContinuousTimeMode => Some(Interface::ModelExchange),
            S::StepComplete | S::StepInProgress | S::StepFailed | S::StepCanceled => {
                Some(Interface::CoSimulation)
            }
            _ => None,
        }
    }
}

/// What an instance was instantiated as (`fmuType`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interface {
    ModelExchange,
    CoSimulation,
}

impl Interface {
    pub fn name(self) -> &'static str {
        match self {
            Interface::ModelExchange => "Model Exchange",
            Interface::CoSimulation => "Co-Simulation",
        }
    }

    /// The state an instance goes to when its initialization ends.
    pub fn initialized(self) -> ModelState {
        match self {
            Interface::ModelExchange => ModelState::EventMode,
            Interface::CoSimulation => ModelState::StepComplete,
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

/// One FMI function: its name (for messages), the states it may be called in, and the
/// interface type it belongs to (`None`: both).
#[derive(Clone, Copy, Debug)]
pub struct Function {
    pub name: &'static str,
    pub allowed: StateMask,
    pub interface: Option<Interface>,
}

impl Function {
    /// Whether an instance of `interface` in `state` may call it.
    #[inline(always)]
    pub fn allows(&self, interface: Interface, state: ModelState) -> bool {
        self.allowed.contains(state) && self.interface.is_none_or(|i| i == interface)
    }
}

/// A function of both interface types.
const fn f(name: &'static str, allowed: StateMask) -> Function {
    Function {
        name,
        allowed,
        interface: None,
    }
}

/// A function of Model Exchange only.
const fn me(name: &'static str, allowed: StateMask) -> Function {
    Function {
        name,
        allowed,
        interface: Some(Interface::ModelExchange),
    }
}

/// A function of Co-Simulation only.
const fn cs(name: &'static str, allowed: StateMask) -> Function {
    Function {
        name,
        allowed,
        interface: Some(Interface::CoSimulation),
    }
}

// The rows of the tables. "Any state with an instance but fatal" recurs:
const LIVE: StateMask = mask(&[
    S::Instantiated,
    S::InitializationMode,
    S::EventMode,
    S::ContinuousTimeMode,
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
    S::EventMode,
    S::ContinuousTimeMode,
    S::StepComplete,
    S::StepFailed,
    S::StepCanceled,
    S::Terminated,
    S::Error,
]);
const READABLE: StateMask = mask(&[
    S::InitializationMode,
    S::EventMode,
    S::ContinuousTimeMode,
    S::StepComplete,
    S::StepFailed,
    S::StepCanceled,
    S::Terminated,
    S::Error,
]);
const WRITABLE: StateMask = mask(&[
    S::Instantiated,
    S::InitializationMode,
    S::EventMode,
    S::ContinuousTimeMode,
    S::StepComplete,
]);
const STATUS: StateMask = mask(&[
    S::StepComplete,
    S::StepInProgress,
    S::StepFailed,
    S::StepCanceled,
    S::Terminated,
]);
/// Model Exchange, once initialized and not yet terminated.
const RUNNING_ME: StateMask = mask(&[S::EventMode, S::ContinuousTimeMode]);
/// Where the continuous states and event indicators may be read.
const STATES_READABLE: StateMask = mask(&[
    S::InitializationMode,
    S::EventMode,
    S::ContinuousTimeMode,
    S::Terminated,
    S::Error,
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
/// Not in continuous-time mode: only continuous Real inputs may change there.
const WRITABLE_DISCRETE: StateMask = mask(&[
    S::Instantiated,
    S::InitializationMode,
    S::EventMode,
    S::StepComplete,
]);
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
