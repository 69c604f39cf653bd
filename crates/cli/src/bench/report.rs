//! The benchmark's table, its verdict on the performance targets (docs/performance.md), and
//! its JSON.

use super::clock::{num, Stat};
use super::precision::{self, Point};
use super::Figures;
use serde_json::{json, Value};
use std::fmt::Write as _;

/// How far below zero a part of the split may come out from noise alone (differences of
/// medians on a busy 2-core machine).
const NOISE_NS: f64 = 10.0;

/// A clean release build of every FMU.
#[derive(Clone, Debug)]
pub struct Build {
    pub command: String,
    pub seconds: f64,
    /// (model, bytes of the .fmu)
    pub fmus: Vec<(String, u64)>,
}

/// Everything one `mechfmu bench` measured.
#[derive(Clone, Debug, Default)]
pub struct Report {
    pub mechanisms: Vec<Figures>,
    /// The native FMU, the FMU under FMPy and scipy, on the Oscillator.
    pub precision: Vec<Point>,
    pub build: Option<Build>,
    /// ns per call without and with `catch_unwind`.
    pub catch_unwind: Option<(Stat, Stat)>,
    pub python_versions: Value,
    pub runs: usize,
    /// Notes for the reader (skipped parts and why).
    pub notes: Vec<String>,
}

/// One performance target and whether it is met.
#[derive(Clone, Debug)]
pub struct Target {
    pub what: String,
    pub limit: String,
    pub value: String,
    /// None: not measured in this run.
    pub met: Option<bool>,
}

const NATIVE: &str = "FMU (native loop)";
const FMPY: &str = "FMU (FMPy low-level loop)";

fn e(x: f64) -> String {
    if x.is_finite() {
        format!("{x:.1e}")
    } else {
        "-".into()
    }
}

fn f(x: f64, digits: usize) -> String {
    if x.is_finite() {
        format!("{x:.digits$}")
    } else {
        "-".into()
    }
}

fn spread(s: &Stat) -> String {
    if s.runs == 0 {
        return "-".into();
    }
    format!("{:.0}–{:.0}", s.min, s.max)
}

impl Report {
    fn points(&self, method: &str) -> Vec<&Point> {
        self.precision
            .iter()
            .filter(|p| p.method == method)
            .collect()
    }

    fn scipy(&self) -> Vec<Point> {
        self.precision
            .iter()
            .filter(|p| p.method.starts_with("scipy"))
            .cloned()
            .collect()
    }

