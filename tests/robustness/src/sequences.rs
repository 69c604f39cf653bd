//! Random FMI call sequences with hostile arguments, checked against an oracle.
//!
//! A sequence instantiates one or two instances, each for Model Exchange or Co-Simulation
//! (when the FMU declares both), and makes random calls of all 44 functions: half of them
//! chosen among those the standard allows in the instance's state and interface type (so
//! sequences get deep: initialized, stepping or integrating, in event mode, failed,
//! restored), half among all (so the other interface type's functions are called too),
//! with arguments drawn from sane and hostile values (NULL instance and array pointers,
//! foreign pointers to memory that is not an instance, value references out of range,
//! NaN/±inf/huge values, bad step sizes and communication points, huge or non-finite
//! times, state and derivative arrays of the wrong length, FMU states of this instance and
//! of the other one (of the other interface type too), serialized bytes that are valid,
//! corrupted, random, or corrupted with a repaired checksum). A Model Exchange instance in
//! continuous-time mode is also driven as an importer's integrator would: explicit Euler
//! steps through fmi2GetContinuousStates, fmi2GetDerivatives, fmi2SetTime,
//! fmi2SetContinuousStates, fmi2CompletedIntegratorStep and fmi2GetEventIndicators.
//!
//! The oracle keeps its own copy of the standard's state machines (sections 3.2.3 and
//! 4.2.4) and checks after every call:
//! - the status is one the standard allows for the function (never fmi2Fatal/fmi2Pending,
//!   fmi2Discard only from fmi2DoStep, the status getters, fmi2GetDerivatives and
//!   fmi2GetEventIndicators);
//! - a call the state table forbids returns fmi2Error and says "illegal call sequence"; a
//!   function of the other interface type returns fmi2Error and names the interface type;
//!   an FMU state saved in a state only the other interface type has (event mode,
//!   continuous-time mode; step complete, step failed) is refused with fmi2Error;
//! - every status other than fmi2OK comes with a logged message of that status (when the
//!   importer gave a logger and has not switched that category off);
//! - the logger is always called with "%s", a declared category and UTF-8 text, and no
//!   message reports a caught panic ("internal error");
//! - no NaN is returned after fmi2OK (values, directional and output derivatives,
//!   statuses), and nothing that is not finite from fmi2GetDerivatives,
//!   fmi2GetEventIndicators, fmi2GetContinuousStates and
//!   fmi2GetNominalsOfContinuousStates (nominals > 0); nothing is written past the
//!   elements of an output array;
//! - Model Exchange arrays: a wrong `nx`/`ni`, a NULL array or non-finite states given to
//!   fmi2SetContinuousStates return fmi2Error; finite states of the right number are
//!   accepted and fmi2GetContinuousStates returns them bit for bit; what
//!   fmi2GetContinuousStates and fmi2GetDerivatives return is what fmi2GetReal returns
//!   for the state and derivative variables; fmi2SetTime accepts a finite time and
//!   refuses any other; fmi2SetReal in continuous-time mode accepts continuous inputs
//!   only; fmi2NewDiscreteStates and fmi2CompletedIntegratorStep fill their fmi2Boolean
//!   outputs with fmi2True/fmi2False (and refuse NULL pointers);
//! - after fmi2DoStep returns fmi2OK the values are not NaN; after fmi2Discard,
//!   fmi2Terminated is true and fmi2LastSuccessfulTime lies in the step;
//! - every instance can be freed at the end (no state the instance cannot leave);
//! - allocateMemory/freeMemory/stepFinished are never called (they abort the process).

use crate::ffi::*;
use crate::fmu::{Fmu, Var};
use crate::importer::{callbacks, Sink};
use crate::rng::Rng;
use std::ffi::{c_char, CString};
use std::fmt::Write as _;

/// Index of each function in [`FUNCTION_NAMES`].
mod f {
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
    pub fn co_simulation_only(function: usize) -> bool {
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
    pub fn model_exchange_only(function: usize) -> bool {
        (ENTER_EVENT_MODE..COUNT).contains(&function)
    }
}

/// What an instance was instantiated as.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    ModelExchange,
    CoSimulation,
}

impl Kind {
    fn name(self) -> &'static str {
        match self {
            Kind::ModelExchange => "Model Exchange",
            Kind::CoSimulation => "Co-Simulation",
        }
    }
    /// The state initialization ends in.
    fn initialized(self) -> St {
        match self {
            Kind::ModelExchange => St::EventMode,
            Kind::CoSimulation => St::StepComplete,
        }
    }
}

/// The states of the standard's state machines (Co-Simulation, section 4.2.4, and Model
/// Exchange, section 3.2.3), in the order of the bits of the runtime's serialized state
/// field.
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

