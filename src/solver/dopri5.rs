//! The Dormand–Prince 5(4) pair (HNW I, II.5, Table 5.2) and the adaptive driver.
//!
//! Local extrapolation: the 5th-order solution is propagated, the embedded 4th-order
//! one only serves the error estimate. FSAL: the 7th stage is f at the new point and
//! becomes the next step's first stage, so an accepted step costs 6 rhs evaluations.

use super::controller::{self, ERR_PREV_FLOOR};
use super::initial_step::initial_step;
use super::norm::error_norm;
use super::{OdeSystem, SolverError, SolverMemory, StepStats, Tolerance, MIN_RTOL};

// Nodes c_i.
const C2: f64 = 1.0 / 5.0;
const C3: f64 = 3.0 / 10.0;
const C4: f64 = 4.0 / 5.0;
const C5: f64 = 8.0 / 9.0;
// Coupling coefficients a_ij.
const A21: f64 = 1.0 / 5.0;
const A31: f64 = 3.0 / 40.0;
const A32: f64 = 9.0 / 40.0;
const A41: f64 = 44.0 / 45.0;
const A42: f64 = -56.0 / 15.0;
const A43: f64 = 32.0 / 9.0;
const A51: f64 = 19372.0 / 6561.0;
const A52: f64 = -25360.0 / 2187.0;
const A53: f64 = 64448.0 / 6561.0;
const A54: f64 = -212.0 / 729.0;
const A61: f64 = 9017.0 / 3168.0;
const A62: f64 = -355.0 / 33.0;
const A63: f64 = 46732.0 / 5247.0;
const A64: f64 = 49.0 / 176.0;
const A65: f64 = -5103.0 / 18656.0;
// 5th-order weights b_i (= row 7 of A, which is what makes FSAL work; b2 = b7 = 0).
const B1: f64 = 35.0 / 384.0;
const B3: f64 = 500.0 / 1113.0;
const B4: f64 = 125.0 / 192.0;
const B5: f64 = -2187.0 / 6784.0;
const B6: f64 = 11.0 / 84.0;
// Error weights e_i = b_i - b̂_i (5th minus embedded 4th order; e2 = 0).
const E1: f64 = 71.0 / 57600.0;
const E3: f64 = -71.0 / 16695.0;
const E4: f64 = 71.0 / 1920.0;
const E5: f64 = -17253.0 / 339200.0;
const E6: f64 = 22.0 / 525.0;
const E7: f64 = -1.0 / 40.0;

/// A leftover shorter than this fraction of the step is absorbed into the step
/// instead of being taken as a micro-step.
const STRETCH: f64 = 1e-10;
/// Shrink factor after a step produced NaN/inf: there is no error estimate to scale by.
const NON_FINITE_SHRINK: f64 = 10.0;
const DEFAULT_MAX_STEPS: u64 = 1_000_000;

/// Smallest step allowed at time `t`; below it `t + h` no longer moves reliably.
fn h_min(t: f64) -> f64 {
    16.0 * f64::EPSILON * t.abs().max(1.0)
}

/// `out = y + h·Σ a_j k_j`, summed in the given order; false if any entry is non-finite.
fn combine<const N: usize>(out: &mut [f64], y: &[f64], h: f64, terms: [(f64, &[f64]); N]) -> bool {
    let mut finite = true;
    for (i, (o, &yi)) in out.iter_mut().zip(y).enumerate() {
        let mut acc = 0.0;
        for &(a, k) in &terms {
            acc += a * k[i];
        }
        *o = yi + h * acc;
        finite &= o.is_finite();
    }
    finite
}

fn all_finite(v: &[f64]) -> bool {
    v.iter().all(|x| x.is_finite())
}

/// Adaptive Dormand–Prince 5(4) integrator for systems of a fixed dimension.
#[derive(Clone, Debug)]
pub struct Dopri5 {
    dim: usize,
    max_steps: u64,
    mem: SolverMemory,
    k1: Vec<f64>,
    k2: Vec<f64>,
    k3: Vec<f64>,
    k4: Vec<f64>,
    k5: Vec<f64>,
    k6: Vec<f64>,
    k7: Vec<f64>,
    /// Stage argument (also the initial-step probe point).
    y_stage: Vec<f64>,
    y_new: Vec<f64>,
    /// Local error estimate `h·Σ e_i k_i` of the last attempted step.
    err: Vec<f64>,
    /// rhs evaluations during the current call.
    evals: u64,
}

