//! Random FMI call sequences with hostile arguments, checked against an oracle, for FMI 2.0
//! ([`Fmi2`]) and FMI 3.0 ([`Fmi3`]) alike.
//!
//! A sequence instantiates one or two instances, each for Model Exchange or Co-Simulation
//! (FMI 3.0's Co-Simulation with or without event mode and early return), and makes random
//! calls of all the standard's functions (44 of FMI 2.0, 75 of FMI 3.0): half of them
//! chosen among those the standard allows in the instance's state and interface type (so
//! sequences get deep: initialized, stepping or integrating, in event mode, failed,
//! restored), half among all (so the other interface type's functions, and FMI 3.0's
//! functions of features not offered, are called too), with arguments drawn from sane and
//! hostile values (NULL instance and array pointers, foreign pointers to memory that is
//! not an instance, value references out of range, NaN/±inf/huge values, bad step sizes
//! and communication points, huge or non-finite times, state and derivative arrays of the
//! wrong length, FMU states of this instance and of the other one (of the other interface
//! type too), serialized bytes that are valid, corrupted, random, or corrupted with a
//! repaired checksum). FMI 3.0 adds misaligned pointers, instances and FMU states of FMI
//! 2.0 made by the same binary (and FMI 2.0's serialized states), `nValues` that do not
//! count the elements of the arrays asked, a symmetric matrix set asymmetric, the
//! independent variable set, out arguments left NULL. A Model Exchange instance in
//! continuous-time mode is also driven as an importer's integrator would: explicit Euler
//! steps through GetContinuousStates, GetDerivatives, SetTime, SetContinuousStates,
//! CompletedIntegratorStep and GetEventIndicators.
//!
//! The machinery both standards share (the sequence, its instances and FMU states, the
//! argument generators, the checks after every call, the FMU state and Model Exchange
//! array calls, the teardown) is written once over [`Standard`]; each standard adds its
//! state table, instantiation, the importer's next call and its calls of its own.
//!
//! The oracle keeps its own copy of the standards' state machines (FMI 2.0 sections 3.2.3
//! and 4.2.4, FMI 3.0 sections 2.3, 3.2 and 4.2) and checks after every call:
//! - the status is one the standard allows for the function (never Fatal or fmi2Pending,
//!   Discard only from DoStep, GetDerivatives, GetEventIndicators and FMI 2.0's status
//!   getters);
//! - a call the state table forbids returns Error and says "illegal call sequence"; a
//!   function of the other interface type returns Error and names the interface type;
//!   an FMU state saved by an instance of the other interface type (or, in FMI 3.0, of
//!   the other standard, or in event mode for a Co-Simulation instance without it) is
//!   refused with Error, one this sequence saved otherwise restores; a call on anything
//!   but a live instance of the standard returns Error; FMI 3.0's functions of features not offered (clocks,
//!   configuration mode, Scheduled Execution, per-element dependencies) return Error;
//! - every status other than OK comes with a logged message of that status (when the
//!   importer gave a logger and has not switched that category off);
//! - the logger is always called with a declared category and UTF-8 text (FMI 2.0's with
//!   "%s"), and no message reports a caught panic ("internal error");
//! - no NaN is returned after OK (values, directional, adjoint and output derivatives,
//!   statuses), and nothing that is not finite from GetDerivatives, GetEventIndicators,
//!   GetContinuousStates and GetNominalsOfContinuousStates (nominals > 0); nothing is
//!   written past the elements of an output array; every boolean written is 0 or 1;
//! - Model Exchange arrays: a wrong `nx`/`ni`, a NULL array or non-finite states given to
//!   SetContinuousStates return Error; finite states of the right number are accepted and
//!   GetContinuousStates returns them bit for bit; what GetContinuousStates and
//!   GetDerivatives return is what reading the state and derivative variables returns;
//!   SetTime accepts a finite time and refuses any other; SetReal/SetFloat64 in
//!   continuous-time mode accepts continuous inputs only;
//! - FMI 3.0 values: value references that are no variable, `nValues` other than the
//!   elements asked, NULL or misaligned arrays return Error; values set with OK read back
//!   bit for bit; the number of continuous states and event indicators is the
//!   modelDescription's;
//! - after DoStep returns OK the values are not NaN; after a step that ended the
//!   simulation (fmi2Discard, fmi3Discard, an FMI 3.0 early return) terminateSimulation is
//!   true and the last successful time lies in the step; FMI 3.0 returns early only when
//!   the instance allows it and the modelDescription says it might, asks for event
//!   handling only with event mode, and after OK its last successful time is t + h;
//! - every instance can be freed at the end (no state the instance cannot leave);
//! - allocateMemory/freeMemory/stepFinished/intermediateUpdate are never called (they
//!   abort the process).

mod args;
mod core;
mod fmi2;
mod fmi3;
mod fmu_states;
mod hostile;
mod machine;
mod me_calls;
mod model;
mod state_bytes;
mod stats;

pub use self::core::{Sequence, Standard};
pub use fmi2::{allowed, Fmi2};
pub use fmi3::Fmi3;
pub use machine::{Kind, St};
pub use state_bytes::{fix_checksum, fnv, layout, mutate_semantically, Layout};
pub use stats::Stats;

/// Runs `count` sequences of `fmu` (of standard `S`) with seeds `first..first + count`;
/// prints `begin <seed>` before each (so a crash can be attributed) when `announce`.
/// Returns the statistics and the failures (each naming its seed).
pub fn run_many<S: Standard>(
    fmu: &S::Fmu,
    first: u64,
    count: u64,
    announce: bool,
    trace: bool,
) -> (Stats, Vec<String>) {
    let mut stats = Stats::default();
    let mut failures = vec![];
    for seed in first..first + count {
        if announce {
            println!("begin {seed}");
        }
        if trace {
            println!("sequence seed {seed} on {}", S::fmu_name(fmu));
        }
        match Sequence::<S>::new(fmu, S::model(fmu), seed, trace).run() {
            Ok(s) => stats.add(&s),
            Err(f) => {
                stats.sequences += 1;
                failures.push(f);
            }
        }
    }
    (stats, failures)
}
