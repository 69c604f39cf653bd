//! Hairer's mixed absolute/relative RMS norm (HNW I, II.4, eq. (4.11)).

use super::Tolerance;

/// `1 / (atol + rtol·max(|a|, |b|))`, the weight of a component whose values are `a` and
/// `b`. Both endpoints of a step are known before its last stage is evaluated, so the
/// division runs while the model does; the error, known only after that stage, is then
/// multiplied by it ([`ratio_sq`]) rather than divided on the chain to the next step size.
/// `a` and `b` are finite (the solver checks every point): a plain comparison picks the
/// larger, with no NaN case for `max` to handle.
#[inline(always)]
pub(crate) fn inverse_scale(tol: Tolerance, a: f64, b: f64) -> f64 {
    let (a, b) = (a.abs(), b.abs());
    1.0 / (tol.atol + tol.rtol * if a > b { a } else { b })
}

/// `(num · inv_scale)^2` for `inv_scale` from [`inverse_scale`], with a zero `num` counted
/// as 0, so pure relative control (`atol == 0`, a zero scale, an infinite weight) does not
/// turn an exactly-zero component into NaN.
#[inline(always)]
pub(crate) fn ratio_sq(num: f64, inv_scale: f64) -> f64 {
    if num == 0.0 {
        0.0
    } else {
        let r = num * inv_scale;
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
        .map(|(&e, (&a, &b))| ratio_sq(e, inverse_scale(tol, a, b)))
        .sum();
    // Times 1/n, not over n: a constant, where the division would wait for the sum.
    sum * (1.0 / err.len() as f64)
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
        .map(|(&x, &yi)| ratio_sq(x, inverse_scale(tol, yi, 0.0)))
        .sum();
    (sum / v.len() as f64).sqrt()
}
