//! The ODE solver inside every exported FMU: Dormand–Prince 5(4), and 8(5,3) for tight
//! tolerances, with error control.
//!
//! The method, error norm, PI step-size controller and initial step heuristic follow
//! Hairer–Nørsett–Wanner, *Solving Ordinary Differential Equations I*, II.4 and IV.2
//! (the reference code `dopri5.f`), so behaviour can be compared against that code.
//!
//! Design constraints that come from the FMU layer:
//! * `integrate` lands on the communication point exactly and never evaluates the
//!   right-hand side beyond it, so `fmi2DoStep` can report that time verbatim.
//! * On failure the last accepted (finite) point is kept, for `fmi2Discard`.
//! * Everything that influences the future lives in [`SolverMemory`] (plain `Copy`
//!   data), so FMU state snapshots continue bit-for-bit.
//! * The dimension is a compile-time constant ([`StateVector`]): no allocation, no I/O,
//!   no `unsafe`, fully deterministic.

mod controller;
mod dop853;
mod dopri5;
mod initial_step;
mod locate;
mod norm;
mod powers;
mod runge_kutta;
#[cfg(test)]
mod tests;

pub use controller::Control;
pub use dop853::{Dop853, Dp853};
pub use dopri5::{Dopri5, Dp5};
pub use runge_kutta::{Method, RungeKutta};

use controller::{can_remember, Controller, LOG2_ERR_PREV_FLOOR};

use std::fmt;

/// The state of a system whose dimension is fixed at compile time: `[f64; N]`.
///
/// A fixed dimension lets the solver keep its work vectors inline (no allocation, the
/// solver is plain data) and lets the compiler unroll its loops over the components.
pub trait StateVector: Copy + fmt::Debug + PartialEq + Send + Sync + 'static {
    /// The number of components.
    const DIM: usize;
    /// All components zero.
    const ZERO: Self;
    fn as_slice(&self) -> &[f64];
    fn as_mut_slice(&mut self) -> &mut [f64];
}

impl<const N: usize> StateVector for [f64; N] {
    const DIM: usize = N;
    const ZERO: Self = [0.0; N];
    #[inline(always)]
    fn as_slice(&self) -> &[f64] {
        self
    }
    #[inline(always)]
    fn as_mut_slice(&mut self) -> &mut [f64] {
        self
    }
}

/// Whether every entry is finite (without stopping early: no branch per entry).
#[inline(always)]
pub(crate) fn all_finite<V: StateVector>(v: &V) -> bool {
    all_finite_entries(v.as_slice())
}

/// [`all_finite`] of a slice, as `x - x == 0` (false for NaN and the infinities): two
/// vector instructions per pair of entries, where `is_finite` takes five per entry.
#[inline(always)]
#[allow(clippy::eq_op)]
pub(crate) fn all_finite_entries(v: &[f64]) -> bool {
    v.iter().fold(true, |ok, &x| ok & (x - x == 0.0))
}

/// The integrator of an FMU: Dormand–Prince 5(4) ([`Dopri5`]) or 8(5,3) ([`Dop853`]),
/// chosen per communication interval by what the interval costs.
///
/// While one Dopri5 step reaches the end of the interval (its proposed step covers it),
/// Dopri5 runs: 6 evaluations, and no method can do it in fewer steps. When Dopri5 would
/// need two steps or more (12 evaluations or more), one Dop853 step costs the same and is
/// far more accurate, and Dop853's larger steps make it cheaper still on long intervals, so
/// Dop853 runs. It hands back to Dopri5 once a single Dop853 step covered the interval and
/// its 3rd-order embedded error, a conservative stand-in for Dopri5's 4th-order one, makes
/// Dopri5's controller propose a step that covers the interval too.
///
/// Which method runs is part of the [`SolverMemory`], so a restored snapshot continues
/// bit for bit.
#[derive(Clone, Debug)]
pub struct Solver<V: StateVector> {
    dopri5: Dopri5<V>,
    dop853: Dop853<V>,
    mem: SolverMemory,
}

impl<V: StateVector> Default for Solver<V> {
    fn default() -> Self {
        Self::new()
    }
}

impl<V: StateVector> Solver<V> {
    pub fn new() -> Self {
        Solver {
            dopri5: Dopri5::new(),
            dop853: Dop853::new(),
            mem: SolverMemory::FRESH,
        }
    }

    /// Whether the next call over an interval of length `interval` runs the 8th-order
    /// method.
    pub fn high_order(&self, interval: f64) -> bool {
        self.mem.high_order
            || self
                .mem
                .h_next
                .is_some_and(|h| !runge_kutta::reaches(h, interval))
    }

