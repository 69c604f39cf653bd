//! The benchmark's table on stdout: one section per kind of figure, each with its legend,
//! then the targets.

use super::format::{count, e, f, percent, share, spread};
use super::Report;
use crate::figures::CallFigures;
use crate::model_exchange::LIMIT_NS;
use crate::precision::{self, FMPY, NATIVE};
use std::fmt::Write as _;

impl Report {
    /// The human-readable table.
    pub fn table(&self) -> String {
        let mut o = String::new();
        let _ = writeln!(
            o,
            "CPU time per call, median of {} runs (thread CPU time; min–max of the runs in brackets)\n",
            self.runs
        );
        self.table_steps(&mut o);
        self.table_model_exchange(&mut o);
        self.table_calls(&mut o);
        self.table_against_c(&mut o);
        self.table_instructions(&mut o);
        self.table_catch_unwind(&mut o);
        self.table_work_precision(&mut o);
        self.table_build(&mut o);
        self.table_verdict(&mut o);
        o
    }

    /// `fmi2DoStep` from a native loop: ns per step, its work and where the ns go.
    fn table_steps(&self, o: &mut String) {
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
                    percent(s.fmi3_ratio()),
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
    }

    /// Model Exchange: ns per derivative evaluation, and its instructions where counted.
    fn table_model_exchange(&self, o: &mut String) {
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
            let _ = writeln!(o, "  into the values, evaluate, derivatives out: Part::Evaluate); overhead = ME API - equations (limit {:.0} ns,", LIMIT_NS);
            let _ = writeln!(o, "  FAIL above it), of which FMI = the FMI layer (ME API - the simulation's ME code alone, Part::ModelExchange)");
            let _ = writeln!(o, "  and sim. = the simulation's ME code (flags, checks, copies). evals/pt: model evaluations per point (1: none reused).\n");
            self.table_me_instructions(o);
        }
    }

    /// Instructions per Model Exchange derivative evaluation, where counted (valgrind).
    fn table_me_instructions(&self, o: &mut String) {
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

    /// ns per array call and per co-simulation cycle, and the same cycle under FMPy.
    fn table_calls(&self, o: &mut String) {
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
                let call = |c: &CallFigures| format!("{:.1} ({})", c.ns.median, c.n);
                let _ = writeln!(
                    o,
                    "{:<18} {:>12} {:>12} {:>12} {:>10.0} {:>11} {:>8} {:>13} {:>5} KiB",
                    m.name,
                    call(&m.get_outputs),
                    call(&m.get_many),
                    m.set_inputs.as_ref().map_or("-".into(), call),
                    m.cycle.median,
                    m.fmpy.map_or("-".into(), |s| f(s.median, 2)),
                    share(m.fmu_share()),
                    m.simulate_fmu
                        .map_or("-".into(), |s| format!("{} µs", f(s.median, 2))),
                    m.fmu_bytes.div_ceil(1024)
                );
            }
            let _ = writeln!(o, "  get/set: ns per array call (number of variables); cycle: set inputs + fmi2DoStep + get outputs;");
            let _ = writeln!(o, "  FMPy µs: the same cycle in FMPy's low-level loop (FMU2Slave); share = cycle / FMPy µs.\n");
        }
    }

    /// Each mechanism's `fmi2DoStep` + one `fmi2GetReal` against the C step: instructions
    /// and time, and their ratio to the C step's.
    fn table_against_c(&self, o: &mut String) {
        let Some(c) = &self.c_step else {
            return;
        };
        let (h, tol) = crate::c_step::AGAINST_C;
        let _ = writeln!(
            o,
            "Against C: fmi2DoStep + one fmi2GetReal (an importer's loop), h = {h:e}, tol = {tol:e};"
        );
        let _ = writeln!(
            o,
            "  the C step: the Oscillator's Dormand-Prince step written plainly in C (crates/bench/c)"
        );
        let _ = writeln!(
            o,
            "{:<18} {:>12} {:>7} {:>8} {:>7}",
            "", "instructions", "× C", "ns", "× C"
        );
        let ratio = |x: f64, of: f64| {
            if x.is_finite() && of.is_finite() && of > 0.0 {
                format!("{:.2}", x / of)
            } else {
                "-".into()
            }
        };
        let c_instructions = c.instructions.unwrap_or(f64::NAN);
        let _ = writeln!(
            o,
            "{:<18} {:>12} {:>7} {:>8.1} {:>7}",
            "C step",
            count(c.instructions),
            ratio(c_instructions, c_instructions),
            c.ns.median,
            ratio(c.ns.median, c.ns.median)
        );
        for m in &self.mechanisms {
            let counted = m.instructions.map(|i| i.step_get_per_step);
            let _ = writeln!(
                o,
                "{:<18} {:>12} {:>7} {:>8.1} {:>7}",
                m.name,
                count(counted),
                ratio(counted.unwrap_or(f64::NAN), c_instructions),
                m.step_get.median,
                ratio(m.step_get.median, c.ns.median)
            );
        }
        let _ = writeln!(o);
    }

    /// Instructions per `fmi2DoStep` and `fmi3DoStep`, and their split (valgrind).
    fn table_instructions(&self, o: &mut String) {
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
                        count(c.fmi3_per_step),
                        c.fmi3_ratio().map_or("-".into(), percent),
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
    }

    /// What `catch_unwind` adds around a call.
    fn table_catch_unwind(&self, o: &mut String) {
        if let Some((direct, guarded)) = &self.catch_unwind {
            let _ = writeln!(
                o,
                "catch_unwind around a call that does not panic: {:.2} ns per call ({:.2} ns guarded, {:.2} ns direct)\n",
                guarded.median - direct.median,
                guarded.median,
                direct.median
            );
        }
    }

    /// The Oscillator's work–precision: error and CPU time per tolerance and method.
    fn table_work_precision(&self, o: &mut String) {
        if !self.precision.is_empty() {
            let scipy = self.scipy();
            let methods = self.precision_methods();
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
                    match self.precision_point(m, tol) {
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
                let _ = write!(
                    line,
                    " | {:>7} {:>8}",
                    self.speedup_text(NATIVE, tol, &scipy),
                    self.speedup_text(FMPY, tol, &scipy)
                );
                let _ = writeln!(o, "{line}");
            }
            let _ = writeln!(o, "  vs scipy's best: scipy's CPU time for the same error (log–log interpolation along its best");
            let _ = writeln!(o, "  method's front) over the FMU's, native loop then FMPy loop; '>': scipy never gets this accurate");
            let _ = writeln!(o, "  (compared with its most accurate run); '<': the FMU is less accurate than any scipy run.\n");
        }
    }

    /// The clean build's time and archives.
    fn table_build(&self, o: &mut String) {
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
    }

    /// The targets, met or not, and the notes.
    fn table_verdict(&self, o: &mut String) {
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
    }
}