impl Dopri5 {
    /// Allocates all work vectors up front so `integrate` never allocates.
    pub fn new(dim: usize) -> Self {
        let v = || vec![0.0; dim];
        Dopri5 {
            dim,
            max_steps: DEFAULT_MAX_STEPS,
            mem: SolverMemory::FRESH,
            k1: v(),
            k2: v(),
            k3: v(),
            k4: v(),
            k5: v(),
            k6: v(),
            k7: v(),
            y_stage: v(),
            y_new: v(),
            err: v(),
            evals: 0,
        }
    }

    /// Length of the state vector this solver was built for.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Limit on step attempts (accepted + rejected) per `integrate` call; default 1_000_000.
    pub fn set_max_steps(&mut self, n: u64) {
        self.max_steps = n;
    }

    /// Advance y from *t to exactly t_end (t_end > *t; t_end == *t is a no-op Ok).
    ///
    /// On success `*t == t_end` exactly (it is assigned; the last step is clamped to land
    /// on `t_end`, and a leftover below 1e-10·h is absorbed by stretching the step).
    /// The rhs is never evaluated beyond `t_end`. On error, `*t` and `y` hold the last
    /// accepted point (finite), and the error carries that time.
    ///
    /// k1 is recomputed at the start of each call, so inputs may change between calls.
    /// The step size proposed at the end is remembered for the next call; a last step
    /// that was shortened to land on `t_end` does not shrink it (unless its own error
    /// asked for a smaller step). A zero-dimensional system is a no-op (`*t = t_end`,
    /// no callbacks).
    ///
    /// # Errors
    /// [`SolverError`] when the tolerance cannot be met above the minimum step
    /// (16·ε·max(|t|, 1)), the rhs keeps producing NaN/inf, the step budget is used up,
    /// or `OdeSystem::accepted` asks to stop. The solver memory is that after the last
    /// accepted step.
    ///
    /// # Panics
    /// If `y.len() != self.dim()`, if `*t` or `t_end` is not finite or `t_end < *t`,
    /// or if a tolerance is negative or not finite. These are caller bugs; the FMU
    /// layer validates them before calling.
    pub fn integrate<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
        t: &mut f64,
        t_end: f64,
        y: &mut [f64],
        tol: Tolerance,
    ) -> Result<StepStats, SolverError> {
        assert_eq!(
            y.len(),
            self.dim,
            "state length does not match solver dimension"
        );
        assert!(
            t.is_finite() && t_end.is_finite() && t_end >= *t,
            "integrate needs finite t <= t_end, got t = {} and t_end = {t_end}",
            *t
        );
        assert!(
            tol.rtol.is_finite() && tol.rtol >= 0.0 && tol.atol.is_finite() && tol.atol >= 0.0,
            "tolerances must be finite and non-negative, got {tol:?}"
        );
        let mut stats = StepStats::default();
        if t_end == *t {
            return Ok(stats);
        }
        if self.dim == 0 {
            *t = t_end;
            return Ok(stats);
        }
        let tol = Tolerance {
            rtol: tol.rtol.max(MIN_RTOL),
            atol: tol.atol,
        };
        self.evals = 0;
        let result = self.run(sys, t, t_end, y, tol, &mut stats);
        stats.rhs_evals = self.evals;
        result.map(|()| stats)
    }

    fn run<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
        t: &mut f64,
        t_end: f64,
        y: &mut [f64],
        tol: Tolerance,
        stats: &mut StepStats,
    ) -> Result<(), SolverError> {
        if !all_finite(y) {
            return Err(SolverError::NonFinite { t: *t });
        }
        sys.rhs(*t, y, &mut self.k1);
        self.evals += 1;
        if !all_finite(&self.k1) {
            return Err(SolverError::NonFinite { t: *t });
        }

        let mut h = match self.mem.h_next {
            Some(h) if h.is_finite() && h > 0.0 => h,
            _ => initial_step(
                sys,
                *t,
                y,
                &self.k1,
                t_end - *t,
                tol,
                &mut self.y_stage,
                &mut self.k2,
                &mut self.evals,
            ),
        };
        let mut err_prev = if self.mem.err_prev.is_finite() {
            self.mem.err_prev.max(ERR_PREV_FLOOR)
        } else {
            ERR_PREV_FLOOR
        };
        // After a rejection the next accepted step may not grow (dopri5.f `REJECT`).
        // Every call ends on an accepted step, so this never needs to be remembered.
        let mut last_rejected = false;
        let mut attempts: u64 = 0;

        loop {
            if attempts >= self.max_steps {
                return Err(SolverError::TooManySteps {
                    t: *t,
                    max_steps: self.max_steps,
                });
            }
            attempts += 1;

            // A step below h_min may not move t at all; only the final remainder may be
            // that short.
            h = h.max(h_min(*t));
            let remaining = t_end - *t;
            let last = remaining <= h * (1.0 + STRETCH);
            let h_step = if last { remaining } else { h };
            let t_new = if last { t_end } else { *t + h_step };

            let finite = self.stages(sys, *t, h_step, t_new, y);
            let err = if finite {
                error_norm(&self.err, y, &self.y_new, tol)
            } else {
                f64::NAN
            };

            if !err.is_finite() {
                stats.rejected += 1;
                last_rejected = true;
                h = h_step / NON_FINITE_SHRINK;
                if h < h_min(*t) {
                    return Err(SolverError::NonFinite { t: *t });
                }
            } else if err > 1.0 {
                stats.rejected += 1;
                last_rejected = true;
                h = controller::after_reject(h_step, err);
                if h < h_min(*t) {
                    return Err(SolverError::StepSizeTooSmall { t: *t, h });
                }
            } else {
                stats.accepted += 1;
                let (mut h_new, e) = controller::after_accept(h_step, err, err_prev);
                err_prev = e;
                if last_rejected {
                    h_new = h_new.min(h_step);
                }
                last_rejected = false;
                if last && h_new >= h_step {
                    // Clamping, not the error, made this step short: keep the longer
                    // step for the next call.
                    h_new = h_new.max(h);
                }
                // The system may refuse the new point (the model stops holding there): then
                // the integration ends at the last point it accepted, which y and t still hold.
                if let Err(message) = sys.accepted(t_new, &self.y_new) {
                    return Err(SolverError::Stopped { t: *t, message });
                }
                y.copy_from_slice(&self.y_new);
                std::mem::swap(&mut self.k1, &mut self.k7);
                *t = t_new;
                self.mem = SolverMemory {
                    h_next: Some(h_new),
                    err_prev,
                };
                if last {
                    return Ok(());
                }
                h = h_new;
            }
        }
    }

    /// Stages 2..7 of one step of size `h` from `(t, y)` with `k1 = f(t, y)` already
    /// set; fills `y_new` (5th order), `k7 = f(t_new, y_new)` and `err`. `t_new` is
    /// passed separately so the last step uses the exact end time. Stops early and
    /// returns false as soon as a stage argument or derivative is non-finite, so the
    /// rhs is never fed NaN by the solver.
    fn stages<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
        t: f64,
        h: f64,
        t_new: f64,
        y: &[f64],
    ) -> bool {
        let Dopri5 {
            k1,
            k2,
            k3,
            k4,
            k5,
            k6,
            k7,
            y_stage,
            y_new,
            err,
            evals,
            ..
        } = self;
        let mut eval = |tt: f64, arg: &[f64], k: &mut [f64]| -> bool {
            sys.rhs(tt, arg, k);
            *evals += 1;
            all_finite(k)
        };

        combine(y_stage, y, h, [(A21, &k1[..])])
            && eval(t + C2 * h, y_stage, k2)
            && combine(y_stage, y, h, [(A31, &k1[..]), (A32, &k2[..])])
            && eval(t + C3 * h, y_stage, k3)
            && combine(
                y_stage,
                y,
                h,
                [(A41, &k1[..]), (A42, &k2[..]), (A43, &k3[..])],
            )
            && eval(t + C4 * h, y_stage, k4)
            && combine(
                y_stage,
                y,
                h,
                [
                    (A51, &k1[..]),
                    (A52, &k2[..]),
                    (A53, &k3[..]),
                    (A54, &k4[..]),
                ],
            )
            && eval(t + C5 * h, y_stage, k5)
            && combine(
                y_stage,
                y,
                h,
                [
                    (A61, &k1[..]),
                    (A62, &k2[..]),
                    (A63, &k3[..]),
                    (A64, &k4[..]),
                    (A65, &k5[..]),
                ],
            )
            && eval(t_new, y_stage, k6)
            && combine(
                y_new,
                y,
                h,
                [
                    (B1, &k1[..]),
                    (B3, &k3[..]),
                    (B4, &k4[..]),
                    (B5, &k5[..]),
                    (B6, &k6[..]),
                ],
            )
            && eval(t_new, y_new, k7)
            && {
                for (i, e) in err.iter_mut().enumerate() {
                    *e = h
                        * (E1 * k1[i]
                            + E3 * k3[i]
                            + E4 * k4[i]
                            + E5 * k5[i]
                            + E6 * k6[i]
                            + E7 * k7[i]);
                }
                all_finite(err)
            }
    }

    pub fn memory(&self) -> SolverMemory {
        self.mem
    }

    pub fn restore(&mut self, m: SolverMemory) {
        self.mem = m;
    }

    /// Back to a fresh solver (as after `new`); keeps `max_steps` and the work vectors.
    pub fn forget(&mut self) {
        self.mem = SolverMemory::FRESH;
    }
}

