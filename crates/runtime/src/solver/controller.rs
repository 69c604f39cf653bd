//! PI step-size controller of `dopri5.f` (HNW I, IV.2, "Lund stabilization").
//!
//! The previous step's error enters with a small weight (`BETA`), which damps the
//! accept/reject oscillations a pure I-controller shows on mildly stiff problems.
//!
//! `dopri5.f` computes `err^EXPO1 / err_prev^BETA` with two calls of `pow`; here it is
//! `2^(EXPO1·log2 err − BETA·log2 err_prev)` with `log2 err_prev` kept from the step that
//! produced it, so an accepted step costs one `log2` and one `2^x`, both the cheap ones of
//! [`powers`](super::powers): the factor only proposes the next step size (the error test
//! decides what is accepted), and agrees with the two powers to about 1e-8.
//!
//! The chain from a step's last stage to the next step's size is the tail every step
//! waits for, so it has no division: `dopri5.f`'s `h / (fac / SAFE)` is `h · SAFE · 2^-x`
//! here, with the bounds as growth factors (`FAC1`, `FAC2`), and the error norm multiplies
//! by reciprocal scales computed while the last stage evaluates (measured: 5-15 ns of
//! every `fmi2DoStep`). This form alone is a few ulp from `dopri5.f`'s arithmetic.
//!
//! Neither is the platform's C library's (glibc, msvcrt, libSystem round differently in
//! the last bit): they are plain arithmetic, so the step sizes, and with them every
//! trajectory, are the same bits on every platform.

use super::powers::{exp2, log2};

/// A method's controller constants (`dopri5.f` and `dop853.f` defaults).
#[derive(Clone, Copy, Debug)]
pub struct Control {
    /// Weight of the previous error (`BETA`; 0 makes it an I-controller).
    pub beta: f64,
    /// Exponent of the current error: 1/(q+1) for an order-q estimate, minus the PI
    /// correction (`EXPO1`).
    pub expo1: f64,
    /// `FAC1`: the least the step may become after an accepted step, as a factor (< 1).
    pub min_growth: f64,
    /// `FAC2`: the most the step may grow per step, as a factor (> 1).
    pub max_growth: f64,
}

/// Safety factor: aim a little below the tolerance so the next step is likely accepted.
const SAFE: f64 = 0.9;
/// Floor of the remembered error, so a step with (nearly) zero error cannot make the
/// next proposal explode through the `err_prev^BETA` denominator.
#[cfg(test)]
pub(crate) const ERR_PREV_FLOOR: f64 = 1e-4;
/// `log2(ERR_PREV_FLOOR)` (checked by a test): the memory of a fresh controller, and of
/// every step whose error is below the floor.
pub(crate) const LOG2_ERR_PREV_FLOOR: f64 = -13.287712379549449;

/// Whether `log2_err_prev` is one the controller can remember: between the floor's and 0
/// (an accepted error norm is at most 1).
#[inline]
pub(crate) fn can_remember(log2_err_prev: f64) -> bool {
    (LOG2_ERR_PREV_FLOOR..=0.0).contains(&log2_err_prev)
}

/// The controller's memory during one integration call: `log2` of the error norm of the
/// last accepted step, floored at `log2(ERR_PREV_FLOOR)`. The logarithm, not the norm, is
/// what the formula uses and what the solver remembers ([`SolverMemory`]): no square root
/// to take, and a memory restored elsewhere proposes bit for bit what it would have here.
///
/// [`SolverMemory`]: super::SolverMemory
#[derive(Clone, Copy, Debug)]
pub(crate) struct Controller {
    control: Control,
    log2_err_prev: f64,
}

impl Controller {
    /// Resumes from a remembered `log2_err_prev`; one the controller cannot have
    /// remembered (non-finite or out of range, as in a forged memory handed to `restore`)
    /// counts as the floor's.
    #[inline]
    pub(crate) fn new(control: Control, log2_err_prev: f64) -> Self {
        Controller {
            control,
            log2_err_prev: if can_remember(log2_err_prev) {
                log2_err_prev
            } else {
                LOG2_ERR_PREV_FLOOR
            },
        }
    }