    /// The performance targets, judged on this run's figures.
    ///
    /// The plumbing is not judged where the parts it is made of do not add up
    /// ([`Split::adds_up`](super::native::Split::adds_up)).
    pub fn targets(&self) -> Vec<Target> {
        let mut t = Vec::new();
        for m in &self.mechanisms {
            let worst = |f: &dyn Fn(&super::native::Split) -> f64| {
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
            let stepped = !m.steps.is_empty();
            let runtime = worst(&|s| s.runtime());
            let inconsistent = m
                .steps
                .iter()
                .map(|s| s.split())
                .find(|p| !p.adds_up(NOISE_NS));
            if stepped {
                t.push(Target {
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
            });
                let beyond = worst(&|s| s.beyond_rhs());
                t.push(Target {
                    what: format!(
                        "{}: all beyond the rhs, the solver's arithmetic included",
                        m.name
                    ),
                    limit: "≤ 25 ns".into(),
                    value: show(beyond),
                    met: beyond.map(|w| w.0 <= 25.0),
                });
            }
            t.extend(super::fmi3::target(m));
            if let Some(me) = &m.model_exchange {
                t.push(Target {
                    what: format!(
                        "{}: Model Exchange overhead per derivative evaluation",
                        m.name
                    ),
                    limit: format!("≤ {:.0} ns", super::model_exchange::LIMIT_NS),
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
        }
        let scipy = self.scipy();
        if !scipy.is_empty() {
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
        }
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

    /// The human-readable table.
    pub fn table(&self) -> String {
        let mut o = String::new();
        let _ = writeln!(
            o,
            "CPU time per call, median of {} runs (thread CPU time; min–max of the runs in brackets)\n",
            self.runs
        );
        let stepped = self.mechanisms.iter().any(|m| !m.steps.is_empty());
        if stepped {
            let _ = writeln!(o, "fmi2DoStep from a native loop (the .so through libloading), default experiment interval per run");
            let _ = writeln!(
            o,
            "{:<18} {:>6} {:>6} {:>8} {:>11} {:>6} {:>7} {:>5} {:>4} {:>4} {:>7} | {:>6} {:>5} {:>6} {:>5} {:>5} | {:>6} {:>7} | {:>5} {:>7}",
            "mechanism", "h", "tol", "ns/step", "(min–max)", "fmi3", "fmi3 Δ", "evals", "acc", "rej", "ns/eval",
            "rhs", "copy", "solver", "step", "fmi", ">rhs", "plumb.", "own", "overlap"
        );
            for m in &self.mechanisms {
                for s in &m.steps {
                    let p = s.split();
                    let iso = s.isolated();
                    let _ = writeln!(
                    o,
                    "{:<18} {:>6} {:>6} {:>8.0} {:>11} {:>6} {:>7} {:>5.2} {:>4.2} {:>4.2} {:>7.1} | {:>6.0} {:>5.0} {:>6.0} {:>5.0} {:>5.0} | {:>6.0} {:>7.0} | {:>5.0} {:>7.0}",
                    m.name,
                    e(s.h),
                    e(s.tol),
                    s.ns.median,
                    spread(&s.ns),
                    f(s.fmi3_ns.median, 0),
                    super::fmi3::percent(s.fmi3_ratio()),
                    s.evals,
                    s.accepted,
                    s.rejected,
                    s.evaluate_ns.median / s.evals,
                    p.rhs,
                    p.copying,
                    p.solver,
                    p.step,
                    p.fmi,
                    p.beyond_rhs(),
                    p.runtime(),
                    iso.plumbing,
                    iso.overlap_lost
                );
                }
            }
            let _ = writeln!(o, "  fmi3 = ns per fmi3DoStep of the same binary over the same run, timed beside fmi2DoStep; fmi3 Δ = fmi3 / ns/step - 1.");
            let _ = writeln!(o, "  evals/acc/rej: model evaluations, accepted and rejected solver steps per fmi2DoStep.");
            let _ = writeln!(o, "  Split of ns/step, from the parts run alone in the FMU on the same trajectory (mechfmu_bench):");
            let _ = writeln!(o, "  rhs = the model's equations (evaluate at every stage, outputs and any projection once per step);");
            let _ = writeln!(o, "  ns/eval = one stage evaluation (the states into the named values, evaluate, the derivatives out of");
            let _ = writeln!(o, "  them); copy = what the solver's callback adds to that (its slices in and out, its count); solver = Runge-Kutta");
            let _ = writeln!(o, "  arithmetic and error control; step = Simulation::step's checks and bookkeeping; fmi = the C call,");
            let _ = writeln!(o, "  instance/state checks, unwinding guard. >rhs = all but rhs; plumb. = copy + step + fmi.");
            let _ = writeln!(o, "  own = the plumbing from fmi2DoStep and the solver timed again with every call isolated from the");
            let _ = writeln!(o, "  next (lfence), its own instructions; overlap = plumb. - own: back to back, the solver's calls overlap");
            let _ = writeln!(o, "  in the processor, and the instructions between them inside fmi2DoStep take up the room it needs.\n");
        }

        if self.mechanisms.iter().any(|m| m.model_exchange.is_some()) {
            let runs = (self.mechanisms.iter())
                .filter_map(|m| m.model_exchange.as_ref())
                .map(|me| me.api.runs)
                .max()
                .unwrap_or(0);
            let _ = writeln!(
                o,
                "Model Exchange: one derivative evaluation, ns (fmi2SetTime + fmi2SetContinuousStates + fmi2GetDerivatives), median of {runs} runs"
            );
            let _ = writeln!(
                o,
                "{:<18} {:>7} {:>7} {:>11} {:>9} {:>11} {:>9} | {:>8} {:>5} {:>7} {:>7}",
                "mechanism",
                "points",
                "ME API",
                "(min–max)",
                "equations",
                "(min–max)",
                "overhead",
                "FMI",
                "sim.",
                "evals/pt",
                ""
            );
            for m in &self.mechanisms {
                let Some(me) = &m.model_exchange else {
                    continue;
                };
                let mark = match me.met() {
                    Some(true) => "",
                    Some(false) => "FAIL",
                    None => "-",
                };
                let _ = writeln!(
                    o,
                    "{:<18} {:>7} {:>7.1} {:>11} {:>9.1} {:>11} {:>9.1} | {:>8.1} {:>5.1} {:>7.2} {:>7}",
                    m.name,
                    me.evaluations,
                    me.api.median,
                    spread(&me.api),
                    me.equations.median,
                    spread(&me.equations),
                    me.overhead(),
                    me.fmi_layer(),
                    me.simulation_code(),
                    me.evals_per_point,
                    mark
                );
            }
            let _ = writeln!(o, "  ns per evaluation at a new point each (new time, new states: an explicit Euler walk of the default");
            let _ = writeln!(o, "  experiment's interval, each point waiting for the last one's derivatives). ME API = the three exported");
            let _ = writeln!(o, "  calls from a native loop; equations = the same points by the equations alone in the FMU (time and states");
            let _ = writeln!(o, "  into the values, evaluate, derivatives out: Part::Evaluate); overhead = ME API - equations (limit {:.0} ns,", super::model_exchange::LIMIT_NS);
            let _ = writeln!(o, "  FAIL above it), of which FMI = the FMI layer (ME API - the simulation's ME code alone, Part::ModelExchange)");
            let _ = writeln!(o, "  and sim. = the simulation's ME code (flags, checks, copies). evals/pt: model evaluations per point (1: none reused).\n");
            if self.mechanisms.iter().any(|m| m.me_instructions.is_some()) {
                let _ = writeln!(
                    o,
                    "Instructions per Model Exchange derivative evaluation (valgrind, repeatable)"
                );
                let _ = writeln!(
                    o,
                    "{:<18} {:>7} {:>9} {:>9} | {:>6} {:>5}",
                    "mechanism", "ME API", "equations", "overhead", "FMI", "sim."
                );
                for m in &self.mechanisms {
                    if let Some(c) = &m.me_instructions {
                        let _ = writeln!(
                            o,
                            "{:<18} {:>7.1} {:>9.1} {:>9.1} | {:>6.1} {:>5.1}",
                            m.name,
                            c.api,
                            c.equations,
                            c.overhead(),
                            c.api - c.simulation,
                            c.simulation - c.equations
                        );
                    }
                }
                let _ = writeln!(o);
            }
        }

        if self.mechanisms.iter().any(|m| m.get_many.ns.runs > 0) {
            let _ = writeln!(
                o,
                "Calls (native), and the same cycle under FMPy (default step and tolerance)"
            );
            let _ = writeln!(
                o,
                "{:<18} {:>12} {:>12} {:>12} {:>10} {:>11} {:>8} {:>13} {:>8}",
                "mechanism",
                "get outputs",
                "get 10 vars",
                "set inputs",
                "cycle ns",
                "FMPy µs",
                "share",
                "simulate_fmu",
                ".fmu"
            );
            for m in &self.mechanisms {
                let call = |c: &super::CallFigures| format!("{:.1} ({})", c.ns.median, c.n);
                let _ = writeln!(
                    o,
                    "{:<18} {:>12} {:>12} {:>12} {:>10.0} {:>11} {:>8} {:>13} {:>5} KiB",
                    m.name,
                    call(&m.get_outputs),
                    call(&m.get_many),
                    m.set_inputs.as_ref().map_or("-".into(), call),
                    m.cycle.median,
                    m.fmpy.map_or("-".into(), |s| f(s.median, 2)),
                    m.fmu_share()
                        .map_or("-".into(), |s| format!("{:.1} %", s * 100.0)),
                    m.simulate_fmu
                        .map_or("-".into(), |s| format!("{} µs", f(s.median, 2))),
                    m.fmu_bytes.div_ceil(1024)
                );
            }
            let _ = writeln!(o, "  get/set: ns per array call (number of variables); cycle: set inputs + fmi2DoStep + get outputs;");
            let _ = writeln!(o, "  FMPy µs: the same cycle in FMPy's low-level loop (FMU2Slave); share = cycle / FMPy µs.\n");
        }

        if self.mechanisms.iter().any(|m| m.instructions.is_some()) {
            let _ = writeln!(
                o,
                "Instructions per fmi2DoStep (valgrind, repeatable), h = 1e-2, tol = 1e-6; fmi3 = per fmi3DoStep, same run"
            );
            let _ = writeln!(
                o,
                "{:<18} {:>8} {:>8} {:>7} | {:>6} {:>5} {:>6} {:>5} {:>5} | {:>6} {:>7} | {:>11}",
                "mechanism",
                "total",
                "fmi3",
                "fmi3 Δ",
                "rhs",
                "copy",
                "solver",
                "step",
                "fmi",
                ">rhs",
                "plumb.",
                "get outputs"
            );
            for m in &self.mechanisms {
                if let Some(c) = &m.instructions {
                    let p = c.split();
                    let _ = writeln!(
                        o,
                        "{:<18} {:>8.0} {:>8} {:>7} | {:>6.0} {:>5.0} {:>6.0} {:>5.0} {:>5.0} | {:>6.0} {:>7.0} | {:>11.0}",
                        m.name,
                        c.per_step,
                        c.fmi3_per_step.map_or("-".into(), |n| format!("{n:.0}")),
                        c.fmi3_ratio().map_or("-".into(), super::fmi3::percent),
                        p.rhs,
                        p.copying,
                        p.solver,
                        p.step,
                        p.fmi,
                        p.beyond_rhs(),
                        p.runtime(),
                        c.per_get_real
                    );
                }
            }
            let _ = writeln!(o);
        }

        if let Some((direct, guarded)) = &self.catch_unwind {
            let _ = writeln!(
                o,
                "catch_unwind around a call that does not panic: {:.2} ns per call ({:.2} ns guarded, {:.2} ns direct)\n",
                guarded.median - direct.median,
                guarded.median,
                direct.median
            );
        }

        if !self.precision.is_empty() {
            let scipy = self.scipy();
            let mut methods: Vec<&str> = self.precision.iter().map(|p| p.method.as_str()).collect();
            methods.dedup();
            let _ = writeln!(o, "Work–precision, Oscillator free response over 20 s, output every 0.1 s: max |x - exact|, CPU µs per run");
            let mut header = format!("{:>7}", "tol");
            for m in &methods {
                let _ = write!(header, " | {:^25}", m.trim_start_matches("scipy "));
            }
            let _ = write!(header, " | {:>16}", "vs scipy's best");
            let _ = writeln!(o, "{header}");
            for &tol in &precision::TOLERANCES {
                let mut line = format!("{:>7}", e(tol));
                for m in &methods {
                    match self
                        .precision
                        .iter()
                        .find(|p| p.method == *m && p.tol == tol)
                    {
                        Some(p) => {
                            let _ = write!(
                                line,
                                " | {:>9} {:>13}",
                                e(p.error),
                                format!("{} µs", f(p.cpu.median * 1e6, 1))
                            );
                        }
                        None => {
                            let _ = write!(line, " | {:>25}", "-");
                        }
                    }
                }
                let ratio = |method: &str| {
                    self.precision
                        .iter()
                        .find(|p| p.method == method && p.tol == tol)
                        .and_then(|p| precision::speedup(p, &scipy))
                        .map_or("-".into(), |s| {
                            format!("{}{:.0}×", s.bound.unwrap_or(""), s.ratio)
                        })
                };
                let _ = write!(line, " | {:>7} {:>8}", ratio(NATIVE), ratio(FMPY));
                let _ = writeln!(o, "{line}");
            }
            let _ = writeln!(o, "  vs scipy's best: scipy's CPU time for the same error (log–log interpolation along its best");
            let _ = writeln!(o, "  method's front) over the FMU's, native loop then FMPy loop; '>': scipy never gets this accurate");
            let _ = writeln!(o, "  (compared with its most accurate run); '<': the FMU is less accurate than any scipy run.\n");
        }

        if let Some(b) = &self.build {
            let _ = writeln!(
                o,
                "Clean release build of every FMU ({}): {:.0} s",
                b.command, b.seconds
            );
            for (name, bytes) in &b.fmus {
                let _ = writeln!(o, "  {name:<18} {} KiB", bytes.div_ceil(1024));
            }
            let _ = writeln!(o);
        }

        let _ = writeln!(o, "Targets");
        for t in self.targets() {
            let mark = match t.met {
                Some(true) => "met    ",
                Some(false) => "NOT met",
                None => "n/a    ",
            };
            let _ = writeln!(o, "  {mark}  {:<66} {:<26} {}", t.what, t.limit, t.value);
        }
        for n in &self.notes {
            let _ = writeln!(o, "note: {n}");
        }
        o
    }

    /// The same figures as Markdown tables (for the README).
    pub fn markdown(&self) -> String {
        let mut o = String::new();
        let _ = writeln!(
            o,
            "`mechfmu bench`: CPU time (thread CPU clock), medians of {} runs, on the 2-core build machine.\n",
            self.runs
        );
        let stepped = self.mechanisms.iter().any(|m| !m.steps.is_empty());
        if stepped {
            let _ = writeln!(
                o,
                "**fmi2DoStep from a native loop**, ns per step and where they go:\n"
            );
            let _ = writeln!(
            o,
            "| mechanism | h | tol | ns/step | fmi3DoStep ns/step | fmi3 vs fmi2 | evals/step | rhs | copy | solver | step | FMI | plumbing (copy+step+FMI) | own (isolated) | overlap lost |"
        );
            let _ = writeln!(
                o,
                "|---|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|"
            );
            for m in &self.mechanisms {
                for s in &m.steps {
                    let p = s.split();
                    let iso = s.isolated();
                    let _ = writeln!(
                    o,
                    "| {} | {} | {} | {:.0} | {} | {} | {:.2} | {:.0} | {:.0} | {:.0} | {:.0} | {:.0} | {:.0} | {:.0} | {:.0} |",
                    m.name,
                    e(s.h),
                    e(s.tol),
                    s.ns.median,
                    f(s.fmi3_ns.median, 0),
                    super::fmi3::percent(s.fmi3_ratio()),
                    s.evals,
                    p.rhs,
                    p.copying,
                    p.solver,
                    p.step,
                    p.fmi,
                    p.runtime(),
                    iso.plumbing,
                    iso.overlap_lost
                );
                }
            }
        }
        if self.mechanisms.iter().any(|m| m.instructions.is_some()) {
            let _ = writeln!(
                o,
                "\n**Instructions** per step (valgrind), h 1e-2, tol 1e-6:\n"
            );
            let _ = writeln!(o, "| mechanism | fmi2DoStep | fmi3DoStep | fmi3 vs fmi2 |");
            let _ = writeln!(o, "|---|---:|---:|---:|");
            for m in &self.mechanisms {
                if let Some(c) = &m.instructions {
                    let _ = writeln!(
                        o,
                        "| {} | {:.0} | {} | {} |",
                        m.name,
                        c.per_step,
                        c.fmi3_per_step.map_or("-".into(), |n| format!("{n:.0}")),
                        c.fmi3_ratio().map_or("-".into(), super::fmi3::percent)
                    );
                }
            }
        }
        if self.mechanisms.iter().any(|m| m.model_exchange.is_some()) {
            let _ = writeln!(
                o,
                "\n**Model Exchange**, ns per derivative evaluation (`fmi2SetTime` + `fmi2SetContinuousStates` + `fmi2GetDerivatives`) at a new point each, next to the equations alone at the same points:\n"
            );
            let _ = writeln!(
                o,
                "| mechanism | ME API (ns/eval) | equations alone (ns/eval) | ME overhead (ns/eval) | of which FMI layer | of which simulation's ME code |"
            );
            let _ = writeln!(o, "|---|---:|---:|---:|---:|---:|");
            for m in &self.mechanisms {
                if let Some(me) = &m.model_exchange {
                    let _ = writeln!(
                        o,
                        "| {} | {} | {} | {} | {} | {} |",
                        m.name,
                        f(me.api.median, 1),
                        f(me.equations.median, 1),
                        f(me.overhead(), 1),
                        f(me.fmi_layer(), 1),
                        f(me.simulation_code(), 1)
                    );
                }
            }
        }
        if self.mechanisms.iter().any(|m| m.get_many.ns.runs > 0) {
            let _ = writeln!(o, "\n**Calls and FMPy** (default step and tolerance):\n");
            let _ = writeln!(
            o,
            "| mechanism | fmi2GetReal outputs (ns) | fmi2GetReal 10 vars (ns) | cycle (ns) | FMPy low-level loop (µs/step) | FMU share | .fmu (KiB) |"
        );
            let _ = writeln!(o, "|---|---:|---:|---:|---:|---:|---:|");
            for m in &self.mechanisms {
                let _ = writeln!(
                    o,
                    "| {} | {:.1} ({}) | {:.1} | {:.0} | {} | {} | {} |",
                    m.name,
                    m.get_outputs.ns.median,
                    m.get_outputs.n,
                    m.get_many.ns.median,
                    m.cycle.median,
                    m.fmpy.map_or("-".into(), |s| f(s.median, 2)),
                    m.fmu_share()
                        .map_or("-".into(), |s| format!("{:.1} %", s * 100.0)),
                    m.fmu_bytes.div_ceil(1024)
                );
            }
        }
        if !self.precision.is_empty() {
            let scipy = self.scipy();
            let mut methods: Vec<&str> = self.precision.iter().map(|p| p.method.as_str()).collect();
            methods.dedup();
            let _ = writeln!(
                o,
                "\n**Work–precision**, Oscillator over 20 s, output every 0.1 s: max error of x, CPU µs per run:\n"
            );
            let mut header = "| tol |".to_string();
            let mut rule = "|---|".to_string();
            for m in &methods {
                let _ = write!(header, " {m} |");
                rule.push_str("---:|");
            }
            let _ = writeln!(
                o,
                "{header} native vs scipy's best | FMPy vs scipy's best |"
            );
            let _ = writeln!(o, "{rule}---:|---:|");
            for &tol in &precision::TOLERANCES {
                let _ = write!(o, "| {} |", e(tol));
                for m in &methods {
                    match self
                        .precision
                        .iter()
                        .find(|p| p.method == *m && p.tol == tol)
                    {
                        Some(p) => {
                            let _ =
                                write!(o, " {} in {} µs |", e(p.error), f(p.cpu.median * 1e6, 0));
                        }
                        None => o.push_str(" - |"),
                    }
                }
                for method in [NATIVE, FMPY] {
                    let r = self
                        .precision
                        .iter()
                        .find(|p| p.method == method && p.tol == tol)
                        .and_then(|p| precision::speedup(p, &scipy))
                        .map_or("-".into(), |s| {
                            format!("{}{:.0}×", s.bound.unwrap_or(""), s.ratio)
                        });
                    let _ = write!(o, " {r} |");
                }
                let _ = writeln!(o);
            }
        }
        if let Some(b) = &self.build {
            let _ = writeln!(o, "\nClean release build of every FMU: {:.0} s.", b.seconds);
        }
        let _ = writeln!(o, "\n**Targets**:\n");
        let _ = writeln!(o, "| target | limit | measured | met |");
        let _ = writeln!(o, "|---|---|---|---|");
        for t in self.targets() {
            let met = match t.met {
                Some(true) => "yes",
                Some(false) => "**no**",
                None => "-",
            };
            let _ = writeln!(o, "| {} | {} | {} | {met} |", t.what, t.limit, t.value);
        }
        o
    }

    pub fn to_json(&self) -> Value {
        let mechanisms: Vec<Value> = self
            .mechanisms
            .iter()
            .map(|m| {
                let call =
                    |c: &super::CallFigures| json!({ "variables": c.n, "ns": c.ns.to_json() });
                json!({
                    "name": m.name,
                    "fmu": m.fmu.display().to_string(),
                    "fmu_bytes": m.fmu_bytes,
                    "do_step": m.steps.iter().map(|s| s.to_json()).collect::<Vec<_>>(),
                    "get_real_outputs": call(&m.get_outputs),
                    "get_real_many": call(&m.get_many),
                    "set_real_inputs": m.set_inputs.as_ref().map(call),
                    "cycle": { "h": m.default_h, "tol": m.default_tol, "ns": m.cycle.to_json() },
                    "model_exchange": m.model_exchange.as_ref().map(|me| me.to_json()),
                    "model_exchange_instructions": m.me_instructions.map(|c| c.to_json()),
                    "instructions": m.instructions.map(|c| c.to_json()),
                    "fmpy_low_level_us_per_step": m.fmpy.map(|s| s.to_json()),
                    "fmpy_simulate_fmu_us_per_step": m.simulate_fmu.map(|s| s.to_json()),
                    "fmu_share_under_fmpy": m.fmu_share().map(num),
                })
            })
            .collect();
        let scipy = self.scipy();
        let precision: Vec<Value> = self
            .precision
            .iter()
            .map(|p| {
                let mut v = p.to_json();
                if !p.method.starts_with("scipy") {
                    if let Some(s) = precision::speedup(p, &scipy) {
                        v["vs_scipy_best"] =
                            json!({ "ratio": num(s.ratio), "method": s.best, "bound": s.bound });
                    }
                }
                v
            })
            .collect();
        let targets: Vec<Value> = self
            .targets()
            .iter()
            .map(|t| json!({ "what": t.what, "limit": t.limit, "value": t.value, "met": t.met }))
            .collect();
        json!({
            "schema": "mechfmu-bench/1",
            "runs": self.runs,
            "clock": "thread CPU time (CLOCK_THREAD_CPUTIME_ID); Python: process_time",
            "machine": { "cpus": std::thread::available_parallelism().map(|n| n.get()).unwrap_or(0) },
            "mechanisms": mechanisms,
            "catch_unwind_ns": self.catch_unwind.map(|(d, g)| json!({ "direct": d.to_json(), "guarded": g.to_json() })),
            "work_precision": precision,
            "build": self.build.as_ref().map(|b| json!({ "command": b.command, "seconds": b.seconds,
                "fmus": b.fmus.iter().map(|(n, s)| json!({ "name": n, "bytes": s })).collect::<Vec<_>>() })),
            "python": self.python_versions,
            "targets": targets,
            "notes": self.notes,
        })
    }
}