const ALL_STATES: [St; 11] = [
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
    /// The interface type only whose machine has this state (`None`: both have it).
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
fn status_allowed(function: usize, s: Status) -> bool {
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

fn category_index(s: Status) -> usize {
    match s {
        OK => 0,
        WARNING => 1,
        DISCARD => 2,
        ERROR => 3,
        _ => 4,
    }
}

/// What an FMU state captured, as far as the oracle needs it.
#[derive(Clone, Copy, Debug)]
struct Snap {
    st: St,
    time: f64,
    stop: Option<f64>,
}

struct Handle {
    ptr: FmuState,
    snap: Snap,
}

/// One live instance and the oracle's model of it.
struct Inst {
    c: Component,
    sink: Box<Sink>,
    _callbacks: Box<CallbackFunctions>,
    _name: CString,
    /// Messages can be checked (a logger and our environment were given).
    logs: bool,
    kind: Kind,
    st: St,
    time: f64,
    stop: Option<f64>,
    categories: [bool; 5],
    /// Model Exchange: the continuous states and derivatives last read (empty: unknown).
    x: Vec<f64>,
    dx: Vec<f64>,
    /// The states last given to fmi2SetContinuousStates, while nothing else can have
    /// changed them: fmi2GetContinuousStates must return them bit for bit.
    x_set: Option<Vec<f64>>,
    /// fmi2CompletedIntegratorStep asked for an event.
    event_requested: bool,
}

impl Inst {
    fn new(
        c: Component,
        sink: Box<Sink>,
        callbacks: Box<CallbackFunctions>,
        name: CString,
        logs: bool,
        kind: Kind,
        categories: [bool; 5],
    ) -> Inst {
        Inst {
            c,
            sink,
            _callbacks: callbacks,
            _name: name,
            logs,
            kind,
            st: St::Instantiated,
            time: 0.0,
            stop: None,
            categories,
            x: vec![],
            dx: vec![],
            x_set: None,
            event_requested: false,
        }
    }
}

/// Counts over a run.
#[derive(Clone, Debug, Default)]
pub struct Stats {
    pub sequences: u64,
    pub calls: u64,
    pub statuses: [u64; 6],
    pub steps_ok: u64,
    pub steps_discarded: u64,
    pub illegal_calls: u64,
    pub states_restored: u64,
    pub deserialized: u64,
    pub me_instances: u64,
    pub me_steps: u64,
    pub events: u64,
}

impl Stats {
    pub fn add(&mut self, o: &Stats) {
        self.sequences += o.sequences;
        self.calls += o.calls;
        for i in 0..6 {
            self.statuses[i] += o.statuses[i];
        }
        self.steps_ok += o.steps_ok;
        self.steps_discarded += o.steps_discarded;
        self.illegal_calls += o.illegal_calls;
        self.states_restored += o.states_restored;
        self.deserialized += o.deserialized;
        self.me_instances += o.me_instances;
        self.me_steps += o.me_steps;
        self.events += o.events;
    }
}

impl std::fmt::Display for Stats {
    fn fmt(&self, w: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(
            w,
            "{} sequences, {} calls (OK {}, Warning {}, Discard {}, Error {}), {} steps OK, {} discarded, {} illegal calls refused, {} states restored, {} deserialized, {} Model Exchange instances, {} integrator steps, {} event iterations",
            self.sequences,
            self.calls,
            self.statuses[0],
            self.statuses[1],
            self.statuses[2],
            self.statuses[3],
            self.steps_ok,
            self.steps_discarded,
            self.illegal_calls,
            self.states_restored,
            self.deserialized,
            self.me_instances,
            self.me_steps,
            self.events
        )
    }
}

/// The component a call is made on.
#[derive(Clone, Copy, PartialEq, Eq, Debug)]
enum Target {
    Live(usize),
    Null,
    /// A pointer to memory that is not an instance (zeros or noise).
    Foreign,
}

pub struct Sequence<'a> {
    fmu: &'a Fmu,
    rng: Rng,
    seed: u64,
    trace: bool,
    log: String,
    insts: Vec<Inst>,
    handles: Vec<Handle>,
    serialized: Vec<(Vec<u8>, Snap)>,
    zeros: Vec<u64>,
    noise: Vec<u64>,
    pub stats: Stats,
    failure: Option<String>,
    vars: Vec<Var>,
    vr_end: u32,
    /// The FMU declares Model Exchange.
    me: bool,
    /// Continuous states and event indicators, from the modelDescription.
    nx: usize,
    ni: usize,
    /// Arguments for an importer's integrator step (set by [`Sequence::me_step`]): its
    /// calls use these instead of hostile ones.
    sane: bool,
    /// The importer's integrator step size (Model Exchange).
    h_me: f64,
    /// The continuous states' start values (1 where none is declared).
    x_start: Vec<f64>,
    /// The value references of the states and of their derivatives, in the state vector's
    /// order.
    state_vrs: Vec<u32>,
    derivative_vrs: Vec<u32>,
    /// After the call: fmi2GetReal of these variables of this instance, if it succeeds,
    /// returns these values (what fmi2GetContinuousStates or fmi2GetDerivatives returned).
    same_as_variables: Option<(Component, Vec<u32>, Vec<f64>)>,
}

const SANE_NAMES: [&str; 4] = ["instance", "Oscillator", "x%s%n%d %p", "ünïcødé name"];

fn hostile_f64(rng: &mut Rng) -> f64 {
    *rng.pick(&[
        f64::NAN,
        -f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        0.0,
        -0.0,
        1e308,
        -1e308,
        f64::MAX,
        f64::MIN,
        f64::MIN_POSITIVE,
        5e-324,
        -5e-324,
        1e-300,
        -1.0,
        1.0,
        1e6,
        -1e6,
        1e15,
        1e-12,
    ])
}

impl<'a> Sequence<'a> {
    pub fn new(fmu: &'a Fmu, seed: u64, trace: bool) -> Sequence<'a> {
        let mut rng = Rng::new(seed);
        let noise = (0..8192).map(|_| rng.next_u64()).collect();
        Sequence {
            fmu,
            rng,
            seed,
            trace,
            log: String::new(),
            insts: vec![],
            handles: vec![],
            serialized: vec![],
            zeros: vec![0; 8192],
            noise,
            stats: Stats::default(),
            failure: None,
            vars: fmu.md.variables.clone(),
            vr_end: fmu.md.vr_end(),
            me: fmu.md.model_exchange.is_some(),
            nx: fmu.md.nx(),
            ni: fmu.md.number_of_event_indicators,
            sane: false,
            h_me: fmu.md.experiment.step / 4.0,
            x_start: fmu
                .md
                .states()
                .iter()
                .map(|v| v.start.unwrap_or(1.0))
                .collect(),
            state_vrs: fmu.md.states().iter().map(|v| v.vr).collect(),
            derivative_vrs: fmu.md.derivative_vars().iter().map(|v| v.vr).collect(),
            same_as_variables: None,
        }
    }

    fn note(&mut self, what: impl FnOnce() -> String) {
        if self.trace {
            let line = what();
            println!("  {line}");
        }
    }

    fn fail(&mut self, what: String) {
        if self.failure.is_none() {
            self.failure = Some(what);
        }
    }

    /// Runs the sequence; `Err` describes the first oracle violation.
    pub fn run(mut self) -> Result<Stats, String> {
        self.stats.sequences = 1;
        // The functions without an instance.
        self.check_platform();
        let long = self.rng.chance(0.1);
        let n_calls = 1 + self.rng.below(if long { 300 } else { 60 });
        self.instantiate();
        for _ in 0..n_calls {
            if self.failure.is_some() {
                break;
            }
            self.random_call();
        }
        if self.failure.is_none() {
            self.teardown();
        }
        let _ = &self.log;
        match self.failure.take() {
            None => Ok(self.stats.clone()),
            Some(f) => Err(format!("seed {}: {f}", self.seed)),
        }
    }

    fn check_platform(&mut self) {
        // SAFETY: no arguments.
        let (p, v) = unsafe {
            (
                (self.fmu.api.get_types_platform)(),
                (self.fmu.api.get_version)(),
            )
        };
        let s = |p: CStr| {
            // SAFETY: the FMU returns a static NUL-terminated string (NULL checked).
            (!p.is_null()).then(|| {
                unsafe { std::ffi::CStr::from_ptr(p) }
                    .to_string_lossy()
                    .into_owned()
            })
        };
        self.stats.calls += 2;
        if s(p).as_deref() != Some("default") || s(v).as_deref() != Some("2.0") {
            self.fail(format!(
                "fmi2GetTypesPlatform/fmi2GetVersion returned {:?}/{:?}",
                s(p),
                s(v)
            ));
        }
    }

    // -----------------------------------------------------------------------------------
    // Instances
    // -----------------------------------------------------------------------------------

    fn instantiate(&mut self) {
        if self.insts.len() >= 2 {
            return;
        }
        let sink = Box::<Sink>::default();
        let mut cb = Box::new(callbacks(&sink));
        let hostile = self.rng.chance(0.15);
        let mut expect_null = false;
        let mut logs = true;
        if self.rng.chance(0.05) {
            cb.logger = None;
            logs = false;
        } else if self.rng.chance(0.03) {
            cb.component_environment = std::ptr::null_mut();
            logs = false;
        }
        if self.rng.chance(0.5) {
            cb.allocate_memory = None;
            cb.free_memory = None;
            cb.step_finished = None;
        }
        let mut name_bytes: Vec<u8> = self.rng.pick(&SANE_NAMES).as_bytes().to_vec();
        if self.rng.chance(0.02) {
            name_bytes = "n".repeat(10_000).into_bytes();
        }
        let mut name_null = false;
        let mut guid = self.fmu.md.guid.clone();
        let mut guid_null = false;
        let mut fmu_type = if self.me && self.rng.chance(0.4) {
            MODEL_EXCHANGE
        } else {
            CO_SIMULATION
        };
        let mut callbacks_null = false;
        if hostile {
            expect_null = true;
            match self.rng.below(9) {
                0 => name_null = true,
                1 => name_bytes = vec![],
                2 => name_bytes = vec![b'a', 0xff, 0xfe],
                // Model Exchange is hostile only to an FMU that does not declare it.
                3 if !self.me => fmu_type = MODEL_EXCHANGE,
                3 => fmu_type = 2,
                4 => fmu_type = *self.rng.pick(&[2, 7, u32::MAX]),
                5 => guid_null = true,
                6 => {
                    guid = self
                        .rng
                        .pick(&["", "{00000000-0000-0000-0000-000000000000}", "garbage"])
                        .to_string()
                }
                7 => guid = guid.trim_matches(|c| c == '{' || c == '}').to_string(),
                _ => callbacks_null = true,
            }
        }
        let name = CString::new(name_bytes.clone()).expect("no NUL");
        let guid_c = CString::new(guid).expect("no NUL");
        let resources = match self.rng.below(3) {
            0 => None,
            1 => Some(CString::new("file:///tmp/mechfmu-robustness/resources/").unwrap()),
            _ => Some(CString::new("\u{1}garbage: not a URI %s").unwrap()),
        };
        let visible = *self.rng.pick(&[0, 1, 2, -1]);
        let logging_on = *self.rng.pick(&[0, 1, 1, 5, -1]);
        self.note(|| {
            format!(
                "fmi2Instantiate(name {:?}, type {fmu_type}, guid {}, callbacks {}, logger {}, loggingOn {logging_on})",
                if name_null { None } else { Some(String::from_utf8_lossy(&name_bytes).into_owned()) },
                if guid_null { "NULL".into() } else { format!("{:?}", guid_c) },
                if callbacks_null { "NULL" } else { "given" },
                logs
            )
        });
        // SAFETY: every pointer is NULL or valid for the call; the callbacks and the sink
        // outlive the instance (they move into `Inst`).
        let c = unsafe {
            (self.fmu.api.instantiate)(
                if name_null {
                    std::ptr::null()
                } else {
                    name.as_ptr()
                },
                fmu_type,
                if guid_null {
                    std::ptr::null()
                } else {
                    guid_c.as_ptr()
                },
                resources.as_ref().map_or(std::ptr::null(), |r| r.as_ptr()),
                if callbacks_null {
                    std::ptr::null()
                } else {
                    &*cb
                },
                visible,
                logging_on,
            )
        };
        self.stats.calls += 1;
        for v in sink.take_violations() {
            self.fail(format!("fmi2Instantiate: {v}"));
        }
        if expect_null {
            if !c.is_null() {
                self.fail(
                    "fmi2Instantiate accepted hostile arguments (returned an instance)".into(),
                );
                // SAFETY: the instance it returned.
                unsafe { (self.fmu.api.free_instance)(c) };
                return;
            }
            if logs && !callbacks_null && sink.is_empty() {
                self.fail("fmi2Instantiate refused its arguments without a logged message".into());
            }
            return;
        }
        if c.is_null() {
            let why = sink
                .all()
                .iter()
                .map(|m| m.text.clone())
                .collect::<Vec<_>>()
                .join("; ");
            self.fail(format!(
                "fmi2Instantiate failed with valid arguments: {why}"
            ));
            return;
        }
        let kind = if fmu_type == MODEL_EXCHANGE {
            self.stats.me_instances += 1;
            Kind::ModelExchange
        } else {
            Kind::CoSimulation
        };
        self.insts.push(Inst::new(
            c,
            sink,
            cb,
            name,
            logs,
            kind,
            [logging_on != 0, true, true, true, true],
        ));
    }

    /// A well-formed instance with a logger (for cleaning up).
    fn clean_instance(&mut self) {
        let sink = Box::<Sink>::default();
        let cb = Box::new(callbacks(&sink));
        let name = CString::new("cleanup").unwrap();
        let guid = CString::new(self.fmu.md.guid.as_str()).unwrap();
        // SAFETY: valid strings; callbacks and sink outlive the instance.
        let c = unsafe {
            (self.fmu.api.instantiate)(
                name.as_ptr(),
                CO_SIMULATION,
                guid.as_ptr(),
                std::ptr::null(),
                &*cb,
                0,
                0,
            )
        };
        self.stats.calls += 1;
        if c.is_null() {
            self.fail("fmi2Instantiate with valid arguments failed".into());
            return;
        }
        self.insts.push(Inst::new(
            c,
            sink,
            cb,
            name,
            true,
            Kind::CoSimulation,
            [false, true, true, true, true],
        ));
    }

    fn teardown(&mut self) {
        // Free every FMU state through a live instance, then the instances.
        if !self.handles.is_empty()
            && !self
                .insts
                .iter()
                .any(|i| allowed(f::FREE_FMU_STATE, i.kind, i.st))
        {
            // FMU states outlive the instance that made them: free them through a new one.
            self.clean_instance();
        }
        while let Some(h) = self.handles.pop() {
            let Some(i) = self
                .insts
                .iter()
                .position(|i| allowed(f::FREE_FMU_STATE, i.kind, i.st))
            else {
                self.fail(format!(
                    "cannot free an FMU state: every instance is in a state that forbids it ({:?})",
                    self.insts.iter().map(|i| i.st).collect::<Vec<_>>()
                ));
                return;
            };
            let mut slot = h.ptr;
            // SAFETY: a live handle and a valid slot.
            let s = unsafe { (self.fmu.api.free_fmu_state)(self.insts[i].c, &mut slot) };
            self.stats.calls += 1;
            if s != OK || !slot.is_null() {
                self.fail(format!(
                    "teardown: fmi2FreeFMUstate returned {}",
                    status_name(s)
                ));
                return;
            }
        }
        while let Some(inst) = self.insts.pop() {
            if !allowed(f::FREE_INSTANCE, inst.kind, inst.st) {
                self.fail(format!(
                    "the instance is in state {:?}, from which fmi2FreeInstance is not allowed: it can never be freed (a leak)",
                    inst.st
                ));
                // Leave it: freeing it would be an illegal call.
                std::mem::forget(inst);
                return;
            }
            // SAFETY: a live instance, freed once.
            unsafe { (self.fmu.api.free_instance)(inst.c) };
            self.stats.calls += 1;
            for v in inst.sink.take_violations() {
                self.fail(format!("fmi2FreeInstance: {v}"));
            }
        }
    }

    // -----------------------------------------------------------------------------------
    // Argument generators
    // -----------------------------------------------------------------------------------

    fn target(&mut self) -> (Target, Component) {
        let r = self.rng.unit();
        if self.insts.is_empty() || r < 0.04 {
            return (Target::Null, std::ptr::null_mut());
        }
        if r < 0.07 {
            let p = if self.rng.chance(0.5) {
                self.zeros.as_mut_ptr()
            } else {
                self.noise.as_mut_ptr()
            };
            return (Target::Foreign, p.cast());
        }
        let i = self.rng.below(self.insts.len());
        (Target::Live(i), self.insts[i].c)
    }

    fn vr(&mut self) -> u32 {
        if self.rng.chance(0.85) && self.vr_end > 0 {
            self.rng.below(self.vr_end as usize) as u32
        } else {
            *self
                .rng
                .pick(&[self.vr_end, self.vr_end + 1, 1000, 1 << 31, u32::MAX])
        }
    }

    fn vrs(&mut self) -> Vec<u32> {
        let n = match self.rng.below(10) {
            0 => 0,
            1..=6 => 1 + self.rng.below(4),
            7 | 8 => self.vr_end as usize + self.rng.below(4),
            _ => 1 + self.rng.below(64),
        };
        (0..n).map(|_| self.vr()).collect()
    }

    /// A value reference of a variable of the given kinds, if there is one.
    fn vr_where(&mut self, pred: impl Fn(&Var) -> bool) -> Option<u32> {
        let c: Vec<u32> = self.vars.iter().filter(|v| pred(v)).map(|v| v.vr).collect();
        (!c.is_empty()).then(|| *self.rng.pick(&c))
    }

    fn value_for(&mut self, vr: u32) -> f64 {
        if self.rng.chance(0.25) {
            return hostile_f64(&mut self.rng);
        }
        let var = self.vars.iter().find(|v| v.vr == vr);
        let start = var.and_then(|v| v.start).unwrap_or(1.0);
        let lo = var.and_then(|v| v.min);
        let x = start * (0.5 + self.rng.unit())
            + if self.rng.chance(0.3) {
                self.rng.unit() - 0.5
            } else {
                0.0
            };
        match lo {
            Some(lo) if x < lo => lo + self.rng.unit(),
            _ => x,
        }
    }

    fn ptr_or_null<T>(&mut self, v: &[T]) -> *const T {
        if self.rng.chance(0.04) {
            std::ptr::null()
        } else {
            v.as_ptr()
        }
    }

    // -----------------------------------------------------------------------------------
    // Calls
    // -----------------------------------------------------------------------------------

    fn random_call(&mut self) {
        if self.insts.is_empty() || self.rng.chance(0.01) {
            self.instantiate();
            return;
        }
        // Half the calls are legal in the instance's state (so sequences reach deep states).
        let i = self.rng.below(self.insts.len());
        // A quarter of the calls are what a normal importer would do next.
        if self.rng.chance(0.25) {
            let next = match self.insts[i].st {
                St::Instantiated if self.rng.chance(0.3) => f::SETUP_EXPERIMENT,
                St::Instantiated => f::ENTER_INIT,
                St::Init if self.rng.chance(0.2) => f::SET_REAL,
                St::Init => f::EXIT_INIT,
                St::StepComplete if self.rng.chance(0.15) => f::SET_REAL,
                St::StepComplete if self.rng.chance(0.05) => f::GET_FMU_STATE,
                St::StepComplete => f::DO_STEP,
                St::EventMode if self.rng.chance(0.35) => f::NEW_DISCRETE_STATES,
                St::EventMode if self.rng.chance(0.1) => f::SET_REAL,
                St::EventMode if self.rng.chance(0.05) => f::GET_FMU_STATE,
                St::EventMode => f::ENTER_CONTINUOUS_TIME_MODE,
                St::ContinuousTimeMode
                    if self.insts[i].event_requested || self.rng.chance(0.03) =>
                {
                    f::ENTER_EVENT_MODE
                }
                St::ContinuousTimeMode if self.rng.chance(0.05) => f::GET_FMU_STATE,
                St::ContinuousTimeMode if self.rng.chance(0.05) => f::SET_REAL,
                St::ContinuousTimeMode => {
                    self.me_step(i);
                    return;
                }
                _ if !self.handles.is_empty() && self.rng.chance(0.3) => f::SET_FMU_STATE,
                _ => f::RESET,
            };
            self.call(next);
            return;
        }
        let function = if self.rng.chance(0.5) {
            let (kind, st) = (self.insts[i].kind, self.insts[i].st);
            let legal: Vec<usize> = (0..f::COUNT)
                .filter(|&g| g != f::INSTANTIATE && allowed(g, kind, st))
                .flat_map(|g| {
                    // Weight the calls that move the simulation on.
                    let w = match g {
                        f::DO_STEP => 8,
                        f::GET_REAL | f::SET_REAL => 3,
                        f::EXIT_INIT | f::ENTER_INIT | f::SETUP_EXPERIMENT => 3,
                        f::SET_TIME | f::SET_CONTINUOUS_STATES | f::GET_DERIVATIVES => 3,
                        f::ENTER_CONTINUOUS_TIME_MODE => 3,
                        f::FREE_INSTANCE => 0,
                        _ => 1,
                    };
                    std::iter::repeat_n(g, w)
                })
                .collect();
            if legal.is_empty() {
                self.rng.below(f::COUNT)
            } else {
                *self.rng.pick(&legal)
            }
        } else {
            self.rng.below(f::COUNT)
        };
        self.call(function);
    }

    /// One explicit Euler step of an importer's integrator on Model Exchange instance `i`
    /// in continuous-time mode, each call checked as any other: the states and their
    /// derivatives, the time and states moved on, the step completed, sometimes the event
    /// indicators. Stops at the first call that does not succeed.
    fn me_step(&mut self, i: usize) {
        self.stats.me_steps += 1;
        self.sane = true;
        let (target, c) = (Target::Live(i), self.insts[i].c);
        let mut calls = vec![
            f::GET_CONTINUOUS_STATES,
            f::GET_DERIVATIVES,
            f::SET_TIME,
            f::SET_CONTINUOUS_STATES,
            f::COMPLETED_INTEGRATOR_STEP,
        ];
        if self.rng.chance(0.3) {
            calls.push(f::GET_EVENT_INDICATORS);
        }
        for function in calls {
            if self.failure.is_some() || self.insts[i].st != St::ContinuousTimeMode {
                break;
            }
            if !matches!(self.call_on(function, target, c), Some(OK | WARNING)) {
                break;
            }
        }
        self.sane = false;
    }

    /// Makes one call of `function` with generated arguments and checks the result.
    fn call(&mut self, function: usize) {
        if function == f::INSTANTIATE {
            self.instantiate();
            return;
        }
        if matches!(function, f::GET_TYPES_PLATFORM | f::GET_VERSION) {
            self.check_platform();
            return;
        }
        let (target, c) = self.target();
        self.call_on(function, target, c);
    }

    /// Makes one call of `function` on `target` with generated arguments and checks the
    /// result; its status (`None` for fmi2FreeInstance).
    fn call_on(&mut self, function: usize, target: Target, c: Component) -> Option<Status> {
        let before = match target {
            Target::Live(i) => {
                let inst = &mut self.insts[i];
                if matches!(
                    function,
                    f::SETUP_EXPERIMENT
                        | f::ENTER_INIT
                        | f::EXIT_INIT
                        | f::RESET
                        | f::SET_REAL
                        | f::SET_FMU_STATE
                        | f::NEW_DISCRETE_STATES
                ) {
                    // What may change the continuous states other than
                    // fmi2SetContinuousStates.
                    inst.x_set = None;
                }
                Some((inst.kind, inst.st, inst.sink.len()))
            }
            _ => None,
        };
        let legal = before.is_none_or(|(kind, st, _)| allowed(function, kind, st));
        let status = self.dispatch(function, target, c, legal);
        let status = status?;
        self.stats.calls += 1;
        self.stats.statuses[(status as usize).min(5)] += 1;
        let name = FUNCTION_NAMES[function];
        self.note(|| format!("  -> {}", status_name(status)));
        if let (true, Target::Live(i), Some((_, _, n))) = (self.trace, target, before) {
            if let Some(inst) = self.insts.get(i) {
                for m in inst.sink.since(n) {
                    println!("       [{}] {}", status_name(m.status), m.text);
                }
            }
        }
        if !status_allowed(function, status) {
            self.fail(format!(
                "{name} returned {} (not allowed)",
                status_name(status)
            ));
        }
        match target {
            Target::Null | Target::Foreign => {
                if status != ERROR {
                    self.fail(format!(
                        "{name} on a {target:?} instance returned {}",
                        status_name(status)
                    ));
                }
            }
            Target::Live(i) => {
                let (kind, st_before, n_before) = before.expect("live");
                let inst = &self.insts[i];
                let new = inst.sink.since(n_before);
                let violations = inst.sink.take_violations();
                let (logs, cats) = (inst.logs, inst.categories);
                for v in violations {
                    self.fail(format!("{name}: {v}"));
                }
                if let Some(m) = new
                    .iter()
                    .find(|m| m.text.contains("internal error") || m.text.contains("panicked"))
                {
                    self.fail(format!("{name} panicked inside the FMU: {}", m.text));
                }
                if !legal {
                    self.stats.illegal_calls += 1;
                    // A function of the other interface type: the message names its type.
                    let foreign = if f::co_simulation_only(function) {
                        Some(Kind::CoSimulation)
                    } else if f::model_exchange_only(function) {
                        Some(Kind::ModelExchange)
                    } else {
                        None
                    }
                    .filter(|&k| k != kind);
                    let expected = foreign.map_or("illegal call sequence", Kind::name);
                    if status != ERROR {
                        self.fail(format!(
                            "{name} in state {st_before:?} of a {} instance (not allowed by the standard) returned {}",
                            kind.name(),
                            status_name(status)
                        ));
                    } else if logs
                        && cats[3]
                        && !new
                            .iter()
                            .any(|m| m.status == ERROR && m.text.contains(expected))
                    {
                        self.fail(format!("{name} in state {st_before:?} of a {} instance refused without a message saying '{expected}'", kind.name()));
                    }
                }
                if status != OK
                    && logs
                    && cats[category_index(status)]
                    && !new.iter().any(|m| m.status == status)
                {
                    self.fail(format!(
                        "{name} returned {} without a logged message of that status (messages: {:?})",
                        status_name(status),
                        new.iter().map(|m| &m.text).collect::<Vec<_>>()
                    ));
                }
                if let Some(m) = new.iter().find(|m| m.status > status && m.status != OK) {
                    self.fail(format!(
                        "{name} returned {} but logged a {} message: {}",
                        status_name(status),
                        status_name(m.status),
                        m.text
                    ));
                }
            }
        }
        if let Some((c, vrs, got)) = self.same_as_variables.take() {
            let mut values = vec![f64::NAN; vrs.len()];
            // SAFETY: a live instance, arrays of vrs.len() elements.
            let g =
                unsafe { (self.fmu.api.get_real)(c, vrs.as_ptr(), vrs.len(), values.as_mut_ptr()) };
            self.stats.calls += 1;
            if g == OK
                && values
                    .iter()
                    .zip(&got)
                    .any(|(a, b)| a.to_bits() != b.to_bits())
            {
                self.fail(format!(
                    "{name} returned {got:?}, but fmi2GetReal of those variables {vrs:?} returns {values:?}"
                ));
            }
        }
        Some(status)
    }

    /// The live instance (panics otherwise: only called for `Target::Live`).
    fn inst(&mut self, t: Target) -> Option<&mut Inst> {
        match t {
            Target::Live(i) => Some(&mut self.insts[i]),
            _ => None,
        }
    }

    fn dispatch(
        &mut self,
        function: usize,
        target: Target,
        c: Component,
        legal: bool,
    ) -> Option<Status> {
        let api = self.fmu.api;
        let name = FUNCTION_NAMES[function];
        let s = match function {
            f::SET_DEBUG_LOGGING => {
                let on: Boolean = *self.rng.pick(&[0, 1, 2, -1]);
                let pool: [&[u8]; 9] = [
                    b"logEvents",
                    b"logStatusWarning",
                    b"logStatusDiscard",
                    b"logStatusError",
                    b"logStatusFatal",
                    b"logAll",
                    b"logUnknown",
                    b"",
                    b"\xff\xfe",
                ];
                let n = self.rng.below(4);
                let mut names: Vec<Option<CString>> = (0..n)
                    .map(|_| {
                        if self.rng.chance(0.05) {
                            None
                        } else {
                            let i = if self.rng.chance(0.8) {
                                self.rng.below(6)
                            } else {
                                self.rng.below(9)
                            };
                            Some(CString::new(pool[i]).unwrap())
                        }
                    })
                    .collect();
                if n == 0 && self.rng.chance(0.5) {
                    names.clear();
                }
                let ptrs: Vec<CStr> = names
                    .iter()
                    .map(|n| n.as_ref().map_or(std::ptr::null(), |c| c.as_ptr()))
                    .collect();
                let null_array = self.rng.chance(0.05);
                let nc = if null_array && self.rng.chance(0.5) {
                    usize::MAX
                } else {
                    ptrs.len()
                };
                self.note(|| {
                    format!(
                        "{name}(on {on}, {nc} categories {names:?}{})",
                        if null_array { ", NULL array" } else { "" }
                    )
                });
                // SAFETY: `nc` strings at `ptrs` (or a NULL array).
                let s = unsafe {
                    (api.set_debug_logging)(
                        c,
                        on,
                        nc,
                        if null_array {
                            std::ptr::null()
                        } else {
                            ptrs.as_ptr()
                        },
                    )
                };
                if let (Some(inst), true) = (self.inst(target), legal) {
                    // The oracle's copy of the category logic.
                    if !(null_array && nc > 0)
                        && names
                            .iter()
                            .all(|n| n.as_ref().is_some_and(|c| c.to_str().is_ok()))
                    {
                        if names.is_empty() {
                            inst.categories = [on != 0; 5];
                        } else {
                            for n in names.iter().flatten() {
                                match crate::importer::CATEGORIES
                                    .iter()
                                    .position(|c| c.as_bytes() == n.as_bytes())
                                {
                                    Some(5) => inst.categories = [on != 0; 5],
                                    Some(k) => inst.categories[k] = on != 0,
                                    None => break,
                                }
                            }
                        }
                    }
                }
                s
            }
            f::FREE_INSTANCE => {
                self.note(|| format!("{name}({target:?})"));
                // SAFETY: NULL, foreign memory, or a live instance.
                unsafe { (api.free_instance)(c) };
                self.stats.calls += 1;
                if let Target::Live(i) = target {
                    if legal {
                        let inst = self.insts.remove(i);
                        for v in inst.sink.take_violations() {
                            self.fail(format!("{name}: {v}"));
                        }
                    }
                }
                return None;
            }
            f::SETUP_EXPERIMENT => {
                let e = self.fmu.md.experiment.clone();
                let tol_defined: Boolean = *self.rng.pick(&[0, 1, 1, 1, 7]);
                let tol = match self.rng.below(6) {
                    0 => e.tolerance,
                    1 => self.rng.log_uniform(1e-10, 1e-2),
                    2 => 1e-6,
                    3 => *self
                        .rng
                        .pick(&[0.0, -1.0, f64::NAN, f64::INFINITY, 1e300, 10.0, 1e-14]),
                    4 if self.rng.chance(0.05) => 1e-300,
                    _ => e.tolerance,
                };
                let start = match self.rng.below(6) {
                    0..=2 => e.start,
                    3 => self.rng.unit() * 100.0 - 50.0,
                    4 => hostile_f64(&mut self.rng),
                    _ => 0.0,
                };
                let stop_defined: Boolean = *self.rng.pick(&[0, 0, 1, 1, -3]);
                let stop = match self.rng.below(4) {
                    0 => start + e.stop - e.start,
                    1 => start + self.rng.unit() * 10.0,
                    2 => hostile_f64(&mut self.rng),
                    _ => start - 1.0,
                };
                self.note(|| format!("{name}({target:?}, tol {tol_defined}:{tol:e}, start {start:e}, stop {stop_defined}:{stop:e})"));
                // SAFETY: scalar arguments.
                let s = unsafe {
                    (api.setup_experiment)(c, tol_defined, tol, start, stop_defined, stop)
                };
                if let (Some(inst), true, OK) = (self.inst(target), legal, s) {
                    inst.time = start;
                    inst.stop = (stop_defined != 0).then_some(stop);
                }
                s
            }
            f::ENTER_INIT
            | f::EXIT_INIT
            | f::TERMINATE
            | f::RESET
            | f::CANCEL_STEP
            | f::ENTER_EVENT_MODE
            | f::ENTER_CONTINUOUS_TIME_MODE => {
                self.note(|| format!("{name}({target:?})"));
                let g = match function {
                    f::ENTER_INIT => api.enter_initialization_mode,
                    f::EXIT_INIT => api.exit_initialization_mode,
                    f::TERMINATE => api.terminate,
                    f::RESET => api.reset,
                    f::ENTER_EVENT_MODE => api.enter_event_mode,
                    f::ENTER_CONTINUOUS_TIME_MODE => api.enter_continuous_time_mode,
                    _ => api.cancel_step,
                };
                // SAFETY: NULL, foreign memory, or a live instance.
                let s = unsafe { g(c) };
                if let (Some(inst), true) = (self.inst(target), legal) {
                    match (function, s) {
                        (f::ENTER_INIT, OK) => inst.st = St::Init,
                        (f::EXIT_INIT, OK | WARNING) => inst.st = inst.kind.initialized(),
                        (f::ENTER_EVENT_MODE, OK) => {
                            inst.st = St::EventMode;
                            inst.event_requested = false;
                        }
                        (f::ENTER_CONTINUOUS_TIME_MODE, OK) => inst.st = St::ContinuousTimeMode,
                        // A model failure at initialization: the Error state.
                        (f::EXIT_INIT, _) => inst.st = St::Error,
                        (f::TERMINATE, OK) => inst.st = St::Terminated,
                        (f::RESET, OK) => {
                            inst.st = St::Instantiated;
                            inst.time = 0.0;
                            inst.stop = None;
                            inst.x.clear();
                            inst.dx.clear();
                            inst.event_requested = false;
                        }
                        _ => {}
                    }
                }
                s
            }
            f::GET_REAL => {
                let vrs = self.vrs();
                let n = vrs.len();
                let mut out = vec![-7.5e-77f64; n + 4];
                let vp = self.ptr_or_null(&vrs);
                let op = if self.rng.chance(0.04) {
                    std::ptr::null_mut()
                } else {
                    out.as_mut_ptr()
                };
                self.note(|| {
                    format!(
                        "{name}({target:?}, vr {vrs:?}{}{})",
                        if vp.is_null() { ", NULL vr" } else { "" },
                        if op.is_null() { ", NULL value" } else { "" }
                    )
                });
                // SAFETY: arrays of n elements (or NULL).
                let s = unsafe { (api.get_real)(c, vp, n, op) };
                self.check_canaries(name, &out[n..], -7.5e-77);
                if matches!(s, OK | WARNING) {
                    if let Some(k) = out[..n].iter().position(|x| x.is_nan()) {
                        self.fail(format!(
                            "{name} returned {} with NaN for value reference {}",
                            status_name(s),
                            vrs[k]
                        ));
                    }
                }
                s
            }
            f::GET_INTEGER | f::GET_BOOLEAN | f::GET_STRING => {
                let vrs = self.vrs();
                let n = vrs.len();
                let mut ints = vec![0x5a5a_5a5a_i32; n + 4];
                let mut strs: Vec<CStr> = vec![std::ptr::null(); n + 4];
                let vp = self.ptr_or_null(&vrs);
                let null_out = self.rng.chance(0.04);
                self.note(|| format!("{name}({target:?}, vr {vrs:?})"));
                // SAFETY: arrays of n elements (or NULL).
                let s = unsafe {
                    match function {
                        f::GET_INTEGER => (api.get_integer)(
                            c,
                            vp,
                            n,
                            if null_out {
                                std::ptr::null_mut()
                            } else {
                                ints.as_mut_ptr()
                            },
                        ),
                        f::GET_BOOLEAN => (api.get_boolean)(
                            c,
                            vp,
                            n,
                            if null_out {
                                std::ptr::null_mut()
                            } else {
                                ints.as_mut_ptr()
                            },
                        ),
                        _ => (api.get_string)(
                            c,
                            vp,
                            n,
                            if null_out {
                                std::ptr::null_mut()
                            } else {
                                strs.as_mut_ptr()
                            },
                        ),
                    }
                };
                if ints[n..].iter().any(|&x| x != 0x5a5a_5a5a)
                    || strs[n..].iter().any(|p| !p.is_null())
                {
                    self.fail(format!("{name} wrote past the {n} elements it was given"));
                }
                if n > 0 && s == OK && matches!(target, Target::Live(_)) && legal {
                    self.fail(format!("{name} of Real variables {vrs:?} returned fmi2OK (this FMU has no such variables)"));
                }
                s
            }
            f::SET_REAL => {
                let vrs = self.vrs();
                let values: Vec<f64> = vrs.iter().map(|&v| self.value_for(v)).collect();
                let vp = self.ptr_or_null(&vrs);
                let xp = self.ptr_or_null(&values);
                self.note(|| format!("{name}({target:?}, vr {vrs:?}, values {values:?})"));
                // SAFETY: arrays of n elements (or NULL).
                let s = unsafe { (api.set_real)(c, vp, vrs.len(), xp) };
                if let (Target::Live(i), true, OK | WARNING) = (target, legal, s) {
                    if self.insts[i].st == St::ContinuousTimeMode {
                        let continuous_input = |vr: &u32| {
                            self.vars.iter().any(|v| {
                                v.vr == *vr && v.is("input") && v.variability == "continuous"
                            })
                        };
                        if let Some(vr) = vrs.iter().find(|vr| !continuous_input(vr)) {
                            self.fail(format!(
                                "{name} in continuous-time mode returned {} for value reference {vr}, which is not a continuous input",
                                status_name(s)
                            ));
                        }
                    }
                }
                s
            }
            f::SET_INTEGER | f::SET_BOOLEAN | f::SET_STRING => {
                let vrs = self.vrs();
                let n = vrs.len();
                let ints: Vec<i32> = (0..n).map(|_| self.rng.next_u64() as i32).collect();
                let cstrings: Vec<CString> = (0..n)
                    .map(|i| CString::new(format!("s{i}%s")).unwrap())
                    .collect();
                let strs: Vec<CStr> = cstrings
                    .iter()
                    .map(|s| {
                        if self.rng.chance(0.2) {
                            std::ptr::null()
                        } else {
                            s.as_ptr()
                        }
                    })
                    .collect();
                let vp = self.ptr_or_null(&vrs);
                self.note(|| format!("{name}({target:?}, vr {vrs:?})"));
                // SAFETY: arrays of n elements (or NULL).
                let s = unsafe {
                    match function {
                        f::SET_INTEGER => (api.set_integer)(c, vp, n, self.ptr_or_null(&ints)),
                        f::SET_BOOLEAN => (api.set_boolean)(c, vp, n, self.ptr_or_null(&ints)),
                        _ => (api.set_string)(c, vp, n, self.ptr_or_null(&strs)),
                    }
                };
                if n > 0 && s == OK && matches!(target, Target::Live(_)) && legal {
                    self.fail(format!("{name} of value references {vrs:?} returned fmi2OK (this FMU has no such variables)"));
                }
                s
            }
            f::GET_FMU_STATE => {
                // A fresh slot, or one holding a live state (which is then overwritten).
                let reuse = (!self.handles.is_empty() && self.rng.chance(0.3))
                    .then(|| self.rng.below(self.handles.len()));
                let mut slot: FmuState =
                    reuse.map_or(std::ptr::null_mut(), |k| self.handles[k].ptr);
                let null_slot = self.rng.chance(0.05);
                self.note(|| {
                    format!(
                        "{name}({target:?}, slot {}{})",
                        if reuse.is_some() { "reused" } else { "NULL" },
                        if null_slot { ", NULL slot pointer" } else { "" }
                    )
                });
                // SAFETY: a valid slot (or NULL) holding NULL or a live state.
                let s = unsafe {
                    (api.get_fmu_state)(
                        c,
                        if null_slot {
                            std::ptr::null_mut()
                        } else {
                            &mut slot
                        },
                    )
                };
                if let (Target::Live(i), OK) = (target, s) {
                    let inst = &self.insts[i];
                    let snap = Snap {
                        st: inst.st,
                        time: inst.time,
                        stop: inst.stop,
                    };
                    match reuse {
                        Some(k) => {
                            if slot != self.handles[k].ptr {
                                self.fail(format!("{name} replaced a reused state's handle"));
                            }
                            self.handles[k].snap = snap;
                        }
                        None if slot.is_null() => {
                            self.fail(format!("{name} returned fmi2OK and no state"))
                        }
                        None => self.handles.push(Handle { ptr: slot, snap }),
                    }
                }
                s
            }
            f::SET_FMU_STATE | f::SERIALIZED_SIZE | f::SERIALIZE => {
                let (k, h) = self.state_handle();
                self.note(|| format!("{name}({target:?}, state {k:?})"));
                match function {
                    f::SET_FMU_STATE => {
                        // SAFETY: a live state, NULL, or foreign memory.
                        let s = unsafe { (api.set_fmu_state)(c, h) };
                        if let (Target::Live(i), true, Some(k)) = (target, legal, k) {
                            let snap = self.handles[k].snap;
                            let kind = self.insts[i].kind;
                            let foreign = snap.st.kind().filter(|&other| other != kind);
                            if let Some(other) = foreign {
                                if s != ERROR {
                                    self.fail(format!(
                                        "{name} of a state saved in {:?} (a {} state) into a {} instance returned {}",
                                        snap.st,
                                        other.name(),
                                        kind.name(),
                                        status_name(s)
                                    ));
                                }
                            } else if s == OK {
                                let inst = &mut self.insts[i];
                                inst.st = snap.st;
                                inst.time = snap.time;
                                inst.stop = snap.stop;
                                inst.x.clear();
                                inst.dx.clear();
                                inst.event_requested = false;
                                self.stats.states_restored += 1;
                            }
                        }
                        s
                    }
                    f::SERIALIZED_SIZE => {
                        let mut size = usize::MAX;
                        let null = self.rng.chance(0.05);
                        // SAFETY: a valid out pointer (or NULL).
                        let s = unsafe {
                            (api.serialized_fmu_state_size)(
                                c,
                                h,
                                if null {
                                    std::ptr::null_mut()
                                } else {
                                    &mut size
                                },
                            )
                        };
                        if s == OK && !null && !(16..1 << 20).contains(&size) {
                            self.fail(format!(
                                "{name} returned fmi2OK with an implausible size {size}"
                            ));
                        }
                        s
                    }
                    _ => {
                        let mut size = 0usize;
                        // SAFETY: a valid out pointer.
                        let s0 = unsafe { (api.serialized_fmu_state_size)(c, h, &mut size) };
                        self.stats.calls += 1;
                        let ask = match self.rng.below(8) {
                            0 => size.wrapping_add(1),
                            1 => size.saturating_sub(1),
                            2 => 0,
                            _ => size,
                        };
                        let mut buf = vec![0x77u8; ask + 8];
                        let null = self.rng.chance(0.05);
                        // SAFETY: `ask` writable bytes (or NULL).
                        let s = unsafe {
                            (api.serialize_fmu_state)(
                                c,
                                h,
                                if null {
                                    std::ptr::null_mut()
                                } else {
                                    buf.as_mut_ptr().cast()
                                },
                                ask,
                            )
                        };
                        if buf[ask..].iter().any(|&b| b != 0x77) {
                            self.fail(format!("{name} wrote past the {ask} bytes it was given"));
                        }
                        if s == OK {
                            if s0 != OK || ask != size {
                                self.fail(format!("{name} returned fmi2OK for a buffer of {ask} bytes; the size is {size}"));
                            }
                            if let Some(k) = k {
                                buf.truncate(ask);
                                let snap = self.handles[k].snap;
                                self.serialized.push((buf, snap));
                            }
                        }
                        s
                    }
                }
            }
            f::FREE_FMU_STATE => {
                let (k, h) = self.state_handle();
                let mut slot = h;
                let null_slot = self.rng.chance(0.05);
                self.note(|| {
                    format!(
                        "{name}({target:?}, state {k:?}{})",
                        if null_slot { ", NULL slot pointer" } else { "" }
                    )
                });
                // SAFETY: a valid slot (or NULL) holding a live state, NULL or foreign memory.
                let s = unsafe {
                    (api.free_fmu_state)(
                        c,
                        if null_slot {
                            std::ptr::null_mut()
                        } else {
                            &mut slot
                        },
                    )
                };
                if s == OK {
                    if let (Some(k), false) = (k, null_slot) {
                        if !slot.is_null() {
                            self.fail(format!(
                                "{name} returned fmi2OK but did not set the slot to NULL"
                            ));
                        }
                        self.handles.remove(k);
                    }
                } else if let (Some(_), false, true) =
                    (k, null_slot, matches!(target, Target::Live(_)) && legal)
                {
                    self.fail(format!(
                        "{name} of a live state returned {}",
                        status_name(s)
                    ));
                }
                s
            }
            f::DESERIALIZE => {
                let (bytes, snap) = self.serialized_bytes();
                let reuse = (!self.handles.is_empty() && self.rng.chance(0.2))
                    .then(|| self.rng.below(self.handles.len()));
                let mut slot: FmuState =
                    reuse.map_or(std::ptr::null_mut(), |k| self.handles[k].ptr);
                let null_bytes = self.rng.chance(0.04);
                let size = if null_bytes && self.rng.chance(0.5) {
                    usize::MAX
                } else {
                    bytes.len()
                };
                self.note(|| {
                    format!(
                        "{name}({target:?}, {} bytes{}, slot {})",
                        size,
                        if null_bytes { " at NULL" } else { "" },
                        if reuse.is_some() { "reused" } else { "NULL" }
                    )
                });
                // SAFETY: `size` readable bytes (or NULL); a valid slot.
                let s = unsafe {
                    (api.deserialize_fmu_state)(
                        c,
                        if null_bytes {
                            std::ptr::null()
                        } else {
                            bytes.as_ptr().cast()
                        },
                        size,
                        &mut slot,
                    )
                };
                if let (Target::Live(_), OK) = (target, s) {
                    self.stats.deserialized += 1;
                    let snap = snap.or_else(|| decode_snap(&bytes));
                    match (snap, reuse) {
                        (None, _) => {
                            self.fail(format!("{name} accepted bytes this oracle cannot read"))
                        }
                        (Some(snap), Some(k)) => self.handles[k].snap = snap,
                        (Some(snap), None) => self.handles.push(Handle { ptr: slot, snap }),
                    }
                }
                s
            }
            f::DIRECTIONAL_DERIVATIVE => {
                let unknowns = self.vrs();
                let knowns = self.vrs();
                let dv: Vec<f64> = knowns
                    .iter()
                    .map(|_| {
                        if self.rng.chance(0.8) {
                            self.rng.unit() * 2.0 - 1.0
                        } else {
                            hostile_f64(&mut self.rng)
                        }
                    })
                    .collect();
                let n = unknowns.len();
                let mut out = vec![-7.5e-77f64; n + 4];
                let (up, kp, dp) = (
                    self.ptr_or_null(&unknowns),
                    self.ptr_or_null(&knowns),
                    self.ptr_or_null(&dv),
                );
                let op = if self.rng.chance(0.04) {
                    std::ptr::null_mut()
                } else {
                    out.as_mut_ptr()
                };
                self.note(|| {
                    format!(
                        "{name}({target:?}, unknowns {unknowns:?}, knowns {knowns:?}, dv {dv:?})"
                    )
                });
                // SAFETY: arrays of their lengths (or NULL).
                let s =
                    unsafe { (api.get_directional_derivative)(c, up, n, kp, knowns.len(), dp, op) };
                self.check_canaries(name, &out[n..], -7.5e-77);
                if s == OK && out[..n].iter().any(|x| x.is_nan()) {
                    self.fail(format!("{name} returned fmi2OK with NaN"));
                }
                s
            }
            f::SET_INPUT_DERIVATIVES | f::GET_OUTPUT_DERIVATIVES => {
                let mut vrs = self.vrs();
                if self.rng.chance(0.5) {
                    let want_input = function == f::SET_INPUT_DERIVATIVES;
                    if let Some(v) = self.vr_where(|v| {
                        if want_input {
                            v.is("input")
                        } else {
                            v.is("output")
                        }
                    }) {
                        vrs = vec![v];
                    }
                }
                let n = vrs.len();
                let orders: Vec<i32> = (0..n)
                    .map(|_| *self.rng.pick(&[1, 1, 2, 2, 0, 3, -1, i32::MAX, i32::MIN]))
                    .collect();
                let values: Vec<f64> = (0..n)
                    .map(|_| {
                        if self.rng.chance(0.7) {
                            self.rng.unit() * 4.0 - 2.0
                        } else {
                            hostile_f64(&mut self.rng)
                        }
                    })
                    .collect();
                let (vp, opp) = (self.ptr_or_null(&vrs), self.ptr_or_null(&orders));
                self.note(|| {
                    format!("{name}({target:?}, vr {vrs:?}, order {orders:?}, values {values:?})")
                });
                if function == f::SET_INPUT_DERIVATIVES {
                    let xp = self.ptr_or_null(&values);
                    // SAFETY: arrays of n elements (or NULL).
                    unsafe { (api.set_real_input_derivatives)(c, vp, n, opp, xp) }
                } else {
                    let mut out = vec![-7.5e-77f64; n + 4];
                    let op = if self.rng.chance(0.04) {
                        std::ptr::null_mut()
                    } else {
                        out.as_mut_ptr()
                    };
                    // SAFETY: arrays of n elements (or NULL).
                    let s = unsafe { (api.get_real_output_derivatives)(c, vp, n, opp, op) };
                    self.check_canaries(name, &out[n..], -7.5e-77);
                    if s == OK && out[..n].iter().any(|x| x.is_nan()) {
                        self.fail(format!("{name} returned fmi2OK with NaN"));
                    }
                    s
                }
            }
            f::DO_STEP => return Some(self.do_step(target, c, legal)),
            f::GET_STATUS
            | f::GET_REAL_STATUS
            | f::GET_INTEGER_STATUS
            | f::GET_BOOLEAN_STATUS
            | f::GET_STRING_STATUS => {
                let kind: StatusKind = *self.rng.pick(&[0, 1, 2, 3, 3, 2, 4, u32::MAX]);
                let null = self.rng.chance(0.05);
                self.note(|| {
                    format!(
                        "{name}({target:?}, kind {kind}{})",
                        if null { ", NULL value" } else { "" }
                    )
                });
                let mut st: Status = 99;
                let mut real = -7.5e-77;
                let mut int: Integer = 0x5a5a;
                let mut string: CStr = std::ptr::null();
                // SAFETY: valid out pointers (or NULL).
                let s = unsafe {
                    match function {
                        f::GET_STATUS => (api.get_status)(
                            c,
                            kind,
                            if null { std::ptr::null_mut() } else { &mut st },
                        ),
                        f::GET_REAL_STATUS => (api.get_real_status)(
                            c,
                            kind,
                            if null {
                                std::ptr::null_mut()
                            } else {
                                &mut real
                            },
                        ),
                        f::GET_INTEGER_STATUS => (api.get_integer_status)(
                            c,
                            kind,
                            if null { std::ptr::null_mut() } else { &mut int },
                        ),
                        f::GET_BOOLEAN_STATUS => (api.get_boolean_status)(
                            c,
                            kind,
                            if null { std::ptr::null_mut() } else { &mut int },
                        ),
                        _ => (api.get_string_status)(
                            c,
                            kind,
                            if null {
                                std::ptr::null_mut()
                            } else {
                                &mut string
                            },
                        ),
                    }
                };
                if s == OK && !null {
                    let bad = match function {
                        f::GET_STATUS => st > PENDING,
                        f::GET_REAL_STATUS => !real.is_finite(),
                        f::GET_BOOLEAN_STATUS => !(int == 0 || int == 1),
                        f::GET_STRING_STATUS => string.is_null(),
                        _ => false,
                    };
                    if bad {
                        self.fail(format!(
                            "{name}(kind {kind}) returned fmi2OK with a bad value"
                        ));
                    }
                }
                if !string.is_null() {
                    // SAFETY: the FMU promises a NUL-terminated string.
                    let _ = unsafe { std::ffi::CStr::from_ptr(string) }.to_bytes().len();
                }
                s
            }
            f::SET_TIME => {
                let time = match target {
                    Target::Live(i) => self.insts[i].time,
                    _ => 0.0,
                };
                let t = if self.sane {
                    time + self.h_me
                } else {
                    match self.rng.below(12) {
                        0..=5 => time + self.rng.log_uniform(1e-6, 0.1),
                        6 => time,
                        // Backwards: after a rejected step, an importer goes back.
                        7 => time - self.rng.unit(),
                        8 => *self
                            .rng
                            .pick(&[1e308, -1e308, f64::MAX, f64::MIN, 1e15, -1e15]),
                        9 => *self.rng.pick(&[5e-324, -0.0, 0.0, time * (1.0 + 1e-15)]),
                        _ => {
                            *self
                                .rng
                                .pick(&[f64::NAN, -f64::NAN, f64::INFINITY, f64::NEG_INFINITY])
                        }
                    }
                };
                self.note(|| format!("{name}({target:?}, time {t:e} (FMU at {time:e}))"));
                // SAFETY: scalar arguments.
                let s = unsafe { (api.set_time)(c, t) };
                if let (Target::Live(i), true) = (target, legal) {
                    if t.is_finite() != (s == OK) {
                        self.fail(format!(
                            "{name}(time {t:e}) returned {} (a finite time is accepted, no other)",
                            status_name(s)
                        ));
                    }
                    if s == OK {
                        self.insts[i].time = t;
                    }
                }
                s
            }
            f::SET_CONTINUOUS_STATES => {
                let n = self.nx;
                let len = self.array_len(n);
                let cap = len.min(n + 8);
                // From what the importer knows of the instance: an Euler step from the last
                // states read, those states, or the start values.
                let (x, dx) = match target {
                    Target::Live(i) => (self.insts[i].x.clone(), self.insts[i].dx.clone()),
                    _ => (vec![], vec![]),
                };
                let mut values: Vec<f64> = if x.len() == n && dx.len() == n {
                    x.iter().zip(&dx).map(|(x, d)| x + self.h_me * d).collect()
                } else if x.len() == n {
                    x
                } else {
                    self.x_start.clone()
                };
                if !self.sane && self.rng.chance(0.2) {
                    for v in values.iter_mut() {
                        *v *= 1.0 + 0.1 * (self.rng.unit() - 0.5);
                    }
                }
                values.resize(cap, 0.5);
                if !self.sane && cap > 0 && self.rng.chance(0.25) {
                    let k = self.rng.below(cap);
                    values[k] = hostile_f64(&mut self.rng);
                }
                let null = !self.sane && self.rng.chance(0.04);
                self.note(|| {
                    format!(
                        "{name}({target:?}, x {values:?}{}, nx {len})",
                        if null { " at NULL" } else { "" }
                    )
                });
                // SAFETY: `cap` readable elements (or NULL); a longer `len` is one the FMU
                // must refuse before reading (nx is in its modelDescription).
                let s = unsafe {
                    (api.set_continuous_states)(
                        c,
                        if null {
                            std::ptr::null()
                        } else {
                            values.as_ptr()
                        },
                        len,
                    )
                };
                if let (Target::Live(i), true) = (target, legal) {
                    let right = len == n && !(null && n > 0);
                    let finite = values[..cap.min(len)].iter().all(|x| x.is_finite());
                    if !right && s != ERROR {
                        self.fail(format!(
                            "{name} with nx = {len}{} (the FMU has {n} states) returned {}",
                            if null { " and x = NULL" } else { "" },
                            status_name(s)
                        ));
                    } else if right && !finite && s != ERROR {
                        self.fail(format!(
                            "{name} with non-finite states {values:?} returned {}",
                            status_name(s)
                        ));
                    } else if right && finite && s != OK {
                        self.fail(format!(
                            "{name} refused finite states {values:?} ({})",
                            status_name(s)
                        ));
                    }
                    if s == OK {
                        let inst = &mut self.insts[i];
                        values.truncate(n);
                        inst.x_set = Some(values.clone());
                        inst.x = values;
                        inst.dx.clear();
                    }
                }
                s
            }
            f::GET_DERIVATIVES
            | f::GET_EVENT_INDICATORS
            | f::GET_CONTINUOUS_STATES
            | f::GET_NOMINALS => {
                let n = if function == f::GET_EVENT_INDICATORS {
                    self.ni
                } else {
                    self.nx
                };
                let len = self.array_len(n);
                let cap = len.min(n + 8);
                let canary = -7.5e-77f64;
                let mut out = vec![canary; cap + 4];
                let null = !self.sane && self.rng.chance(0.04);
                let g = match function {
                    f::GET_DERIVATIVES => api.get_derivatives,
                    f::GET_EVENT_INDICATORS => api.get_event_indicators,
                    f::GET_CONTINUOUS_STATES => api.get_continuous_states,
                    _ => api.get_nominals_of_continuous_states,
                };
                self.note(|| {
                    format!(
                        "{name}({target:?}, n {len}{})",
                        if null { ", NULL array" } else { "" }
                    )
                });
                // SAFETY: `cap` writable elements (or NULL); a longer `len` is one the FMU
                // must refuse before writing.
                let s = unsafe {
                    g(
                        c,
                        if null {
                            std::ptr::null_mut()
                        } else {
                            out.as_mut_ptr()
                        },
                        len,
                    )
                };
                self.check_canaries(name, &out[cap.min(len)..], canary);
                let right = len == n && !(null && n > 0);
                if let (Target::Live(_), true, false, false) = (target, legal, right, s == ERROR) {
                    self.fail(format!(
                        "{name} with n = {len}{} (the FMU has {n}) returned {}",
                        if null { " and a NULL array" } else { "" },
                        status_name(s)
                    ));
                }
                if matches!(s, OK | WARNING) && right && !null {
                    let got = &out[..n];
                    let bad = if function == f::GET_NOMINALS {
                        got.iter().position(|x| !(x.is_finite() && *x > 0.0))
                    } else {
                        got.iter().position(|x| !x.is_finite())
                    };
                    if let Some(k) = bad {
                        self.fail(format!(
                            "{name} returned {} with element {k} = {} ({got:?})",
                            status_name(s),
                            got[k]
                        ));
                    }
                    if let (Target::Live(i), true) = (target, legal) {
                        let got = got.to_vec();
                        match function {
                            f::GET_CONTINUOUS_STATES => {
                                if let Some(set) = &self.insts[i].x_set {
                                    if set
                                        .iter()
                                        .zip(&got)
                                        .any(|(a, b)| a.to_bits() != b.to_bits())
                                    {
                                        let set = set.clone();
                                        self.fail(format!(
                                            "{name} returned {got:?}, not the states {set:?} fmi2SetContinuousStates was given"
                                        ));
                                    }
                                }
                                self.insts[i].x = got.clone();
                            }
                            f::GET_DERIVATIVES => self.insts[i].dx = got.clone(),
                            _ => {}
                        }
                        // The same numbers as the variables they are: checked once this
                        // call's messages are (fmi2GetReal may log its own).
                        let vrs = match function {
                            f::GET_CONTINUOUS_STATES => self.state_vrs.clone(),
                            f::GET_DERIVATIVES => self.derivative_vrs.clone(),
                            _ => vec![],
                        };
                        if !vrs.is_empty() {
                            self.same_as_variables = Some((c, vrs, got));
                        }
                    }
                }
                s
            }
            f::NEW_DISCRETE_STATES => {
                let null = !self.sane && self.rng.chance(0.05);
                let mut info = EventInfo {
                    new_discrete_states_needed: -1,
                    terminate_simulation: -1,
                    nominals_of_continuous_states_changed: -1,
                    values_of_continuous_states_changed: -1,
                    next_event_time_defined: -1,
                    next_event_time: f64::NAN,
                };
                self.note(|| {
                    format!(
                        "{name}({target:?}{})",
                        if null { ", NULL eventInfo" } else { "" }
                    )
                });
                // SAFETY: a valid out pointer (or NULL).
                let s = unsafe {
                    (api.new_discrete_states)(
                        c,
                        if null {
                            std::ptr::null_mut()
                        } else {
                            &mut info
                        },
                    )
                };
                if let (Target::Live(_), true, true) = (target, legal, null) {
                    if s != ERROR {
                        self.fail(format!(
                            "{name} with a NULL fmi2EventInfo returned {}",
                            status_name(s)
                        ));
                    }
                }
                if matches!(s, OK | WARNING) && !null {
                    let flags = [
                        info.new_discrete_states_needed,
                        info.terminate_simulation,
                        info.nominals_of_continuous_states_changed,
                        info.values_of_continuous_states_changed,
                        info.next_event_time_defined,
                    ];
                    if flags.iter().any(|&b| b != 0 && b != 1)
                        || (info.next_event_time_defined == 1 && !info.next_event_time.is_finite())
                    {
                        self.fail(format!("{name} returned {} with {info:?}", status_name(s)));
                    }
                    if let (Target::Live(i), true) = (target, legal) {
                        self.stats.events += 1;
                        let inst = &mut self.insts[i];
                        inst.x.clear();
                        inst.dx.clear();
                    }
                }
                s
            }
            f::COMPLETED_INTEGRATOR_STEP => {
                let no_prior: Boolean = if self.sane {
                    1
                } else {
                    *self.rng.pick(&[0, 1, 2])
                };
                let null_event = !self.sane && self.rng.chance(0.04);
                let null_terminate = !self.sane && self.rng.chance(0.04);
                let (mut event, mut terminate): (Boolean, Boolean) = (-1, -1);
                self.note(|| {
                    format!(
                        "{name}({target:?}, noSetFMUStatePriorToCurrentPoint {no_prior}{}{})",
                        if null_event {
                            ", NULL enterEventMode"
                        } else {
                            ""
                        },
                        if null_terminate {
                            ", NULL terminateSimulation"
                        } else {
                            ""
                        }
                    )
                });
                // SAFETY: valid out pointers (or NULL).
                let s = unsafe {
                    (api.completed_integrator_step)(
                        c,
                        no_prior,
                        if null_event {
                            std::ptr::null_mut()
                        } else {
                            &mut event
                        },
                        if null_terminate {
                            std::ptr::null_mut()
                        } else {
                            &mut terminate
                        },
                    )
                };
                let null = null_event || null_terminate;
                if let (Target::Live(i), true) = (target, legal) {
                    if null && s != ERROR {
                        self.fail(format!(
                            "{name} with a NULL out pointer returned {}",
                            status_name(s)
                        ));
                    }
                    if matches!(s, OK | WARNING) && !null {
                        if ![event, terminate].iter().all(|&b| b == 0 || b == 1) {
                            self.fail(format!(
                                "{name} returned {} with enterEventMode = {event}, terminateSimulation = {terminate}",
                                status_name(s)
                            ));
                        }
                        self.insts[i].event_requested = event == 1;
                    }
                }
                s
            }
            _ => unreachable!("function {function}"),
        };
        Some(s)
    }

    /// A length for an array of `n` elements: mostly right, sometimes wrong, rarely absurd
    /// (always right for an importer's integrator step).
    fn array_len(&mut self, n: usize) -> usize {
        if self.sane {
            return n;
        }
        match self.rng.below(20) {
            0..=14 => n,
            15 => 0,
            16 => n + 1 + self.rng.below(3),
            17 => n.saturating_sub(1),
            18 => n.wrapping_sub(1),
            _ => *self.rng.pick(&[usize::MAX, 1 << 40, (1 << 24) + 1]),
        }
    }

    fn check_canaries(&mut self, name: &str, tail: &[f64], canary: f64) {
        if tail.iter().any(|x| x.to_bits() != canary.to_bits()) {
            self.fail(format!("{name} wrote past the elements it was given"));
        }
    }

    /// An FMU state handle: a live one of this sequence (`Some(index)`), NULL, or foreign
    /// memory.
    fn state_handle(&mut self) -> (Option<usize>, FmuState) {
        let r = self.rng.unit();
        if !self.handles.is_empty() && r < 0.85 {
            let k = self.rng.below(self.handles.len());
            return (Some(k), self.handles[k].ptr);
        }
        if r < 0.92 {
            return (None, std::ptr::null_mut());
        }
        let p = if self.rng.chance(0.5) {
            self.zeros.as_mut_ptr()
        } else {
            self.noise.as_mut_ptr()
        };
        (None, p.cast())
    }

    /// Bytes to deserialize, and what they capture when known.
    fn serialized_bytes(&mut self) -> (Vec<u8>, Option<Snap>) {
        let have = !self.serialized.is_empty();
        let r = self.rng.below(10);
        if have && r < 4 {
            let k = self.rng.below(self.serialized.len());
            let (b, s) = &self.serialized[k];
            return (b.clone(), Some(*s));
        }
        if have && r < 7 {
            let k = self.rng.below(self.serialized.len());
            let mut b = self.serialized[k].0.clone();
            match self.rng.below(4) {
                0 => {
                    let i = self.rng.below(b.len());
                    b[i] ^= 1 << self.rng.below(8);
                }
                1 => b.truncate(self.rng.below(b.len())),
                2 => b.push(self.rng.next_u64() as u8),
                _ => {
                    // Corrupt the body, then repair the checksum (FNV-1a 64 of the body, as
                    // the format documents): what only a deliberate forger could send.
                    mutate_semantically(&mut self.rng, &mut b);
                    fix_checksum(&mut b);
                }
            }
            return (b, None);
        }
        let n = if self.rng.chance(0.2) {
            0
        } else {
            self.rng.below(600)
        };
        let mut b: Vec<u8> = (0..n).map(|_| self.rng.next_u64() as u8).collect();
        if n >= 8 && self.rng.chance(0.5) {
            b[..8].copy_from_slice(b"mechfmuS");
        }
        (b, None)
    }

    fn do_step(&mut self, target: Target, c: Component, legal: bool) -> Status {
        let e = self.fmu.md.experiment.clone();
        let (time, stop) = match target {
            Target::Live(i) => (self.insts[i].time, self.insts[i].stop),
            _ => (0.0, None),
        };
        let h = match self.rng.below(20) {
            0..=8 => e.step,
            9..=11 => self.rng.log_uniform(1e-6, 1.0),
            12 => 1e-3,
            13 => *self.rng.pick(&[
                0.0,
                -0.0,
                -1.0,
                -e.step,
                f64::NAN,
                f64::INFINITY,
                f64::NEG_INFINITY,
            ]),
            14 => *self.rng.pick(&[
                5e-324,
                1e-300,
                1e-15 * time.abs().max(1e-300),
                f64::MIN_POSITIVE,
            ]),
            // Enormous steps: refused beyond a stop time, else integrated honestly (and
            // expensive), so rare.
            15 if stop.is_some_and(|s| s < 1e6) || self.rng.chance(0.01) => {
                *self.rng.pick(&[1e300, f64::MAX, 1e6, 1e3])
            }
            16 => self.rng.log_uniform(1.0, 10.0),
            _ => e.step,
        };
        let t = match self.rng.below(20) {
            0..=15 => time,
            16 => time * (1.0 + 1e-13) + 1e-300,
            17 => time + *self.rng.pick(&[1.0, -1.0, 1e-3, -1e-3]),
            _ => *self.rng.pick(&[
                f64::NAN,
                f64::INFINITY,
                f64::NEG_INFINITY,
                0.0,
                -time,
                1e308,
            ]),
        };
        let no_prior: Boolean = *self.rng.pick(&[0, 1, 2]);
        self.note(|| format!("fmi2DoStep({target:?}, t {t:e} (FMU at {time:e}), h {h:e}, noSetFMUStatePriorToCurrentPoint {no_prior})"));
        // SAFETY: scalar arguments.
        let s = unsafe { (self.fmu.api.do_step)(c, t, h, no_prior) };
        let Target::Live(i) = target else { return s };
        if !legal {
            return s;
        }
        match s {
            OK | WARNING => {
                self.stats.steps_ok += 1;
                self.insts[i].time = t + h;
                // The values after a successful step are numbers.
                let vrs = self.fmu.md.all_vrs();
                let mut out = vec![0.0; vrs.len()];
                // SAFETY: arrays of vrs.len() elements.
                let g = unsafe {
                    (self.fmu.api.get_real)(c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr())
                };
                self.stats.calls += 1;
                if g != OK {
                    self.fail(format!(
                        "fmi2GetReal after a successful fmi2DoStep returned {}",
                        status_name(g)
                    ));
                } else if let Some(k) = out.iter().position(|x| x.is_nan()) {
                    self.fail(format!(
                        "after fmi2DoStep(t {t:e}, h {h:e}) returned {}, `{}` is NaN",
                        status_name(s),
                        self.vars[k].name
                    ));
                }
            }
            DISCARD => {
                self.stats.steps_discarded += 1;
                self.insts[i].st = St::StepFailed;
                let mut last = f64::NAN;
                let mut term: Boolean = -1;
                // SAFETY: valid out pointers.
                let (a, b) = unsafe {
                    (
                        (self.fmu.api.get_real_status)(c, LAST_SUCCESSFUL_TIME, &mut last),
                        (self.fmu.api.get_boolean_status)(c, TERMINATED, &mut term),
                    )
                };
                self.stats.calls += 2;
                if a != OK
                    || !(last >= t.min(t + h) - 1e-9 * t.abs()
                        && last <= (t + h).max(t) + 1e-9 * t.abs())
                {
                    self.fail(format!("after fmi2Discard of [{t:e}, {:e}], fmi2LastSuccessfulTime = {last:e} ({})", t + h, status_name(a)));
                }
                if b != OK || term != 1 {
                    self.fail(format!(
                        "after fmi2Discard, fmi2Terminated = {term} ({})",
                        status_name(b)
                    ));
                }
                self.insts[i].time = last;
                // The values at the last successful time are numbers.
                let vrs = self.fmu.md.all_vrs();
                let mut out = vec![0.0; vrs.len()];
                // SAFETY: arrays of vrs.len() elements.
                let g = unsafe {
                    (self.fmu.api.get_real)(c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr())
                };
                self.stats.calls += 1;
                if g == OK {
                    if let Some(k) = out.iter().position(|x| x.is_nan()) {
                        self.fail(format!(
                            "after fmi2Discard (step [{t:e}, {:e}]), fmi2GetReal returned fmi2OK with `{}` = NaN",
                            t + h,
                            self.vars[k].name
                        ));
                    }
                }
            }
            _ => {}
        }
        s
    }
}

/// FNV-1a 64, the serialized state's checksum (documented in the runtime's format).
pub fn fnv(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
    })
}

