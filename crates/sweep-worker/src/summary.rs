//! The summaries of a case, to the bit what `summarize` in `python/mechfmu_sweep/runner.py`
//! computes with numpy 2.4: numpy's NaN propagation and tie-breaking in `max`/`min`, and
//! `np.trapezoid`'s arithmetic summed in numpy's pairwise order.

/// A summary function, as the setup names it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Func {
    Final,
    Max,
    Min,
    MaxAbs,
    MinAbs,
    Mean,
    Rms,
}

impl Func {
    pub fn parse(name: &str) -> Option<Func> {
        Some(match name {
            "final" => Func::Final,
            "max" => Func::Max,
            "min" => Func::Min,
            "max_abs" => Func::MaxAbs,
            "min_abs" => Func::MinAbs,
            "mean" => Func::Mean,
            "rms" => Func::Rms,
            _ => return None,
        })
    }
}

/// A series of samples seen through accessors, so the summaries read a column of the
/// sample buffer in place: `len` samples (at least one), times `t(i)`, values `y(i)`.
pub struct Series<T, Y> {
    pub len: usize,
    pub t: T,
    pub y: Y,
}

/// `summarize(func, t, y)` of runner.py.
pub fn summarize<T: Fn(usize) -> f64, Y: Fn(usize) -> f64>(func: Func, s: &Series<T, Y>) -> f64 {
    let Some(last) = s.len.checked_sub(1) else {
        return f64::NAN;
    };
    match func {
        Func::Final => (s.y)(last),
        Func::Max => extreme(s.len, &s.y, |acc, x| acc > x),
        Func::Min => extreme(s.len, &s.y, |acc, x| acc < x),
        Func::MaxAbs => extreme(s.len, |i| (s.y)(i).abs(), |acc, x| acc > x),
        Func::MinAbs => extreme(s.len, |i| (s.y)(i).abs(), |acc, x| acc < x),
        Func::Mean | Func::Rms => {
            let span = (s.t)(last) - (s.t)(0);
            // `span <= 0` is false for NaN, as in Python, which then divides by it.
            if span <= 0.0 {
                let y = (s.y)(last);
                return if func == Func::Mean { y } else { y.abs() };
            }
            if func == Func::Mean {
                trapezoid(s.len, &s.t, &s.y) / span
            } else {
                // numpy squares the samples into an array first: the same products.
                (trapezoid(s.len, &s.t, |i| (s.y)(i) * (s.y)(i)) / span).sqrt()
            }
        }
    }
}

/// numpy's `max`/`min` reduction: the first NaN if there is one; otherwise the extreme,
/// where a later value equal to the one held (`0.0` and `-0.0`) replaces it, as numpy's
/// loops do (`keeps(held, x)`: whether the held value stays).
fn extreme(n: usize, y: impl Fn(usize) -> f64, keeps: impl Fn(f64, f64) -> bool) -> f64 {
    let mut held = y(0);
    for i in 1..n {
        let x = y(i);
        if x.is_nan() {
            return x;
        }
        if !keeps(held, x) {
            held = x;
        }
    }
    held
}

/// `np.trapezoid(y, t)`: the pairwise sum of `((t[i+1] - t[i]) * (y[i+1] + y[i])) / 2.0`.
fn trapezoid(n: usize, t: impl Fn(usize) -> f64, y: impl Fn(usize) -> f64) -> f64 {
    let term = |i: usize| ((t(i + 1) - t(i)) * (y(i + 1) + y(i))) / 2.0;
    pairwise_sum(0, n.saturating_sub(1), &term)
}

