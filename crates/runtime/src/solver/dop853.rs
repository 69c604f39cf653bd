//! The Dormand–Prince 8(5,3) method of `dop853.f` (HNW I, II.10; Prince & Dormand 1981
//! with Hairer's error estimator).
//!
//! Twelve stages and FSAL: an accepted step costs 12 rhs evaluations, twice Dopri5's,
//! but an 8th-order step is so much longer at tight tolerances that it needs several
//! times fewer of them. The error estimate blends a 5th- and a 3rd-order difference
//! (`err5² / sqrt(err5² + 0.01·err3²)`), which keeps it from underestimating on steps
//! where the 5th-order difference happens to be small.
//!
//! Coefficients: the published tableau (as in `dop853.f` and SciPy's
//! `dop853_coefficients.py`), checked by the order conditions in the tests. They keep
//! their published 30 digits, so they can be compared with the source digit by digit;
//! the compiler rounds each to the nearest `f64`.
#![allow(clippy::excessive_precision)]

use super::controller::Control;
use super::norm::{inverse_scale, ratio_sq};
use super::runge_kutta::{combine, evaluate, evaluate_new_point, Method, RungeKutta};
use super::{all_finite, OdeSystem, StateVector, Tolerance};

// Nodes c_i (stage i is evaluated at t + c_i h).
const C2: f64 = 0.526001519587677318785587544488e-01;
const C3: f64 = 0.789002279381515978178381316732e-01;
const C4: f64 = 0.118350341907227396726757197510;
const C5: f64 = 0.281649658092772603273242802490;
const C6: f64 = 0.333333333333333333333333333333;
const C7: f64 = 0.25;
const C8: f64 = 0.307692307692307692307692307692;
const C9: f64 = 0.651282051282051282051282051282;
const C10: f64 = 0.6;
const C11: f64 = 0.857142857142857142857142857142;

// Coupling coefficients a_ij (zero entries omitted).
const A21: f64 = 5.26001519587677318785587544488e-2;
const A31: f64 = 1.97250569845378994544595329183e-2;
const A32: f64 = 5.91751709536136983633785987549e-2;
const A41: f64 = 2.95875854768068491816892993775e-2;
const A43: f64 = 8.87627564304205475450678981324e-2;
const A51: f64 = 2.41365134159266685502369798665e-1;
const A53: f64 = -8.84549479328286085344864962717e-1;
const A54: f64 = 9.24834003261792003115737966543e-1;
const A61: f64 = 3.7037037037037037037037037037e-2;
const A64: f64 = 1.70828608729473871279604482173e-1;
const A65: f64 = 1.25467687566822425016691814123e-1;
const A71: f64 = 3.7109375e-2;
const A74: f64 = 1.70252211019544039314978060272e-1;
const A75: f64 = 6.02165389804559606850219397283e-2;
const A76: f64 = -1.7578125e-2;
const A81: f64 = 3.70920001185047927108779319836e-2;
const A84: f64 = 1.70383925712239993810214054705e-1;
const A85: f64 = 1.07262030446373284651809199168e-1;
const A86: f64 = -1.53194377486244017527936158236e-2;
const A87: f64 = 8.27378916381402288758473766002e-3;
const A91: f64 = 6.24110958716075717114429577812e-1;
const A94: f64 = -3.36089262944694129406857109825;
const A95: f64 = -8.68219346841726006818189891453e-1;
const A96: f64 = 2.75920996994467083049415600797e1;
const A97: f64 = 2.01540675504778934086186788979e1;
const A98: f64 = -4.34898841810699588477366255144e1;
const A101: f64 = 4.77662536438264365890433908527e-1;
const A104: f64 = -2.48811461997166764192642586468;
const A105: f64 = -5.90290826836842996371446475743e-1;
const A106: f64 = 2.12300514481811942347288949897e1;
const A107: f64 = 1.52792336328824235832596922938e1;
const A108: f64 = -3.32882109689848629194453265587e1;
const A109: f64 = -2.03312017085086261358222928593e-2;
const A111: f64 = -9.3714243008598732571704021658e-1;
const A114: f64 = 5.18637242884406370830023853209;
const A115: f64 = 1.09143734899672957818500254654;
const A116: f64 = -8.14978701074692612513997267357;
const A117: f64 = -1.85200656599969598641566180701e1;
const A118: f64 = 2.27394870993505042818970056734e1;
const A119: f64 = 2.49360555267965238987089396762;
const A1110: f64 = -3.0467644718982195003823669022;
const A121: f64 = 2.27331014751653820792359768449;
const A124: f64 = -1.05344954667372501984066689879e1;
const A125: f64 = -2.00087205822486249909675718444;
const A126: f64 = -1.79589318631187989172765950534e1;
const A127: f64 = 2.79488845294199600508499808837e1;
const A128: f64 = -2.85899827713502369474065508674;
const A129: f64 = -8.87285693353062954433549289258;
const A1210: f64 = 1.23605671757943030647266201528e1;
const A1211: f64 = 6.43392746015763530355970484046e-1;