pub fn fix_checksum(b: &mut [u8]) {
    if b.len() < 8 {
        return;
    }
    let n = b.len() - 8;
    let c = fnv(&b[..n]);
    b[n..].copy_from_slice(&c.to_le_bytes());
}

/// Offsets of the fields of a serialized state (format version 3), if it parses.
pub struct Layout {
    pub values: usize,
    pub n_values: usize,
    pub state_field: usize,
}

pub fn layout(b: &[u8]) -> Option<Layout> {
    let u32_at = |i: usize| {
        b.get(i..i + 4)
            .map(|x| u32::from_le_bytes(x.try_into().unwrap()) as usize)
    };
    let mut at = 12;
    for _ in 0..2 {
        at += 4 + u32_at(at)?;
    }
    let n_values = u32_at(at)?;
    let values = at + 4;
    at = values + 8 * n_values;
    let n_inputs = u32_at(at)?;
    at += 4 + 24 * n_inputs + 9 + 8 + 16 + 1;
    (at + 2 + 9 + 8 + 4 + 8 == b.len()).then_some(Layout {
        values,
        n_values,
        state_field: at,
    })
}

/// Corrupts fields of a serialized state with values of the right size.
pub fn mutate_semantically(rng: &mut Rng, b: &mut [u8]) {
    let Some(l) = layout(b) else { return };
    for _ in 0..1 + rng.below(3) {
        match rng.below(4) {
            0 => {
                let bits: u16 = if rng.chance(0.8) {
                    1 << rng.below(ALL_STATES.len())
                } else {
                    rng.next_u64() as u16
                };
                b[l.state_field..l.state_field + 2].copy_from_slice(&bits.to_le_bytes());
            }
            1 if l.n_values > 0 => {
                let k = rng.below(l.n_values);
                let x = hostile_f64(rng);
                b[l.values + 8 * k..l.values + 8 * k + 8]
                    .copy_from_slice(&x.to_bits().to_le_bytes());
            }
            _ => {
                let i = 12 + rng.below(b.len().saturating_sub(20).max(1));
                if i < b.len() - 8 {
                    b[i] = rng.next_u64() as u8;
                }
            }
        }
    }
}

