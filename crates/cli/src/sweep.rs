//! `mechfmu sweep`: a parameter sweep of an FMU on Dask distributed.
//!
//! This side checks that the FMU and the files exist, makes sure the Python environment is
//! there, then passes the arguments through to `python -m mechfmu_sweep` (the package in
//! `python/`, installed in the venv), which owns the grammar of the specs, schedules and
//! summaries (`python/mechfmu_sweep/design.py`, `runner.py`): it checks every value and the
//! names against the FMU's model description, and runs the sweep. A request it refuses ends
//! with its message naming the problem (exit status 2) and a non-zero exit of this command.
//! Otherwise the exit status is that of the sweep machinery: cases that fail are rows of the
//! results (status and the FMU's message), not a failure of the command.

use std::ffi::OsString;
use std::path::PathBuf;
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
    #[arg(long = "param", value_name = "NAME=SPEC", required = true)]
    params: Vec<String>,
    /// Random draws per grid point (default 100 when a spec is random).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    cases: Option<u64>,
    /// Seed of the random draws (default: a fresh one, reported and stored with the results).
    #[arg(long, value_name = "S")]
    seed: Option<u64>,
    /// Run on an existing Dask cluster, e.g. tcp://127.0.0.1:8786 (default: a local one).
    #[arg(long, value_name = "ADDRESS", conflicts_with = "workers")]
    scheduler: Option<String>,
    /// Worker processes of the local cluster (default: one per core), one thread each.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    workers: Option<u32>,
    /// Cases per Dask task (default: about 8 tasks per worker, at most 512 cases each with
    /// the native engine, 16 with fmpy).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
    chunk_size: Option<u32>,
    /// Start time in s (default: the FMU's DefaultExperiment).
    #[arg(long, value_name = "T")]
    start_time: Option<f64>,
    /// Stop time in s (default: the FMU's DefaultExperiment).
    #[arg(long, value_name = "T")]
    stop_time: Option<f64>,
    /// Communication step in s, the sampling of the summaries (default: as fmpy.simulate_fmu).
    #[arg(long, value_name = "H")]
    output_interval: Option<f64>,
    /// Relative tolerance (default: the FMU's DefaultExperiment).
    #[arg(long, value_name = "TOL")]
    tolerance: Option<f64>,
    /// Time-varying inputs for every case: an fmpy-style CSV (time, then one column per input).
    #[arg(long, value_name = "FILE.csv")]
    input: Option<PathBuf>,
    /// A per-case input signal NAME=SHAPE(args); its arguments are design variables NAME.arg.
    #[arg(long = "input-schedule", value_name = "NAME=SHAPE(args)")]
    input_schedules: Vec<String>,
    /// A summary column besides the final outputs, e.g. 'max_abs(phi)', 'max(T)', 'min(x)'.
    #[arg(long = "summary", value_name = "EXPR")]
    summaries: Vec<String>,
    /// Where to write the results: .parquet or .csv (default: CSV on standard output).
    #[arg(long, value_name = "FILE")]
    out: Option<PathBuf>,
    /// Plot a swept parameter against a summary into this PNG.
    #[arg(long, value_name = "PNG")]
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
    /// What runs the cases: `native` (this command's compiled case runner, no Python per
    /// step; the default where it can run) or `fmpy` (FMPy, the default with --scheduler).
    /// Both give the same numbers.
    #[arg(long, value_name = "ENGINE", value_parser = ["native", "fmpy"])]
    engine: Option<String>,
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
    // the native engine's workers run `<this executable> sweep-worker`
    if let Ok(exe) = std::env::current_exe() {
        cmd.env(EXE_ENV, exe);
    }
    let status = cmd
        .status()
        .map_err(|e| format!("cannot run {}: {e}", python.display()))?;
    match status.code() {
        Some(0) => Ok(()),
        // a request python -m mechfmu_sweep refused: its message (above) names the problem
        Some(2) => Err("the sweep was not started (the message above names the problem)".into()),
        _ => Err(format!("the sweep failed ({status})")),
    }
}

/// The environment variable naming this executable to the Python side (`native.py`).
const EXE_ENV: &str = "MECHFMU_EXE";

/// mechfmu's files holding `python/mechfmu_sweep` and `tests/python/requirements.txt` (whose
/// venv gets the package installed): the checkout, the installed command's copy, or
/// `MECHFMU_ROOT` if set.
fn project_root() -> Result<PathBuf, String> {
    let root = crate::home::root()?;
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

/// The arguments of `python -m mechfmu_sweep`, in its own option names, as `--name=value`
/// (a value that starts with `-`, such as `-1e-6`, must not read as an option).
fn python_args(a: &Args) -> Vec<OsString> {
    let mut v: Vec<OsString> = vec![a.fmu.clone().into()];
    let mut opt = |name: &str, value: OsString| {
        let mut arg = OsString::from(format!("--{name}="));
        arg.push(value);
        v.push(arg);
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
        ("engine", a.engine.clone()),
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
