//! The states of an instance and the rows of a state table: which function may be called
//! in which state. Each standard's table is written in its layer (`fmi2::state`,
//! `fmi3::state`) with these.
//!
//! The machines of both interface types share the states before initialization ends and
//! after it (Instantiated, InitializationMode, Terminated, Error, Fatal); the states between
//! are Model Exchange's (ContinuousTimeMode), Co-Simulation's (StepComplete, which FMI 3.0
//! calls Step Mode, ...) or, in FMI 3.0, both's (EventMode). So one mask per function
//! serves both interface types' tables, and a function of one interface type only says so
//! ([`Function::interface`]): an instance of the other type is refused it in every state.

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

    /// Every state, in the order of their bits.
    pub const ALL: [ModelState; 11] = [
        S::Instantiated,
        S::InitializationMode,
        S::StepComplete,
        S::StepInProgress,
        S::StepFailed,
        S::StepCanceled,
        S::Terminated,
        S::Error,
        S::Fatal,
        S::EventMode,
        S::ContinuousTimeMode,
    ];
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

use super::Version;
use ModelState as S;

pub const fn mask(states: &[ModelState]) -> StateMask {
    let mut bits = 0;
    let mut i = 0;
    while i < states.len() {
        bits |= states[i] as u16;
        i += 1;
    }
    StateMask(bits)
}

/// Every state but `excluded`.
pub const fn all_but(excluded: &[ModelState]) -> StateMask {
    StateMask(mask(&ModelState::ALL).0 & !mask(excluded).0)
}

impl StateMask {
    pub fn contains(self, state: ModelState) -> bool {
        self.0 & state as u16 != 0
    }
}

// The rows both standards' tables share.
pub const WRITABLE: StateMask = mask(&[
    S::Instantiated,
    S::InitializationMode,
    S::EventMode,
    S::ContinuousTimeMode,
    S::StepComplete,
]);
/// Not in continuous-time mode: only continuous inputs may change there.
pub const WRITABLE_DISCRETE: StateMask = mask(&[
    S::Instantiated,
    S::InitializationMode,
    S::EventMode,
    S::StepComplete,
]);
/// Where the continuous states and event indicators may be read.
pub const STATES_READABLE: StateMask = mask(&[
    S::InitializationMode,
    S::EventMode,
    S::ContinuousTimeMode,
    S::Terminated,
    S::Error,
]);

/// One FMI function: its standard and name (for messages), the states it may be called
/// in, and the interface type it belongs to (`None`: both).
#[derive(Clone, Copy, Debug)]
pub struct Function {
    pub version: Version,
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
pub const fn f(version: Version, name: &'static str, allowed: StateMask) -> Function {
    Function {
        version,
        name,
        allowed,
        interface: None,
    }
}

/// A function of Model Exchange only.
pub const fn me(version: Version, name: &'static str, allowed: StateMask) -> Function {
    Function {
        interface: Some(Interface::ModelExchange),
        ..f(version, name, allowed)
    }
}

/// A function of Co-Simulation only.
pub const fn cs(version: Version, name: &'static str, allowed: StateMask) -> Function {
    Function {
        interface: Some(Interface::CoSimulation),
        ..f(version, name, allowed)
    }
}

/// `f`, `me` and `cs` of one standard, for the rows of its table.
macro_rules! row_constructors {
    ($version:expr) => {
        const fn f(name: &'static str, allowed: StateMask) -> Function {
            $crate::fmi::machine::f($version, name, allowed)
        }
        const fn me(name: &'static str, allowed: StateMask) -> Function {
            $crate::fmi::machine::me($version, name, allowed)
        }
        const fn cs(name: &'static str, allowed: StateMask) -> Function {
            $crate::fmi::machine::cs($version, name, allowed)
        }
    };
}
pub(crate) use row_constructors;
