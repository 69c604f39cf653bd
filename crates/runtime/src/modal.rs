//! Undamped vibration modes of a linear(ized) mechanism: `M q̈ + K q = 0`.
//!
//! Used by mechanisms for their calculated parameters (natural frequencies, mode shapes).

use nalgebra::{SMatrix, SVector};

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
    let (_, eigenvectors) = symmetric_eigen(a)?;
    let lt = l.transpose();
    let mut modes = [Mode {
        omega: 0.0,
        shape: SVector::zeros(),
    }; N];
    for (i, mode) in modes.iter_mut().enumerate() {
        let y = SVector::<f64, N>::from_iterator(eigenvectors.column(i).iter().copied());
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

/// Sweeps after which [`symmetric_eigen`] gives up; it needs well under 10 for the matrices
/// of a mechanism (the convergence is quadratic).
const MAX_SWEEPS: usize = 50;

/// Eigenvalues and orthonormal eigenvectors (the columns, in the eigenvalues' order, which is
/// not sorted) of the symmetric matrix `a`, by the cyclic Jacobi method (Golub & Van Loan,
/// *Matrix Computations*, §8.5; Numerical Recipes' `jacobi`).
///
/// Why not nalgebra's `SymmetricEigen`: it is generic over nalgebra's type-level dimensions,
/// not over a const `N`, so it needs a `DMatrix` copy, and that allocates. `undamped_modes`
/// runs in `calculate`, thus in `fmi2SetReal` of a tunable parameter, which must not
/// allocate. This works on `SMatrix` (on the stack) only; Jacobi is accurate to rounding for
/// symmetric matrices, and for the small `N` of a mechanism it is as fast as any.
///
/// Each rotation annihilates one off-diagonal entry `a_pq`, with `t = tan φ` the smaller
/// root, `t = sign(θ) / (|θ| + sqrt(θ² + 1))`, `θ = (a_qq - a_pp) / (2 a_pq)` (or
/// `t = a_pq / (a_qq - a_pp)` when `θ` is so large that `θ²` would lose it), and the entries
/// updated in the stable form `a' = a - s (b + τ a)`, `τ = s / (1 + c)`. An entry negligible
/// beside both its diagonal entries is set to zero without a rotation (it is below their
/// rounding). The sweeps stop when every off-diagonal entry is zero, which the quadratic
/// convergence reaches within a few sweeps of rounding level (by underflow, if need be).
/// An `Err` if `a` is not finite, if a rotation overflows, or if [`MAX_SWEEPS`] sweeps do
/// not converge.
fn symmetric_eigen<const N: usize>(
    a: SMatrix<f64, N, N>,
) -> Result<(SVector<f64, N>, SMatrix<f64, N, N>), String> {
    // Below this fraction of a diagonal entry's rounding, an off-diagonal entry is negligible.
    const NEGLIGIBLE: f64 = 0.01 * f64::EPSILON;
    let original = a;
    let mut a = a;
    let mut v = SMatrix::<f64, N, N>::identity();
    for _ in 0..MAX_SWEEPS {
        let mut off = 0.0;
        for p in 0..N {
            for q in p + 1..N {
                off += a[(p, q)].abs();
            }
        }
        if !off.is_finite() || !a.iter().all(|x| x.is_finite()) {
            // A NaN would end the sweeps at once: every rotation sets its entry to zero.
            return Err(format!(
                "the symmetric eigenvalue problem of {original:?} is not finite"
            ));
        }
        if off == 0.0 {
            return Ok((a.diagonal(), v));
        }
        for p in 0..N {
            for q in p + 1..N {
                let apq = a[(p, q)];
                if apq == 0.0 {
                    continue;
                }
                let (app, aqq) = (a[(p, p)], a[(q, q)]);
                if apq.abs() <= NEGLIGIBLE * app.abs() && apq.abs() <= NEGLIGIBLE * aqq.abs() {
                    a[(p, q)] = 0.0;
                    a[(q, p)] = 0.0;
                    continue;
                }
                let h = aqq - app;
                if !h.is_finite() {
                    return Err(format!(
                        "the symmetric eigenvalue problem of {original:?} overflows"
                    ));
                }
                let t = if apq.abs() <= NEGLIGIBLE * h.abs() {
                    apq / h
                } else {
                    let theta = 0.5 * h / apq;
                    let t = 1.0 / (theta.abs() + (theta * theta + 1.0).sqrt());
                    if theta < 0.0 {
                        -t
                    } else {
                        t
                    }
                };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let s = t * c;
                let tau = s / (1.0 + c);
                a[(p, p)] = app - t * apq;
                a[(q, q)] = aqq + t * apq;
                a[(p, q)] = 0.0;
                a[(q, p)] = 0.0;
                for r in (0..N).filter(|&r| r != p && r != q) {
                    let (arp, arq) = (a[(r, p)], a[(r, q)]);
                    let new_rp = arp - s * (arq + tau * arp);
                    let new_rq = arq + s * (arp - tau * arq);
                    a[(r, p)] = new_rp;
                    a[(p, r)] = new_rp;
                    a[(r, q)] = new_rq;
                    a[(q, r)] = new_rq;
                }
                for r in 0..N {
                    let (vrp, vrq) = (v[(r, p)], v[(r, q)]);
                    v[(r, p)] = vrp - s * (vrq + tau * vrp);
                    v[(r, q)] = vrq + s * (vrp - tau * vrq);
                }
            }
        }
    }
    Err(format!(
        "the Jacobi eigenvalue iteration on {original:?} did not converge in {MAX_SWEEPS} sweeps"
    ))
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
    use nalgebra::{DMatrix, Matrix2, Matrix3, SymmetricEigen, Vector3};

    /// Decomposes `a` and checks what any symmetric eigen-decomposition must give: `VᵀV = I`
    /// and `A V = V Λ` to rounding. Returns the eigenpairs sorted by eigenvalue.
    fn decompose<const N: usize>(a: SMatrix<f64, N, N>) -> Vec<(f64, SVector<f64, N>)> {
        let (values, vectors) = symmetric_eigen(a).unwrap();
        let orthonormality =
            (vectors.transpose() * vectors - SMatrix::<f64, N, N>::identity()).amax();
        assert!(
            orthonormality <= 4.0 * f64::EPSILON,
            "VᵀV - I = {orthonormality:e} for {a}"
        );
        let residual = (a * vectors - vectors * SMatrix::from_diagonal(&values)).amax();
        assert!(
            residual <= 8.0 * f64::EPSILON * a.amax(),
            "A V - V Λ = {residual:e} for {a}"
        );
        let mut pairs: Vec<_> = (0..N)
            .map(|i| (values[i], vectors.column(i).into_owned()))
            .collect();
        pairs.sort_by(|x, y| x.0.total_cmp(&y.0));
        pairs
    }

    #[test]
    fn jacobi_diagonal_is_returned_as_is() {
        let a = SMatrix::<f64, 4, 4>::from_diagonal(&SVector::from([3.0, -1.0, 0.0, 2.5]));
        let (values, vectors) = symmetric_eigen(a).unwrap();
        assert_eq!(values, SVector::from([3.0, -1.0, 0.0, 2.5]));
        assert_eq!(vectors, SMatrix::<f64, 4, 4>::identity());
    }

    #[test]
    fn jacobi_2x2_closed_form() {
        for (p, q, r) in [
            (2.0, -1.0, 2.0),
            (1.0, 0.3, 5.0),
            (-4.0, 2.0, 1e-3),
            (1e6, 1.0, 1.0),
        ] {
            let pairs = decompose(Matrix2::new(p, q, q, r));
            let (mean, radius) = (0.5 * (p + r), (0.25 * (p - r) * (p - r) + q * q).sqrt());
            for (value, exact) in pairs
                .iter()
                .map(|x| x.0)
                .zip([mean - radius, mean + radius])
            {
                assert!(
                    (value - exact).abs() <= 4.0 * f64::EPSILON * exact.abs().max(radius),
                    "{value} vs {exact} for ({p}, {q}, {r})"
                );
            }
        }
    }

    #[test]
    fn jacobi_3x3_second_difference() {
        let a = Matrix3::new(2.0, -1.0, 0.0, -1.0, 2.0, -1.0, 0.0, -1.0, 2.0);
        let pairs = decompose(a);
        let s = 2f64.sqrt();
        let exact = [
            (2.0 - s, Vector3::new(0.5, 0.5 * s, 0.5)),
            (2.0, Vector3::new(0.5 * s, 0.0, -0.5 * s)),
            (2.0 + s, Vector3::new(0.5, -0.5 * s, 0.5)),
        ];
        for ((value, vector), (exact_value, exact_vector)) in pairs.iter().zip(exact) {
            assert!(
                (value - exact_value).abs() <= 4.0 * f64::EPSILON,
                "{value} vs {exact_value}"
            );
            // Unit eigenvectors, defined up to sign.
            assert!((vector.dot(&exact_vector).abs() - 1.0).abs() <= 4.0 * f64::EPSILON);
        }
    }

    #[test]
    fn jacobi_repeated_eigenvalues() {
        let (values, vectors) = symmetric_eigen(SMatrix::<f64, 5, 5>::identity()).unwrap();
        assert_eq!(values, SVector::<f64, 5>::repeat(1.0));
        assert_eq!(vectors, SMatrix::<f64, 5, 5>::identity());
        // All ones: eigenvalues 0, 0, 0, 4 (three zero, so the sweeps end by underflow).
        let pairs = decompose(SMatrix::<f64, 4, 4>::repeat(1.0));
        for (value, exact) in pairs.iter().map(|x| x.0).zip([0.0, 0.0, 0.0, 4.0]) {
            assert!(
                (value - exact).abs() <= 8.0 * f64::EPSILON,
                "{value} vs {exact}"
            );
        }
        assert!((pairs[3].1.abs() - SVector::<f64, 4>::repeat(0.5)).amax() <= 4.0 * f64::EPSILON);
    }

    /// Symmetric positive definite `Bᵀ B + I`, `B` from a fixed pseudo-random sequence.
    fn spd<const N: usize>(seed: u64) -> SMatrix<f64, N, N> {
        let mut state = seed;
        let b = SMatrix::<f64, N, N>::from_fn(|_, _| {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (state >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
        });
        b.transpose() * b + SMatrix::identity()
    }

    fn agrees_with_nalgebra<const N: usize>(a: SMatrix<f64, N, N>) {
        let pairs = decompose(a);
        let reference = SymmetricEigen::new(DMatrix::from_column_slice(N, N, a.as_slice()));
        let mut order: Vec<usize> = (0..N).collect();
        order.sort_by(|&i, &j| reference.eigenvalues[i].total_cmp(&reference.eigenvalues[j]));
        for ((value, vector), i) in pairs.iter().zip(order) {
            let exact = reference.eigenvalues[i];
            assert!(
                (value - exact).abs() <= 16.0 * f64::EPSILON * a.amax(),
                "{value} vs nalgebra's {exact} for {a}"
            );
            let other = reference.eigenvectors.column(i);
            let cosine = vector
                .iter()
                .zip(other.iter())
                .map(|(x, y)| x * y)
                .sum::<f64>();
            assert!(
                (cosine.abs() - 1.0).abs() <= 1e-13,
                "eigenvectors of {value}: cos = {cosine}"
            );
        }
    }

    #[test]
    fn jacobi_agrees_with_nalgebra_on_spd_matrices() {
        for seed in 1..=5 {
            agrees_with_nalgebra(spd::<2>(seed));
            agrees_with_nalgebra(spd::<3>(seed));
            agrees_with_nalgebra(spd::<4>(seed));
            agrees_with_nalgebra(spd::<6>(seed));
        }
    }

    #[test]
    fn jacobi_not_finite_is_an_error() {
        for x in [f64::NAN, f64::INFINITY] {
            let error = symmetric_eigen(Matrix2::new(1.0, x, x, 1.0)).unwrap_err();
            assert!(error.contains("not finite"), "{error}");
            let error = symmetric_eigen(Matrix2::new(x, 0.0, 0.0, 1.0)).unwrap_err();
            assert!(error.contains("not finite"), "{error}");
        }
        // Finite, but its rotations overflow.
        let big = f64::MAX;
        assert!(symmetric_eigen(Matrix2::new(big, big, big, -big)).is_err());
    }

    #[test]
    fn three_masses_in_a_chain() {
        // m = 1, k = 1 between the walls and the three masses: ω² = 2 - √2, 2, 2 + √2,
        // shapes (1/√2, 1, 1/√2), (1, 0, -1), (-1/√2, 1, -1/√2).
        let stiffness = Matrix3::new(2.0, -1.0, 0.0, -1.0, 2.0, -1.0, 0.0, -1.0, 2.0);
        let modes = undamped_modes(&Matrix3::identity(), &stiffness).unwrap();
        let h = 0.5f64.sqrt();
        let exact = [
            (2.0 - 2f64.sqrt(), Vector3::new(h, 1.0, h)),
            (2.0, Vector3::new(1.0, 0.0, -1.0)),
            (2.0 + 2f64.sqrt(), Vector3::new(-h, 1.0, -h)),
        ];
        for (mode, (omega2, shape)) in modes.iter().zip(exact) {
            assert!(
                (mode.omega - omega2.sqrt()).abs() <= 4.0 * f64::EPSILON,
                "{mode:?}"
            );
            assert!(
                (mode.shape - shape).amax() <= 4.0 * f64::EPSILON,
                "{mode:?}"
            );
        }
    }

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
