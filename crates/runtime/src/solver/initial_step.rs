//! Hairer's initial step-size heuristic (HNW I, II.4, "Starting step size"; `HINIT`).
//!
//! Balances two guesses: one from the size of y relative to f (a step that changes y
//! by 1%), and one from an estimate of the second derivative so that the local error
//! of an method of order p is about the tolerance. Costs one extra rhs evaluation.

use super::norm::weighted_rms;
use super::{all_finite_entries, OdeSystem, Tolerance};

/// Proposes a first step from `(t, y)` with `f0 = f(t, y)`. The probe point stays
/// within `max_probe` (the distance to the communication point), so the rhs is never
/// evaluated beyond it; the returned step itself may be longer (the caller clamps and
/// remembers the longer step for later calls).
/// `y1`/`f1` are scratch. Returns the step and adds its rhs evaluations to `evals`.
#[allow(clippy::too_many_arguments)]
pub(crate) fn initial_step<S: OdeSystem + ?Sized>(
    sys: &mut S,
    t: f64,
    y: &[f64],
    f0: &[f64],
    max_probe: f64,
    tol: Tolerance,
    order: i32,
    y1: &mut [f64],
    f1: &mut [f64],
    evals: &mut u64,
) -> f64 {
    let dnf = weighted_rms(f0, y, tol);
    let dny = weighted_rms(y, y, tol);
    let h0 = if dnf <= 1e-5 || dny <= 1e-5 {
        // (HINIT compares the squares with 1e-10.)
        1e-6
    } else {
        0.01 * dny / dnf
    };
    // The probe stays inside the interval, but a shorter probe still estimates y''
    // (only with more rounding noise), so the proposal is not capped by a short first
    // communication step.
    let h_probe = h0.min(max_probe);

    // Explicit Euler probe to estimate ‖y''‖.
    for ((y1i, &yi), &fi) in y1.iter_mut().zip(y).zip(f0) {
        *y1i = yi + h_probe * fi;
    }
    if !all_finite_entries(y1) {
        // The probe point overflowed: the rhs is never fed it. Start small, as below.
        return h_probe;
    }
    sys.rhs(t + h_probe, y1, f1);
    *evals += 1;
    for (f1i, &fi) in f1.iter_mut().zip(f0) {
        *f1i -= fi;
    }
    let der2 = weighted_rms(f1, y, tol) / h_probe;
    if !der2.is_finite() {
        // The probe hit a NaN/overflow; start small and let step control sort it out.
        return h_probe;
    }
    let der12 = der2.max(dnf);
    let h1 = if der12 <= 1e-15 {
        (h0 * 1e-3).max(1e-6)
    } else {
        libm::pow(0.01 / der12, 1.0 / f64::from(order))
    };
    (100.0 * h0).min(h1)
}
