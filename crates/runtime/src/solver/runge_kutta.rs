//! The adaptive driver shared by the explicit Runge–Kutta pairs: step-size control,
//! exact landing on the end point, FSAL, honest failure. A [`Method`] supplies one
//! attempted step (its stages and error estimate); everything else is here.

use super::controller::{Control, Controller};
use super::initial_step::initial_step;
use super::{
    all_finite, all_finite_entries, OdeSystem, SolverError, SolverMemory, StateVector, StepStats,
    Tolerance,
};

/// A leftover shorter than this fraction of the step is absorbed into the step
/// instead of being taken as a micro-step.
const STRETCH: f64 = 1e-10;
/// Shrink factor after a step produced NaN/inf: there is no error estimate to scale by.
const NON_FINITE_SHRINK: f64 = 10.0;
const DEFAULT_MAX_STEPS: u64 = 1_000_000;

/// Smallest step allowed at time `t`; below it `t + h` no longer moves reliably.
fn h_min(t: f64) -> f64 {
    // `t` is finite: a plain comparison, no NaN case for `max` to handle.
    let magnitude = t.abs();
    16.0 * f64::EPSILON * if magnitude > 1.0 { magnitude } else { 1.0 }
}

/// Whether a step of size `h` ends the `remaining` interval (a leftover below
/// `STRETCH·h` is absorbed by stretching the step).
#[inline(always)]
pub(crate) fn reaches(h: f64, remaining: f64) -> bool {
    remaining <= h * (1.0 + STRETCH)
}

/// `out = y + h·Σ a_j k_j`; false if any entry is non-finite. The dimension is a
/// constant of `V`, so the loops unroll and need no bounds checks.
///
/// The order of the sum is chosen for latency: each stage waits only for the newest
/// derivative, the last term, so everything before it (`y` plus the earlier terms) is
/// summed while the model is still evaluating, and the newest derivative then costs one
/// multiplication and one addition. `h·a_j` is formed first (per step, not per entry).
#[inline(always)]
pub(crate) fn combine<V: StateVector, const K: usize>(
    out: &mut V,
    y: &V,
    h: f64,
    terms: [(f64, &V); K],
) -> bool {
    let (out, y) = (out.as_mut_slice(), y.as_slice());
    let weights = terms.map(|(a, _)| h * a);
    let term = |j: usize, i: usize| weights[j] * terms[j].1.as_slice()[i];
    for i in 0..V::DIM {
        let newest = term(K - 1, i);
        out[i] = if K == 1 {
            y[i] + newest
        } else {
            let earlier = (1..K - 1).fold(term(0, i), |sum, j| sum + term(j, i));
            (y[i] + earlier) + newest
        };
    }
    all_finite_entries(out)
}

/// `k = f(t, arg)`, counted. A function rather than a closure in each method's stages so
/// that it is always inlined (a closure can be left as a call per stage).
///
/// `k` is not checked here: every derivative but the one at the new point enters a later
/// stage argument with a nonzero weight, and a non-finite entry times a nonzero weight is
/// non-finite, so [`combine`]'s check catches it before the rhs sees it (the methods check
/// the new point's derivative themselves). One check per stage instead of two.
#[inline(always)]
pub(crate) fn evaluate<V: StateVector, S: OdeSystem + ?Sized>(
    sys: &mut S,
    evals: &mut u64,
    t: f64,
    arg: &V,
    k: &mut V,
) {
    sys.rhs(t, arg.as_slice(), k.as_mut_slice());
    *evals += 1;
}

/// [`evaluate`] at the new point of a step, which the system may have evaluated last
/// ([`OdeSystem::rhs_reusing`]).
#[inline(always)]
pub(crate) fn evaluate_new_point<V: StateVector, S: OdeSystem + ?Sized>(
    sys: &mut S,
    evals: &mut u64,
    t: f64,
    y_new: &V,
    k: &mut V,
) {
    sys.rhs_reusing(t, y_new.as_slice(), k.as_mut_slice());
    *evals += 1;
}

