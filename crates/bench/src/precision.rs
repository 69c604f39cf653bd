//! Work–precision of the Oscillator: over 20 s with output every 0.1 s, the largest error
//! of `x` against the closed-form free response, and the CPU time, at tolerances 1e-4 …
//! 1e-12. The same problem goes to scipy (`scripts/bench_fmpy.py`), which gets the exact
//! solution from here, so both sides are scored against the very same numbers.

use crate::binary::Binary;
use crate::clock::{num, Stat};
use crate::instance::Instance;
use mechfmu::fmi2::ffi::fmi2Warning;
use mechfmu_host::cpu_clock::cpu_ns;
use mechfmu_host::description::ModelDescription;
use serde_json::{json, Value};

/// Relative (= absolute) tolerances of the work–precision diagram.
pub const TOLERANCES: [f64; 9] = [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12];
/// Simulated time (s).
pub const T_END: f64 = 20.0;
/// Output interval = communication step (s).
pub const OUTPUT: f64 = 0.1;

/// The method of the FMU's points from a native loop.
pub const NATIVE: &str = "FMU (native loop)";
/// The method of the FMU's points under FMPy's low-level loop (`scripts/bench_fmpy.py`).
pub const FMPY: &str = "FMU (FMPy low-level loop)";

/// The Oscillator's free response problem, from its modelDescription's start values.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Problem {
    pub m: f64,
    pub c: f64,
    pub k: f64,
    pub x0: f64,
    pub v0: f64,
    /// Value reference of `x`.
    pub vr_x: u32,
}

impl Problem {
    /// Reads m, c, k, x(0), ẋ(0) from the description; refuses a forced configuration
    /// (the closed form is the free response).
    pub fn of(d: &ModelDescription) -> Result<Problem, String> {
        let start = |name: &str| -> Result<f64, String> {
            d.variable(name).and_then(|v| v.start).ok_or_else(|| {
                format!(
                    "{} has no variable `{name}` with a start value",
                    d.model_identifier
                )
            })
        };
        for forced in ["F", "F0"] {
            if start(forced)? != 0.0 {
                return Err(format!(
                    "{forced} starts at a nonzero value: no closed form"
                ));
            }
        }
        Ok(Problem {
            m: start("m")?,
            c: start("c")?,
            k: start("k")?,
            x0: start("x")?,
            v0: start("x_dot")?,
            vr_x: d.variable("x").map(|v| v.vr).unwrap_or_default(),
        })
    }

    /// x(t) of m ẍ + c ẋ + k x = 0 from (x0, v0), every damping regime.
    pub fn exact(&self, t: f64) -> f64 {
        let Problem {
            m, c, k, x0, v0, ..
        } = *self;
        let wn = (k / m).sqrt();
        let zeta = c / (2.0 * (m * k).sqrt());
        if (zeta - 1.0).abs() < 1e-12 {
            (x0 + (v0 + wn * x0) * t) * (-wn * t).exp()
        } else if zeta < 1.0 {
            let wd = wn * (1.0 - zeta * zeta).sqrt();
            (-zeta * wn * t).exp()
                * (x0 * (wd * t).cos() + (v0 + zeta * wn * x0) / wd * (wd * t).sin())
        } else {
            let s = wn * (zeta * zeta - 1.0).sqrt();
            let (r1, r2) = (-zeta * wn + s, -zeta * wn - s);
            let a = (v0 - r2 * x0) / (r1 - r2);
            a * (r1 * t).exp() + (x0 - a) * (r2 * t).exp()
        }
    }

    /// The output times 0.1, 0.2, …, 20 and the exact x there.
    pub fn grid(&self) -> (Vec<f64>, Vec<f64>) {
        let n = (T_END / OUTPUT).round() as usize;
        let t: Vec<f64> = (1..=n).map(|i| i as f64 * OUTPUT).collect();
        let x = t.iter().map(|&t| self.exact(t)).collect();
        (t, x)
    }
}

/// One point of a work–precision diagram.
#[derive(Clone, Debug)]
pub struct Point {
    pub method: String,
    pub tol: f64,
    /// Largest |x - exact| over the output grid.
    pub error: f64,
    /// CPU seconds of one whole run.
    pub cpu: Stat,
}

impl Point {
    pub fn to_json(&self) -> Value {
        json!({ "method": self.method, "tol": self.tol, "error": num(self.error), "cpu_s": self.cpu.to_json() })
    }

    pub fn from_json(v: &Value) -> Option<Point> {
        Some(Point {
            method: v["method"].as_str()?.to_string(),
            tol: v["tol"].as_f64()?,
            error: v["error"].as_f64().unwrap_or(f64::NAN),
            cpu: Stat {
                median: v["cpu_s"]["median"].as_f64()?,
                min: v["cpu_s"]["min"].as_f64().unwrap_or(f64::NAN),
                max: v["cpu_s"]["max"].as_f64().unwrap_or(f64::NAN),
                runs: v["cpu_s"]["runs"].as_u64().unwrap_or(0) as usize,
            },
        })
    }
}

/// The FMU from a native loop on one reused instance: per run fmi2Reset, setup,
/// initialization, then 200 × (fmi2DoStep of 0.1 s, fmi2GetReal of x); all of it timed.
pub fn native(binary: &Binary, problem: &Problem, runs: usize) -> Result<Vec<Point>, String> {
    let (grid, exact) = problem.grid();
    let mut inst = Instance::new(binary)?;
    let mut x = vec![0.0; grid.len()];
    let mut points = Vec::new();
    for (i, &tol) in TOLERANCES.iter().enumerate() {
        let mut samples = Vec::with_capacity(runs);
        for run in 0..=runs {
            let t0 = cpu_ns();
            inst.start(tol, 0.0, &[], i > 0 || run > 0)?;
            let mut t = 0.0;
            for xi in x.iter_mut() {
                let status = inst.do_step(t, OUTPUT);
                if status > fmi2Warning {
                    return Err(format!(
                        "fmi2DoStep at t = {t}: {}",
                        inst.messages().join("; ")
                    ));
                }
                t += OUTPUT;
                inst.get_real(&[problem.vr_x], std::slice::from_mut(xi));
            }
            let ns = (cpu_ns() - t0) as f64;
            if run > 0 {
                samples.push(ns * 1e-9);
            }
        }
        points.push(Point {
            method: NATIVE.into(),
            tol,
            error: max_error(&x, &exact),
            cpu: Stat::of(&samples),
        });
    }
    Ok(points)
}