    /// [`RungeKutta::integrate`] with the method the interval calls for.
    ///
    /// Never inlined, for the reason `Simulation::step` is not: the benchmark's
    /// `Part::Integrate` runs the very code a step runs.
    #[inline(never)]
    pub fn integrate<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
        t: &mut f64,
        t_end: f64,
        y: &mut V,
        tol: Tolerance,
    ) -> Result<StepStats, SolverError> {
        let interval = t_end - *t;
        if !self.high_order(interval) {
            self.dopri5.restore(self.mem);
            let r = self.dopri5.integrate(sys, t, t_end, y, tol);
            self.mem = self.dopri5.memory();
            return r;
        }
        self.dop853.restore(SolverMemory {
            high_order: true,
            ..self.mem
        });
        let r = self.dop853.integrate(sys, t, t_end, y, tol);
        self.mem = self.dop853.memory();
        if matches!(
            r,
            Ok(StepStats {
                accepted: 1,
                rejected: 0,
                ..
            })
        ) {
            // One step covered the interval: would one Dopri5 step have done as well?
            let mut controller = Controller::new(Dp5::<V>::CONTROL, LOG2_ERR_PREV_FLOOR);
            let err_squared = self.dop853.method.err3_squared();
            if err_squared <= 1.0 {
                let h = controller.after_accept(interval, err_squared);
                if runge_kutta::reaches(h, interval) {
                    self.mem = SolverMemory {
                        h_next: Some(h),
                        log2_err_prev: controller.log2_err_prev(),
                        high_order: false,
                    };
                }
            }
        }
        r
    }

    pub fn memory(&self) -> SolverMemory {
        self.mem
    }

    pub fn restore(&mut self, m: SolverMemory) {
        self.mem = m;
    }

    /// Back to a fresh solver.
    pub fn forget(&mut self) {
        self.mem = SolverMemory::FRESH;
    }
}

/// Relative tolerances below this are raised to it: below ~10 ulp the error estimate
/// is dominated by rounding and the controller would shrink the step forever.
pub const MIN_RTOL: f64 = 10.0 * f64::EPSILON;

/// A first-order system dy/dt = f(t, y).
pub trait OdeSystem {
    /// dy/dt = f(t, y). Writes dydt (same length as y).
    ///
    /// Must be a pure function of `(t, y)` for the duration of one
    /// [`Dopri5::integrate`] call: the last stage is reused as the first stage of the
    /// next step (FSAL), so changing behaviour mid-call (e.g. in `accepted`) is not seen
    /// until the next call. Non-finite outputs are tolerated and make the solver retry
    /// with a smaller step.
    fn rhs(&mut self, t: f64, y: &[f64], dydt: &mut [f64]);
    /// dy/dt at a point the system may have evaluated last: the start of an integration
    /// call (the end of the previous one) and the new point of a step (the same as the
    /// last stage's for a system at rest). A system that keeps its last evaluation can
    /// return it instead of evaluating again. The other stages, whose points are new, call
    /// [`OdeSystem::rhs`] and pay for no such check. Default: `rhs`.
    fn rhs_reusing(&mut self, t: f64, y: &[f64], dydt: &mut [f64]) {
        self.rhs(t, y, dydt);
    }
    /// Called for every point the error test accepts, before it is committed. Err(message)
    /// refuses it: the integration stops at the last point inside the step where the
    /// system is still [valid](OdeSystem::valid_at) (located by bisection), which `t` and `y`
    /// then keep -> SolverError::Stopped.
    fn accepted(&mut self, _t: f64, _y: &[f64]) -> Result<(), String> {
        Ok(())
    }
    /// Whether the system is valid at a point: what `accepted` decides. The event location
    /// probes points out of order, so a system whose `accepted` has side effects (warnings
    /// it records) overrides this with a check free of them. Default: `accepted`'s verdict,
    /// side effects included.
    fn valid_at(&mut self, t: f64, y: &[f64]) -> bool {
        self.accepted(t, y).is_ok()
    }
}

/// Mixed error tolerance: component i may err by about `atol + rtol·|y_i|`.
///
/// Valid by construction ([`Tolerance::new`]): both finite and non-negative, `rtol` raised
/// to [`MIN_RTOL`] if smaller, so the solver checks nothing per call. `atol == 0` (pure
/// relative control) is allowed but fails on components that cross zero with a nonzero
/// error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tolerance {
    rtol: f64,
    atol: f64,
}

impl Tolerance {
    /// `rtol` relative (raised to [`MIN_RTOL`] if smaller) and `atol` absolute, in the
    /// units of the state; `None` if either is negative or not finite.
    pub const fn new(rtol: f64, atol: f64) -> Option<Tolerance> {
        if rtol.is_finite() && rtol >= 0.0 && atol.is_finite() && atol >= 0.0 {
            Some(Tolerance {
                rtol: rtol.max(MIN_RTOL),
                atol,
            })
        } else {
            None
        }
    }

