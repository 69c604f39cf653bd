//! Sine and cosine together, within an ulp, in four fifths of the instructions of the `libm`
//! crate's `sincos` (47 against 61 within `π/4`, 89 against 108 up to `10^6`, 324 against 988
//! beyond), and made once for two calls on one angle.
//!
//! Equations take both of an angle almost always, often of several angles per evaluation,
//! and evaluate them at every stage of every step: with a library's `sincos`, a quarter of
//! a double pendulum's step. Here the argument is reduced once and both polynomials share its square.
//!
//! `#[inline]`, not `always`: inlined everywhere, it made the equations that take an
//! occasional sine (the Oscillator's forcing) too large for the compiler to inline them into
//! the solver's stages, which cost more than the call saves.
//!
//! - `|x| ≤ π/4`: the polynomials directly.
//! - `|x| < 10^6`: `x = n π/2 + r`, `n` rounded from `x · 2/π`, `r` as the sum `hi + lo`
//!   of two doubles (Cody and Waite: `π/2` split in four parts whose first three have 33
//!   bits, so that `n` times them is exact for `|n| < 2^20`), then the quadrant `n mod 4`
//!   picks and signs the two. Where `r` is smallest against `n` (about `2^-52`), three
//!   parts would leave an error of an ulp.
//! - beyond: Payne and Hanek's reduction, `x · 2/π` modulo 4 from only the 192 bits of
//!   `2/π` that matter at `x`'s exponent, multiplied exactly in integers; `r` to about 120
//!   bits. NaN for infinities and NaN.
//!
//! No call, no loop, and only constant tables, indexed within their bounds: the compiler
//! sees a function of its argument alone, and two calls on one angle (a kinetic energy's
//! and a potential energy's `sin φ`) become one.
//!
//! Plain IEEE arithmetic in a fixed order, no fused multiply-add: every platform computes
//! the same bits.

use std::f64::consts::{FRAC_2_PI, FRAC_PI_4};

/// `π/2 = P1 + P2 + P3 + P4` to 2^-159: `P1`, `P2` and `P3` have 33 significant bits, `P4`
/// 53.
const P1: f64 = f64::from_bits(0x3ff9_21fb_5440_0000);
const P2: f64 = f64::from_bits(0x3dd0_b461_1a60_0000);
const P3: f64 = f64::from_bits(0x3ba3_198a_2e00_0000);
const P4: f64 = f64::from_bits(0x397b_839a_2520_49c1);

/// Below this, `|n| < 2^20`, so `n · P1`, `n · P2` and `n · P3` are exact.
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
    let (hi, lo, quadrant) = if magnitude < MEDIUM {
        let shifted = x * FRAC_2_PI + ROUNDING;
        let n = shifted - ROUNDING;
        let quadrant = shifted.to_bits().wrapping_sub(ROUNDING.to_bits()) & 3;
        let (hi, lo) = reduce(x, n);
        (hi, lo, quadrant)
    } else if x.is_finite() {
        reduce_large(x)
    } else {
        return (f64::NAN, f64::NAN);
    };
    let z = hi * hi;
    let s = hi + (hi * z * sine_series(z) + lo * (1.0 - 0.5 * z));
    let c = cos_near_zero(hi, lo, z);
    match quadrant {
        0 => (s, c),
        1 => (c, -s),
        2 => (-s, -c),
        _ => (-c, s),
    }
}

/// `x - n π/2` as `hi + lo`, `|lo| ≤ ulp(hi)/2`.
#[inline(always)]
fn reduce(x: f64, n: f64) -> (f64, f64) {
    // Exact: n P1 has at most 53 bits, and x is within a factor 2 of it.
    let r = x - n * P1;
    // n P2 and n P3 are exact; the subtractions' rounding errors are recovered (Knuth's
    // two-sum). Only n P4 (2^-83 at most) rounds, by 2^-136, and the errors' sum, by 2^-105
    // of r: far below an ulp of any r above 2^-80.
    let (y, first_error) = two_sum(r, -(n * P2));
    let (y, second_error) = two_sum(y, -(n * P3));
    two_sum(y, (first_error + second_error) - n * P4)
}

/// `a + b` and its rounding error, exactly.
#[inline(always)]
fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let sum = a + b;
    let b_part = sum - a;
    let a_part = sum - b_part;
    (sum, (a - a_part) + (b - b_part))
}

/// The bits of `2/π` after 64 zero bits: bit `64 + k` from the top of the first word is the
/// bit of weight `2^-(k+1)` (mpmath, 800 digits). An exponent's window starts at most at
/// bit 1033 and ends within word 19; the words beyond pad the table to a power of two, so
/// that an index masked into it is never out of bounds.
const TWO_OVER_PI: [u64; 32] = [
    0x0000_0000_0000_0000,
    0xa2f9_836e_4e44_1529,
    0xfc27_57d1_f534_ddc0,
    0xdb62_9599_3c43_9041,
    0xfe51_63ab_debb_c561,
    0xb724_6e3a_424d_d2e0,
    0x0649_2eea_09d1_921c,
    0xfe1d_eb1c_b129_a73e,
    0xe882_35f5_2ebb_4484,
    0xe99c_7026_b45f_7e41,
    0x3991_d639_8353_39f4,
    0x9c84_5f8b_bdf9_283b,
    0x1ff8_97ff_de05_980f,
    0xef2f_118b_5a0a_6d1f,
    0x6d36_7ecf_27cb_09b7,
    0x4f46_3f66_9e5f_ea2d,
    0x7527_bac7_ebe5_f17b,
    0x3d07_39f7_8a52_92ea,
    0x6bfb_5fb1_1f8d_5d08,
    0x5603_3046_fc7b_6bab,
    0xf0cf_bc20_9af4_361d,
    0xa9e3_9161_5ee6_1b08,
    0x6599_855f_14a0_6840,
    0x8dff_d880_4d73_2731,
    0x0606_1556_ca73_a8c9,
    0x60e2_7bc0_8c6b_47c4,
    0x19c3_67cd_dce8_092a,
    0x8359_c476_8b96_1ca6,
    0xddaf_44d1_5719_053e,
    0xa5ff_0705_3f7e_33e8,
    0x32c2_de4f_9832_7dbb,
    0xc33d_26ef_6b1e_5ef8,
];

