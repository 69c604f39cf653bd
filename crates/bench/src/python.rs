//! The FMPy and scipy figures, from `scripts/bench_fmpy.py` run by the project venv: the
//! script's configuration (the same cycle per mechanism as the native loop, the Oscillator's
//! work–precision problem), its run, and its results into the report.

use crate::binary::Binary;
use crate::clock::Stat;
use crate::effort::{steps_per_run, Effort};
use crate::precision::{self, Problem};
use crate::report::Report;
use serde_json::{json, Value};
use std::path::Path;
use std::process::Command;

/// The script's configuration: per mechanism of `report` (loaded as `binaries`) its FMPy
/// cycle at the default step and tolerance, and the Oscillator's `problem` if it has one.
pub fn config(
    report: &Report,
    binaries: &[&Binary],
    problem: Option<&Problem>,
    effort: Effort,
) -> Value {
    let loops: Vec<Value> = (report.mechanisms.iter().zip(binaries))
        .map(|(m, bin)| {
            let d = &bin.description;
            let inputs: Vec<(u32, f64)> = d
                .with_causality("input")
                .iter()
                .map(|v| (v.vr, v.start.unwrap_or(0.0)))
                .collect();
            let outputs: Vec<u32> = d.with_causality("output").iter().map(|v| v.vr).collect();
            json!({
                "name": m.name,
                "fmu": m.fmu.display().to_string(),
                "h": d.step,
                "tol": d.tolerance,
                "start": d.start,
                "steps": steps_per_run(bin, d.step, effort),
                "inputs": inputs,
                "outputs": outputs,
            })
        })
        .collect();
    let precision_cfg = match problem {
        Some(p) => {
            let (grid, exact) = p.grid();
            let fmu = (report.mechanisms.iter())
                .find(|m| m.name == "Oscillator")
                .map(|m| m.fmu.display().to_string());
            json!({
                "fmu": fmu,
                "problem": { "m": p.m, "c": p.c, "k": p.k, "x0": p.x0, "v0": p.v0, "vr_x": p.vr_x },
                "grid": grid, "exact": exact,
                "tolerances": precision::TOLERANCES,
                "t_end": precision::T_END, "output": precision::OUTPUT,
            })
        }
        None => Value::Null,
    };
    json!({
        "runs": effort.runs.clamp(3, 9),
        "loops": loops,
        "simulate": loops,
        "precision": precision_cfg,
    })
}

/// The script's `result` into `report`: each mechanism's µs per step under FMPy's
/// low-level loop and `simulate_fmu`, scipy's work–precision points, the versions.
pub fn record(result: &Value, report: &mut Report) {
    let stat = |v: &Value| -> Option<Stat> {
        Some(Stat {
            median: v["median"].as_f64()?,
            min: v["min"].as_f64()?,
            max: v["max"].as_f64()?,
            runs: v["runs"].as_u64()? as usize,
        })
    };
    for m in report.mechanisms.iter_mut() {
        let find = |key: &str| {
            result[key]
                .as_array()
                .into_iter()
                .flatten()
                .find(|l| l["name"] == m.name.as_str())
                .and_then(|l| stat(&l["us_per_step"]))
        };
        m.fmpy = find("loops");
        m.simulate_fmu = find("simulate_fmu");
    }
    report.precision.extend(
        result["precision"]
            .as_array()
            .into_iter()
            .flatten()
            .filter_map(precision::Point::from_json),
    );
    report.python_versions = result["versions"].clone();
}

/// Runs the script with `config` (written to `work_dir/bench_fmpy.json`); returns its JSON.
pub fn run(python: &Path, script: &Path, config: &Value, work_dir: &Path) -> Result<Value, String> {
    std::fs::create_dir_all(work_dir)
        .map_err(|e| format!("cannot create {}: {e}", work_dir.display()))?;
    let path = work_dir.join("bench_fmpy.json");
    std::fs::write(&path, config.to_string())
        .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    let output = Command::new(python)
        .arg(script)
        .arg(&path)
        .output()
        .map_err(|e| format!("cannot run {} {}: {e}", python.display(), script.display()))?;
    if !output.status.success() {
        return Err(format!(
            "{} failed ({}):\n{}",
            script.display(),
            output.status,
            String::from_utf8_lossy(&output.stderr).trim()
        ));
    }
    let text = String::from_utf8_lossy(&output.stdout);
    let last = text
        .lines()
        .rev()
        .find(|l| l.trim_start().starts_with('{'))
        .unwrap_or("");
    serde_json::from_str(last)
        .map_err(|e| format!("{} printed no JSON result ({e}): {text}", script.display()))
}
