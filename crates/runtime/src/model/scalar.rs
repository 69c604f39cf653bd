//! The scalar type equations are written over: `f64` for simulation, dual numbers for
//! exact derivatives.

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
    /// `(sin x, cos x)` from `libm`'s `sincos` of the real part, with the derivatives the
    /// chain rule gives.
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
        libm::sincos(self)
    }
}

impl sealed::Sealed for Dual64 {}
impl Scalar for Dual64 {
    #[inline(always)]
    fn portable_sin_cos(self) -> (Self, Self) {
        let (s, c) = libm::sincos(self.re);
        (Dual64::new(s, self.eps * c), Dual64::new(c, -self.eps * s))
    }
}

impl sealed::Sealed for HyperHyperDual64 {}
impl Scalar for HyperHyperDual64 {
    #[inline(always)]
    fn portable_sin_cos(self) -> (Self, Self) {
        let (s, c) = libm::sincos(self.re);
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
/// On `f64` it is the `libm` crate's `sincos` (musl's, within an ulp): pure Rust, so the
/// same bits on every platform whatever its C library, and about a quarter faster than
/// glibc's `sincos`, which saves and restores the rounding mode at every call (measured in a
/// dependent chain: 15 against 19 ns). On the dual numbers it is the same `sincos` of the
/// real part with the chain rule's derivatives (num-dual's own would call the platform's).
#[inline(always)]
pub fn sin_cos<S: Scalar>(x: S) -> (S, S) {
    x.portable_sin_cos()
}

/// `sin x`: as [`sin_cos`], `libm`'s.
#[inline(always)]
pub fn sin<S: Scalar>(x: S) -> S {
    if let Some(x) = as_f64(x) {
        return nalgebra::convert(libm::sin(x));
    }
    x.portable_sin_cos().0
}

/// `cos x`: as [`sin_cos`], `libm`'s.
#[inline(always)]
pub fn cos<S: Scalar>(x: S) -> S {
    if let Some(x) = as_f64(x) {
        return nalgebra::convert(libm::cos(x));
    }
    x.portable_sin_cos().1
}

/// `x` itself when `S` is `f64` (None for any other scalar, such as a dual number): one
/// function of libm instead of both. Decided at compile time.
#[inline(always)]
fn as_f64<S: Scalar>(x: S) -> Option<f64> {
    if std::any::TypeId::of::<S>() == std::any::TypeId::of::<f64>() {
        x.to_subset()
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trigonometry_is_libm_on_f64_and_carries_derivatives_on_duals() {
        for i in -2000..=2000 {
            let x = i as f64 * 0.01;
            assert_eq!(sin_cos(x), libm::sincos(x));
            assert_eq!((sin(x), cos(x)), (libm::sin(x), libm::cos(x)));
            // Within an ulp or so of the platform's.
            let (s, c) = sin_cos(x);
            assert!(
                (s - x.sin()).abs() <= 2.0 * f64::EPSILON * x.sin().abs().max(f64::MIN_POSITIVE)
            );
            assert!(
                (c - x.cos()).abs() <= 2.0 * f64::EPSILON * x.cos().abs().max(f64::MIN_POSITIVE)
            );
            // d/dx (sin x, cos x) = (cos x, -sin x).
            // On duals, libm's too.
            let d = Dual64::new(x, 1.0);
            let (ds, dc) = sin_cos(d);
            assert_eq!((ds.re, dc.re), libm::sincos(x));
            assert_eq!((ds.eps, dc.eps), (libm::cos(x), -libm::sin(x)));
            assert_eq!((sin(d).re, cos(d).re), (libm::sin(x), libm::cos(x)));
            assert_eq!((sin(d).eps, cos(d).eps), (libm::cos(x), -libm::sin(x)));
        }
    }
}
