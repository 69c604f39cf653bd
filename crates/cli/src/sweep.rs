//! `mechfmu sweep`: a parameter sweep of an FMU on Dask distributed.
//!
//! This side checks the request (the FMU and files exist, every spec is well formed) so
//! that a typo fails at once with a message naming it, makes sure the Python environment
//! is there, then hands over to `python -m mechfmu_sweep` (the package in `python/`),
//! which checks the names against the FMU's model description and runs the sweep. The
//! exit status is that of the sweep machinery: cases that fail are rows of the results
//! (status and the FMU's message), not a failure of the command.

use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::Command;

const AFTER_HELP: &str = "\
Specs (--param NAME=SPEC; NAME is a parameter, a start value, or an input schedule's argument NAME.arg):
  5                  a constant         2:10:17            17 points from 2 to 10
  2,3,5              a list             uniform(800,1200)  random, drawn per case
  normal(mu,sigma)   random             loguniform(a,b)    random, uniform in log
Grids and lists are crossed (full factorial); --cases random draws are made at each grid point.

Input schedules (--input-schedule NAME=SHAPE(args), arguments by position or name):
  constant(value)  step(t0,value)  pulse(t0,width,value)  bangbang(t0,width,value)  ramp(t0,t1,value)
  each also has NAME.scale; sweep an argument with --param NAME.arg=SPEC.

Summaries (--summary, besides the final value of every output):
  max(v) min(v) max_abs(v) (or 'max|v|') mean(v) rms(v) final(v)

Example:
  mechfmu sweep fmus/Crane.fmu --param l=2:10:17 \\
      --input-schedule 'x_ddot=bangbang(t0=1,width=2,value=0.5)' --param x_ddot.value=0.25,0.5,1 \\
      --summary 'max_abs(phi)' --out crane.parquet --plot crane.png

Usage notes: python/mechfmu_sweep/README.md";

#[derive(clap::Args, Debug)]
#[command(after_help = AFTER_HELP)]
pub struct Args {
    /// The FMU to sweep, e.g. fmus/Crane.fmu (FMI 2.0 Co-Simulation).
    fmu: PathBuf,
    /// A design variable: NAME=SPEC (repeat for each; see the specs below).
    #[arg(long = "param", value_name = "NAME=SPEC", required = true, value_parser = check_param)]
    params: Vec<String>,
    /// Random draws per grid point (default 100 when a spec is random).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    cases: Option<u64>,
    /// Seed of the random draws (default: a fresh one, reported and stored with the results).
    #[arg(long, value_name = "S")]
    seed: Option<u64>,
    /// Run on an existing Dask cluster, e.g. tcp://127.0.0.1:8786 (default: a local one).
    #[arg(long, value_name = "ADDRESS", conflicts_with = "workers", value_parser = check_address)]
    scheduler: Option<String>,
    /// Worker processes of the local cluster (default: one per core), one thread each.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    workers: Option<u32>,
    /// Cases per Dask task (default: about 8 tasks per worker, at most 16 cases each).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    chunk_size: Option<u32>,
    /// Start time in s (default: the FMU's DefaultExperiment).
    #[arg(long, value_name = "T", value_parser = finite)]
    start_time: Option<f64>,
    /// Stop time in s (default: the FMU's DefaultExperiment).
    #[arg(long, value_name = "T", value_parser = finite)]
    stop_time: Option<f64>,
    /// Communication step in s, the sampling of the summaries (default: as fmpy.simulate_fmu).
    #[arg(long, value_name = "H", value_parser = positive)]
    output_interval: Option<f64>,
    /// Relative tolerance (default: the FMU's DefaultExperiment).
    #[arg(long, value_name = "TOL", value_parser = positive)]
    tolerance: Option<f64>,
    /// Time-varying inputs for every case: an fmpy-style CSV (time, then one column per input).
    #[arg(long, value_name = "FILE.csv")]
    input: Option<PathBuf>,
    /// A per-case input signal NAME=SHAPE(args); its arguments are design variables NAME.arg.
    #[arg(long = "input-schedule", value_name = "NAME=SHAPE(args)", value_parser = check_schedule)]
    input_schedules: Vec<String>,
    /// A summary column besides the final outputs, e.g. 'max_abs(phi)', 'max(T)', 'min(x)'.
    #[arg(long = "summary", value_name = "EXPR", value_parser = check_summary)]
    summaries: Vec<String>,
    /// Where to write the results: .parquet or .csv (default: CSV on standard output).
    #[arg(long, value_name = "FILE", value_parser = check_out)]
    out: Option<PathBuf>,
    /// Plot a swept parameter against a summary into this PNG.
    #[arg(long, value_name = "PNG", value_parser = check_png)]
    plot: Option<PathBuf>,
    /// The design column on the plot's x axis (default: the first swept one).
    #[arg(long, value_name = "NAME", requires = "plot")]
    plot_x: Option<String>,
    /// The summary on the plot's y axis (default: the first --summary).
    #[arg(long, value_name = "COLUMN", requires = "plot")]
    plot_y: Option<String>,
    /// No progress bar or progress lines.
    #[arg(long)]
    no_progress: bool,
}

