//! A counting allocator, and the check that the FMI functions an importer calls at every
//! communication step (`fmi2SetReal`, `fmi2DoStep`, `fmi2GetReal`; through FMI 3.0
//! `fmi3SetFloat64`, `fmi3DoStep`, `fmi3GetFloat64`: [`fmi3`]) never allocate once an
//! instance is running. The functions are the real ones (`mechfmu::fmi2::functions`,
//! `mechfmu::fmi3::functions`, what `export_fmu!` exports), called in-process on the
//! mechanism crates.
//!
//! The counts are per thread, so tests running in parallel do not see each other's
//! allocations. The counting allocator is the global one of the test binaries that call
//! [`allocation_tests!`](crate::allocation_tests) (a mechanism crate's `tests/allocations.rs`),
//! and of no other.

pub mod fmi3;

use crate::harness::Harness;
use mechfmu::fmi2::ffi::*;
use mechfmu::fmi2::functions;
use mechfmu::model::{Causality, Mechanism, Variability};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

/// The system allocator, counting the allocations of each thread.
pub struct Counting;

thread_local! {
    // Const-initialized and without destructor: using them never allocates.
    static CALLS: Cell<u64> = const { Cell::new(0) };
    static BYTES: Cell<u64> = const { Cell::new(0) };
}

fn count(bytes: usize) {
    // `try_with`: the thread's locals may already be gone while it exits.
    let _ = CALLS.try_with(|c| c.set(c.get() + 1));
    let _ = BYTES.try_with(|b| b.set(b.get() + bytes as u64));
}

// SAFETY: forwards every call to the system allocator unchanged.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count(layout.size());
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        count(layout.size());
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count(new_size);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
}

/// (allocations, bytes) made by the calling thread so far.
pub fn allocated() -> (u64, u64) {
    (CALLS.with(Cell::get), BYTES.with(Cell::get))
}

/// What one check did, for the test's message.
#[derive(Debug, Default)]
pub struct Work {
    pub steps: u64,
    pub gets: u64,
    pub sets: u64,
}

/// The value references of `M`'s variables that `keep` selects.
fn vrs<M: Mechanism>(keep: impl Fn(&mechfmu::model::Variable) -> bool) -> Vec<fmi2ValueReference> {
    M::VARIABLES
        .iter()
        .enumerate()
        .filter(|(_, v)| keep(v))
        .map(|(vr, _)| vr as fmi2ValueReference)
        .collect()
}

/// Runs `M` through its FMI functions as an importer does: initialization, 20 cycles of
/// warm-up, then `n` measured cycles, each `fmi2SetReal` of every input (to a slightly
/// different value each time), of every tunable parameter (every 10th cycle, when
/// `tunables`), `fmi2DoStep`, and `fmi2GetReal` of every variable and of the outputs.
/// Panics unless the measured cycles allocated nothing.
fn run<M: Mechanism>(n: u64, tunables: bool) -> Work {
    let e = M::EXPERIMENT;
    let mut fmu = Harness::<M>::new();
    fmu.initialize(Some(e.tolerance), e.start, &[])
        .unwrap_or_else(|m| panic!("{}: {m}", M::NAME));
    let c = fmu.component();
    let all = vrs::<M>(|_| true);
    let outputs = vrs::<M>(|v| v.causality == Causality::Output);
    let inputs = vrs::<M>(|v| v.causality == Causality::Input);
    let tunable = if tunables {
        vrs::<M>(|v| v.causality == Causality::Parameter && v.variability == Variability::Tunable)
    } else {
        Vec::new()
    };
    let mut values = vec![0.0; all.len()];
    let mut out = vec![0.0; outputs.len()];
    fmu.get_real(&all, &mut values);
    let input_start: Vec<f64> = inputs.iter().map(|&vr| values[vr as usize]).collect();
    let mut input_values = input_start.clone();
    let tunable_values: Vec<f64> = tunable.iter().map(|&vr| values[vr as usize]).collect();

    let h = e.step;
    let mut t = e.start;
    let cycle = |i: u64, work: &mut Work| {
        for (v, &s) in input_values.iter_mut().zip(&input_start) {
            *v = s + 1e-9 * (i % 7) as f64;
        }
        // SAFETY: a live instance; every array has the length passed with it.
        unsafe {
            if !inputs.is_empty() {
                let s = functions::fmi2SetReal::<M>(
                    c,
                    inputs.as_ptr(),
                    inputs.len(),
                    input_values.as_ptr(),
                );
                assert_eq!(s, fmi2OK, "{}: fmi2SetReal of the inputs", M::NAME);
                work.sets += 1;
            }
            if i.is_multiple_of(10) && !tunable.is_empty() {
                let s = functions::fmi2SetReal::<M>(
                    c,
                    tunable.as_ptr(),
                    tunable.len(),
                    tunable_values.as_ptr(),
                );
                assert_eq!(
                    s,
                    fmi2OK,
                    "{}: fmi2SetReal of the tunable parameters",
                    M::NAME
                );
                work.sets += 1;
            }
            let s = functions::fmi2DoStep::<M>(c, t, h, fmi2True);
            assert_eq!(s, fmi2OK, "{}: fmi2DoStep({t}, {h})", M::NAME);
            work.steps += 1;
            t += h;
            assert_eq!(
                functions::fmi2GetReal::<M>(c, all.as_ptr(), all.len(), values.as_mut_ptr()),
                fmi2OK
            );
            assert_eq!(
                functions::fmi2GetReal::<M>(c, outputs.as_ptr(), outputs.len(), out.as_mut_ptr()),
                fmi2OK
            );
            work.gets += 2;
        }
    };
    // Whatever the warm-up allocates lazily (there should be nothing) is not counted.
    let work = assert_allocates_nothing(M::NAME, n, cycle);
    let messages = fmu.messages();
    assert!(
        messages.iter().all(|(s, _, _)| *s == fmi2OK),
        "{}: {messages:?}",
        M::NAME
    );
    work
}

