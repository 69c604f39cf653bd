//! The scalar type equations are written over: `f64` for simulation, a dual number for
//! exact derivatives.

/// A real scalar the equations can run on: `f64` or a dual number.
///
/// It is nalgebra's [`RealField`](nalgebra::RealField) (arithmetic, `sin`, `cos`, `sqrt`,
/// `atan2`, matrices and their decompositions) for a `Copy` type. For sines and cosines,
/// equations call [`sin_cos`], [`sin`] and [`cos`] (portable and faster on `f64`).
pub trait Scalar: nalgebra::RealField + Copy + Send + Sync + 'static {}

use num_dual::Dual64;
use std::any::Any;

impl<T: nalgebra::RealField + Copy + Send + Sync + 'static> Scalar for T {}

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
/// dependent chain: 15 against 19 ns). On the runtime's dual number ([`Dual64`]) it is the
/// same `sincos` with the derivatives `(cos x, -sin x)` (num-dual's own would call the
/// platform's); other scalars take their own `sin_cos`. The type tests are decided at
/// compile time.
#[inline(always)]
pub fn sin_cos<S: Scalar>(x: S) -> (S, S) {
    if let Some(x) = as_f64(x) {
        let (sin, cos) = libm::sincos(x);
        return (nalgebra::convert(sin), nalgebra::convert(cos));
    }
    if let Some(d) = as_dual(x) {
        let (sin, cos) = libm::sincos(d.re);
        return (
            from_dual(Dual64::new(sin, d.eps * cos)),
            from_dual(Dual64::new(cos, -d.eps * sin)),
        );
    }
    x.sin_cos()
}

/// `sin x`: as [`sin_cos`], `libm`'s on `f64` and [`Dual64`].
#[inline(always)]
pub fn sin<S: Scalar>(x: S) -> S {
    if let Some(x) = as_f64(x) {
        return nalgebra::convert(libm::sin(x));
    }
    if let Some(d) = as_dual(x) {
        return from_dual(Dual64::new(libm::sin(d.re), d.eps * libm::cos(d.re)));
    }
    x.sin()
}

/// `cos x`: as [`sin_cos`], `libm`'s on `f64` and [`Dual64`].
#[inline(always)]
pub fn cos<S: Scalar>(x: S) -> S {
    if let Some(x) = as_f64(x) {
        return nalgebra::convert(libm::cos(x));
    }
    if let Some(d) = as_dual(x) {
        return from_dual(Dual64::new(libm::cos(d.re), -d.eps * libm::sin(d.re)));
    }
    x.cos()
}

/// `x` itself when `S` is [`Dual64`].
#[inline(always)]
fn as_dual<S: Scalar>(x: S) -> Option<Dual64> {
    (&x as &dyn Any).downcast_ref::<Dual64>().copied()
}

/// `d` as `S`, which [`as_dual`] found to be [`Dual64`].
#[inline(always)]
fn from_dual<S: Scalar>(d: Dual64) -> S {
    *(&d as &dyn Any).downcast_ref::<S>().expect("S is Dual64")
}

/// `x` itself when `S` is `f64` (None for any other scalar, such as a dual number).
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
