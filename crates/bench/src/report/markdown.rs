//! The benchmark's figures as Markdown tables (for docs/performance.md).

use super::format::{count, e, f, percent, share};
use super::Report;
use crate::precision::{self, FMPY, NATIVE};
use std::fmt::Write as _;

impl Report {
    /// The same figures as Markdown tables.
    pub fn markdown(&self) -> String {
        let mut o = String::new();
        let _ = writeln!(
            o,
            "`mechfmu bench`: CPU time (thread CPU clock), medians of {} runs, on the 2-core build machine.\n",
            self.runs
        );
        self.markdown_steps(&mut o);
        self.markdown_instructions(&mut o);
        self.markdown_model_exchange(&mut o);
        self.markdown_energies(&mut o);
        self.markdown_calls(&mut o);
        self.markdown_work_precision(&mut o);
        self.markdown_build(&mut o);
        self.markdown_targets(&mut o);
        o
    }

    /// The mechanisms declared again from their energies against the hand-written ones.
    fn markdown_energies(&self, o: &mut String) {
        if self.energies.is_empty() {
            return;
        }
        let _ = writeln!(
            o,
            "\n**Declared from energies** (Lagrange's equations from `T`, `V`, `Q`; `tests/energies`) against the hand-written equations, instructions (valgrind) per `fmi2DoStep` (h 1e-2, tol 1e-6) and per Model Exchange evaluation:\n"
        );
        table_head(
            o,
            1,
            &[
                "mechanism",
                "step, by hand",
                "step, from energies",
                "ratio",
                "ME evaluation, by hand",
                "ME evaluation, from energies",
                "ratio",
            ],
        );
        for e in &self.energies {
            let _ = writeln!(
                o,
                "| {} | {:.0} | {:.0} | {:.2}× | {:.0} | {:.0} | {:.2}× |",
                e.mechanism,
                e.step.0,
                e.step.1,
                e.step_ratio(),
                e.model_exchange.0,
                e.model_exchange.1,
                e.model_exchange_ratio()
            );
        }
    }

    /// `fmi2DoStep` from a native loop, ns per step and where they go.
    fn markdown_steps(&self, o: &mut String) {
        let stepped = self.mechanisms.iter().any(|m| !m.steps.is_empty());
        if stepped {
            let _ = writeln!(
                o,
                "**fmi2DoStep from a native loop**, ns per step and where they go:\n"
            );
            table_head(
                o,
                3,
                &[
                    "mechanism",
                    "h",
                    "tol",
                    "ns/step",
                    "fmi3DoStep ns/step",
                    "fmi3 vs fmi2",
                    "evals/step",
                    "rhs",
                    "copy",
                    "solver",
                    "step",
                    "FMI",
                    "plumbing (copy+step+FMI)",
                    "own (isolated)",
                    "overlap lost",
                ],
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
                    percent(s.fmi3_ratio()),
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
    }

    /// Instructions per step of each standard (valgrind).
    fn markdown_instructions(&self, o: &mut String) {
        if self.mechanisms.iter().any(|m| m.instructions.is_some()) {
            let _ = writeln!(
                o,
                "\n**Instructions** per step (valgrind), h 1e-2, tol 1e-6:\n"
            );
            table_head(
                o,
                1,
                &["mechanism", "fmi2DoStep", "fmi3DoStep", "fmi3 vs fmi2"],
            );
            for m in &self.mechanisms {
                if let Some(c) = &m.instructions {
                    let _ = writeln!(
                        o,
                        "| {} | {:.0} | {} | {} |",
                        m.name,
                        c.per_step,
                        count(c.fmi3_per_step),
                        c.fmi3_ratio().map_or("-".into(), percent)
                    );
                }
            }
        }
    }

    /// Model Exchange, ns per derivative evaluation and its overhead.
    fn markdown_model_exchange(&self, o: &mut String) {
        if self.mechanisms.iter().any(|m| m.model_exchange.is_some()) {
            let _ = writeln!(
                o,
                "\n**Model Exchange**, ns per derivative evaluation (`fmi2SetTime` + `fmi2SetContinuousStates` + `fmi2GetDerivatives`) at a new point each, next to the equations alone at the same points:\n"
            );
            table_head(
                o,
                1,
                &[
                    "mechanism",
                    "ME API (ns/eval)",
                    "equations alone (ns/eval)",
                    "ME overhead (ns/eval)",
                    "of which FMI layer",
                    "of which simulation's ME code",
                ],
            );
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
    }

    /// ns per array call and per cycle, and the same cycle under FMPy.
    fn markdown_calls(&self, o: &mut String) {
        if self.mechanisms.iter().any(|m| m.get_many.ns.runs > 0) {
            let _ = writeln!(o, "\n**Calls and FMPy** (default step and tolerance):\n");
            table_head(
                o,
                1,
                &[
                    "mechanism",
                    "fmi2GetReal outputs (ns)",
                    "fmi2GetReal 10 vars (ns)",
                    "cycle (ns)",
                    "FMPy low-level loop (µs/step)",
                    "FMU share",
                    ".fmu (KiB)",
                ],
            );
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
                    share(m.fmu_share()),
                    m.fmu_bytes.div_ceil(1024)
                );
            }
        }
    }

    /// The Oscillator's work–precision, and each FMU loop against scipy's best.
    fn markdown_work_precision(&self, o: &mut String) {
        if !self.precision.is_empty() {
            let scipy = self.scipy();
            let methods = self.precision_methods();
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
                    match self.precision_point(m, tol) {
                        Some(p) => {
                            let _ =
                                write!(o, " {} in {} µs |", e(p.error), f(p.cpu.median * 1e6, 0));
                        }
                        None => o.push_str(" - |"),
                    }
                }
                for method in [NATIVE, FMPY] {
                    let _ = write!(o, " {} |", self.speedup_text(method, tol, &scipy));
                }
                let _ = writeln!(o);
            }
        }
    }

    /// The clean build's time.
    fn markdown_build(&self, o: &mut String) {
        if let Some(b) = &self.build {
            let _ = writeln!(o, "\nClean release build of every FMU: {:.0} s.", b.seconds);
        }
    }

    /// The targets, met or not.
    fn markdown_targets(&self, o: &mut String) {
        let _ = writeln!(o, "\n**Targets**:\n");
        table_head(o, 4, &["target", "limit", "measured", "met"]);
        for t in self.targets() {
            let met = match t.met {
                Some(true) => "yes",
                Some(false) => "**no**",
                None => "-",
            };
            let _ = writeln!(o, "| {} | {} | {} | {met} |", t.what, t.limit, t.value);
        }
    }
}

/// A Markdown table's head: the row of `columns` and the rule under it, the first `left`
/// columns aligned left and the others right.
fn table_head(o: &mut String, left: usize, columns: &[&str]) {
    let _ = writeln!(o, "| {} |", columns.join(" | "));
    let rule: String = (0..columns.len())
        .map(|i| if i < left { "---|" } else { "---:|" })
        .collect();
    let _ = writeln!(o, "|{rule}");
}

#[cfg(test)]
mod tests {
    use super::table_head;

    #[test]
    fn a_head_has_one_rule_cell_per_column() {
        let mut o = String::new();
        table_head(&mut o, 2, &["mechanism", "h", "ns/step"]);
        assert_eq!(o, "| mechanism | h | ns/step |\n|---|---|---:|\n");
    }
}