/// Runs `cycle` 20 times to warm up (whatever is allocated lazily is allocated there), then
/// `n` times, counted: asserts those allocated nothing (`what` names the run in the failure)
/// and returns their work.
fn assert_allocates_nothing(what: &str, n: u64, mut cycle: impl FnMut(u64, &mut Work)) -> Work {
    let mut warm = Work::default();
    for i in 0..20 {
        cycle(i, &mut warm);
    }
    let mut work = Work::default();
    let before = allocated();
    for i in 0..n {
        cycle(i, &mut work);
    }
    let after = allocated();
    assert_eq!(
        (after.0 - before.0, after.1 - before.1),
        (0, 0),
        "{what}: {work:?} made (allocations, bytes) = {:?}",
        (after.0 - before.0, after.1 - before.1)
    );
    work
}

/// The importer's loop: `fmi2SetReal` of the inputs, `fmi2DoStep`, `fmi2GetReal` of every
/// variable and of the outputs, `n` times after warm-up: no allocation at all.
pub fn check<M: Mechanism>(n: u64) -> Work {
    run::<M>(n, false)
}

/// As [`check`], with every tunable parameter set again every 10th step (which runs the
/// mechanism's `calculate`): no allocation either.
pub fn check_with_tunables<M: Mechanism>(n: u64) -> Work {
    run::<M>(n, true)
}

/// The allocation tests of one mechanism, with the counting allocator as the test
/// binary's global one: the importer's loop through FMI 2.0, the same with tunable
/// parameters set every tenth step, and the loop through FMI 3.0, each over 2,000
/// communication steps. A test file of its own calls it once (its binary then counts every
/// allocation).
#[macro_export]
macro_rules! allocation_tests {
    ($mechanism:ty) => {
        #[global_allocator]
        static ALLOCATOR: $crate::allocations::Counting = $crate::allocations::Counting;

        /// Without the counting allocator as the global one, every check would pass.
        #[test]
        fn the_counting_allocator_counts() {
            let before = $crate::allocations::allocated();
            std::hint::black_box(Box::new(0u64));
            let after = $crate::allocations::allocated();
            assert_eq!((after.0 - before.0, after.1 - before.1), (1, 8));
        }

        #[test]
        fn the_importer_loop_allocates_nothing() {
            let work = $crate::allocations::check::<$mechanism>(2_000);
            assert_eq!(work.steps, 2_000);
        }

        #[test]
        fn setting_tunable_parameters_allocates_nothing() {
            let work = $crate::allocations::check_with_tunables::<$mechanism>(2_000);
            assert_eq!(work.steps, 2_000);
        }

        #[test]
        fn the_importer_loop_through_fmi3_allocates_nothing() {
            let work = $crate::allocations::fmi3::check::<$mechanism>(2_000);
            assert_eq!(work.steps, 2_000);
        }
    };
}
