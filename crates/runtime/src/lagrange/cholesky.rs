//! Solving the mass matrix's equations: Cholesky's factorization, the one for a symmetric
//! positive definite matrix (half the work of LU, no pivoting, and its failure is the test
//! of definiteness).

use crate::model::Scalar;

/// Solves `A x = b` for the symmetric matrix `A = m[rows][rows]` (the rows `rows` of `m`,
/// which must be positive definite), overwriting `b[rows]` with `x[rows]`.
///
/// `Err((k, pivot))` when `A` is not positive definite: `rows[k]` is the first row whose
/// pivot is not a positive number (`b` is then left partly solved).
// Indices, as the textbook writes the factorization: clearer than iterators over rows of `l`.
// Inlined: with the rows constants (every coordinate free) the loops unroll.
#[allow(clippy::needless_range_loop)]
#[inline(always)]
pub(super) fn solve_positive_definite<S: Scalar, const N: usize>(
    m: &[[S; N]; N],
    rows: &[usize],
    b: &mut [S; N],
) -> Result<(), (usize, S)> {
    let n = rows.len();
    // The lower triangle L, with A = L Lᵀ.
    let mut l = [[S::zero(); N]; N];
    for j in 0..n {
        let mut pivot = m[rows[j]][rows[j]];
        for k in 0..j {
            pivot -= l[j][k] * l[j][k];
        }
        // Positive beyond rounding (8 n ε of its diagonal): a singular matrix leaves a pivot
        // of rounding noise, of either sign, and a solution of noise amplified. NaN is not
        // positive either.
        let noise = m[rows[j]][rows[j]] * S::from_subset(&(8.0 * n as f64 * f64::EPSILON));
        if pivot.partial_cmp(&noise) != Some(std::cmp::Ordering::Greater) {
            return Err((j, pivot));
        }
        let diagonal = pivot.sqrt();
        l[j][j] = diagonal;
        let inverse = diagonal.recip();
        for i in j + 1..n {
            let mut sum = m[rows[i]][rows[j]];
            for k in 0..j {
                sum -= l[i][k] * l[j][k];
            }
            l[i][j] = sum * inverse;
        }
    }
    // L y = b, then Lᵀ x = y.
    for i in 0..n {
        let mut sum = b[rows[i]];
        for k in 0..i {
            sum -= l[i][k] * b[rows[k]];
        }
        b[rows[i]] = sum / l[i][i];
    }
    for i in (0..n).rev() {
        let mut sum = b[rows[i]];
        for k in i + 1..n {
            sum -= l[k][i] * b[rows[k]];
        }
        b[rows[i]] = sum / l[i][i];
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn solves_the_rows_it_is_given_and_refuses_an_indefinite_matrix() {
        // rows 0 and 2 of a 3×3 matrix: [[4, 2], [2, 3]] x = (2, 5) → x = (-0.5, 2).
        let m = [[4.0, 9.0, 2.0], [9.0, 0.0, 9.0], [2.0, 9.0, 3.0]];
        let mut b = [2.0, 7.0, 5.0];
        solve_positive_definite(&m, &[0, 2], &mut b).unwrap();
        assert!((b[0] + 0.5).abs() < 1e-15 && (b[2] - 2.0).abs() < 1e-15);
        assert_eq!(b[1], 7.0, "a row not solved for is left alone");

        let singular = [[1.0, 1.0], [1.0, 1.0]];
        let err = solve_positive_definite(&singular, &[0, 1], &mut [1.0, 1.0]).unwrap_err();
        assert_eq!(err, (1, 0.0));
        // Rank one, u uᵀ, whose second pivot is rounding noise (of either sign): refused.
        let mut refused = 0;
        for k in 1..=1000 {
            let (a, b) = (0.37 * k as f64 + 0.1, (k as f64).sqrt() - 7.3);
            let rank_one = [[a * a, a * b], [a * b, b * b]];
            refused +=
                solve_positive_definite(&rank_one, &[0, 1], &mut [1.0, 1.0]).is_err() as usize;
        }
        assert_eq!(refused, 1000);
        let nan = [[f64::NAN]];
        assert!(solve_positive_definite(&nan, &[0], &mut [1.0]).is_err());
    }
}