/// The oracle's reading of a serialized state it did not make itself.
fn decode_snap(b: &[u8]) -> Option<Snap> {
    let l = layout(b)?;
    let f = |i: usize| f64::from_bits(u64::from_le_bytes(b[i..i + 8].try_into().unwrap()));
    let time = f(l.values + 8 * (l.n_values.checked_sub(1)?));
    let bits = u16::from_le_bytes(b[l.state_field..l.state_field + 2].try_into().unwrap());
    let st = ALL_STATES
        .iter()
        .enumerate()
        .find(|(i, _)| bits == 1 << i)
        .map(|(_, s)| *s)?;
    let stop_at = l.state_field + 2;
    let stop = (b[stop_at] == 1).then(|| f(stop_at + 1));
    Some(Snap { st, time, stop })
}

/// Runs `count` sequences with seeds `first..first + count`; prints `begin <seed>` before
/// each (so a crash can be attributed) when `announce`. Returns the statistics and the
/// failures (each naming its seed).
pub fn run_many(
    fmu: &Fmu,
    first: u64,
    count: u64,
    announce: bool,
    trace: bool,
) -> (Stats, Vec<String>) {
    let mut stats = Stats::default();
    let mut failures = vec![];
    let mut out = String::new();
    for seed in first..first + count {
        if announce {
            out.clear();
            let _ = writeln!(out, "begin {seed}");
            print!("{out}");
        }
        if trace {
            println!("sequence seed {seed} on {}", fmu.name());
        }
        match Sequence::new(fmu, seed, trace).run() {
            Ok(s) => stats.add(&s),
            Err(f) => {
                stats.sequences += 1;
                failures.push(f);
            }
        }
    }
    (stats, failures)
}

#[allow(dead_code)]
fn _assert_c_char(_: *const c_char) {}
