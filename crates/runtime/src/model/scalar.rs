//! The scalar type equations are written over: `f64` for simulation, a dual number for
//! exact derivatives.

/// A real scalar the equations can run on: `f64` or a dual number.
///
/// It is nalgebra's [`RealField`](nalgebra::RealField) (arithmetic, `sin`, `cos`, `sqrt`,
/// `atan2`, matrices and their decompositions) for a `Copy` type. For sines and cosines,
/// equations call [`sin_cos`], [`sin`] and [`cos`] (portable and faster on `f64`).
pub trait Scalar: nalgebra::RealField + Copy + Send + Sync + 'static {}

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
/// dependent chain: 15 against 19 ns). Dual numbers take their own `sin_cos`, which carries
/// the derivatives. The type test is decided at compile time.
#[inline(always)]
pub fn sin_cos<S: Scalar>(x: S) -> (S, S) {
    match as_f64(x) {
        Some(x) => {
            let (sin, cos) = libm::sincos(x);
            (nalgebra::convert(sin), nalgebra::convert(cos))
        }
        None => x.sin_cos(),
    }
}

/// `sin x`: as [`sin_cos`], `libm`'s on `f64`.
#[inline(always)]
pub fn sin<S: Scalar>(x: S) -> S {
    match as_f64(x) {
        Some(x) => nalgebra::convert(libm::sin(x)),
        None => x.sin(),
    }
}

/// `cos x`: as [`sin_cos`], `libm`'s on `f64`.
#[inline(always)]
pub fn cos<S: Scalar>(x: S) -> S {
    match as_f64(x) {
        Some(x) => nalgebra::convert(libm::cos(x)),
        None => x.cos(),
    }
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
    use num_dual::Dual64;

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
            let d = Dual64::new(x, 1.0);
            let (ds, dc) = sin_cos(d);
            assert_eq!((ds.re, dc.re), (x.sin(), x.cos()));
            assert!((ds.eps - x.cos()).abs() <= 1e-15 && (dc.eps + x.sin()).abs() <= 1e-15);
            assert_eq!((sin(d).eps, cos(d).eps), (ds.eps, dc.eps));
        }
    }
}