pub fn run(args: Args) -> Result<(), String> {
    if !args.fmu.is_file() {
        return Err(format!(
            "no FMU at {} (build one with `mechfmu build NAME`, which writes fmus/NAME.fmu)",
            args.fmu.display()
        ));
    }
    if let Some(input) = &args.input {
        if !input.is_file() {
            return Err(format!("--input {}: no such file", input.display()));
        }
    }
    let root = project_root()?;
    let python = super::python::ensure_venv(&root)?;
    let mut cmd = Command::new(&python);
    cmd.arg("-m").arg("mechfmu_sweep").args(python_args(&args));
    cmd.env("PYTHONPATH", python_path(&root));
    let status = cmd
        .status()
        .map_err(|e| format!("cannot run {}: {e}", python.display()))?;
    match status.code() {
        Some(0) => Ok(()),
        Some(2) => Err("the sweep was not started (the message above names the problem)".into()),
        _ => Err(format!("the sweep failed ({status})")),
    }
}

/// The repository holding `python/mechfmu_sweep` and `tests/python/requirements.txt`:
/// `MECHFMU_ROOT` if set, else the source tree this binary was built from.
fn project_root() -> Result<PathBuf, String> {
    let root = std::env::var_os("MECHFMU_ROOT")
        .map(PathBuf::from)
        .unwrap_or_else(crate::workspace::source_tree);
    let package = root.join("python/mechfmu_sweep/__main__.py");
    if package.is_file() {
        Ok(root)
    } else {
        Err(format!(
            "cannot find the sweep's Python package at {} (set MECHFMU_ROOT to the mechfmu repository)",
            package.display()
        ))
    }
}

fn python_path(root: &Path) -> OsString {
    let mut paths = vec![root.join("python")];
    if let Some(existing) = std::env::var_os("PYTHONPATH") {
        paths.extend(std::env::split_paths(&existing));
    }
    std::env::join_paths(paths).unwrap_or_else(|_| root.join("python").into_os_string())
}

/// The arguments of `python -m mechfmu_sweep`, in its own option names.
fn python_args(a: &Args) -> Vec<OsString> {
    let mut v: Vec<OsString> = vec![a.fmu.clone().into()];
    let mut opt = |name: &str, value: OsString| {
        v.push(format!("--{name}").into());
        v.push(value);
    };
    for p in &a.params {
        opt("param", p.into());
    }
    for s in &a.input_schedules {
        opt("input-schedule", s.into());
    }
    for s in &a.summaries {
        opt("summary", s.into());
    }
    let numbers = [
        ("cases", a.cases.map(|x| x.to_string())),
        ("seed", a.seed.map(|x| x.to_string())),
        ("workers", a.workers.map(|x| x.to_string())),
        ("chunk-size", a.chunk_size.map(|x| x.to_string())),
        ("start-time", a.start_time.map(|x| format!("{x:?}"))),
        ("stop-time", a.stop_time.map(|x| format!("{x:?}"))),
        (
            "output-interval",
            a.output_interval.map(|x| format!("{x:?}")),
        ),
        ("tolerance", a.tolerance.map(|x| format!("{x:?}"))),
        ("scheduler", a.scheduler.clone()),
        ("plot-x", a.plot_x.clone()),
        ("plot-y", a.plot_y.clone()),
    ];
    for (name, value) in numbers {
        if let Some(value) = value {
            opt(name, value.into());
        }
    }
    let paths = [("input", &a.input), ("out", &a.out), ("plot", &a.plot)];
    for (name, value) in paths {
        if let Some(value) = value {
            opt(name, value.clone().into());
        }
    }
    if a.no_progress {
        v.push("--no-progress".into());
    }
    v
}

// ---------------------------------------------------------------------------------------
// Checks of the values (the grammar of python/mechfmu_sweep/design.py and runner.py)

const DISTRIBUTIONS: [&str; 3] = ["uniform", "normal", "loguniform"];
const SHAPES: [(&str, &[&str]); 5] = [
    ("constant", &["value"]),
    ("step", &["t0", "value"]),
    ("pulse", &["t0", "width", "value"]),
    ("bangbang", &["t0", "width", "value"]),
    ("ramp", &["t0", "t1", "value"]),
];
const SUMMARIES: [&str; 6] = ["final", "max", "min", "max_abs", "mean", "rms"];

fn number(s: &str) -> Result<f64, String> {
    let t = s.trim();
    match t.parse::<f64>() {
        Ok(x) if x.is_finite() => Ok(x),
        _ => Err(format!("`{t}` is not a number")),
    }
}