// 8th-order weights b_i (b2 = b3 = b4 = 0).
const B1: f64 = 5.42937341165687622380535766363e-2;
const B6: f64 = 4.45031289275240888144113950566;
const B7: f64 = 1.89151789931450038304281599044;
const B8: f64 = -5.8012039600105847814672114227;
const B9: f64 = 3.1116436695781989440891606237e-1;
const B10: f64 = -1.52160949662516078556178806805e-1;
const B11: f64 = 2.01365400804030348374776537501e-1;
const B12: f64 = 4.47106157277725905176885569043e-2;

// The 3rd-order estimate: b minus weights on k1, k9, k12 (`BHH1..3`).
const BHH1: f64 = 0.244094488188976377952755905512;
const BHH2: f64 = 0.733846688281611857341361741547;
const BHH3: f64 = 0.220588235294117647058823529412e-1;

// The 5th-order error weights `ER1..ER12` (zero on k2..k5).
const ER1: f64 = 0.1312004499419488073250102996e-1;
const ER6: f64 = -0.1225156446376204440720569753e1;
const ER7: f64 = -0.4957589496572501915214079952;
const ER8: f64 = 0.1664377182454986536961530415e1;
const ER9: f64 = -0.3503288487499736816886487290;
const ER10: f64 = 0.3341791187130174790297318841;
const ER11: f64 = 0.8192320648511571246570742613e-1;
const ER12: f64 = -0.2235530786388629525884427845e-1;

/// Dormand–Prince 8(5,3) with `dop853.f`'s controller.
pub type Dop853<V> = RungeKutta<V, Dp853<V>>;

/// The work vectors of a Dormand–Prince 8(5,3) step.
#[derive(Clone, Debug)]
pub struct Dp853<V: StateVector> {
    /// k[0..12]: the twelve stages; k[12]: f at the new point (the next k1).
    k: [V; 13],
    y_stage: V,
    y_new: V,
    /// The square of the 3rd-order embedded solution's error norm of the last attempt
    /// (`‖y8 − y3‖` scaled like the error test): what a lower-order method would have had
    /// to meet. Squared, as the controller takes it (no square root per attempt).
    err3_squared: f64,
}

impl<V: StateVector> Default for Dp853<V> {
    fn default() -> Self {
        Dp853 {
            k: [V::ZERO; 13],
            y_stage: V::ZERO,
            y_new: V::ZERO,
            err3_squared: f64::NAN,
        }
    }
}

