//! What one `mechfmu bench` measured ([`Report`]): the table it prints ([`table`]), its
//! verdict on the performance targets of docs/performance.md ([`targets`]), the JSON runs
//! are compared with, and the same figures as Markdown ([`markdown`]).

pub mod format;
pub mod markdown;
pub mod table;
pub mod targets;

use crate::clock::{num, Stat};
use crate::energies::EnergyCounts;
use crate::figures::{CallFigures, Figures};
use crate::precision::{self, Point};
use serde_json::{json, Value};
use std::path::Path;

/// A clean release build of every FMU.
#[derive(Clone, Debug)]
pub struct Build {
    pub command: String,
    pub seconds: f64,
    /// (model, bytes of the .fmu)
    pub fmus: Vec<(String, u64)>,
}

/// The C step ([`crate::c_step`]) at [`crate::c_step::AGAINST_C`].
#[derive(Clone, Copy, Debug)]
pub struct CStep {
    /// CPU ns per communication step.
    pub ns: Stat,
    /// Instructions per communication step (None: not counted).
    pub instructions: Option<f64>,
}

/// Everything one `mechfmu bench` measured.
#[derive(Clone, Debug, Default)]
pub struct Report {
    /// The yardstick: the Oscillator's step written plainly in C.
    pub c_step: Option<CStep>,
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
    /// The mechanisms declared again from their energies, against the hand-written ones.
    pub energies: Vec<EnergyCounts>,
}

impl Report {
    /// The work–precision points of `method`.
    fn points(&self, method: &str) -> Vec<&Point> {
        self.precision
            .iter()
            .filter(|p| p.method == method)
            .collect()
    }

    /// scipy's work–precision points, every method's.
    fn scipy(&self) -> Vec<Point> {
        self.precision
            .iter()
            .filter(|p| p.method.starts_with("scipy"))
            .cloned()
            .collect()
    }

    /// The methods of the work–precision points, in the order they were run.
    fn precision_methods(&self) -> Vec<&str> {
        let mut methods: Vec<&str> = self.precision.iter().map(|p| p.method.as_str()).collect();
        methods.dedup();
        methods
    }

    /// The work–precision point of `method` at `tol`, if it ran.
    fn precision_point(&self, method: &str, tol: f64) -> Option<&Point> {
        self.precision
            .iter()
            .find(|p| p.method == method && p.tol == tol)
    }

    /// How much faster `method` is at `tol` than scipy's best for the same error, as the
    /// table and the Markdown write it (`-`: no such point or nothing to compare with).
    fn speedup_text(&self, method: &str, tol: f64, scipy: &[Point]) -> String {
        self.precision_point(method, tol)
            .and_then(|p| precision::speedup(p, scipy))
            .map_or("-".into(), |s| {
                format!("{}{:.0}×", s.bound.unwrap_or(""), s.ratio)
            })
    }

    /// Prints the table, and writes the JSON to `json_path` and the Markdown beside it
    /// (`.md`).
    pub fn write(&self, json_path: &Path) -> Result<(), String> {
        print!("{}", self.table());
        if let Some(dir) = json_path.parent() {
            std::fs::create_dir_all(dir)
                .map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
        }
        let text = serde_json::to_string_pretty(&self.to_json()).map_err(|e| e.to_string())?;
        std::fs::write(json_path, text + "\n")
            .map_err(|e| format!("cannot write {}: {e}", json_path.display()))?;
        let md_path = json_path.with_extension("md");
        std::fs::write(&md_path, self.markdown())
            .map_err(|e| format!("cannot write {}: {e}", md_path.display()))?;
        println!("\nwrote {} and {}", json_path.display(), md_path.display());
        Ok(())
    }

    pub fn to_json(&self) -> Value {
        let mechanisms: Vec<Value> = self
            .mechanisms
            .iter()
            .map(|m| {
                let call = |c: &CallFigures| json!({ "variables": c.n, "ns": c.ns.to_json() });
                json!({
                    "name": m.name,
                    "fmu": m.fmu.display().to_string(),
                    "fmu_bytes": m.fmu_bytes,
                    "do_step": m.steps.iter().map(|s| s.to_json()).collect::<Vec<_>>(),
                    "get_real_outputs": call(&m.get_outputs),
                    "get_real_many": call(&m.get_many),
                    "set_real_inputs": m.set_inputs.as_ref().map(call),
                    "cycle": { "h": m.default_h, "tol": m.default_tol, "ns": m.cycle.to_json() },
                    "step_and_get_real_ns": m.step_get.to_json(),
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
            "c_step": self.c_step.map(|c| json!({
                "h": crate::c_step::AGAINST_C.0, "tol": crate::c_step::AGAINST_C.1,
                "ns": c.ns.to_json(), "instructions": c.instructions.map(num),
            })),
            "mechanisms": mechanisms,
            "catch_unwind_ns": self.catch_unwind.map(|(d, g)| json!({ "direct": d.to_json(), "guarded": g.to_json() })),
            "work_precision": precision,
            "from_energies": self.energies.iter().map(EnergyCounts::to_json).collect::<Vec<_>>(),
            "build": self.build.as_ref().map(|b| json!({ "command": b.command, "seconds": b.seconds,
                "fmus": b.fmus.iter().map(|(n, s)| json!({ "name": n, "bytes": s })).collect::<Vec<_>>() })),
            "python": self.python_versions,
            "targets": targets,
            "notes": self.notes,
        })
    }
}
