//! The benchmark's verdict on the performance targets of docs/performance.md, judged on one
//! run's figures.

use super::format::percent;
use super::Report;
use crate::clock::Stat;
use crate::energies::{self, EnergyCounts};
use crate::figures::Figures;
use crate::model_exchange::LIMIT_NS;
use crate::native::Split;
use crate::precision::{self, FMPY, NATIVE};

/// How far below zero a part of the split may come out from noise alone (differences of
/// medians on a busy 2-core machine).
const NOISE_NS: f64 = 10.0;

/// The target: the Oscillator's step at most this many times the C step's cost.
const AGAINST_C_LIMIT: f64 = 1.5;

/// The target: `fmi3DoStep` within this fraction of `fmi2DoStep`.
const FMI3_LIMIT: f64 = 0.05;

/// One performance target and whether it is met.
#[derive(Clone, Debug)]
pub struct Target {
    pub what: String,
    pub limit: String,
    pub value: String,
    /// None: not measured in this run.
    pub met: Option<bool>,
}

impl Report {
    /// The performance targets, judged on this run's figures.
    pub fn targets(&self) -> Vec<Target> {
        let mut t = Vec::new();
        for m in &self.mechanisms {
            t.extend(plumbing(m));
            t.extend(fmi3(m));
            t.extend(calls(m));
        }
        t.extend(self.against_c());
        t.extend(self.energies.iter().flat_map(from_energies));
        t.extend(self.work_precision());
        t.extend(self.build_targets());
        t
    }

    /// The Oscillator's `fmi2DoStep` + one `fmi2GetReal` within [`AGAINST_C_LIMIT`] of the
    /// C step, in instructions and in time.
    fn against_c(&self) -> Vec<Target> {
        let (Some(c), Some(m)) = (
            &self.c_step,
            self.mechanisms.iter().find(|m| m.name == "Oscillator"),
        ) else {
            return Vec::new();
        };
        let limit = format!("≤ {AGAINST_C_LIMIT}× the C step");
        let judge = |what: &str, ours: Option<f64>, theirs: Option<f64>| {
            let ratio = ours.zip(theirs).map(|(a, b)| a / b);
            Target {
                what: format!("Oscillator fmi2DoStep + fmi2GetReal, {what}"),
                limit: limit.clone(),
                value: ratio.map_or("not measured".into(), |r| format!("{r:.2}×")),
                met: ratio.map(|r| r <= AGAINST_C_LIMIT),
            }
        };
        vec![
            judge(
                "instructions",
                m.instructions.map(|i| i.step_get_per_step),
                c.instructions,
            ),
            judge("time", Some(m.step_get.median), Some(c.ns.median)),
        ]
    }

    /// The Oscillator's work–precision, native and under FMPy, against scipy's best.
    fn work_precision(&self) -> Vec<Target> {
        let mut t = Vec::new();
        let scipy = self.scipy();
        if scipy.is_empty() {
            return t;
        }
        for (method, limit, need) in [
            (NATIVE, "≥ 100× at every tolerance", 100.0),
            (FMPY, "> 1× at every tolerance", 1.0),
        ] {
            let ratios: Vec<(f64, f64)> = self
                .points(method)
                .iter()
                .filter_map(|p| precision::speedup(p, &scipy).map(|s| (s.ratio, p.tol)))
                .collect();
            if let Some(&(worst, tol)) = ratios.iter().min_by(|a, b| a.0.total_cmp(&b.0)) {
                t.push(Target {
                    what: format!(
                        "Oscillator work–precision, {method} vs scipy's best at equal error"
                    ),
                    limit: limit.into(),
                    value: format!("worst {worst:.0}× (tol {tol:e})"),
                    met: Some(worst >= need && ratios.len() == precision::TOLERANCES.len()),
                });
            }
        }
        t
    }

    /// The clean build's time and the size of each archive it wrote.
    fn build_targets(&self) -> Vec<Target> {
        let mut t = Vec::new();
        if let Some(b) = &self.build {
            t.push(Target {
                what: "clean release build of every FMU for every platform".into(),
                limit: "≤ 240 s".into(),
                value: format!("{:.0} s", b.seconds),
                met: Some(b.seconds <= 240.0),
            });
            // the shipped archives, a binary for each platform in each
            for (name, bytes) in &b.fmus {
                t.push(Target {
                    what: format!("{name}: size of the .fmu"),
                    limit: "≤ 2 MiB".into(),
                    value: format!("{} KiB", bytes.div_ceil(1024)),
                    met: Some(*bytes <= 2 << 20),
                });
            }
        }
        t
    }
}

