//! `mechfmu bench`: per mechanism, ns per `fmi2DoStep` from a native loop and where they go,
//! ns per `fmi2GetReal`, µs per step under FMPy, the Oscillator's work–precision against
//! scipy; a table on stdout and JSON for comparing runs. See [`crate::bench`].

use crate::bench::instructions::{self, Probe};
use crate::bench::native::Effort;
use crate::bench::precision::{self, Problem};
use crate::bench::report::{Build, Report};
use crate::bench::{self as b, fmu};
use crate::build::select;
use crate::workspace::{cargo, mechanism_crates};
use serde_json::json;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::Instant;

#[derive(clap::Args)]
pub struct Args {
    /// Model identifiers (default: every mechanism).
    names: Vec<String>,
    /// Where to write the results as JSON (relative to the workspace root); the same figures
    /// go to a Markdown file beside it (`.md`).
    #[arg(long, default_value = "target/bench.json")]
    json: PathBuf,
    /// Folder for the .fmu files built with the runtime's `bench` feature (relative to the
    /// workspace root).
    #[arg(long, default_value = "target/bench/fmus")]
    fmus: PathBuf,
    /// Measure the .fmu files of --fmus as they are, without building them first.
    #[arg(long)]
    no_build: bool,
    /// Timed runs per figure (medians are reported).
    #[arg(long, default_value_t = 15)]
    runs: usize,
    /// A smoke test: few runs and short loops.
    #[arg(long)]
    quick: bool,
    /// Skip the FMPy and scipy figures.
    #[arg(long)]
    no_python: bool,
    /// Only the Model Exchange figures: ns per derivative evaluation through the API
    /// (fmi2SetTime + fmi2SetContinuousStates + fmi2GetDerivatives) next to the equations
    /// alone (with --instructions, their instruction counts).
    #[arg(long)]
    me_only: bool,
    /// Also count instructions with valgrind (repeatable on a busy machine; slower).
    #[arg(long)]
    instructions: bool,
    /// Also time a clean release build of every FMU for every platform (`cargo run
    /// --release -- build --platform all` in a fresh target directory; takes minutes).
    #[arg(long)]
    build_time: bool,
    /// The Cargo.toml of the workspace holding the mechanisms.
    #[arg(long)]
    manifest_path: Option<PathBuf>,

    // The instruction-count probe, run by the benchmark under valgrind.
    #[arg(long, hide = true, value_enum)]
    probe: Option<Probe>,
    #[arg(long, hide = true)]
    probe_so: Option<PathBuf>,
    #[arg(long, hide = true)]
    probe_xml: Option<PathBuf>,
    #[arg(long, hide = true, default_value_t = 1e-2)]
    probe_h: f64,
    #[arg(long, hide = true, default_value_t = 1e-6)]
    probe_tol: f64,
    #[arg(long, hide = true, default_value_t = 1)]
    probe_repeat: usize,
    #[arg(long, hide = true, default_value_t = 100_000)]
    probe_max_steps: usize,
}

fn progress(message: &str) {
    if std::io::stderr().is_terminal() {
        eprint!("\r\x1b[2K{message} ...");
    } else {
        eprintln!("{message} ...");
    }
}

fn clear_progress() {
    if std::io::stderr().is_terminal() {
        eprint!("\r\x1b[2K");
    }
}

/// The workspace root (the folder of the workspace's Cargo.toml).
fn workspace_root(manifest_path: Option<&Path>) -> Result<PathBuf, String> {
    let mut cmd = Command::new(cargo());
    cmd.args(["locate-project", "--workspace", "--message-format", "plain"]);
    if let Some(p) = manifest_path {
        cmd.arg("--manifest-path").arg(p);
    }
    let out = cmd
        .output()
        .map_err(|e| format!("cannot run cargo locate-project: {e}"))?;
    if !out.status.success() {
        return Err(format!(
            "cargo locate-project failed: {}",
            String::from_utf8_lossy(&out.stderr).trim()
        ));
    }
    let manifest = PathBuf::from(String::from_utf8_lossy(&out.stdout).trim());
    manifest
        .parent()
        .map(Path::to_path_buf)
        .ok_or_else(|| format!("{} has no folder", manifest.display()))
}

