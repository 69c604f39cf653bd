//! Sine and cosine together, within an ulp, in three quarters of the instructions of the
//! `libm` crate's `sincos` (fewer still beyond `π/4`, where it calls its general reduction).
//!
//! Equations take both of an angle almost always, often of several angles per evaluation,
//! and evaluate them at every stage of every step: in a double pendulum they were a quarter
//! of a step. Here the argument is reduced once and both polynomials share its square; no
//! table, no loop, no branch but the range's.
//!
//! `#[inline]`, not `always`: inlined everywhere, a call made the equations that take an
//! occasional sine (the Oscillator's forcing) too large for the compiler to inline them into
//! the solver's stages, which cost more than the call saves.
//!
//! - `|x| ≤ π/4`: the polynomials directly.
//! - `|x| < 10^6`: `x = n π/2 + r`, `n` rounded from `x · 2/π`, `r` to about 120 bits as
//!   the sum `hi + lo` of two doubles (Cody and Waite: `π/2` split in three parts whose
//!   first two have 33 bits, so that `n` times them is exact for `|n| < 2^20`), then the
//!   quadrant `n mod 4` picks and signs the two.
//! - beyond, and for infinities and NaN: the `libm` crate's `sincos` (Payne and Hanek's
//!   reduction); no equation meets such angles.
//!
//! Plain IEEE arithmetic in a fixed order, no fused multiply-add: every platform computes
//! the same bits.

use std::f64::consts::{FRAC_2_PI, FRAC_PI_4};

/// `π/2 = P1 + P2 + P3` to 2^-122: `P1` and `P2` have 33 significant bits, `P3` 53.
const P1: f64 = f64::from_bits(0x3ff9_21fb_5440_0000);
const P2: f64 = f64::from_bits(0x3dd0_b461_1a60_0000);
const P3: f64 = f64::from_bits(0x3ba3_198a_2e03_7073);

/// Below this, `|n| < 2^20`, so `n · P1` and `n · P2` are exact.
const MEDIUM: f64 = 1.0e6;

/// Below this, `x³/6` and `x²/2` are under half an ulp of `x` and of 1.
const TINY: f64 = 1.0 / (1u64 << 27) as f64;

/// Adding `1.5 · 2^52` to a number of magnitude below `2^51` rounds it to an integer, which
/// then sits in the sum's low mantissa bits.
const ROUNDING: f64 = 6_755_399_441_055_744.0;

// `sin x = x + x³ S(x²)` and `cos x = 1 - x²/2 + x⁴ C(x²)` on `|x| ≤ π/4`: `S` and `C` are
// Chebyshev fits (mpmath, 50 digits) of `(sin √z / √z - 1) / z` and
// `(cos √z - 1 + z/2) / z²` on `[0, π²/16]`, of degree 6 and 5. Rounded to doubles they
// leave at most 0.06 and 0.01 of an ulp of the result.
const S0: f64 = -0.16666666666666666;
const S1: f64 = 0.008333333333333331;
const S2: f64 = -0.00019841269841265065;
const S3: f64 = 2.7557319219339167e-06;
const S4: f64 = -2.5052106232447578e-08;
const S5: f64 = 1.6058531618986147e-10;
const S6: f64 = -7.586697117706918e-13;
const C0: f64 = 0.041666666666666664;
const C1: f64 = -0.0013888888888887398;
const C2: f64 = 2.480158729876569e-05;
const C3: f64 = -2.7557317271729793e-07;
const C4: f64 = 2.08761462684032e-09;
const C5: f64 = -1.1382632425521717e-11;

/// `(sin x, cos x)`, each within an ulp of the exact value.
#[inline]
pub(crate) fn sin_cos(x: f64) -> (f64, f64) {
    let magnitude = x.abs();
    if magnitude <= FRAC_PI_4 {
        if magnitude < TINY {
            // Exact, and `±0` keeps its sign (the series' sum would turn `-0` into `+0`).
            return (x, 1.0);
        }
        let z = x * x;
        return (sin_near_zero(x, z), cos_near_zero(x, 0.0, z));
    }
    if magnitude < MEDIUM {
        let shifted = x * FRAC_2_PI + ROUNDING;
        let n = shifted - ROUNDING;
        let quadrant = shifted.to_bits().wrapping_sub(ROUNDING.to_bits()) & 3;
        let (hi, lo) = reduce(x, n);
        let z = hi * hi;
        let s = hi + (hi * z * sine_series(z) + lo * (1.0 - 0.5 * z));
        let c = cos_near_zero(hi, lo, z);
        return match quadrant {
            0 => (s, c),
            1 => (c, -s),
            2 => (-s, -c),
            _ => (-c, s),
        };
    }
    libm::sincos(x)
}

/// `x - n π/2` as `hi + lo`, `|lo| ≤ ulp(hi)/2`.
#[inline(always)]
fn reduce(x: f64, n: f64) -> (f64, f64) {
    // Exact: n P1 has at most 53 bits, and x is within a factor 2 of it.
    let r = x - n * P1;
    // n P2 is exact; the subtraction's rounding error is recovered (Knuth's two-sum).
    let (y, error) = two_sum(r, -(n * P2));
    two_sum(y, error - n * P3)
}