/// One explicit Runge–Kutta pair with an embedded error estimate and FSAL: its work
/// vectors and one attempted step.
pub trait Method<V: StateVector>: Clone + std::fmt::Debug + Default {
    /// Order of the propagated solution (for the initial step heuristic).
    const ORDER: i32;
    /// The step-size controller's constants.
    const CONTROL: Control;
    /// f at the start of the step (set by the driver, or kept from the last step: FSAL).
    fn k1(&mut self) -> &mut V;
    /// Scratch vectors (the initial step heuristic's probe point and its derivative).
    fn scratch(&mut self) -> (&V, &mut V, &mut V);
    /// One step of size `h` from `(t, y)` with `k1 = f(t, y)`: computes the new point
    /// (read with [`Method::y_new`]), f there, and returns the square of the error norm
    /// (≤ 1: acceptable; squared because the square root would sit on the chain from the
    /// last stage through the step-size controller, which the processor waits for),
    /// or NaN if a stage derivative, argument or the new point is non-finite (caught at the
    /// latest in the next stage argument: the rhs is never fed NaN by the solver). `t_new`
    /// is the exact end time of the step.
    #[allow(clippy::too_many_arguments)]
    fn attempt<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
        t: f64,
        h: f64,
        t_new: f64,
        y: &V,
        tol: Tolerance,
        evals: &mut u64,
    ) -> f64;
    /// The new point of the last attempt.
    fn y_new(&self) -> &V;
    /// After an accepted step: f at the new point becomes the next step's k1 (FSAL).
    fn advance(&mut self);
}

/// An adaptive integrator with method `T` for systems whose dimension is fixed at
/// compile time (`V = [f64; N]`): the work vectors live inline, so it never allocates,
/// and everything of it that influences the future is its [`SolverMemory`].
#[derive(Clone, Debug)]
pub struct RungeKutta<V: StateVector, T: Method<V>> {
    max_steps: u64,
    mem: SolverMemory,
    pub(crate) method: T,
    _state: std::marker::PhantomData<V>,
}

impl<V: StateVector, T: Method<V>> Default for RungeKutta<V, T> {
    fn default() -> Self {
        Self::new()
    }
}

impl<V: StateVector, T: Method<V>> RungeKutta<V, T> {
    /// A fresh solver (no step size chosen yet).
    pub fn new() -> Self {
        RungeKutta {
            max_steps: DEFAULT_MAX_STEPS,
            mem: SolverMemory::FRESH,
            method: T::default(),
            _state: std::marker::PhantomData,
        }
    }

    /// Length of the state vector.
    pub fn dim(&self) -> usize {
        V::DIM
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
    /// If `*t` or `t_end` is not finite or `t_end < *t`: a caller bug; the FMU layer
    /// validates them before calling. (A [`Tolerance`] is valid by construction.)
    pub fn integrate<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
        t: &mut f64,
        t_end: f64,
        y: &mut V,
        tol: Tolerance,
    ) -> Result<StepStats, SolverError> {
        assert!(
            t.is_finite() && t_end.is_finite() && t_end >= *t,
            "integrate needs finite t <= t_end, got t = {} and t_end = {t_end}",
            *t
        );
        let mut stats = StepStats::default();
        if t_end == *t {
            return Ok(stats);
        }
        if V::DIM == 0 {
            *t = t_end;
            return Ok(stats);
        }
        let result = self.run(sys, t, t_end, y, tol, &mut stats);
        result.map(|()| stats)
    }

