//! The scalar type equations are written over: `f64` for simulation, a dual number for
//! exact derivatives.

/// A real scalar the equations can run on: `f64` or a dual number.
///
/// It is nalgebra's [`RealField`](nalgebra::RealField) (arithmetic, `sin`, `cos`, `sqrt`,
/// `atan2`, matrices and their decompositions) for a `Copy` type.
pub trait Scalar: nalgebra::RealField + Copy + Send + Sync + 'static {}

impl<T: nalgebra::RealField + Copy + Send + Sync + 'static> Scalar for T {}

/// A constant in an equation: `lit::<S>(7.0 / 3.0)`.
#[inline(always)]
pub fn lit<S: Scalar>(x: f64) -> S {
    nalgebra::convert(x)
}
