//! PI step-size controller of `dopri5.f` (HNW I, IV.2, "Lund stabilization").
//!
//! The previous step's error enters with a small weight (`BETA`), which damps the
//! accept/reject oscillations a pure I-controller shows on mildly stiff problems.

/// Weight of the previous error (Hairer's default `BETA = 0.04`).
const BETA: f64 = 0.04;
/// Exponent of the current error: 1/5 for an order-4 estimate, minus the PI correction.
const EXPO1: f64 = 0.2 - BETA * 0.75;
/// Safety factor: aim a little below the tolerance so the next step is likely accepted.
const SAFE: f64 = 0.9;
/// `1/FAC1`: the step shrinks at most by 5 per step.
const MAX_SHRINK: f64 = 5.0;
/// `1/FAC2`: the step grows at most by 10 per step.
const MIN_INV_GROWTH: f64 = 0.1;
/// Floor of the remembered error, so a step with (nearly) zero error cannot make the
/// next proposal explode through the `err_prev^BETA` denominator.
pub(crate) const ERR_PREV_FLOOR: f64 = 1e-4;

/// Proposal after an accepted step (`err <= 1`); returns (next h, new err_prev).
pub(crate) fn after_accept(h: f64, err: f64, err_prev: f64) -> (f64, f64) {
    let fac = err.powf(EXPO1) / err_prev.powf(BETA);
    let fac = (fac / SAFE).clamp(MIN_INV_GROWTH, MAX_SHRINK);
    (h / fac, err.max(ERR_PREV_FLOOR))
}

/// Smaller step after a rejected step (`err > 1`, finite). The PI memory is left alone,
/// as in `dopri5.f`.
pub(crate) fn after_reject(h: f64, err: f64) -> f64 {
    h / (err.powf(EXPO1) / SAFE).min(MAX_SHRINK)
}
