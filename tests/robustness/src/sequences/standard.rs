//! What differs between the standards' sequences, as the shared machinery sees it: the
//! functions and their state table, the calls of one standard only, and the C calls the
//! shared code makes through either standard's functions.

use super::core::Sequence;
use super::machine::{Kind, St, Target};
use crate::ffi::{Component, FmuState, Status};

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
    /// What a sequence of this standard keeps besides the shared state.
    type Extra: Default;
    /// The functions' names, by index.
    const NAMES: &'static [&'static str];
    const FREE_INSTANCE: usize;
    const FREE_FMU_STATE: usize;
    /// An importer's integrator step: get the states, the derivatives, set the time, the
    /// states, complete the step; then sometimes the event indicators (the last).
    const ME_STEP: [usize; 6];

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
    fn dispatch(
        seq: &mut Sequence<Self>,
        function: usize,
        target: Target,
        c: Component,
        legal: bool,
    ) -> Option<Status>;

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
