//! The entry points of `mechfmu bench` (the runtime's `bench` feature): an instance's work
//! counters, and the parts of a step run alone in the FMU's own compiled code. Not FMI
//! functions; they log nothing.

use crate::fmi::boundary::{guarded_or, instance, slice_mut};
use crate::fmi::Version;
use crate::fmi2::ffi::*;
use crate::model::Mechanism;
use crate::simulation::Part;

/// Number of counters [`counters`] reports.
pub const COUNTERS: usize = 4;

/// Copies the instance's cumulative work counters into `out` (at most `n` of them, in the
/// order: communication steps, accepted solver steps, rejected solver steps, model
/// evaluations) and returns how many there are ([`COUNTERS`]); 0 if `c` is not a live
/// instance. Any state.
///
/// # Safety
/// `c` as for the FMI functions; `out` is NULL or points to `n` writable counters.
pub unsafe fn counters<M: Mechanism>(c: fmi2Component, out: *mut u64, n: usize) -> usize {
    guarded_or(0, || {
        // SAFETY: the caller's promise.
        let Some(inst) = (unsafe { instance::<M>(c, Version::Fmi2) }) else {
            return 0;
        };
        let k = inst.sim.counters();
        let all = [k.steps, k.accepted, k.rejected, k.evaluations];
        // SAFETY: the caller's promise.
        if let Ok(out) = unsafe { slice_mut(out, n.min(COUNTERS), "out") } {
            out.copy_from_slice(&all[..out.len()]);
        }
        COUNTERS
    })
}

/// Repeats one part of a communication step `n` times on a copy of the instance's
/// simulation (the codes of [`Part`]; see
/// [`Simulation::bench`](crate::simulation::Simulation::bench)), so a benchmark can time
/// the parts from outside. Changes nothing.
///
/// # Safety
/// `c` as for the FMI functions.
pub unsafe fn bench<M: Mechanism>(c: fmi2Component, part: u32, n: u64, h: f64) -> fmi2Status {
    guarded_or(fmi2Error, || {
        // SAFETY: the caller's promise.
        let Some(inst) = (unsafe { instance::<M>(c, Version::Fmi2) }) else {
            return fmi2Error;
        };
        let Some(part) = Part::from_code(part) else {
            return fmi2Error;
        };
        match inst.sim.bench(part, n, h) {
            Ok(sum) => {
                std::hint::black_box(sum);
                fmi2OK
            }
            Err(_) => fmi2Error,
        }
    })
}