fn finite(s: &str) -> Result<f64, String> {
    number(s)
}

fn positive(s: &str) -> Result<f64, String> {
    let x = number(s)?;
    if x > 0.0 {
        Ok(x)
    } else {
        Err(format!("{x} must be > 0"))
    }
}

/// `name(args)` -> (name, args).
fn call(s: &str) -> Option<(&str, &str)> {
    let s = s.trim();
    let open = s.find('(')?;
    let inner = s.strip_suffix(')')?.get(open + 1..)?;
    let name = s[..open].trim();
    let ident = !name.is_empty()
        && name.chars().all(|c| c.is_ascii_alphanumeric() || c == '_')
        && !name.starts_with(|c: char| c.is_ascii_digit());
    ident.then_some((name, inner))
}

fn assignment<'a>(s: &'a str, what: &str) -> Result<(&'a str, &'a str), String> {
    match s.split_once('=') {
        Some((name, rest)) if !name.trim().is_empty() => Ok((name.trim(), rest.trim())),
        _ => Err(format!("expected {what}")),
    }
}

/// A spec: a value, start:stop:count, v1,v2,..., uniform(a,b), normal(mu,sigma), loguniform(a,b).
fn check_spec(spec: &str) -> Result<(), String> {
    if spec.is_empty() {
        return Err(
            "empty spec (want a value, a:b:n, v1,v2,..., uniform(a,b) or normal(mu,sigma))".into(),
        );
    }
    if let Some((kind, args)) = call(spec) {
        if !DISTRIBUTIONS.contains(&kind) {
            return Err(format!(
                "unknown distribution `{kind}` (known: {})",
                DISTRIBUTIONS.join(", ")
            ));
        }
        let args: Vec<&str> = args.split(',').collect();
        if args.len() != 2 {
            return Err(format!("{kind} takes 2 arguments, got {}", args.len()));
        }
        let (a, b) = (number(args[0])?, number(args[1])?);
        return match kind {
            "uniform" if a >= b => Err("uniform(a,b) needs a < b".into()),
            "normal" if b <= 0.0 => Err("normal(mu,sigma) needs sigma > 0".into()),
            "loguniform" if !(0.0 < a && a < b) => Err("loguniform(a,b) needs 0 < a < b".into()),
            _ => Ok(()),
        };
    }
    if spec.contains(':') {
        let parts: Vec<&str> = spec.split(':').collect();
        let grid_error =
            || "a grid is start:stop:count, e.g. 2:10:17 (count an integer >= 1)".to_string();
        if parts.len() != 3 {
            return Err(grid_error());
        }
        let (a, b) = (number(parts[0])?, number(parts[1])?);
        let n: u64 = parts[2].trim().parse().map_err(|_| grid_error())?;
        if n == 0 {
            return Err(grid_error());
        }
        if n == 1 && a != b {
            return Err("a grid of 1 point needs start == stop (or write the value alone)".into());
        }
        return Ok(());
    }
    spec.split(',').try_for_each(|p| number(p).map(|_| ()))
}

fn check_param(s: &str) -> Result<String, String> {
    let (_, spec) = assignment(s, "NAME=SPEC, e.g. l=2:10:17")?;
    check_spec(spec)?;
    Ok(s.to_string())
}

fn check_schedule(s: &str) -> Result<String, String> {
    let (_, shape) = assignment(s, "NAME=SHAPE(args), e.g. x_ddot=step(1,0.5)")?;
    let known = || {
        SHAPES
            .iter()
            .map(|(n, _)| *n)
            .collect::<Vec<_>>()
            .join(", ")
    };
    let (kind, args) =
        call(shape).ok_or_else(|| format!("expected NAME=SHAPE(args), shapes: {}", known()))?;
    let names = SHAPES
        .iter()
        .find(|(n, _)| *n == kind)
        .map(|(_, a)| *a)
        .ok_or_else(|| format!("unknown shape `{kind}` (known: {})", known()))?;
    let parts: Vec<&str> = if args.trim().is_empty() {
        vec![]
    } else {
        args.split(',').collect()
    };
    if parts.len() > names.len() {
        return Err(format!(
            "{kind} takes at most {} arguments ({})",
            names.len(),
            names.join(", ")
        ));
    }
    let mut keyword = false;
    for part in parts {
        let value = match part.split_once('=') {
            Some((key, value)) => {
                if !names.contains(&key.trim()) {
                    return Err(format!(
                        "{kind} has no argument `{}` (it has {})",
                        key.trim(),
                        names.join(", ")
                    ));
                }
                keyword = true;
                value
            }
            None if keyword => return Err("a positional argument after a keyword one".into()),
            None => part,
        };
        number(value)?;
    }
    Ok(s.to_string())
}