/// `π/2 = PI_2_HI + PI_2_LO` to 2^-107.
const PI_2_HI: f64 = f64::from_bits(0x3ff9_21fb_5444_2d18);
const PI_2_LO: f64 = f64::from_bits(0x3c91_a626_3314_5c07);

/// `|x| ≥ MEDIUM`, finite: `x - n π/2` as `hi + lo` with `n mod 4`.
///
/// `|x| = m · 2^e` with `m` an integer of 53 bits. The bits of `2/π` of weight above
/// `2^(1-e)` contribute multiples of 4 to `x · 2/π` and are skipped; the next 192, as the
/// integer `W`, give `x · 2/π ≡ m W · 2^-190 (mod 4)` to within `2^-137`. The product's
/// bits 191 and 190 are `n mod 4`, the 126 below them the fraction.
#[inline]
fn reduce_large(x: f64) -> (f64, f64, u64) {
    const LOW: u128 = u64::MAX as u128;
    let bits = x.to_bits();
    let exponent = ((bits >> 52) & 0x7ff) as usize;
    let m = u128::from((bits & ((1 << 52) - 1)) | (1 << 52));
    // e = exponent - 1075; the window's first bit is that of weight 2^(1-e), table bit
    // (e - 1) + 63.
    let first = exponent - 1013;
    let (word, shift) = (first / 64, (first % 64) as u32);
    let window = |t: usize| {
        let pair = (u128::from(TWO_OVER_PI[(word + t) & 31]) << 64)
            | u128::from(TWO_OVER_PI[(word + t + 1) & 31]);
        pair >> (64 - shift) & LOW
    };
    let (p0, p1, p2) = (m * window(0), m * window(1), m * window(2));
    let t1 = (p2 >> 64) + (p1 & LOW);
    let t2 = (p1 >> 64) + (p0 & LOW) + (t1 >> 64);
    let mut quadrant = (t2 >> 62) as u64 & 3;
    let mut fraction = ((t2 & ((1 << 62) - 1)) << 64 | (t1 & LOW)) as i128;
    // To the nearest quadrant: the fraction in [-1/2, 1/2).
    if fraction >> 125 == 1 {
        fraction -= 1 << 126;
        quadrant += 1;
    }
    // The fraction (in units of 2^-126) as two doubles, then times π/2.
    let high = fraction as f64;
    let low = (fraction - high as i128) as f64;
    let unit = f64::from_bits((1023 - 126) << 52);
    let (high, low) = (high * unit, low * unit);
    let (product, error) = two_product(high, PI_2_HI);
    let (mut hi, mut lo) = two_sum(product, error + (high * PI_2_LO + low * PI_2_HI));
    if x < 0.0 {
        (hi, lo, quadrant) = (-hi, -lo, 4 - quadrant);
    }
    (hi, lo, quadrant & 3)
}

/// `a · b` and its rounding error, exactly (Dekker, with Veltkamp's splitting: no fused
/// multiply-add, which not every platform has).
#[inline(always)]
fn two_product(a: f64, b: f64) -> (f64, f64) {
    const SPLITTER: f64 = 134_217_729.0; // 2^27 + 1
    let split = |v: f64| {
        let c = SPLITTER * v;
        let high = c - (c - v);
        (high, v - high)
    };
    let product = a * b;
    let ((ah, al), (bh, bl)) = (split(a), split(b));
    (product, ((ah * bh - product) + ah * bl + al * bh) + al * bl)
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
    fn the_closest_approaches_to_multiples_of_half_pi_below_a_million_are_correctly_rounded() {
        // Where x - n π/2 is smallest against n (about 2^-52), the reduction's own error
        // would show; the exact values are mpmath's, rounded.
        assert_eq!(sin_cos(413441.44719405076).1, -2.2756539951781544e-16);
        assert_eq!(sin_cos(826882.8943881015).0, -4.551307990356309e-16);
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
    fn large_arguments_within_an_ulp_of_libm_and_non_finite_ones_nan() {
        let mut x = MEDIUM;
        while x < f64::MAX / 1.01 {
            for x in [
                x,
                -x,
                f64::from_bits(x.to_bits() + 1),
                f64::from_bits(x.to_bits() - 1),
            ] {
                let (s, c) = sin_cos(x);
                let (ls, lc) = libm::sincos(x);
                assert!(
                    ulps(s, ls) <= 1 && ulps(c, lc) <= 1,
                    "x = {x:e}: ({s:e}, {c:e}) against ({ls:e}, {lc:e})"
                );
            }
            x *= 1.0137;
        }
        for x in [
            f64::MAX,
            -f64::MAX,
            1e22,
            6381956970095103.0 * 2f64.powi(797),
        ] {
            let (s, c) = sin_cos(x);
            let (ls, lc) = libm::sincos(x);
            assert!(ulps(s, ls) <= 1 && ulps(c, lc) <= 1, "x = {x:e}");
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
