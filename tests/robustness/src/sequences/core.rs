//! A sequence over either standard: its state, what differs between the standards as the
//! sequence sees it ([`Standard`]), its run, and the checks every call passes whatever the
//! function (see the module documentation of [`sequences`](super)), then the teardown that
//! frees everything it made.

use super::machine::{Call, Handle, Inst, Kind, Snap, St, Target};
use super::model::Model;
use super::stats::Stats;
use crate::ffi::{Component, FmuState, Status, ERROR, OK, WARNING};
use crate::rng::Rng;

pub struct Sequence<'a, S: Standard> {
    pub fmu: &'a S::Fmu,
    pub model: Model,
    pub rng: Rng,
    pub seed: u64,
    pub trace: bool,
    pub insts: Vec<Inst>,
    pub handles: Vec<Handle>,
    pub serialized: Vec<(Vec<u8>, Snap)>,
    pub zeros: Vec<u64>,
    pub noise: Vec<u64>,
    pub stats: Stats,
    pub failure: Option<String>,
    /// Arguments for an importer's integrator step (set by [`Sequence::me_step`]): its
    /// calls use these instead of hostile ones.
    pub sane: bool,
    /// The importer's integrator step size (Model Exchange).
    pub h_me: f64,
    /// After the call: reading these variables of this instance, if it succeeds, returns
    /// these values, none of them NaN (what GetContinuousStates or GetDerivatives returned,
    /// what SetFloat64 set).
    pub same_as_variables: Option<(Component, Vec<u32>, Vec<f64>)>,
    pub extra: S::Extra,
}

/// Which of Model Exchange's array getters (the same signature in both standards).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MeArray {
    Derivatives,
    EventIndicators,
    ContinuousStates,
    Nominals,
}

/// What differs between FMI 2.0's and FMI 3.0's sequences: the functions and their state
/// table, instantiation, the importer's next call, the calls of one standard only; and the
/// C calls the shared machinery makes through either standard's functions.
pub trait Standard: Sized {
    type Fmu: 'static;
    /// The FMU's name, and what the sequences know of its model (from its
    /// modelDescription.xml).
    fn fmu_name(fmu: &Self::Fmu) -> &str;
    fn model(fmu: &Self::Fmu) -> Model;
    /// What a sequence of this standard keeps besides the shared state.
    type Extra: Default;
    /// The functions' names, by index.
    const NAMES: &'static [&'static str];
    const FREE_INSTANCE: usize;
    const FREE_FMU_STATE: usize;
    /// An importer's integrator step: get the states, the derivatives, set the time, the
    /// states, complete the step; then sometimes the event indicators (the last).
    const ME_STEP: [usize; 6];
    /// GetNominalsOfContinuousStates, the one Model Exchange array getter not in a step.
    const GET_NOMINALS: usize;

    fn status_name(s: Status) -> String;
    /// The standard's state table: whether an instance of `kind` in `st` may call
    /// `function`.
    fn allowed(function: usize, kind: Kind, st: St) -> bool;
    /// The interface type `function` belongs to (`None`: both).
    fn interface_of(function: usize) -> Option<Kind>;
    /// Whether `function` may return `s`.
    fn status_allowed(function: usize, s: Status) -> bool;
    /// Whether `function` may change the continuous states (other than by setting them).
    fn moves_states(function: usize) -> bool;

    /// What a sequence does before its first instance (the functions without one).
    fn begin(seq: &mut Sequence<Self>);
    /// What it does after its teardown (or its first failure).
    fn end(seq: &mut Sequence<Self>);
    /// Instantiates a new instance (hostile arguments sometimes).
    fn instantiate(seq: &mut Sequence<Self>);
    /// A well-formed instance with a logger (for cleaning up).
    fn clean_instance(seq: &mut Sequence<Self>);
    /// One call (or an importer's integrator step) chosen at random.
    fn random_call(seq: &mut Sequence<Self>);
    /// Calls `function` with generated arguments and checks what only it promises; its
    /// status (`None` for the free instance function, which returns none).
    fn dispatch(seq: &mut Sequence<Self>, call: Call) -> Option<Status>;

    // The C calls, each with its pointers as the caller gives them.
    /// # Safety
    /// As the standard's function of that name.
    unsafe fn free_instance(fmu: &Self::Fmu, c: Component);
    /// # Safety
    /// As the standard's function of that name.
    unsafe fn get_fmu_state(fmu: &Self::Fmu, c: Component, slot: *mut FmuState) -> Status;
    /// # Safety
    /// As the standard's function of that name.
    unsafe fn set_fmu_state(fmu: &Self::Fmu, c: Component, state: FmuState) -> Status;
    /// # Safety
    /// As the standard's function of that name.
    unsafe fn free_fmu_state(fmu: &Self::Fmu, c: Component, slot: *mut FmuState) -> Status;
    /// # Safety
    /// As the standard's function of that name.
    unsafe fn serialized_size(fmu: &Self::Fmu, c: Component, s: FmuState, n: *mut usize) -> Status;
    /// # Safety
    /// As the standard's function of that name.
    unsafe fn serialize(fmu: &Self::Fmu, c: Component, s: FmuState, b: *mut u8, n: usize)
        -> Status;
    /// # Safety
    /// As the standard's function of that name.
    unsafe fn deserialize(
        fmu: &Self::Fmu,
        c: Component,
        b: *const u8,
        n: usize,
        slot: *mut FmuState,
    ) -> Status;
    /// # Safety
    /// As the standard's function of that name.
    unsafe fn set_time(fmu: &Self::Fmu, c: Component, t: f64) -> Status;
    /// # Safety
    /// As the standard's function of that name.
    unsafe fn set_continuous_states(
        fmu: &Self::Fmu,
        c: Component,
        x: *const f64,
        n: usize,
    ) -> Status;
    /// # Safety
    /// As the standard's function of that name.
    unsafe fn get_me_array(
        fmu: &Self::Fmu,
        which: MeArray,
        c: Component,
        out: *mut f64,
        n: usize,
    ) -> Status;
    /// The values of `vrs` into `out` (as many as their elements).
    ///
    /// # Safety
    /// `c` is a live instance.
    unsafe fn get_values(fmu: &Self::Fmu, c: Component, vrs: &[u32], out: &mut [f64]) -> Status;
}