    fn run<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
        t: &mut f64,
        t_end: f64,
        y: &mut V,
        tol: Tolerance,
        stats: &mut StepStats,
    ) -> Result<(), SolverError> {
        if !all_finite(y) {
            return Err(SolverError::NonFinite { t: *t });
        }
        // The rhs evaluations of this call. A local, not a field: a count in memory the
        // stages reach through `self` is stored after every stage, since any stage may be
        // the last before a return.
        let mut evals: u64 = 1;
        sys.rhs_reusing(*t, y.as_slice(), self.method.k1().as_mut_slice());
        if !all_finite(self.method.k1()) {
            return Err(SolverError::NonFinite { t: *t });
        }

        let mut h = match self.mem.h_next {
            Some(h) if h > 0.0 && h <= f64::MAX => h,
            _ => {
                let (k1, probe, f_probe) = self.method.scratch();
                // Its own count: `evals` handed to a function not inlined would live in memory.
                let mut probes = 0;
                let h = initial_step(
                    sys,
                    *t,
                    y.as_slice(),
                    k1.as_slice(),
                    t_end - *t,
                    tol,
                    T::ORDER,
                    probe.as_mut_slice(),
                    f_probe.as_mut_slice(),
                    &mut probes,
                );
                evals += probes;
                h
            }
        };
        let mut controller = Controller::new(T::CONTROL, self.mem.log2_err_prev);
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
            // `h` is finite and positive (checked when remembered, or the controller's).
            let floor = h_min(*t);
            if h < floor {
                h = floor;
            }
            let remaining = t_end - *t;
            let last = reaches(h, remaining);
            // A branch, not a select: the last step's size is the interval's remainder,
            // known at once, so its stages need not wait for the controller's arithmetic
            // (error norm, log2, exp2) that produced `h`. As a select (what the compiler
            // makes of a plain `if` here) every step waited ~100 cycles for it. The opaque
            // `black_box` cannot be computed speculatively, which keeps the branch.
            let (h_step, t_new) = if last {
                (std::hint::black_box(remaining), t_end)
            } else {
                (h, *t + h)
            };

            let err_squared = (self.method).attempt(sys, *t, h_step, t_new, y, tol, &mut evals);

            if !err_squared.is_finite() {
                stats.rejected += 1;
                last_rejected = true;
                h = h_step / NON_FINITE_SHRINK;
                if h < h_min(*t) {
                    return Err(SolverError::NonFinite { t: *t });
                }
            } else if err_squared > 1.0 {
                stats.rejected += 1;
                last_rejected = true;
                h = controller.after_reject(h_step, err_squared);
                if h < h_min(*t) {
                    return Err(SolverError::StepSizeTooSmall { t: *t, h });
                }
            } else {
                stats.accepted += 1;
                let mut h_new = controller.after_accept(h_step, err_squared);
                if last_rejected {
                    h_new = h_new.min(h_step);
                }
                last_rejected = false;
                if last && h_new >= h_step {
                    // Clamping, not the error, made this step short: keep the longer
                    // step for the next call.
                    if h > h_new {
                        h_new = h;
                    }
                }
                // The system may refuse the new point (the model stops holding there): then
                // the integration ends at the last point inside the step where it holds.
                if let Err(message) = sys.accepted(t_new, self.method.y_new().as_slice()) {
                    let (t0, y0) = (*t, *y);
                    // The call ends in an error, whose caller sees no count.
                    let (method, evals) = (&mut self.method, &mut 0);
                    let (t_stop, y_stop) =
                        super::locate::last_valid_point(sys, (t0, y), t_new, |sys, t_probe| {
                            method.attempt(sys, t0, t_probe - t0, t_probe, &y0, tol, evals);
                            *method.y_new()
                        });
                    if t_stop > *t && sys.accepted(t_stop, y_stop.as_slice()).is_ok() {
                        (*t, *y) = (t_stop, y_stop);
                    }
                    return Err(SolverError::Stopped { t: *t, message });
                }
                *y = *self.method.y_new();
                self.method.advance();
                *t = t_new;
                self.mem = SolverMemory {
                    h_next: Some(h_new),
                    log2_err_prev: controller.log2_err_prev(),
                    ..self.mem
                };
                if last {
                    stats.rhs_evals = evals;
                    return Ok(());
                }
                h = h_new;
            }
        }
    }

    pub fn memory(&self) -> SolverMemory {
        self.mem
    }

    pub fn restore(&mut self, m: SolverMemory) {
        self.mem = m;
    }

    /// Back to a fresh solver (as after `new`); keeps `max_steps`.
    pub fn forget(&mut self) {
        self.mem = SolverMemory::FRESH;
    }
}