    /// What to remember for the next call.
    #[inline]
    pub(crate) fn log2_err_prev(&self) -> f64 {
        self.log2_err_prev
    }

    /// Next step size after an accepted step whose error norm squared is `err_squared`
    /// (`0 <= err_squared <= 1`); remembers the norm's logarithm. Squared as the methods
    /// return it: `log2` of the square is twice that of the norm, so no square root is
    /// taken at all.
    #[inline(always)]
    pub(crate) fn after_accept(&mut self, h: f64, err_squared: f64) -> f64 {
        // Below 1e-300 (0 included) the factor is long clamped to the largest growth.
        let log2_err = 0.5 * log2(err_squared.max(1e-300));
        let Control {
            beta,
            expo1,
            min_growth,
            max_growth,
        } = self.control;
        let x = expo1 * log2_err - beta * self.log2_err_prev;
        let growth = (SAFE * exp2(-x)).clamp(min_growth, max_growth);
        // The floor by comparison, not by the error's size: the logarithm is accurate to
        // 1e-9, and one a hair below the floor's could not be restored (`can_remember`).
        self.log2_err_prev = log2_err.max(LOG2_ERR_PREV_FLOOR);
        h * growth
    }

    /// Smaller step after a rejected step whose error norm squared is `err_squared`
    /// (`> 1`, finite). The memory is left alone, as in `dopri5.f`.
    #[inline]
    pub(crate) fn after_reject(&self, h: f64, err_squared: f64) -> f64 {
        let shrink = exp2(-0.5 * self.control.expo1 * log2(err_squared));
        h * (SAFE * shrink).max(self.control.min_growth)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const DOPRI5: Control = <crate::solver::Dp5<[f64; 1]> as crate::solver::Method<_>>::CONTROL;

    /// The `dopri5.f` formula, with two powers.
    fn reference(h: f64, err: f64, err_prev: f64) -> f64 {
        let c = DOPRI5;
        let fac = err.powf(c.expo1) / err_prev.max(ERR_PREV_FLOOR).powf(c.beta);
        h / (fac / SAFE).clamp(1.0 / c.max_growth, 1.0 / c.min_growth)
    }

    /// A controller that remembers the error norm `err_prev`.
    fn remembering(err_prev: f64) -> Controller {
        Controller::new(DOPRI5, err_prev.max(ERR_PREV_FLOOR).log2())
    }

    #[test]
    fn proposals_match_the_two_power_formula() {
        let errs = [
            0.0, 1e-300, 1e-12, 1e-5, 1e-4, 3e-3, 0.0123, 0.2, 0.7, 0.999, 1.0,
        ];
        let mut worst = 0.0f64;
        for &prev in &errs {
            for &err in &errs {
                let mut c = remembering(prev);
                let h = c.after_accept(0.37, err * err);
                let r = reference(0.37, err, prev);
                worst = worst.max((h - r).abs() / r);
                // Remembered as half the logarithm of the square: within rounding.
                let remembered = err.max(ERR_PREV_FLOOR).log2();
                let d = (c.log2_err_prev() - remembered).abs();
                assert!(d <= 1e-9, "err {err}: remembered {}", c.log2_err_prev());
            }
        }
        // The cheap logarithm and power's accuracy (see `powers`).
        assert!(worst < 2e-8, "relative difference {worst:e}");
    }

    #[test]
    fn the_floor_logarithm_is_exact() {
        assert_eq!(LOG2_ERR_PREV_FLOOR, ERR_PREV_FLOOR.log2());
        assert_eq!(remembering(0.0).log2_err_prev(), LOG2_ERR_PREV_FLOOR);
        // A memory the controller cannot have had counts as the floor.
        for forged in [f64::NAN, f64::INFINITY, 0.5, -14.0] {
            assert_eq!(
                Controller::new(DOPRI5, forged).log2_err_prev(),
                LOG2_ERR_PREV_FLOOR
            );
        }
    }

    #[test]
    fn growth_and_shrink_are_bounded() {
        let mut c = Controller::new(DOPRI5, 0.0);
        assert_eq!(c.after_accept(1.0, 0.0), 10.0);
        // An error norm of 1e6, squared.
        assert_eq!(c.after_reject(1.0, 1e12), 0.2);
    }
}