fn check_summary(s: &str) -> Result<String, String> {
    let t = s.trim();
    let bars = ["max|", "min|"].iter().any(|p| t.starts_with(p)) && t.ends_with('|') && t.len() > 5;
    if bars {
        return Ok(s.to_string());
    }
    match call(t) {
        Some((f, var)) if !var.trim().is_empty() => {
            if SUMMARIES.contains(&f) || f == "min_abs" {
                Ok(s.to_string())
            } else {
                Err(format!(
                    "unknown function `{f}` (known: {})",
                    SUMMARIES.join(", ")
                ))
            }
        }
        _ => Err(format!(
            "expected FUNC(variable) with FUNC one of {}",
            SUMMARIES.join(", ")
        )),
    }
}

fn extension(p: &Path) -> String {
    p.extension()
        .map(|e| e.to_string_lossy().to_lowercase())
        .unwrap_or_default()
}

fn check_out(s: &str) -> Result<PathBuf, String> {
    let p = PathBuf::from(s);
    match extension(&p).as_str() {
        "parquet" | "csv" => Ok(p),
        _ => Err("the extension says the format: .parquet or .csv".into()),
    }
}

fn check_png(s: &str) -> Result<PathBuf, String> {
    let p = PathBuf::from(s);
    if extension(&p) == "png" {
        Ok(p)
    } else {
        Err("the plot is a PNG: give a .png file".into())
    }
}

fn check_address(s: &str) -> Result<String, String> {
    let t = s.trim();
    let hostport = t.split_once("://").map_or(t, |(_, rest)| rest);
    match hostport.rsplit_once(':') {
        Some((host, port)) if !host.is_empty() && port.parse::<u16>().is_ok() => Ok(t.to_string()),
        _ => Err("a scheduler address is [tcp://]HOST:PORT, e.g. tcp://127.0.0.1:8786".into()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn specs() {
        for ok in [
            "5",
            "-1",
            "2:10:17",
            "2,3,5",
            "-1,2",
            "uniform(800,1200)",
            "normal(0, 0.1)",
            "1e3:2e3:3",
            "3:3:1",
        ] {
            check_spec(ok).unwrap_or_else(|e| panic!("{ok}: {e}"));
        }
        for (bad, why) in [
            ("", "empty"),
            ("2:10", "start:stop:count"),
            ("2:10:0", "start:stop:count"),
            ("2:10:1.5", "start:stop:count"),
            ("2:10:1", "1 point"),
            ("uniform(2,1)", "a < b"),
            ("normal(0,-1)", "sigma > 0"),
            ("gauss(0,1)", "unknown distribution"),
            ("uniform(1)", "2 arguments"),
            ("2,x", "`x` is not a number"),
            ("inf", "not a number"),
        ] {
            let e = check_spec(bad).expect_err(bad);
            assert!(e.contains(why), "{bad}: {e}");
        }
    }

    #[test]
    fn params_schedules_summaries() {
        assert!(check_param("l=2:10:17").is_ok());
        assert!(check_param("x_ddot.value=0.1,1").is_ok());
        assert!(check_param("=3").unwrap_err().contains("NAME=SPEC"));
        assert!(check_param("l").unwrap_err().contains("NAME=SPEC"));
        assert!(check_schedule("x_ddot=bangbang(t0=1,width=2,value=0.5)").is_ok());
        assert!(check_schedule("x_ddot=step(1, 0.5)").is_ok());
        assert!(check_schedule("x_ddot=step()").is_ok());
        assert!(check_schedule("x_ddot=sine(1)")
            .unwrap_err()
            .contains("unknown shape"));
        assert!(check_schedule("x_ddot=step(t0=1,amp=2)")
            .unwrap_err()
            .contains("no argument `amp`"));
        assert!(check_schedule("x_ddot=step(t0=1,2)")
            .unwrap_err()
            .contains("positional"));
        assert!(check_schedule("x_ddot=step(1,2,3)")
            .unwrap_err()
            .contains("at most 2"));
        for ok in ["max_abs(phi)", "max|phi|", "max(T)", "min(x)", "rms(x)"] {
            assert!(check_summary(ok).is_ok(), "{ok}");
        }
        assert!(check_summary("avg(x)")
            .unwrap_err()
            .contains("unknown function"));
        assert!(check_summary("phi").unwrap_err().contains("FUNC(variable)"));
    }

    #[test]
    fn files_and_addresses() {
        assert!(check_out("r.parquet").is_ok() && check_out("r.CSV").is_ok());
        assert!(check_out("r.xlsx")
            .unwrap_err()
            .contains(".parquet or .csv"));
        assert!(check_png("p.txt").is_err());
        assert!(check_address("tcp://127.0.0.1:8786").is_ok());
        assert!(check_address("localhost:8786").is_ok());
        assert!(check_address("localhost").is_err());
    }
}