impl<V: StateVector> Dp853<V> {
    /// Stages 2..12, the new point and f there; false as soon as a stage argument (which a
    /// non-finite derivative before it makes non-finite), the new point or f there is
    /// non-finite.
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
        let Dp853 {
            k, y_stage, y_new, ..
        } = self;
        let [k1, k2, k3, k4, k5, k6, k7, k8, k9, k10, k11, k12, k13] = k;
        // A derivative is checked where it is next used, not here (see `evaluate`).
        let mut eval = |tt: f64, arg: &V, k: &mut V| {
            evaluate(sys, evals, tt, arg, k);
            true
        };
        let staged = combine(y_stage, y, h, [(A21, &*k1)])
            && eval(t + C2 * h, y_stage, k2)
            && combine(y_stage, y, h, [(A31, &*k1), (A32, &*k2)])
            && eval(t + C3 * h, y_stage, k3)
            && combine(y_stage, y, h, [(A41, &*k1), (A43, &*k3)])
            && eval(t + C4 * h, y_stage, k4)
            && combine(y_stage, y, h, [(A51, &*k1), (A53, &*k3), (A54, &*k4)])
            && eval(t + C5 * h, y_stage, k5)
            && combine(y_stage, y, h, [(A61, &*k1), (A64, &*k4), (A65, &*k5)])
            && eval(t + C6 * h, y_stage, k6)
            && combine(
                y_stage,
                y,
                h,
                [(A71, &*k1), (A74, &*k4), (A75, &*k5), (A76, &*k6)],
            )
            && eval(t + C7 * h, y_stage, k7)
            && combine(
                y_stage,
                y,
                h,
                [
                    (A81, &*k1),
                    (A84, &*k4),
                    (A85, &*k5),
                    (A86, &*k6),
                    (A87, &*k7),
                ],
            )
            && eval(t + C8 * h, y_stage, k8)
            && combine(
                y_stage,
                y,
                h,
                [
                    (A91, &*k1),
                    (A94, &*k4),
                    (A95, &*k5),
                    (A96, &*k6),
                    (A97, &*k7),
                    (A98, &*k8),
                ],
            )
            && eval(t + C9 * h, y_stage, k9)
            && combine(
                y_stage,
                y,
                h,
                [
                    (A101, &*k1),
                    (A104, &*k4),
                    (A105, &*k5),
                    (A106, &*k6),
                    (A107, &*k7),
                    (A108, &*k8),
                    (A109, &*k9),
                ],
            )
            && eval(t + C10 * h, y_stage, k10)
            && combine(
                y_stage,
                y,
                h,
                [
                    (A111, &*k1),
                    (A114, &*k4),
                    (A115, &*k5),
                    (A116, &*k6),
                    (A117, &*k7),
                    (A118, &*k8),
                    (A119, &*k9),
                    (A1110, &*k10),
                ],
            )
            && eval(t + C11 * h, y_stage, k11)
            && combine(
                y_stage,
                y,
                h,
                [
                    (A121, &*k1),
                    (A124, &*k4),
                    (A125, &*k5),
                    (A126, &*k6),
                    (A127, &*k7),
                    (A128, &*k8),
                    (A129, &*k9),
                    (A1210, &*k10),
                    (A1211, &*k11),
                ],
            )
            && eval(t_new, y_stage, k12)
            && combine(
                y_new,
                y,
                h,
                [
                    (B1, &*k1),
                    (B6, &*k6),
                    (B7, &*k7),
                    (B8, &*k8),
                    (B9, &*k9),
                    (B10, &*k10),
                    (B11, &*k11),
                    (B12, &*k12),
                ],
            );
        // The new point, which the system may hold already (see `evaluate_new_point`).
        staged && {
            evaluate_new_point(sys, evals, t_new, y_new, k13);
            true
        }
            // f at the new point enters no error estimate: checked here, as it becomes the
            // next step's first stage (FSAL).
            && all_finite(k13)
    }

    /// The square of the 3rd-order error norm of the last attempted step (NaN before any).
    pub(crate) fn err3_squared(&self) -> f64 {
        self.err3_squared
    }

    /// The square of `dop853.f`'s error norm `|h|·E5² / sqrt(N·(E5² + 0.01·E3²))`, with E5
    /// and E3 the RMS sums of the 5th- and 3rd-order differences scaled by
    /// `atol + rtol·max(|y|, |y_new|)` (squared: see [`Method::attempt`]).
    #[inline(always)]
    fn error_norm(&mut self, h: f64, y: &V, tol: Tolerance) -> f64 {
        let k = |i: usize| self.k[i].as_slice();
        let (y, y_new) = (y.as_slice(), self.y_new.as_slice());
        let (mut e5, mut e3) = (0.0, 0.0);
        for i in 0..V::DIM {
            let inv_scale = inverse_scale(tol, y[i], y_new[i]);
            let b = B1 * k(0)[i]
                + B6 * k(5)[i]
                + B7 * k(6)[i]
                + B8 * k(7)[i]
                + B9 * k(8)[i]
                + B10 * k(9)[i]
                + B11 * k(10)[i]
                + B12 * k(11)[i];
            let err3 = b - BHH1 * k(0)[i] - BHH2 * k(8)[i] - BHH3 * k(11)[i];
            let err5 = ER1 * k(0)[i]
                + ER6 * k(5)[i]
                + ER7 * k(6)[i]
                + ER8 * k(7)[i]
                + ER9 * k(8)[i]
                + ER10 * k(9)[i]
                + ER11 * k(10)[i]
                + ER12 * k(11)[i];
            e3 += ratio_sq(err3, inv_scale);
            e5 += ratio_sq(err5, inv_scale);
        }
        self.err3_squared = (h * h) * (e3 / V::DIM as f64);
        let mut deno = e5 + 0.01 * e3;
        if deno <= 0.0 {
            deno = 1.0;
        }
        (h * e5) * (h * e5) / (V::DIM as f64 * deno)
    }
}

