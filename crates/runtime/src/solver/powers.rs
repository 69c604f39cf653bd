//! `log2` and `2^x` to the accuracy a step-size proposal needs, in under half a library
//! function's instructions.
//!
//! The controller's factor `2^(-EXPO1·log2 err + BETA·log2 err_prev)` only proposes the
//! next step size; the error test decides what is accepted. A relative error of 1e-8 in
//! it moves a step size by 1e-8 of itself, far below what changes an accepted step's
//! accuracy, and the factor is clamped to [0.2, 10] anyway. A library's `log2` and `exp2`,
//! correct to the last bit, cost about 110 instructions per step of the Oscillator, a tenth
//! of its whole `fmi2DoStep`; these cost about 45 together.
//!
//! Both are plain IEEE arithmetic (additions, multiplications, one division, bit
//! manipulation) in a fixed order, so every platform computes the same bits.

use std::f64::consts::LN_2;

/// The bits of `sqrt(1/2)`: mantissas are reduced into `[sqrt(1/2), sqrt(2))`, where the
/// series below converges fastest.
const SQRT_HALF_BITS: u64 = 0x3fe6_a09e_667f_3bcd;
const MANTISSA: u64 = (1 << 52) - 1;

// `log2 m = (2 / ln 2) · atanh s` with `s = (m - 1) / (m + 1)`, `|s| ≤ 0.1716` on the
// reduced range: the odd series `s + s³/3 + s⁵/5 + …` up to `s⁹` leaves at most 1.1e-9.
const L1: f64 = 2.0 / LN_2;
const L3: f64 = L1 / 3.0;
const L5: f64 = L1 / 5.0;
const L7: f64 = L1 / 7.0;
const L9: f64 = L1 / 9.0;

/// `log2 x` within 1.1e-9 (absolute) for a positive normal `x` (the caller's to ensure:
/// for anything else the result is meaningless, though never a panic).
#[inline(always)]
pub(crate) fn log2(x: f64) -> f64 {
    // x = 2^k · m, m in [sqrt(1/2), sqrt(2)): subtracting sqrt(1/2)'s bits leaves k in the
    // exponent field and m's offset in the mantissa field.
    let offset = x.to_bits().wrapping_sub(SQRT_HALF_BITS);
    let k = ((offset as i64) >> 52) as f64;
    let m = f64::from_bits((offset & MANTISSA) + SQRT_HALF_BITS);
    let s = (m - 1.0) / (m + 1.0);
    let s2 = s * s;
    k + s * (L1 + s2 * (L3 + s2 * (L5 + s2 * (L7 + s2 * L9))))
}

/// Adding `1.5 · 2^52` to a number of magnitude below `2^51` rounds it to an integer (the
/// sum's last mantissa bit is worth 1), which then sits in the sum's low mantissa bits.
const ROUNDING: f64 = 6_755_399_441_055_744.0;

// `2^f = e^(f ln 2)`, Taylor to degree 7, `|f| ≤ 1/2`: at most 7.4e-9 relative.
const E1: f64 = LN_2;
const E2: f64 = E1 * LN_2 / 2.0;
const E3: f64 = E2 * LN_2 / 3.0;
const E4: f64 = E3 * LN_2 / 4.0;
const E5: f64 = E4 * LN_2 / 5.0;
const E6: f64 = E5 * LN_2 / 6.0;
const E7: f64 = E6 * LN_2 / 7.0;

/// Inputs are clamped to this range, where `2^x` is a normal number with room to spare.
const EXP2_RANGE: f64 = 512.0;

/// `2^x` within 7.4e-9 (relative) for `x` in `[-EXP2_RANGE, EXP2_RANGE]`; `x` outside is
/// clamped into it, and NaN gives NaN.
#[inline(always)]
pub(crate) fn exp2(x: f64) -> f64 {
    let x = x.clamp(-EXP2_RANGE, EXP2_RANGE);
    let shifted = x + ROUNDING;
    let n = shifted - ROUNDING;
    let f = x - n;
    // n exactly, from the sum's mantissa bits: 2^n built from its exponent field.
    let n_bits = shifted.to_bits().wrapping_sub(ROUNDING.to_bits());
    let scale = f64::from_bits(n_bits.wrapping_add(1023) << 52);
    let series = 1.0 + f * (E1 + f * (E2 + f * (E3 + f * (E4 + f * (E5 + f * (E6 + f * E7))))));
    scale * series
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every `step`-th double between `lo` and `hi`, by bit pattern, and both ends.
    fn samples(lo: f64, hi: f64, count: u64) -> impl Iterator<Item = f64> {
        let (a, b) = (lo.to_bits(), hi.to_bits());
        let (a, b) = (a.min(b), a.max(b));
        let step = ((b - a) / count).max(1);
        (a..=b)
            .step_by(step as usize)
            .chain([b])
            .map(f64::from_bits)
    }

    #[test]
    fn log2_is_within_its_bound_over_the_normal_numbers() {
        let mut worst = 0.0f64;
        for x in samples(f64::MIN_POSITIVE, f64::MAX, 2_000_000) {
            worst = worst.max((log2(x) - x.log2()).abs());
        }
        // Mantissas near sqrt(2) and sqrt(1/2), where the series is slowest.
        for x in samples(1.40, 1.43, 100_000).chain(samples(0.70, 0.72, 100_000)) {
            worst = worst.max((log2(x) - x.log2()).abs());
        }
        assert!(worst < 1.1e-9, "worst absolute error {worst:e}");
        assert!(worst > 1e-12, "the bound is tight: {worst:e}");
    }

    #[test]
    fn log2_of_powers_of_two_is_exact() {
        for k in -1022..=1023 {
            assert_eq!(log2(2f64.powi(k)), f64::from(k), "2^{k}");
        }
        // Below 1 it is negative, at 1 zero: what the controller's memory relies on.
        assert_eq!(log2(1.0), 0.0);
        assert!(log2(1.0 - f64::EPSILON) < 0.0);
    }

    #[test]
    fn exp2_is_within_its_bound() {
        let mut worst = 0.0f64;
        for x in samples(-EXP2_RANGE, -1e-300, 1_000_000).chain(samples(0.0, EXP2_RANGE, 1_000_000))
        {
            worst = worst.max((exp2(x) - x.exp2()).abs() / x.exp2());
        }
        assert!(worst < 7.4e-9, "worst relative error {worst:e}");
        assert!(worst > 1e-10, "the bound is tight: {worst:e}");
    }

    #[test]
    fn exp2_of_integers_is_exact_and_out_of_range_is_clamped() {
        for n in -512..=512 {
            assert_eq!(exp2(f64::from(n)), 2f64.powi(n), "2^{n}");
        }
        assert_eq!(exp2(1e6), 2f64.powi(512));
        assert_eq!(exp2(f64::NEG_INFINITY), 2f64.powi(-512));
        assert!(exp2(f64::NAN).is_nan());
    }
}