/// `a + b` and its rounding error, exactly.
#[inline(always)]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let sum = a + b;
    let b_part = sum - a;
    let a_part = sum - b_part;
    (sum, (a - a_part) + (b - b_part))
}

#[inline(always)]
fn sine_series(z: f64) -> f64 {
    S0 + z * (S1 + z * (S2 + z * (S3 + z * (S4 + z * (S5 + z * S6)))))
}

/// `sin x`, `|x| ≤ π/4`, `z = x²`.
#[inline(always)]
fn sin_near_zero(x: f64, z: f64) -> f64 {
    x + x * z * sine_series(z)
}

/// `cos (x + lo)`, `|x| ≤ π/4`, `z = x²`.
#[inline(always)]
fn cos_near_zero(x: f64, lo: f64, z: f64) -> f64 {
    let series = C0 + z * (C1 + z * (C2 + z * (C3 + z * (C4 + z * C5))));
    // 1 - z/2 rounds; its error, recovered exactly, joins the small terms.
    let half_z = 0.5 * z;
    let w = 1.0 - half_z;
    w + (((1.0 - w) - half_z) + (z * z * series - x * lo))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The distance in ulps between two finite doubles of the same sign (or zeros).
    fn ulps(a: f64, b: f64) -> u64 {
        let key = |x: f64| {
            let bits = x.to_bits() as i64;
            if bits < 0 {
                i64::MIN - bits
            } else {
                bits
            }
        };
        key(a).abs_diff(key(b))
    }

    /// Deterministic points spread over `[-limit, limit]`, dense near zero and near the
    /// multiples of π/4 where the reduction and the quadrants change.
    fn points(limit: f64) -> impl Iterator<Item = f64> {
        let mut state = 0x9e37_79b9_7f4a_7c15_u64;
        (0..200_000).map(move |i| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let unit = (state >> 11) as f64 / (1u64 << 53) as f64;
            match i % 4 {
                0 => (2.0 * unit - 1.0) * limit,
                1 => (2.0 * unit - 1.0) * 4.0,
                2 => (unit - 0.5) * 1e-3 + ((i / 4) % 64) as f64 * FRAC_PI_4 * 0.5,
                _ => (2.0 * unit - 1.0) * limit.min(1e3) * unit * unit,
            }
        })
    }

    #[test]
    fn within_an_ulp_of_libm_everywhere_it_reduces() {
        let (mut worst, mut equal, mut count) = (0, 0, 0);
        for x in points(MEDIUM) {
            let (s, c) = sin_cos(x);
            let (ls, lc) = libm::sincos(x);
            let d = ulps(s, ls).max(ulps(c, lc));
            worst = worst.max(d);
            equal += usize::from(d == 0);
            count += 1;
            assert!(
                d <= 1,
                "x = {x:e}: ({s:e}, {c:e}) against libm's ({ls:e}, {lc:e})"
            );
        }
        // Mostly the same bits: an ulp apart only where either rounds a near tie.
        assert!(equal * 100 >= count * 95, "{equal} of {count} identical");
        assert_eq!(worst, 1);
    }

    #[test]
    fn odd_and_even_bit_for_bit_and_on_the_unit_circle() {
        for x in points(MEDIUM) {
            let (s, c) = sin_cos(x);
            let (sm, cm) = sin_cos(-x);
            assert_eq!(
                (sm.to_bits(), cm.to_bits()),
                ((-s).to_bits(), c.to_bits()),
                "x = {x:e}"
            );
            assert!(
                (s * s + c * c - 1.0).abs() <= 4.0 * f64::EPSILON,
                "x = {x:e}"
            );
        }
    }

    #[test]
    fn exact_where_the_functions_are() {
        for x in [0.0, -0.0, 1e-300, -1e-300, f64::MIN_POSITIVE, 5e-324] {
            let (s, c) = sin_cos(x);
            assert_eq!(s.to_bits(), x.to_bits(), "sin {x:e}");
            assert_eq!(c, 1.0);
        }
    }

    #[test]
    fn large_and_non_finite_arguments_are_libm_s() {
        for x in [MEDIUM, -MEDIUM, 1e22, -3e300, f64::MAX] {
            assert_eq!(sin_cos(x), libm::sincos(x));
        }
        for x in [f64::INFINITY, f64::NEG_INFINITY, f64::NAN] {
            let (s, c) = sin_cos(x);
            assert!(s.is_nan() && c.is_nan());
        }
    }

    #[test]
    fn near_multiples_of_half_pi_the_small_results_keep_their_digits() {
        // Doubles nearest k π/2: sin or cos is tiny there, and all of it comes from the
        // reduction's low parts.
        for k in 1..2000_i32 {
            let x = f64::from(k) * std::f64::consts::FRAC_PI_2;
            for x in [
                x,
                f64::from_bits(x.to_bits() + 1),
                f64::from_bits(x.to_bits() - 1),
            ] {
                let (s, c) = sin_cos(x);
                let (ls, lc) = libm::sincos(x);
                assert!(ulps(s, ls) <= 1 && ulps(c, lc) <= 1, "x = {x:e}");
            }
        }
    }
}
