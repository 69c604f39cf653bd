//! The Python functions FMPy's simulation loop decides with, ported from CPython's C so the
//! worker takes the same communication points: `math.isclose` and `bisect`.

/// `math.isclose(a, b)` with its defaults `rel_tol=1e-9, abs_tol=0.0` (CPython's
/// `math_isclose_impl`): equal values (infinities too) are close, an infinity is close to
/// nothing else, NaN to nothing.
pub fn isclose(a: f64, b: f64) -> bool {
    const REL_TOL: f64 = 1e-9;
    const ABS_TOL: f64 = 0.0;
    if a == b {
        return true;
    }
    if a.is_infinite() || b.is_infinite() {
        return false;
    }
    let diff = (b - a).abs();
    diff <= (REL_TOL * b).abs() || diff <= (REL_TOL * a).abs() || diff <= ABS_TOL
}

/// `bisect.bisect_left(a, x)`: CPython's loop, comparison for comparison (so an unsorted
/// list or a NaN gives Python's index too).
pub fn bisect_left(a: &[f64], x: f64) -> usize {
    let (mut lo, mut hi) = (0, a.len());
    while lo < hi {
        let mid = (lo + hi) / 2;
        if a[mid] < x {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    lo
}

/// `bisect.bisect_right(a, x)`, likewise.
pub fn bisect_right(a: &[f64], x: f64) -> usize {
    let (mut lo, mut hi) = (0, a.len());
    while lo < hi {
        let mid = (lo + hi) / 2;
        if x < a[mid] {
            hi = mid;
        } else {
            lo = mid + 1;
        }
    }
    lo
}

#[cfg(test)]
mod tests {
    use super::*;

    const INF: f64 = f64::INFINITY;
    const NAN: f64 = f64::NAN;

    #[test]
    fn isclose_is_pythons() {
        // Each (a, b, math.isclose(a, b)) as Python 3.11 answers it.
        let cases = [
            (1.0, 1.0, true),
            (0.0, -0.0, true),
            (0.0, 1e-300, false), // abs_tol = 0: nothing is close to zero but zero
            (1.0, 1.0 + 1e-10, true),
            (1.0, 1.0 + 1.1e-9, false),
            (1.0, 1.0 + 1e-9, false), // the rounded sum is just beyond the tolerance
            (1e9, 1e9 + 1.0, true),
            (1e9, 1e9 + 2.0, false),
            (-5.0, -5.000000001, true),
            (INF, INF, true),
            (-INF, -INF, true),
            (INF, -INF, false),
            (INF, 1e308, false),
            (1e308, INF, false),
            (NAN, NAN, false),
            (NAN, 1.0, false),
            (1.0, NAN, false),
            (0.1 + 0.2, 0.3, true),
        ];
        for (a, b, close) in cases {
            assert_eq!(isclose(a, b), close, "isclose({a}, {b})");
            assert_eq!(isclose(b, a), close, "isclose({b}, {a})");
        }
    }

    #[test]
    fn bisect_finds_pythons_indices() {
        let a = [0.0, 1.0, 1.0, 2.0];
        assert_eq!(bisect_left(&a, 1.0), 1);
        assert_eq!(bisect_right(&a, 1.0), 3);
        assert_eq!(bisect_left(&a, -1.0), 0);
        assert_eq!(bisect_right(&a, 5.0), 4);
        assert_eq!(bisect_left(&a, 1.5), 3);
        assert_eq!(bisect_left(&[], 1.0), 0);
        // NaN compares false: bisect_left walks left, bisect_right walks right.
        assert_eq!(bisect_left(&a, NAN), 0);
        assert_eq!(bisect_right(&a, NAN), 4);
    }
}