    /// The relative tolerance (at least [`MIN_RTOL`]).
    #[inline(always)]
    pub fn rtol(&self) -> f64 {
        self.rtol
    }

    /// The absolute tolerance.
    #[inline(always)]
    pub fn atol(&self) -> f64 {
        self.atol
    }
}

/// Work done by one [`Dopri5::integrate`] call (not cumulative).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct StepStats {
    /// Steps that passed the error test.
    pub accepted: u64,
    /// Steps retried with a smaller size (error too large or NaN/inf).
    pub rejected: u64,
    /// Includes the evaluations of the initial step heuristic and of rejected steps.
    pub rhs_evals: u64,
}

/// Everything of the solver's own that influences the future: the step size to try next
/// (None = choose one with the initial-step heuristic), and the PI controller's memory.
/// Plain data (Copy), so an FMU can snapshot/serialize/restore it and continue bit-for-bit,
/// in this solver or any other.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SolverMemory {
    /// Step size to try first in the next call; `None` runs the initial-step heuristic.
    pub h_next: Option<f64>,
    /// `log2` of the error norm of the last accepted step, floored at `log2(1e-4)` (Hairer's
    /// `FACOLD`), so between about -13.3 and 0: it damps the controller (the "I" of PI).
    /// The floor's for a fresh solver. The logarithm is what the controller computes and
    /// uses, so a memory restored anywhere proposes what it would have where it was saved
    /// (remembering the norm, a restored controller would take `log2` of its square root,
    /// which is not always half the `log2` of the square).
    pub log2_err_prev: f64,
    /// Whether the 8th-order method is running (see [`Solver`]); `h_next` and
    /// `log2_err_prev` are its controller's. False for a fresh solver.
    pub high_order: bool,
}

impl SolverMemory {
    /// The memory of a freshly constructed solver.
    pub const FRESH: SolverMemory = SolverMemory {
        h_next: None,
        log2_err_prev: LOG2_ERR_PREV_FLOOR,
        high_order: false,
    };

    /// Whether this memory is one the solver can have, so that restoring it cannot make
    /// the solver misbehave (for memories read from outside, such as serialized FMU
    /// states): a finite, positive step size, a logarithm between the floor's and 0.
    pub fn is_valid(&self) -> bool {
        self.h_next.is_none_or(|h| h.is_finite() && h > 0.0) && can_remember(self.log2_err_prev)
    }
}

impl Default for SolverMemory {
    fn default() -> Self {
        Self::FRESH
    }
}

/// Why `integrate` stopped early. In every case `t` is the last accepted time, which
/// the caller's `t` and `y` were left at (an FMU reports `fmi2Discard` there).
#[derive(Clone, Debug, PartialEq)]
pub enum SolverError {
    /// The error test failed even with the smallest usable step `h` (a singularity,
    /// a discontinuity the model should handle as an event, or extreme stiffness).
    StepSizeTooSmall { t: f64, h: f64 },
    /// rhs produced NaN/inf and shrinking the step did not help.
    NonFinite { t: f64 },
    /// More than `max_steps` step attempts in one call (see `Dopri5::set_max_steps`).
    TooManySteps { t: f64, max_steps: u64 },
    /// `OdeSystem::accepted` refused the next point; `t` is the last point it accepted.
    Stopped { t: f64, message: String },
}

impl SolverError {
    /// Time of the last accepted point, which the solver state was left at.
    pub fn t(&self) -> f64 {
        match *self {
            SolverError::StepSizeTooSmall { t, .. }
            | SolverError::NonFinite { t }
            | SolverError::TooManySteps { t, .. }
            | SolverError::Stopped { t, .. } => t,
        }
    }
}

impl fmt::Display for SolverError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SolverError::StepSizeTooSmall { t, h } => write!(
                f,
                "step size {h:e} at t = {t} fell below the minimum; the error tolerance \
                 cannot be met there (singularity or very stiff dynamics?)"
            ),
            SolverError::NonFinite { t } => write!(
                f,
                "the right-hand side produced NaN or infinity after t = {t} and reducing \
                 the step size did not help"
            ),
            SolverError::TooManySteps { t, max_steps } => write!(
                f,
                "gave up at t = {t} after {max_steps} step attempts in one integration call"
            ),
            SolverError::Stopped { t, message } => {
                write!(f, "integration stopped by the model at t = {t}: {message}")
            }
        }
    }
}

impl std::error::Error for SolverError {}