pub fn run(args: Args) -> Result<(), String> {
    if let Some(probe) = args.probe {
        let (Some(so), Some(xml)) = (&args.probe_so, &args.probe_xml) else {
            return Err("--probe needs --probe-so and --probe-xml".into());
        };
        return instructions::probe(
            so,
            xml,
            probe,
            args.probe_h,
            args.probe_tol,
            args.probe_repeat,
            args.probe_max_steps,
        );
    }
    let root = workspace_root(args.manifest_path.as_deref())?;
    let fmus_dir = root.join(&args.fmus);
    let crates = select(
        mechanism_crates(args.manifest_path.as_deref())?,
        &args.names,
    )?;
    let names: Vec<String> = crates.iter().map(|c| c.model.clone()).collect();
    if !args.no_build {
        let target_dir = root.join("target/bench/build");
        crate::build::build(
            &names,
            &fmus_dir,
            args.manifest_path.as_deref(),
            crate::build::Flavor::Bench {
                target_dir: &target_dir,
            },
            crate::build::Platforms::Host,
        )?;
    }
    let effort = if args.quick {
        Effort {
            runs: 3,
            max_steps: 2_000,
            calls: 2_000,
        }
    } else {
        Effort {
            runs: args.runs.max(1),
            max_steps: 100_000,
            calls: 20_000,
        }
    };
    let mut report = Report {
        runs: effort.runs,
        ..Report::default()
    };
    let work_dir = root.join("target/bench");

    // Native figures.
    let mut loaded = Vec::new();
    for name in &names {
        let fmu_path = fmus_dir.join(format!("{name}.fmu"));
        if !fmu_path.exists() {
            return Err(format!(
                "{} does not exist: drop --no-build to build it with the runtime's `bench` feature",
                fmu_path.display()
            ));
        }
        let (so, xml) = fmu::extract(&fmu_path, &work_dir.join(name))?;
        let binary = fmu::Binary::load(&so, &xml)?;
        if !binary.has_counters() {
            report.notes.push(format!(
                "{name}: the binary exports no mechfmu_counters/mechfmu_bench (built without the runtime's `bench` feature: drop --no-build): no split"
            ));
        }
        let figures = if args.me_only {
            b::measure_model_exchange(name, fmu_path, &binary, effort, &progress)?
        } else {
            b::measure(name, fmu_path, &binary, effort, &progress)?
        };
        if binary.fmi3.is_none() {
            report.notes.push(format!(
                "{name}: the binary exports no FMI 3.0 functions: no fmi3DoStep figures"
            ));
        }
        if figures.model_exchange.is_none() {
            report.notes.push(format!(
                "{name}: no Model Exchange figures (the FMU declares no ModelExchange or its binary lacks the functions)"
            ));
        }
        report.mechanisms.push(figures);
        loaded.push((so, xml, binary));
    }
    if !args.me_only {
        progress("catch_unwind");
        report.catch_unwind = Some(b::catch_unwind_cost(effort.runs));
    }

    if args.instructions {
        if instructions::available() {
            let exe =
                std::env::current_exe().map_err(|e| format!("cannot find this program: {e}"))?;
            for (m, (so, xml, binary)) in report.mechanisms.iter_mut().zip(&loaded) {
                if !args.me_only {
                    progress(&format!("{}: instructions under valgrind", m.name));
                    let n = b::native::steps_per_run(binary, 1e-2, effort);
                    let evals = m
                        .step(1e-2, 1e-6)
                        .map_or(0, |s| (s.evals * n as f64).round() as u64);
                    m.instructions = Some(instructions::count(
                        &exe,
                        so,
                        xml,
                        1e-2,
                        1e-6,
                        effort,
                        (n, evals),
                        binary.fmi3.is_some(),
                    )?);
                }
                if m.model_exchange.is_some() {
                    progress(&format!(
                        "{}: Model Exchange instructions under valgrind",
                        m.name
                    ));
                    m.me_instructions =
                        Some(instructions::count_model_exchange(&exe, so, xml, effort)?);
                }
            }
        } else {
            report
                .notes
                .push("--instructions: valgrind is not installed".into());
        }
    }

    if args.me_only {
        clear_progress();
        return finish(&report, &root, &args.json);
    }

    // Work–precision of the Oscillator, natively.
    let oscillator = loaded
        .iter()
        .find(|(_, _, bin)| bin.description.model_identifier == "Oscillator");
    let problem = match oscillator {
        Some((_, _, bin)) => match Problem::of(&bin.description) {
            Ok(p) => Some(p),
            Err(e) => {
                report.notes.push(format!("work–precision skipped: {e}"));
                None
            }
        },
        None => {
            report
                .notes
                .push("work–precision: needs the Oscillator among the mechanisms".into());
            None
        }
    };
    if let (Some(problem), Some((_, _, bin))) = (&problem, oscillator) {
        progress("Oscillator: work–precision, native loop");
        report.precision = precision::native(bin, problem, effort.runs)?;
    }

    // FMPy and scipy.
    if args.no_python {
        report
            .notes
            .push("FMPy and scipy skipped (--no-python)".into());
    } else {
        clear_progress();
        let python = crate::python::ensure_venv(&root)?;
        progress("FMPy low-level loops, simulate_fmu, scipy work–precision (Python)");
        let loops: Vec<serde_json::Value> = report
            .mechanisms
            .iter()
            .zip(&loaded)
            .map(|(m, (_, _, bin))| {
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
                    "steps": b::native::steps_per_run(bin, d.step, effort),
                    "inputs": inputs,
                    "outputs": outputs,
                })
            })
            .collect();
        let precision_cfg = match (&problem, oscillator) {
            (Some(p), Some(_)) => {
                let (grid, exact) = p.grid();
                let fmu = report
                    .mechanisms
                    .iter()
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
            _ => serde_json::Value::Null,
        };
        let config = json!({
            "runs": effort.runs.clamp(3, 9),
            "loops": loops,
            "simulate": loops,
            "precision": precision_cfg,
        });
        let result = b::python::run(
            &python,
            &root.join("scripts/bench_fmpy.py"),
            &config,
            &work_dir,
        )?;
        let stat = |v: &serde_json::Value| -> Option<b::clock::Stat> {
            Some(b::clock::Stat {
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

    if args.build_time {
        clear_progress();
        report.build = Some(clean_build(&root, &names)?);
    }
    clear_progress();

    finish(&report, &root, &args.json)
}

/// Prints the table and writes the JSON and Markdown files.
fn finish(report: &Report, root: &Path, json: &Path) -> Result<(), String> {
    print!("{}", report.table());
    let json_path = root.join(json);
    if let Some(dir) = json_path.parent() {
        std::fs::create_dir_all(dir)
            .map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    }
    let text = serde_json::to_string_pretty(&report.to_json()).map_err(|e| e.to_string())?;
    std::fs::write(&json_path, text + "\n")
        .map_err(|e| format!("cannot write {}: {e}", json_path.display()))?;
    let md_path = json_path.with_extension("md");
    std::fs::write(&md_path, report.markdown())
        .map_err(|e| format!("cannot write {}: {e}", md_path.display()))?;
    println!("\nwrote {} and {}", json_path.display(), md_path.display());
    Ok(())
}

/// `cargo run --release -- build` in a fresh target directory (a clean build, without
/// touching the workspace's `target/`), timed by the wall clock.
fn clean_build(root: &Path, names: &[String]) -> Result<Build, String> {
    let target = std::env::temp_dir().join(format!("mechfmu-bench-build-{}", std::process::id()));
    let out = target.join("fmus");
    let _ = std::fs::remove_dir_all(&target);
    eprintln!(
        "timing a clean release build in {} (cargo run --release -- build --platform all) ...",
        target.display()
    );
    let started = Instant::now();
    let output = Command::new(cargo())
        .current_dir(root)
        .env("CARGO_TARGET_DIR", &target)
        .args([
            "run",
            "--release",
            "--",
            "build",
            "--platform",
            "all",
            "--out",
        ])
        .arg(&out)
        .output()
        .map_err(|e| format!("cannot run cargo: {e}"))?;
    let seconds = started.elapsed().as_secs_f64();
    if !output.status.success() {
        let _ = std::fs::remove_dir_all(&target);
        return Err(format!(
            "the clean build failed:\n{}",
            String::from_utf8_lossy(&output.stderr)
        ));
    }
    let fmus = std::fs::read_dir(&out)
        .map_err(|e| format!("cannot read {}: {e}", out.display()))?
        .flatten()
        .filter_map(|e| {
            let name = e
                .file_name()
                .to_string_lossy()
                .strip_suffix(".fmu")?
                .to_string();
            Some((name, e.metadata().ok()?.len()))
        })
        .collect::<Vec<_>>();
    let _ = std::fs::remove_dir_all(&target);
    let mut fmus = fmus;
    fmus.sort();
    let built: Vec<&str> = fmus.iter().map(|(n, _)| n.as_str()).collect();
    let missing: Vec<&String> = names
        .iter()
        .filter(|n| !built.contains(&n.as_str()))
        .collect();
    if !missing.is_empty() {
        return Err(format!("the clean build made no .fmu for {missing:?}"));
    }
    Ok(Build {
        command: "cargo run --release -- build --platform all (fresh CARGO_TARGET_DIR)".into(),
        seconds,
        fmus,
    })
}