impl<'a, S: Standard> Sequence<'a, S> {
    pub fn new(fmu: &'a S::Fmu, model: Model, seed: u64, trace: bool) -> Self {
        let mut rng = Rng::new(seed);
        let noise = (0..8192).map(|_| rng.next_u64()).collect();
        Sequence {
            fmu,
            h_me: model.experiment.step / 4.0,
            model,
            rng,
            seed,
            trace,
            insts: vec![],
            handles: vec![],
            serialized: vec![],
            zeros: vec![0; 8192],
            noise,
            stats: Stats::default(),
            failure: None,
            sane: false,
            same_as_variables: None,
            extra: S::Extra::default(),
        }
    }

    pub(crate) fn note(&mut self, what: impl FnOnce() -> String) {
        if self.trace {
            let line = what();
            println!("  {line}");
        }
    }

    pub(crate) fn fail(&mut self, what: String) {
        if self.failure.is_none() {
            self.failure = Some(what);
        }
    }

    /// Runs the sequence; `Err` describes the first oracle violation.
    pub fn run(mut self) -> Result<Stats, String> {
        self.stats.sequences = 1;
        S::begin(&mut self);
        let long = self.rng.chance(0.1);
        let n_calls = 1 + self.rng.below(if long { 300 } else { 60 });
        S::instantiate(&mut self);
        for _ in 0..n_calls {
            if self.failure.is_some() {
                break;
            }
            S::random_call(&mut self);
        }
        if self.failure.is_none() {
            self.teardown();
        }
        S::end(&mut self);
        match self.failure.take() {
            None => Ok(self.stats.clone()),
            Some(f) => Err(format!("seed {}: {f}", self.seed)),
        }
    }

    /// The live instance of `t`, if it is one.
    pub(crate) fn inst(&mut self, t: Target) -> Option<&mut Inst> {
        match t {
            Target::Live(i) => Some(&mut self.insts[i]),
            _ => None,
        }
    }

