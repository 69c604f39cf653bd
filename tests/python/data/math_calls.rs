//! `MathCalls`: a mechanism whose output calls every smooth function of `Scalar`'s arithmetic
//! (the rounding ones have no derivative, and panic on the dual numbers), so a build for each
//! platform links every libm call Rust lowers them to (on the Macs, against the libSystem stub
//! mechfmu carries). It drifts: `x` grows at 0.1 per second.

#![forbid(unsafe_code)]

use mechfmu::model::{lit, Experiment, Mechanism, Scalar, Variable};

mechfmu::mechanism! {
    /// A state that drifts, and an output that calls every math function on it.
    pub struct MathCalls / MathCallsValues {
        /// The drifting state
        x: Variable::state("1", 0.5, "x_dot"),
        /// Its rate
        x_dot: Variable::output("1/s"),
        /// Every function of `x` summed
        y: Variable::output("1"),
    }
}

impl Mechanism for MathCalls {
    const EXPERIMENT: Experiment = Experiment::until(1.0).step(0.1).tolerance(1e-6);

    fn evaluate<S: Scalar>(v: &mut MathCallsValues<S>) {
        let x = v.x;
        let one = lit::<S>(1.0);
        let (s, c) = x.sin_cos();
        let trigonometry = s + c + x.sin() * x.cos() + x.tan() + x.asin() + x.acos() + x.atan() + x.atan2(one);
        let hyperbolic = x.sinh() + x.cosh() + x.tanh() + x.asinh() + (one + x).acosh() + x.atanh();
        let exponential = x.exp() + x.exp2() + x.exp_m1() + x.ln() + x.ln_1p() + x.log2() + x.log10() + x.log(lit(3.0));
        let powers = x.sqrt() + x.cbrt() + x.powf(lit(1.5)) + lit::<S>(10.0).powf(x) + x.powi(3) + x.hypot(one);
        let others = x.mul_add(x, one) + x.recip() + x.abs() + x.copysign(-one) + x.max(one) + x.min(one);
        v.x_dot = lit(0.1);
        v.y = trigonometry + hyperbolic + exponential + powers + others;
    }
}

mechfmu::export_fmu!(MathCalls);