impl<V: StateVector> Method<V> for Dp853<V> {
    const ORDER: i32 = 8;
    /// `dop853.f`'s defaults: no PI term (BETA = 0), EXPO1 = 1/8, shrink ≤ 1/0.333,
    /// growth ≤ 6.
    const CONTROL: Control = Control {
        beta: 0.0,
        expo1: 1.0 / 8.0,
        min_growth: 0.333,
        max_growth: 6.0,
    };

    #[inline(always)]
    fn k1(&mut self) -> &mut V {
        &mut self.k[0]
    }

    fn scratch(&mut self) -> (&V, &mut V, &mut V) {
        let [k1, k2, ..] = &mut self.k;
        (k1, &mut self.y_stage, k2)
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
            self.error_norm(h, y, tol)
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
        self.k[0] = self.k[12];
    }
}

/// The tableau as arrays, for the order-condition tests.
#[cfg(test)]
pub(crate) mod tableau {
    use super::*;
    pub(crate) const C: [f64; 12] = [0.0, C2, C3, C4, C5, C6, C7, C8, C9, C10, C11, 1.0];
    pub(crate) const B: [f64; 12] = [B1, 0.0, 0.0, 0.0, 0.0, B6, B7, B8, B9, B10, B11, B12];
    pub(crate) const A: [[f64; 11]; 12] = [
        [0.0; 11],
        [A21, 0., 0., 0., 0., 0., 0., 0., 0., 0., 0.],
        [A31, A32, 0., 0., 0., 0., 0., 0., 0., 0., 0.],
        [A41, 0., A43, 0., 0., 0., 0., 0., 0., 0., 0.],
        [A51, 0., A53, A54, 0., 0., 0., 0., 0., 0., 0.],
        [A61, 0., 0., A64, A65, 0., 0., 0., 0., 0., 0.],
        [A71, 0., 0., A74, A75, A76, 0., 0., 0., 0., 0.],
        [A81, 0., 0., A84, A85, A86, A87, 0., 0., 0., 0.],
        [A91, 0., 0., A94, A95, A96, A97, A98, 0., 0., 0.],
        [A101, 0., 0., A104, A105, A106, A107, A108, A109, 0., 0.],
        [A111, 0., 0., A114, A115, A116, A117, A118, A119, A1110, 0.],
        [
            A121, 0., 0., A124, A125, A126, A127, A128, A129, A1210, A1211,
        ],
    ];
}