/// Which solution a fixed-step run propagates.
#[cfg(test)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum FixedOrder {
    Fifth,
    /// The embedded solution, `y_new - err`.
    Fourth,
}

#[cfg(test)]
impl Dopri5 {
    /// `n` equal steps over `[t0, t1]` without error control, for order tests.
    pub(crate) fn integrate_fixed<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
        t0: f64,
        t1: f64,
        n: u32,
        y: &mut [f64],
        order: FixedOrder,
    ) {
        let h = (t1 - t0) / f64::from(n);
        for j in 0..n {
            let t = t0 + f64::from(j) * h;
            let t_new = if j + 1 == n { t1 } else { t + h };
            sys.rhs(t, y, &mut self.k1);
            assert!(self.stages(sys, t, t_new - t, t_new, y));
            for ((yi, &y5), &e) in y.iter_mut().zip(&self.y_new).zip(&self.err) {
                *yi = match order {
                    FixedOrder::Fifth => y5,
                    FixedOrder::Fourth => y5 - e,
                };
            }
        }
    }

    /// One step of size `h` from `(t, y)`; returns the embedded error estimate vector
    /// and writes the 5th-order result into `y`.
    pub(crate) fn single_step_error<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
        t: f64,
        h: f64,
        y: &mut [f64],
    ) -> Vec<f64> {
        sys.rhs(t, y, &mut self.k1);
        assert!(self.stages(sys, t, h, t + h, y));
        y.copy_from_slice(&self.y_new);
        self.err.clone()
    }
}

/// Tableau as arrays, for the consistency tests.
#[cfg(test)]
pub(crate) mod tableau {
    use super::*;
    pub(crate) const C: [f64; 7] = [0.0, C2, C3, C4, C5, 1.0, 1.0];
    pub(crate) const A: [[f64; 6]; 7] = [
        [0.0; 6],
        [A21, 0.0, 0.0, 0.0, 0.0, 0.0],
        [A31, A32, 0.0, 0.0, 0.0, 0.0],
        [A41, A42, A43, 0.0, 0.0, 0.0],
        [A51, A52, A53, A54, 0.0, 0.0],
        [A61, A62, A63, A64, A65, 0.0],
        [B1, 0.0, B3, B4, B5, B6],
    ];
    pub(crate) const B: [f64; 7] = [B1, 0.0, B3, B4, B5, B6, 0.0];
    pub(crate) const E: [f64; 7] = [E1, 0.0, E3, E4, E5, E6, E7];
}
