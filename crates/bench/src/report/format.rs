//! How the report writes its numbers: a missing figure (not a number, no runs) as `-`.

use crate::clock::Stat;

/// `x` in scientific notation with one decimal.
pub fn e(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.1e}")
    } else {
        "-".into()
    }
}

/// `x` with `digits` decimals.
pub fn f(x: f64, digits: usize) -> String {
    if x.is_finite() {
        format!("{x:.digits$}")
    } else {
        "-".into()
    }
}

/// The range of the runs, `min–max`.
pub fn spread(s: &Stat) -> String {
    if s.runs == 0 {
        return "-".into();
    }
    format!("{:.0}–{:.0}", s.min, s.max)
}

/// A ratio (`fmi3DoStep` over `fmi2DoStep`) as a signed percentage.
pub fn percent(ratio: f64) -> String {
    if ratio.is_finite() {
        format!("{:+.1} %", (ratio - 1.0) * 100.0)
    } else {
        "-".into()
    }
}

/// A fraction as a percentage with one decimal (`-`: none).
pub fn share(fraction: Option<f64>) -> String {
    fraction.map_or("-".into(), |s| format!("{:.1} %", s * 100.0))
}

/// A count (instructions) without decimals (`-`: not counted).
pub fn count(n: Option<f64>) -> String {
    n.map_or("-".into(), |n| format!("{n:.0}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_difference_reads_both_ways() {
        assert_eq!(percent(1.031), "+3.1 %");
        assert_eq!(percent(0.98), "-2.0 %");
        assert_eq!(percent(f64::NAN), "-");
    }
}