pub fn max_error(x: &[f64], exact: &[f64]) -> f64 {
    x.iter()
        .zip(exact)
        .map(|(a, b)| (a - b).abs())
        .fold(
            0.0,
            |m: f64, e| if e.is_nan() { f64::NAN } else { m.max(e) },
        )
}

/// How a method's CPU time compares with the best of `others` at the same accuracy.
#[derive(Clone, Debug, PartialEq)]
pub struct Speedup {
    /// The others' (interpolated) CPU time to reach this error, over this CPU time.
    pub ratio: f64,
    /// Which of the others was fastest there.
    pub best: String,
    /// `None`: interpolated within the others' range. `Some(">")`: they never get this
    /// accurate (compared with their most accurate run: a lower bound). `Some("<")`: this
    /// is less accurate than any of their runs (compared with their cheapest: an upper
    /// bound).
    pub bound: Option<&'static str>,
}

/// CPU time another method needs for error `e`: log–log interpolation along its Pareto
/// front (the runs no other run of it beats in both error and time).
fn time_for_error(points: &[&Point], e: f64) -> Option<(f64, Option<&'static str>)> {
    let mut pts: Vec<(f64, f64)> = points
        .iter()
        .filter(|p| p.error.is_finite() && p.error > 0.0 && p.cpu.median > 0.0)
        .map(|p| (p.error, p.cpu.median))
        .collect();
    if pts.is_empty() {
        return None;
    }
    pts.sort_by(|a, b| a.0.total_cmp(&b.0));
    // Pareto front: going from the most accurate to the least, keep strictly cheaper runs.
    let mut front: Vec<(f64, f64)> = Vec::new();
    for p in pts {
        if front.last().is_none_or(|l| p.1 < l.1) {
            front.push(p);
        }
    }
    let (first, last) = (front[0], front[front.len() - 1]);
    if e < first.0 {
        return Some((first.1, Some(">")));
    }
    if e >= last.0 {
        return Some((last.1, if e > last.0 { Some("<") } else { None }));
    }
    let w = front.windows(2).find(|w| e >= w[0].0 && e <= w[1].0)?;
    let (a, b) = (w[0], w[1]);
    let f = (e.ln() - a.0.ln()) / (b.0.ln() - a.0.ln());
    Some(((a.1.ln() + f * (b.1.ln() - a.1.ln())).exp(), None))
}

/// `point` against the best of the `others` (grouped by method) at `point`'s error.
pub fn speedup(point: &Point, others: &[Point]) -> Option<Speedup> {
    if !(point.error.is_finite() && point.cpu.median > 0.0) {
        return None;
    }
    let mut methods: Vec<&str> = others.iter().map(|p| p.method.as_str()).collect();
    methods.sort();
    methods.dedup();
    let e = point.error.max(f64::MIN_POSITIVE);
    methods
        .iter()
        .filter_map(|m| {
            let pts: Vec<&Point> = others.iter().filter(|p| p.method == *m).collect();
            time_for_error(&pts, e).map(|(t, bound)| (t, bound, *m))
        })
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(t, bound, m)| Speedup {
            ratio: t / point.cpu.median,
            best: m.to_string(),
            bound,
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(method: &str, error: f64, cpu: f64) -> Point {
        Point {
            method: method.into(),
            tol: 0.0,
            error,
            cpu: Stat::of(&[cpu]),
        }
    }

    #[test]
    fn closed_form_starts_at_the_initial_conditions() {
        let pr = Problem {
            m: 1.0,
            c: 0.4,
            k: 4.0,
            x0: 1.0,
            v0: 0.0,
            vr_x: 6,
        };
        assert_eq!(pr.exact(0.0), 1.0);
        let h = 1e-6;
        let v = (pr.exact(h) - pr.exact(-h)) / (2.0 * h);
        assert!(v.abs() < 1e-8);
        let (t, x) = pr.grid();
        assert_eq!((t.len(), x.len()), (200, 200));
        assert!((t[199] - 20.0).abs() < 1e-12);
    }

    #[test]
    fn speedup_interpolates_along_the_front() {
        let scipy = [
            p("A", 1e-4, 1e-3),
            p("A", 1e-6, 1e-2),
            p("B", 1e-6, 5e-3),
            p("B", 1e-8, 5e-2),
        ];
        // A interpolates between its two runs (geometric middle: 3.16e-3 s); B is less
        // accurate than 1e-5 only at its cheapest run (5e-3 s, an upper bound).
        let s = speedup(&p("fmu", 1e-5, 1e-5), &scipy).unwrap();
        assert_eq!((s.best.as_str(), s.bound), ("A", None));
        assert!((s.ratio - 316.227_766).abs() < 1e-3, "{s:?}");
        // Nobody reaches 1e-10: compared with the cheaper most-accurate run (a lower bound).
        let never = speedup(&p("fmu", 1e-10, 1e-5), &scipy).unwrap();
        assert_eq!((never.best.as_str(), never.bound), ("A", Some(">")));
        assert!((never.ratio - 1e3).abs() < 1e-6);
    }
}
