//! The oracle's model of an instance: its interface type, the state of the standard's
//! state machine it is in, what it was set up with, and what the importer knows of its
//! continuous states; the FMU states it saved and the targets of a call.

use crate::ffi::{CallbackFunctions, Component, FmuState};
use crate::importer::Sink;
use std::ffi::CString;

/// What an instance was instantiated as.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    ModelExchange,
    CoSimulation,
}

impl Kind {
    pub fn name(self) -> &'static str {
        match self {
            Kind::ModelExchange => "Model Exchange",
            Kind::CoSimulation => "Co-Simulation",
        }
    }
    /// The state initialization ends in (FMI 2.0; FMI 3.0 without event mode).
    pub fn initialized(self) -> St {
        match self {
            Kind::ModelExchange => St::EventMode,
            Kind::CoSimulation => St::StepComplete,
        }
    }
}

/// The states of the standards' state machines (FMI 2.0: Co-Simulation, section 4.2.4,
/// and Model Exchange, section 3.2.3; FMI 3.0: section 2.3, its Step Mode is
/// `StepComplete`, a step that ended the simulation leaves `StepFailed`), in the order of
/// the bits of the runtime's serialized state field.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum St {
    Instantiated,
    Init,
    StepComplete,
    StepInProgress,
    StepFailed,
    StepCanceled,
    Terminated,
    Error,
    Fatal,
    EventMode,
    ContinuousTimeMode,
}

pub const ALL_STATES: [St; 11] = [
    St::Instantiated,
    St::Init,
    St::StepComplete,
    St::StepInProgress,
    St::StepFailed,
    St::StepCanceled,
    St::Terminated,
    St::Error,
    St::Fatal,
    St::EventMode,
    St::ContinuousTimeMode,
];

impl St {
    /// The interface type only whose FMI 2.0 machine has this state (`None`: both have
    /// it).
    pub fn kind(self) -> Option<Kind> {
        match self {
            St::EventMode | St::ContinuousTimeMode => Some(Kind::ModelExchange),
            St::StepComplete | St::StepInProgress | St::StepFailed | St::StepCanceled => {
                Some(Kind::CoSimulation)
            }
            _ => None,
        }
    }
}

/// What an FMU state captured, as far as the oracle needs it.
#[derive(Clone, Copy, Debug)]
pub struct Snap {
    pub st: St,
    pub time: f64,
    pub stop: Option<f64>,
    /// The interface type of the instance that saved it (from the serialized flags when
    /// the oracle read it from bytes).
    pub kind: Kind,
    /// Saved by the other standard's functions (FMI 3.0 sequences only).
    pub other_standard: bool,
    /// Read from bytes this sequence did not serialize itself (edited, forged).
    pub forged: bool,
}

/// An FMU state handle of the sequence and what it holds.
pub struct Handle {
    pub ptr: FmuState,
    pub snap: Snap,
}

/// One live instance and the oracle's model of it.
pub struct Inst {
    pub c: Component,
    pub sink: Box<Sink>,
    /// FMI 2.0's callbacks (they must outlive the instance).
    pub _callbacks: Option<Box<CallbackFunctions>>,
    pub _name: CString,
    /// Messages can be checked (a logger and our environment were given).
    pub logs: bool,
    pub kind: Kind,
    pub st: St,
    pub time: f64,
    pub stop: Option<f64>,
    pub categories: [bool; 5],
    /// FMI 3.0 Co-Simulation: instantiated with `eventModeUsed`, `earlyReturnAllowed`.
    pub event_mode_used: bool,
    pub early_return_allowed: bool,
    /// Model Exchange: the continuous states and derivatives last read (empty: unknown).
    pub x: Vec<f64>,
    pub dx: Vec<f64>,
    /// The states last given to SetContinuousStates, while nothing else can have changed
    /// them: GetContinuousStates must return them bit for bit.
    pub x_set: Option<Vec<f64>>,
    /// CompletedIntegratorStep asked for an event.
    pub event_requested: bool,
}

impl Inst {
    pub fn new(c: Component, sink: Box<Sink>, name: CString, logs: bool, kind: Kind) -> Inst {
        Inst {
            c,
            sink,
            _callbacks: None,
            _name: name,
            logs,
            kind,
            st: St::Instantiated,
            time: 0.0,
            stop: None,
            categories: [true; 5],
            event_mode_used: false,
            early_return_allowed: false,
            x: vec![],
            dx: vec![],
            x_set: None,
            event_requested: false,
        }
    }

    /// What an FMU state saved now captures.
    pub fn snap(&self) -> Snap {
        Snap {
            st: self.st,
            time: self.time,
            stop: self.stop,
            kind: self.kind,
            other_standard: false,
            forged: false,
        }
    }

    /// Restored from `snap`: what the importer knew of the states is gone.
    pub fn restore(&mut self, snap: &Snap) {
        self.st = snap.st;
        self.time = snap.time;
        self.stop = snap.stop;
        self.x.clear();
        self.dx.clear();
        self.event_requested = false;
    }

    /// Reset: Instantiated at time 0 again, what the importer knew of the states gone.
    pub fn reset(&mut self) {
        self.restore(&Snap {
            st: St::Instantiated,
            time: 0.0,
            stop: None,
            ..self.snap()
        });
    }

    /// In event mode (an event requested before is being handled).
    pub fn enter_event_mode(&mut self) {
        self.st = St::EventMode;
        self.event_requested = false;
    }
}

/// A call about to be made: the function (its index in the standard's table), the
/// instance it is made on, and whether the oracle's state machine allows it there.
#[derive(Clone, Copy, Debug)]
pub struct Call {
    function: usize,
    target: Target,
    c: Component,
    legal: bool,
}

impl Call {
    pub fn new(function: usize, target: Target, c: Component, legal: bool) -> Call {
        Call {
            function,
            target,
            c,
            legal,
        }
    }

    /// The function, target, instance pointer and legality, to bind by name.
    pub fn parts(self) -> (usize, Target, Component, bool) {
        (self.function, self.target, self.c, self.legal)
    }
}

/// The instance a call is made on.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
pub enum Target {
    Live(usize),
    Null,
    /// A pointer to memory that is not an instance (zeros or noise).
    Foreign,
    /// A live instance's pointer plus one byte.
    Misaligned,
    /// A live instance of the other standard, made by the same binary.
    OtherStandard,
}
