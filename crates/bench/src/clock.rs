//! Timing: the calling thread's CPU time ([`mechfmu_host::cpu_clock`]), and medians of
//! repeated runs.
//!
//! Thread CPU time rather than wall-clock time: on a shared machine another process taking
//! the core stops this clock, so a run is charged for its own work only (cache and
//! frequency effects of the neighbours remain; medians of repeated runs take care of most).

use serde_json::{json, Value};

use mechfmu_host::cpu_clock::cpu_ns;

/// CPU nanoseconds `f` takes, with its result.
pub fn time<T>(f: impl FnOnce() -> T) -> (f64, T) {
    let t0 = cpu_ns();
    let r = f();
    let t1 = cpu_ns();
    ((t1 - t0) as f64, r)
}

/// The spread of repeated measurements of one quantity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stat {
    pub median: f64,
    pub min: f64,
    pub max: f64,
    pub runs: usize,
}

impl Stat {
    /// Median, minimum and maximum of `samples` (NaN for none).
    pub fn of(samples: &[f64]) -> Stat {
        let mut s: Vec<f64> = samples.iter().copied().filter(|x| !x.is_nan()).collect();
        s.sort_by(f64::total_cmp);
        let n = s.len();
        let median = match n {
            0 => f64::NAN,
            _ if n % 2 == 1 => s[n / 2],
            _ => 0.5 * (s[n / 2 - 1] + s[n / 2]),
        };
        Stat {
            median,
            min: s.first().copied().unwrap_or(f64::NAN),
            max: s.last().copied().unwrap_or(f64::NAN),
            runs: n,
        }
    }

    pub fn to_json(self) -> Value {
        json!({ "median": num(self.median), "min": num(self.min), "max": num(self.max), "runs": self.runs })
    }
}

/// A JSON number, or null for NaN/inf (which JSON cannot carry).
pub fn num(x: f64) -> Value {
    if x.is_finite() {
        json!(x)
    } else {
        Value::Null
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn median_of_odd_and_even_counts() {
        assert_eq!(Stat::of(&[3.0, 1.0, 2.0]).median, 2.0);
        assert_eq!(Stat::of(&[4.0, 1.0, 2.0, 3.0]).median, 2.5);
        assert!(Stat::of(&[]).median.is_nan());
        let s = Stat::of(&[5.0, f64::NAN, 1.0]);
        assert_eq!((s.min, s.max, s.runs), (1.0, 5.0, 2));
    }

    #[test]
    fn cpu_clock_advances_with_work() {
        let (ns, x) = time(|| (0..2_000_000u64).map(std::hint::black_box).sum::<u64>());
        assert!(x > 0 && ns > 0.0);
    }
}
