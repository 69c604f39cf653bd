//! Where, inside an accepted step, the system stops holding: the integration then ends at
//! that time rather than at the step's start, so an importer learns when a limit was
//! crossed (to a few units in the last place of the time, with the method's accuracy).
//!
//! Bisection on [`OdeSystem::valid_at`] over the step, each probe's states computed by one
//! step of the method from the step's start to the probe (as accurate as the step itself:
//! an interpolant of lower order would misplace the crossing by more than the tolerance).
//! It runs once, where a simulation ends, so its cost (a method step per halving) does not
//! matter.

use super::{all_finite, OdeSystem, StateVector};

/// Halvings at most: a step of size h is resolved to h·2⁻⁶⁴, or to one ulp of the time.
const MAX_HALVINGS: u32 = 64;

/// A point in `[t0, t1)` where `sys` is valid next to one where it is not (within the
/// resolution of [`MAX_HALVINGS`]): its time and states (`t0` and `y0` if none further).
/// With a single crossing in the step, as within one accepted step of a limit's indicator,
/// that is the crossing. `state_at(sys, t)` gives the states at `t` in `(t0, t1)`.
pub fn last_valid_point<V: StateVector, S: OdeSystem + ?Sized>(
    sys: &mut S,
    (t0, y0): (f64, &V),
    t1: f64,
    mut state_at: impl FnMut(&mut S, f64) -> V,
) -> (f64, V) {
    let (mut lo, mut hi) = (t0, t1);
    let mut y_lo = *y0;
    for _ in 0..MAX_HALVINGS {
        let mid = lo + 0.5 * (hi - lo);
        if mid <= lo || mid >= hi {
            break;
        }
        let y_mid = state_at(sys, mid);
        if all_finite(&y_mid) && sys.valid_at(mid, y_mid.as_slice()) {
            (lo, y_lo) = (mid, y_mid);
        } else {
            hi = mid;
        }
    }
    (lo, y_lo)
}
