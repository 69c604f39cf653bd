//! Undamped vibration modes of a linear(ized) mechanism: `M q̈ + K q = 0`.
//!
//! Used by mechanisms for their calculated parameters (natural frequencies, mode shapes).

use nalgebra::{DMatrix, SMatrix, SVector, SymmetricEigen};

/// One undamped mode: natural frequency and shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mode<const N: usize> {
    /// Natural frequency ω (rad/s), ≥ 0.
    pub omega: f64,
    /// Shape, scaled so that its component of largest magnitude is +1 (on a tie, the first).
    pub shape: SVector<f64, N>,
}

/// Relative difference under which two components count as equally large when a shape is
/// scaled: far above the rounding of the eigenvectors (~1e-16), far below any physical
/// difference.
pub const TIE: f64 = 1e-12;

/// The undamped modes of `M q̈ + K q = 0` (`M` symmetric positive definite, `K` symmetric
/// positive semi-definite), by ascending frequency.
///
/// The generalized problem `K a = ω² M a` is made a standard symmetric one with the Cholesky
/// factor `M = L Lᵀ`: `(L⁻¹ K L⁻ᵀ) y = ω² y`, `a = L⁻ᵀ y`. Its eigenvectors are accurate to
/// rounding; each `ω²` is then taken as the Rayleigh quotient `aᵀ K a / aᵀ M a` of the scaled
/// shape, exact to second order in the shape's error, so a free-floating body (shape (1, 1),
/// `K a = 0`) gets ω = 0 rather than the square root of a rounding error.
///
/// ```
/// use mechfmu::nalgebra::{Matrix2, Vector2};
/// // m1 = m2 = 1, k1 = k2 = k3 = 1: ω = 1 (1 : 1) and sqrt(3) (1 : -1).
/// let modes = mechfmu::modal::undamped_modes(&Matrix2::identity(), &Matrix2::new(2.0, -1.0, -1.0, 2.0)).unwrap();
/// assert!((modes[0].omega - 1.0).abs() < 1e-15 && modes[0].shape == Vector2::new(1.0, 1.0));
/// assert!((modes[1].omega - 3f64.sqrt()).abs() < 1e-15 && modes[1].shape == Vector2::new(1.0, -1.0));
/// ```
pub fn undamped_modes<const N: usize>(
    mass: &SMatrix<f64, N, N>,
    stiffness: &SMatrix<f64, N, N>,
) -> Result<[Mode<N>; N], String> {
    let l = mass
        .cholesky()
        .ok_or_else(|| format!("the mass matrix {mass:?} is not positive definite"))?
        .unpack();
    let singular = || "the mass matrix is singular".to_string();
    // L⁻¹ K, then L⁻¹ (L⁻¹ K)ᵀ = L⁻¹ K L⁻ᵀ (K is symmetric).
    let half = l.solve_lower_triangular(stiffness).ok_or_else(singular)?;
    let a = l
        .solve_lower_triangular(&half.transpose())
        .ok_or_else(singular)?;
    let a = (a + a.transpose()) * 0.5;
    // A dynamically sized copy: nalgebra's eigen-decomposition is not generic over a
    // const dimension (this runs at initialization only).
    let eigen = SymmetricEigen::try_new(
        DMatrix::from_column_slice(N, N, a.as_slice()),
        f64::EPSILON,
        1000,
    )
    .ok_or_else(|| format!("the eigenvalues of {a:?} did not converge"))?;
    let lt = l.transpose();
    let mut modes = [Mode {
        omega: 0.0,
        shape: SVector::zeros(),
    }; N];
    for (i, mode) in modes.iter_mut().enumerate() {
        let y = SVector::<f64, N>::from_iterator(eigen.eigenvectors.column(i).iter().copied());
        let shape = scale_shape(lt.solve_upper_triangular(&y).ok_or_else(singular)?);
        let omega2 = shape.dot(&(stiffness * shape)) / shape.dot(&(mass * shape));
        // K ≥ 0 makes ω² ≥ 0; a negative value can only be rounding.
        *mode = Mode {
            omega: omega2.max(0.0).sqrt(),
            shape,
        };
    }
    modes.sort_by(|a, b| a.omega.total_cmp(&b.omega));
    Ok(modes)
}

/// Scales a shape so that its component of largest magnitude is +1. Components equal in
/// magnitude to within [`TIE`] count as a tie: the first is then +1 and the others exactly ±1.
fn scale_shape<const N: usize>(a: SVector<f64, N>) -> SVector<f64, N> {
    let largest = a.amax();
    let big = (0..N)
        .find(|&i| a[i].abs() >= largest * (1.0 - TIE))
        .unwrap_or(0);
    let mut s = a / a[big];
    for (i, x) in s.iter_mut().enumerate() {
        if i == big {
            *x = 1.0;
        } else if (x.abs() - 1.0).abs() <= TIE {
            *x = x.signum();
        }
        *x += 0.0; // turns -0.0 into 0.0
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Matrix2;

    #[test]
    fn the_notes_examples() {
        // 2 m1 = m2 = 2, k1 = k2 = 0, k3 = 1: ω = 0 (1 : 1) and sqrt(3/2) (1 : -1/2).
        let modes = undamped_modes(
            &Matrix2::new(1.0, 0.0, 0.0, 2.0),
            &Matrix2::new(1.0, -1.0, -1.0, 1.0),
        )
        .unwrap();
        assert_eq!(modes[0].omega, 0.0);
        assert_eq!(modes[0].shape, SVector::from([1.0, 1.0]));
        assert!((modes[1].omega - 1.5f64.sqrt()).abs() < 1e-15);
        assert!((modes[1].shape - SVector::from([1.0, -0.5])).norm() < 1e-15);
    }

    #[test]
    fn not_positive_definite_is_an_error() {
        assert!(undamped_modes(&Matrix2::new(1.0, 0.0, 0.0, 0.0), &Matrix2::identity()).is_err());
    }
}
