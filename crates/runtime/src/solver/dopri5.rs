//! The Dormand–Prince 5(4) pair (HNW I, II.5, Table 5.2).
//!
//! Local extrapolation: the 5th-order solution is propagated, the embedded 4th-order
//! one only serves the error estimate. FSAL: the 7th stage is f at the new point and
//! becomes the next step's first stage, so an accepted step costs 6 rhs evaluations.

use super::controller::Control;
use super::norm::error_norm_squared;
use super::runge_kutta::{combine, evaluate, evaluate_new_point, Method, RungeKutta};
use super::{all_finite, OdeSystem, StateVector, Tolerance};

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

/// Dormand–Prince 5(4) with `dopri5.f`'s controller.
pub type Dopri5<V> = RungeKutta<V, Dp5<V>>;

/// The work vectors of a Dormand–Prince 5(4) step.
#[derive(Clone, Debug)]
pub struct Dp5<V: StateVector> {
    k1: V,
    k2: V,
    k3: V,
    k4: V,
    k5: V,
    k6: V,
    k7: V,
    /// Stage argument (also the initial-step probe point).
    y_stage: V,
    y_new: V,
    /// Local error estimate `h·Σ e_i k_i` of the last attempted step.
    err: V,
}

impl<V: StateVector> Default for Dp5<V> {
    fn default() -> Self {
        let z = V::ZERO;
        Dp5 {
            k1: z,
            k2: z,
            k3: z,
            k4: z,
            k5: z,
            k6: z,
            k7: z,
            y_stage: z,
            y_new: z,
            err: z,
        }
    }
}

impl<V: StateVector> Dp5<V> {
    /// Stages 2..7 of one step of size `h` from `(t, y)` with `k1 = f(t, y)` already
    /// set; fills `y_new` (5th order), `k7 = f(t_new, y_new)` and `err`. `t_new` is
    /// passed separately so the last step uses the exact end time. Stops early and
    /// returns false as soon as a stage argument (which a non-finite derivative before it
    /// makes non-finite), the new point or the error is non-finite, so the rhs is never
    /// fed NaN by the solver.
    #[inline(always)]
    fn stages<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
        t: f64,
        h: f64,
        t_new: f64,
        y: &V,
        evals: &mut u64,
    ) -> bool {
        let Dp5 {
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
        } = self;
        // A derivative is checked where it is next used, not here (see `evaluate`).
        let mut eval = |tt: f64, arg: &V, k: &mut V| {
            evaluate(sys, evals, tt, arg, k);
            true
        };
        let staged = combine(y_stage, y, h, [(A21, &*k1)])
            && eval(t + C2 * h, y_stage, k2)
            && combine(y_stage, y, h, [(A31, &*k1), (A32, &*k2)])
            && eval(t + C3 * h, y_stage, k3)
            && combine(y_stage, y, h, [(A41, &*k1), (A42, &*k2), (A43, &*k3)])
            && eval(t + C4 * h, y_stage, k4)
            && combine(
                y_stage,
                y,
                h,
                [(A51, &*k1), (A52, &*k2), (A53, &*k3), (A54, &*k4)],
            )
            && eval(t + C5 * h, y_stage, k5)
            && combine(
                y_stage,
                y,
                h,
                [
                    (A61, &*k1),
                    (A62, &*k2),
                    (A63, &*k3),
                    (A64, &*k4),
                    (A65, &*k5),
                ],
            )
            && eval(t_new, y_stage, k6)
            && combine(
                y_new,
                y,
                h,
                [(B1, &*k1), (B3, &*k3), (B4, &*k4), (B5, &*k5), (B6, &*k6)],
            );
        // The new point, which the system may hold already (see `evaluate_new_point`).
        staged
            && {
                evaluate_new_point(sys, evals, t_new, y_new, k7);
                true
            }
            && {
                let e = err.as_mut_slice();
                let (k1, k3, k4, k5, k6, k7) = (
                    k1.as_slice(),
                    k3.as_slice(),
                    k4.as_slice(),
                    k5.as_slice(),
                    k6.as_slice(),
                    k7.as_slice(),
                );
                for i in 0..V::DIM {
                    e[i] = h
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
}

impl<V: StateVector> Method<V> for Dp5<V> {
    const ORDER: i32 = 5;
    /// `dopri5.f`'s defaults: BETA = 0.04, EXPO1 = 1/5 − 0.75·BETA, shrink ≤ 5, growth ≤ 10.
    const CONTROL: Control = Control {
        beta: 0.04,
        expo1: 0.2 - 0.04 * 0.75,
        min_growth: 0.2,
        max_growth: 10.0,
    };

    #[inline(always)]
    fn k1(&mut self) -> &mut V {
        &mut self.k1
    }

    fn scratch(&mut self) -> (&V, &mut V, &mut V) {
        (&self.k1, &mut self.y_stage, &mut self.k2)
    }

    #[inline(always)]
    fn attempt<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
        t: f64,
        h: f64,
        t_new: f64,
        y: &V,
        tol: Tolerance,
        evals: &mut u64,
    ) -> f64 {
        if self.stages(sys, t, h, t_new, y, evals) {
            error_norm_squared(
                self.err.as_slice(),
                y.as_slice(),
                self.y_new.as_slice(),
                tol,
            )
        } else {
            f64::NAN
        }
    }

    #[inline(always)]
    fn y_new(&self) -> &V {
        &self.y_new
    }

    #[inline(always)]
    fn advance(&mut self) {
        self.k1 = self.k7;
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
impl<V: StateVector> Dopri5<V> {
    /// `n` equal steps over `[t0, t1]` without error control, for order tests.
    pub(crate) fn integrate_fixed<S: OdeSystem + ?Sized>(
        &mut self,
        sys: &mut S,
        t0: f64,
        t1: f64,
        n: u32,
        y: &mut V,
        order: FixedOrder,
    ) {
        let h = (t1 - t0) / f64::from(n);
        for j in 0..n {
            let t = t0 + f64::from(j) * h;
            let t_new = if j + 1 == n { t1 } else { t + h };
            let m = &mut self.method;
            sys.rhs(t, y.as_slice(), m.k1.as_mut_slice());
            assert!(m.stages(sys, t, t_new - t, t_new, y, &mut 0));
            for ((yi, &y5), &e) in (y.as_mut_slice().iter_mut())
                .zip(m.y_new.as_slice())
                .zip(m.err.as_slice())
            {
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
        y: &mut V,
    ) -> V {
        let m = &mut self.method;
        sys.rhs(t, y.as_slice(), m.k1.as_mut_slice());
        assert!(m.stages(sys, t, h, t + h, y, &mut 0));
        *y = m.y_new;
        m.err
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