/// `np.add.reduce` of `a(start..start + n)`: numpy's pairwise summation (unrolled by 8 up
/// to 128 terms, halves above, at a multiple of 8).
pub fn pairwise_sum(start: usize, n: usize, a: &impl Fn(usize) -> f64) -> f64 {
    if n < 8 {
        let mut res = 0.0;
        for i in start..start + n {
            res += a(i);
        }
        res
    } else if n <= 128 {
        let mut r = [0.0; 8];
        for (j, rj) in r.iter_mut().enumerate() {
            *rj = a(start + j);
        }
        let unrolled = n - n % 8;
        let mut i = 8;
        while i < unrolled {
            for (j, rj) in r.iter_mut().enumerate() {
                *rj += a(start + i + j);
            }
            i += 8;
        }
        let mut res = ((r[0] + r[1]) + (r[2] + r[3])) + ((r[4] + r[5]) + (r[6] + r[7]));
        for k in unrolled..n {
            res += a(start + k);
        }
        res
    } else {
        let mut n2 = n / 2;
        n2 -= n2 % 8;
        pairwise_sum(start, n2, a) + pairwise_sum(start + n2, n - n2, a)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sequence Rust and Python compute alike (correctly rounded operations only):
    /// `((i*7919)%1009 - 504)/7.0 + i/3.0`.
    fn python_seq(i: usize) -> f64 {
        (((i * 7919) % 1009) as f64 - 504.0) / 7.0 + i as f64 / 3.0
    }

    #[test]
    fn pairwise_sum_is_numpys_add_reduce() {
        // np.add.reduce(np.array([((i*7919)%1009 - 504)/7.0 + i/3.0 for i in range(n)]))
        // with numpy 2.4.
        for (n, bits) in [
            (5, 0x3ff5555555555558u64),
            (8, 0xc039861861861862),
            (100, 0x409ace4924924924),
            (129, 0x40a63f2492492492),
            (1001, 0x41045ff618618618),
        ] {
            let sum = pairwise_sum(0, n, &python_seq);
            assert_eq!(sum.to_bits(), bits, "n = {n}: {sum}");
        }
        // A different grouping gives different bits: the test can tell.
        let naive: f64 = (0..1001).map(python_seq).sum();
        assert_ne!(naive.to_bits(), 0x41045ff618618618);
    }

    fn series(n: usize) -> Series<impl Fn(usize) -> f64, impl Fn(usize) -> f64> {
        Series {
            len: n,
            t: |i: usize| i as f64 * 0.01,
            y: |i: usize| python_seq(i) / 100.0,
        }
    }

    const FUNCS: [Func; 7] = [
        Func::Final,
        Func::Max,
        Func::Min,
        Func::MaxAbs,
        Func::MinAbs,
        Func::Mean,
        Func::Rms,
    ];

    #[test]
    fn summaries_are_runner_pys_to_the_bit() {
        // summarize(f, t, y) of runner.py with t = [i*0.01], y = seq/100.0, numpy 2.4, in
        // the order of FUNCS.
        let expected: [(usize, [u64; 7]); 3] = [
            (
                2,
                [
                    0x3fe032b65e991cc5,
                    0x3fe032b65e991cc5,
                    0xbfe70a3d70a3d70a,
                    0x3fe70a3d70a3d70a,
                    0x3fe032b65e991cc5,
                    0xbfbb5e1c482ae914,
                    0x3fe3ea41ea38339c,
                ],
            ),
            (
                9,
                [
                    0x3fdc389055d229ef,
                    0x3fe4ff832b65e992,
                    0xbfe70a3d70a3d70a,
                    0x3fe70a3d70a3d70a,
                    0x3fb36202ecfb9c86,
                    0x3fa4d0b3719d803d,
                    0x3fdca7f120f8aa8e,
                ],
            ),
            (
                1001,
                [
                    0x40091cc4ff832b65,
                    0x4010000000000000,
                    0xbfe70a3d70a3d70a,
                    0x4010000000000000,
                    0x3f6767dce434a99a,
                    0x3ffaafb5e9c1bba3,
                    0x3fff838bc3766e4e,
                ],
            ),
        ];
        for (n, bits) in expected {
            for (func, bits) in FUNCS.iter().zip(bits) {
                let value = summarize(*func, &series(n));
                assert_eq!(value.to_bits(), bits, "{func:?} of {n} samples: {value}");
            }
        }
    }

    #[test]
    fn one_sample_has_no_span() {
        let y0 = python_seq(0) / 100.0;
        for func in FUNCS {
            let expected = if matches!(func, Func::MaxAbs | Func::MinAbs | Func::Rms) {
                y0.abs()
            } else {
                y0
            };
            assert_eq!(summarize(func, &series(1)), expected, "{func:?}");
        }
    }

    #[test]
    fn a_nan_propagates_like_numpys() {
        let values = [1.0, f64::NAN, 3.0, -2.0];
        let s = Series {
            len: 4,
            t: |i: usize| i as f64,
            y: |i: usize| values[i],
        };
        // Every function but the first, `Final`, which takes the last value.
        for &func in &FUNCS[1..] {
            assert!(summarize(func, &s).is_nan(), "{func:?}");
        }
        assert_eq!(summarize(Func::Final, &s), -2.0);
    }

    #[test]
    fn signed_zeros_tie_as_in_numpy() {
        // np.max(np.array([0.0, -0.0])) is -0.0, np.max(np.array([-0.0, 0.0])) is 0.0.
        for (values, max_negative) in [([0.0, -0.0], true), ([-0.0, 0.0], false)] {
            let s = Series {
                len: 2,
                t: |i: usize| i as f64,
                y: |i: usize| values[i],
            };
            assert_eq!(summarize(Func::Max, &s).is_sign_negative(), max_negative);
            assert_eq!(summarize(Func::Min, &s).is_sign_negative(), max_negative);
        }
    }

    #[test]
    fn unknown_names_are_refused() {
        assert_eq!(Func::parse("max_abs"), Some(Func::MaxAbs));
        assert_eq!(Func::parse("median"), None);
    }
}
