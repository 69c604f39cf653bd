//! Hairer's mixed absolute/relative RMS norm (HNW I, II.4, eq. (4.11)).

use super::Tolerance;

/// `(num / scale)^2`, with `0/0` counted as 0 so pure relative control (`atol == 0`)
/// does not turn an exactly-zero component into NaN.
#[inline]
pub(crate) fn ratio_sq(num: f64, scale: f64) -> f64 {
    if num == 0.0 {
        0.0
    } else {
        let r = num / scale;
        r * r
    }
}

/// The square of the RMS over i of `err_i / (atol + rtol·max(|y_i|, |y_new_i|))`; a step
/// is acceptable when this is ≤ 1. Using the larger of the two endpoints keeps components
/// that pass near zero from demanding absurdly small steps. Returns 0 for an empty system.
/// Squared, so that no square root delays the step-size controller (see
/// [`Method::attempt`](super::Method::attempt)).
#[inline(always)]
pub(crate) fn error_norm_squared(err: &[f64], y: &[f64], y_new: &[f64], tol: Tolerance) -> f64 {
    debug_assert!(err.len() == y.len() && y.len() == y_new.len());
    if err.is_empty() {
        return 0.0;
    }
    let sum: f64 = err
        .iter()
        .zip(y.iter().zip(y_new))
        .map(|(&e, (&a, &b))| ratio_sq(e, tol.atol + tol.rtol * a.abs().max(b.abs())))
        .sum();
    sum / err.len() as f64
}

/// RMS of `v_i / (atol + rtol·|y_i|)`, the norm the initial step heuristic uses.
pub(crate) fn weighted_rms(v: &[f64], y: &[f64], tol: Tolerance) -> f64 {
    debug_assert!(v.len() == y.len());
    if v.is_empty() {
        return 0.0;
    }
    let sum: f64 = v
        .iter()
        .zip(y)
        .map(|(&x, &yi)| ratio_sq(x, tol.atol + tol.rtol * yi.abs()))
        .sum();
    (sum / v.len() as f64).sqrt()
}