    /// One explicit Euler step of an importer's integrator on Model Exchange instance `i`
    /// in continuous-time mode, each call checked as any other: the states and their
    /// derivatives, the time and states moved on, the step completed, sometimes the event
    /// indicators. Stops at the first call that does not succeed.
    pub(crate) fn me_step(&mut self, i: usize) {
        self.stats.me_steps += 1;
        self.sane = true;
        let (target, c) = (Target::Live(i), self.insts[i].c);
        let mut calls = S::ME_STEP[..5].to_vec();
        if self.rng.chance(0.3) {
            calls.push(S::ME_STEP[5]);
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

    /// Makes one call of `function` on `target` with generated arguments and checks the
    /// result; its status (`None` for the free instance function).
    pub(crate) fn call_on(
        &mut self,
        function: usize,
        target: Target,
        c: Component,
    ) -> Option<Status> {
        let before = match target {
            Target::Live(i) => {
                let inst = &mut self.insts[i];
                if S::moves_states(function) {
                    inst.x_set = None;
                }
                Some((inst.kind, inst.st, inst.sink.len()))
            }
            _ => None,
        };
        let legal = before.is_none_or(|(kind, st, _)| S::allowed(function, kind, st));
        let status = S::dispatch(self, Call::new(function, target, c, legal))?;
        self.stats.calls += 1;
        self.stats.statuses[(status as usize).min(5)] += 1;
        let name = S::NAMES[function];
        self.note(|| format!("  -> {}", S::status_name(status)));
        if let (true, Target::Live(i), Some((_, _, n))) = (self.trace, target, before) {
            if let Some(inst) = self.insts.get(i) {
                for m in inst.sink.since(n) {
                    println!("       [{}] {}", S::status_name(m.status), m.text);
                }
            }
        }
        if !S::status_allowed(function, status) {
            self.fail(format!(
                "{name} returned {} (not allowed)",
                S::status_name(status)
            ));
        }
        match (target, before) {
            (Target::Live(i), Some((kind, st_before, n_before))) => {
                self.check_messages(function, i, kind, st_before, n_before, legal, status)
            }
            _ => {
                if status != ERROR {
                    self.fail(format!(
                        "{name} on a {target:?} instance returned {}",
                        S::status_name(status)
                    ));
                }
            }
        }
        if let Some((c, vrs, got)) = self.same_as_variables.take() {
            let mut values = vec![f64::NAN; got.len()];
            // SAFETY: the live instance the call was made on.
            let g = unsafe { S::get_values(self.fmu, c, &vrs, &mut values) };
            self.stats.calls += 1;
            if g == OK
                && values
                    .iter()
                    .zip(&got)
                    .any(|(a, b)| a.to_bits() != b.to_bits() || a.is_nan())
            {
                self.fail(format!(
                    "{name} gave {got:?}, but reading those variables {vrs:?} returns {values:?} with {}",
                    S::status_name(g)
                ));
            }
        }
        Some(status)
    }

    /// The checks of a call on live instance `i` that returned `status`: the logger's
    /// contract, no caught panic, an illegal call refused with a message saying why, and
    /// a message of the status returned (none of a worse one).
    #[allow(clippy::too_many_arguments)]
    fn check_messages(
        &mut self,
        function: usize,
        i: usize,
        kind: Kind,
        st_before: St,
        n_before: usize,
        legal: bool,
        status: Status,
    ) {
        let name = S::NAMES[function];
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
            let expected = S::interface_of(function)
                .filter(|&k| k != kind)
                .map_or("illegal call sequence", Kind::name);
            if status != ERROR {
                self.fail(format!(
                    "{name} in state {st_before:?} of a {} instance (not allowed by the standard) returned {}",
                    kind.name(),
                    S::status_name(status)
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
                S::status_name(status),
                new.iter().map(|m| &m.text).collect::<Vec<_>>()
            ));
        }
        if let Some(m) = new.iter().find(|m| m.status > status && m.status != OK) {
            self.fail(format!(
                "{name} returned {} but logged a {} message: {}",
                S::status_name(status),
                S::status_name(m.status),
                m.text
            ));
        }
    }

    /// Frees every FMU state through a live instance, then the instances: every instance
    /// must be in a state it can be freed from.
    pub(crate) fn teardown(&mut self) {
        let can_free_states = |i: &Inst| S::allowed(S::FREE_FMU_STATE, i.kind, i.st);
        if !self.handles.is_empty() && !self.insts.iter().any(can_free_states) {
            // FMU states outlive the instance that made them: free them through a new one.
            S::clean_instance(self);
        }
        while let Some(h) = self.handles.pop() {
            let Some(i) = self.insts.iter().position(can_free_states) else {
                self.fail(format!(
                    "cannot free an FMU state: every instance is in a state that forbids it ({:?})",
                    self.insts.iter().map(|i| i.st).collect::<Vec<_>>()
                ));
                return;
            };
            let mut slot = h.ptr;
            // SAFETY: a live handle and a valid slot.
            let s = unsafe { S::free_fmu_state(self.fmu, self.insts[i].c, &mut slot) };
            self.stats.calls += 1;
            if s != OK || !slot.is_null() {
                self.fail(format!(
                    "teardown: {} returned {}",
                    S::NAMES[S::FREE_FMU_STATE],
                    S::status_name(s)
                ));
                return;
            }
        }
        while let Some(inst) = self.insts.pop() {
            if !S::allowed(S::FREE_INSTANCE, inst.kind, inst.st) {
                self.fail(format!(
                    "the instance is in state {:?}, from which {} is not allowed: it can never be freed (a leak)",
                    inst.st,
                    S::NAMES[S::FREE_INSTANCE]
                ));
                // Leave it: freeing it would be an illegal call.
                std::mem::forget(inst);
                return;
            }
            // SAFETY: a live instance, freed once.
            unsafe { S::free_instance(self.fmu, inst.c) };
            self.stats.calls += 1;
            for v in inst.sink.take_violations() {
                self.fail(format!("{}: {v}", S::NAMES[S::FREE_INSTANCE]));
            }
        }
    }
}

/// The index of the log category of status `s` (`logEvents` for OK).
pub fn category_index(s: Status) -> usize {
    match s {
        OK => 0,
        1 => 1,
        2 => 2,
        3 => 3,
        _ => 4,
    }
}

/// The part of a [`Standard`] implementation that is the same text in both standards: the
/// forwarding to the sequence's methods of the standard, and the C calls whose functions
/// have the same names and arguments in both tables (the derivatives getter's name, which
/// differs, given).
macro_rules! standard_c_calls {
    ($get_derivatives:ident) => {
        fn clean_instance(seq: &mut Sequence<Self>) {
            seq.clean_instance();
        }
        fn random_call(seq: &mut Sequence<Self>) {
            seq.random_call();
        }
        fn dispatch(
            seq: &mut Sequence<Self>,
            call: $crate::sequences::machine::Call,
        ) -> Option<Status> {
            seq.dispatch(call)
        }

        unsafe fn free_instance(fmu: &Self::Fmu, c: Component) {
            // SAFETY: the caller's promise.
            unsafe { (fmu.api.free_instance)(c) }
        }
        unsafe fn get_fmu_state(fmu: &Self::Fmu, c: Component, slot: *mut FmuState) -> Status {
            // SAFETY: the caller's promise.
            unsafe { (fmu.api.get_fmu_state)(c, slot) }
        }
        unsafe fn set_fmu_state(fmu: &Self::Fmu, c: Component, state: FmuState) -> Status {
            // SAFETY: the caller's promise.
            unsafe { (fmu.api.set_fmu_state)(c, state) }
        }
        unsafe fn free_fmu_state(fmu: &Self::Fmu, c: Component, slot: *mut FmuState) -> Status {
            // SAFETY: the caller's promise.
            unsafe { (fmu.api.free_fmu_state)(c, slot) }
        }
        unsafe fn serialized_size(
            fmu: &Self::Fmu,
            c: Component,
            s: FmuState,
            n: *mut usize,
        ) -> Status {
            // SAFETY: the caller's promise.
            unsafe { (fmu.api.serialized_fmu_state_size)(c, s, n) }
        }
        unsafe fn serialize(
            fmu: &Self::Fmu,
            c: Component,
            s: FmuState,
            b: *mut u8,
            n: usize,
        ) -> Status {
            // SAFETY: the caller's promise (FMI 2.0's bytes are C chars).
            unsafe { (fmu.api.serialize_fmu_state)(c, s, b.cast(), n) }
        }
        unsafe fn deserialize(
            fmu: &Self::Fmu,
            c: Component,
            b: *const u8,
            n: usize,
            slot: *mut FmuState,
        ) -> Status {
            // SAFETY: the caller's promise.
            unsafe { (fmu.api.deserialize_fmu_state)(c, b.cast(), n, slot) }
        }
        unsafe fn set_time(fmu: &Self::Fmu, c: Component, t: f64) -> Status {
            // SAFETY: the caller's promise.
            unsafe { (fmu.api.set_time)(c, t) }
        }
        unsafe fn set_continuous_states(
            fmu: &Self::Fmu,
            c: Component,
            x: *const f64,
            n: usize,
        ) -> Status {
            // SAFETY: the caller's promise.
            unsafe { (fmu.api.set_continuous_states)(c, x, n) }
        }
        unsafe fn get_me_array(
            fmu: &Self::Fmu,
            which: $crate::sequences::core::MeArray,
            c: Component,
            out: *mut f64,
            n: usize,
        ) -> Status {
            use $crate::sequences::core::MeArray;
            let g = match which {
                MeArray::Derivatives => fmu.api.$get_derivatives,
                MeArray::EventIndicators => fmu.api.get_event_indicators,
                MeArray::ContinuousStates => fmu.api.get_continuous_states,
                MeArray::Nominals => fmu.api.get_nominals_of_continuous_states,
            };
            // SAFETY: the caller's promise.
            unsafe { g(c, out, n) }
        }
    };
}
pub(crate) use standard_c_calls;