/// What `fmi2DoStep` adds to the model's equations: the plumbing proper and all beyond the
/// rhs, each at its worst configuration. The plumbing is not judged where the parts it is
/// made of do not add up ([`Split::adds_up`]).
fn plumbing(m: &Figures) -> Vec<Target> {
    if m.steps.is_empty() {
        return Vec::new();
    }
    let worst = |f: &dyn Fn(&Split) -> f64| {
        m.steps
            .iter()
            .map(|s| (f(&s.split()), s.h, s.tol))
            .filter(|p| p.0.is_finite())
            .max_by(|a, b| a.0.total_cmp(&b.0))
    };
    let show = |w: Option<(f64, f64, f64)>| {
        w.map_or("-".into(), |(p, h, tol)| {
            format!("{p:.0} ns (h {h:e}, tol {tol:e})")
        })
    };
    let runtime = worst(&|s| s.runtime());
    let inconsistent = m
        .steps
        .iter()
        .map(|s| s.split())
        .find(|p| !p.adds_up(NOISE_NS));
    let beyond = worst(&|s| s.beyond_rhs());
    vec![
        Target {
            what: format!(
                "{}: plumbing per fmi2DoStep (checks, lookup, guards, copying)",
                m.name
            ),
            limit: "≤ 25 ns".into(),
            value: match inconsistent {
                Some(p) => format!(
                    "not judged: the parts alone do not add up (copy {:.0}, solver {:.0}, step {:.0}, fmi {:.0} ns)",
                    p.copying, p.solver, p.step, p.fmi
                ),
                None => show(runtime),
            },
            met: if inconsistent.is_some() {
                None
            } else {
                runtime.map(|w| w.0 <= 25.0)
            },
        },
        Target {
            what: format!(
                "{}: all beyond the rhs, the solver's arithmetic included",
                m.name
            ),
            limit: "≤ 25 ns".into(),
            value: show(beyond),
            met: beyond.map(|w| w.0 <= 25.0),
        },
    ]
}

/// `fmi3DoStep` within 5 % of `fmi2DoStep`: judged on the instruction counts where they
/// were counted (repeatable), else on the median of its configurations' time ratios (the
/// extremes of four ratios on a busy machine are mostly noise; they are shown beside it).
fn fmi3(m: &Figures) -> Option<Target> {
    let ratios: Vec<f64> = (m.steps.iter())
        .map(|s| s.fmi3_ratio())
        .filter(|r| r.is_finite())
        .collect();
    let time = Stat::of(&ratios);
    let counted = m.instructions.and_then(|c| c.fmi3_ratio());
    let mut value = Vec::new();
    if let Some(c) = counted {
        value.push(format!("instructions {} (h 1e-2, tol 1e-6)", percent(c)));
    }
    if time.runs > 0 {
        value.push(format!(
            "time {} (median of {} configurations; {} to {})",
            percent(time.median),
            time.runs,
            percent(time.min),
            percent(time.max)
        ));
    }
    let judged = counted.or((time.runs > 0).then_some(time.median))?;
    Some(Target {
        what: format!("{}: fmi3DoStep within 5 % of fmi2DoStep", m.name),
        limit: "≤ 5 % apart".into(),
        value: value.join("; "),
        met: Some((judged - 1.0).abs() <= FMI3_LIMIT),
    })
}

/// Model Exchange's overhead per derivative evaluation, `fmi2GetReal` of many variables,
/// the FMU's share of a step under FMPy, and the Oscillator's `fmi2DoStep`.
fn calls(m: &Figures) -> Vec<Target> {
    let mut t = Vec::new();
    if let Some(me) = &m.model_exchange {
        t.push(Target {
            what: format!(
                "{}: Model Exchange overhead per derivative evaluation",
                m.name
            ),
            limit: format!("≤ {LIMIT_NS:.0} ns"),
            value: if me.overhead().is_finite() {
                format!(
                    "{:.1} ns ({:.1} − {:.1})",
                    me.overhead(),
                    me.api.median,
                    me.equations.median
                )
            } else {
                "not measured (no mechfmu_bench)".into()
            },
            met: me.met(),
        });
    }
    if m.get_many.ns.runs > 0 {
        t.push(Target {
            what: format!("{}: fmi2GetReal of {} variables", m.name, m.get_many.n),
            limit: "≤ 50 ns".into(),
            value: format!("{:.1} ns", m.get_many.ns.median),
            met: Some(m.get_many.ns.median <= 50.0),
        });
    }
    if let Some(share) = m.fmu_share() {
        t.push(Target {
            what: format!("{}: FMU's share of a step under FMPy", m.name),
            limit: "≤ 5 %".into(),
            value: format!("{:.1} %", share * 100.0),
            met: Some(share <= 0.05),
        });
    }
    if m.name == "Oscillator" {
        if let Some(s) = m.step(1e-2, 1e-6) {
            t.push(Target {
                what: "Oscillator: fmi2DoStep at tol 1e-6, h 1e-2".into(),
                limit: "≤ 300 ns".into(),
                value: format!("{:.0} ns", s.ns.median),
                met: Some(s.ns.median <= 300.0),
            });
        }
    }
    t
}

/// A mechanism declared from its energies against its hand-written declaration: per step
/// and per Model Exchange evaluation, in instructions.
fn from_energies(e: &EnergyCounts) -> Vec<Target> {
    let limit = format!("≤ {}× the hand-written one's", energies::LIMIT);
    let target = |what: &str, (hand, twin): (f64, f64)| Target {
        what: format!(
            "{} declared from its energies: instructions per {what}",
            e.mechanism
        ),
        limit: limit.clone(),
        value: format!("{:.2}× ({twin:.0} against {hand:.0})", twin / hand),
        met: Some(twin <= energies::LIMIT * hand),
    };
    vec![
        target("fmi2DoStep", e.step),
        target("Model Exchange evaluation", e.model_exchange),
    ]
}
