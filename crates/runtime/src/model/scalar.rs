//! The scalar type equations are written over: `f64` for simulation, dual numbers for
//! exact derivatives.

use super::trig;
use num_dual::{Dual64, HyperHyperDual64};

/// A real scalar the equations can run on: `f64`, or one of the dual numbers the runtime
/// differentiates with (first derivatives for directional derivatives and the model
/// structure; second and third for the equations of motion of a mechanism declared from
/// its energies, [`lagrange`](crate::lagrange)).
///
/// It is nalgebra's [`RealField`](nalgebra::RealField) (arithmetic, `sin`, `cos`, `sqrt`,
/// `atan2`, matrices and their decompositions) for a `Copy` type. For sines and cosines,
/// equations call [`sin_cos`], [`sin`] and [`cos`]: the same bits on every platform, and
/// faster on `f64`. The set of scalars is the runtime's (the trait is sealed).
pub trait Scalar: nalgebra::RealField + Copy + Send + Sync + 'static + sealed::Sealed {
    /// `(sin x, cos x)` from the runtime's `sin_cos` of the real part, with the derivatives
    /// the chain rule gives.
    #[doc(hidden)]
    fn portable_sin_cos(self) -> (Self, Self);
}

/// Implemented by the runtime's scalars only (the jets of [`lagrange`](crate::lagrange)
/// implement it there).
pub(crate) mod sealed {
    pub trait Sealed {}
}

impl sealed::Sealed for f64 {}
impl Scalar for f64 {
    #[inline(always)]
    fn portable_sin_cos(self) -> (f64, f64) {
        trig::sin_cos(self)
    }
}

impl sealed::Sealed for Dual64 {}
impl Scalar for Dual64 {
    #[inline(always)]
    fn portable_sin_cos(self) -> (Self, Self) {
        let (s, c) = trig::sin_cos(self.re);
        (Dual64::new(s, self.eps * c), Dual64::new(c, -self.eps * s))
    }
}

impl sealed::Sealed for HyperHyperDual64 {}
impl Scalar for HyperHyperDual64 {
    #[inline(always)]
    fn portable_sin_cos(self) -> (Self, Self) {
        let (s, c) = trig::sin_cos(self.re);
        let x = self;
        // The chain rule to third order (Faà di Bruno) for three infinitesimals.
        let chain = |f0: f64, f1: f64, f2: f64, f3: f64| {
            HyperHyperDual64::new(
                f0,
                f1 * x.eps1,
                f1 * x.eps2,
                f1 * x.eps3,
                f1 * x.eps1eps2 + f2 * x.eps1 * x.eps2,
                f1 * x.eps1eps3 + f2 * x.eps1 * x.eps3,
                f1 * x.eps2eps3 + f2 * x.eps2 * x.eps3,
                f1 * x.eps1eps2eps3
                    + f2 * (x.eps1 * x.eps2eps3 + x.eps2 * x.eps1eps3 + x.eps3 * x.eps1eps2)
                    + f3 * x.eps1 * x.eps2 * x.eps3,
            )
        };
        (chain(s, c, -s, -c), chain(c, -s, -c, s))
    }
}

/// A constant in an equation: `lit::<S>(7.0 / 3.0)`.
#[inline(always)]
pub fn lit<S: Scalar>(x: f64) -> S {
    nalgebra::convert(x)
}

/// `(sin x, cos x)`, for equations to call instead of `x.sin_cos()`.
///
/// On `f64` it is the runtime's own, within an ulp (`model::trig`): plain arithmetic, so the
/// same bits on every platform whatever its C library, a fifth fewer instructions than the
/// `libm` crate's `sincos`, and a function of its argument alone that the compiler can see,
/// so two calls on one angle are made once. On the dual numbers it is the same function of the real
/// part with the chain rule's derivatives (num-dual's own would call the platform's).
#[inline(always)]
pub fn sin_cos<S: Scalar>(x: S) -> (S, S) {
    x.portable_sin_cos()
}

/// `sin x`: [`sin_cos`]'s first (the same bits; the cosine's work, unused, is dropped).
#[inline(always)]
pub fn sin<S: Scalar>(x: S) -> S {
    x.portable_sin_cos().0
}

/// `cos x`: [`sin_cos`]'s second.
#[inline(always)]
pub fn cos<S: Scalar>(x: S) -> S {
    x.portable_sin_cos().1
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trigonometry_is_the_runtime_s_on_f64_and_carries_derivatives_on_duals() {
        for i in -2000..=2000 {
            let x = i as f64 * 0.01;
            let (s, c) = trig::sin_cos(x);
            assert_eq!(sin_cos(x), (s, c));
            assert_eq!((sin(x), cos(x)), (s, c));
            // Within an ulp or so of the platform's.
            assert!(
                (s - x.sin()).abs() <= 2.0 * f64::EPSILON * x.sin().abs().max(f64::MIN_POSITIVE)
            );
            assert!(
                (c - x.cos()).abs() <= 2.0 * f64::EPSILON * x.cos().abs().max(f64::MIN_POSITIVE)
            );
            // d/dx (sin x, cos x) = (cos x, -sin x), from the same values.
            let d = Dual64::new(x, 1.0);
            let (ds, dc) = sin_cos(d);
            assert_eq!((ds.re, dc.re), (s, c));
            assert_eq!((ds.eps, dc.eps), (c, -s));
            assert_eq!((sin(d).re, cos(d).re), (s, c));
            assert_eq!((sin(d).eps, cos(d).eps), (c, -s));
        }
    }
}
