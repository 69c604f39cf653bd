//! `mechfmu-fmi-run EXPERIMENT.json [--out FILE] [--interface cs|me] [--substeps N]`: runs one
//! experiment on an FMU through the `fmi` crate and writes the result as CSV (to stdout, or
//! FILE). `--interface cs` (the default) runs it in Co-Simulation, `--interface me` in Model
//! Exchange with the crate's own fixed-step RK4, `--substeps` RK4 steps per communication step
//! (default 1; Model Exchange only). The CSV is the same under both. See the library's
//! documentation ([`mechfmu_fmi_run`]) for why this importer exists and how it drives the FMU.
//!
//! Exit status: 0 on success; 1 when the run fails (import, unknown variable, an FMI call
//! not returning `fmi2OK`, the FMU asking to terminate the simulation), with one message on
//! stderr naming the call, the variables and the time; 2 for a usage error. The FMU's log
//! messages go to stderr, prefixed with `[FMU ...]`.

use mechfmu_fmi_run::{run, run_me, Experiment, Interface, MeOptions};
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

const USAGE: &str =
    "usage: mechfmu-fmi-run EXPERIMENT.json [--out FILE] [--interface cs|me] [--substeps N]";

/// Writes the FMU's messages (the `fmi` crate forwards its logger callback to `log`) and the
/// crate's own warnings and errors to stderr.
struct StderrLog;

impl log::Log for StderrLog {
    fn enabled(&self, _: &log::Metadata) -> bool {
        true
    }

    fn log(&self, record: &log::Record) {
        // the fmi crate gives the FMU's messages the module path "logger" (FMI 2.0: the
        // instance as target) or "fmu" (FMI 3.0: the category as target)
        if matches!(record.module_path(), Some("logger" | "fmu")) {
            eprintln!(
                "[FMU {}] {}: {}",
                record.level(),
                record.target(),
                record.args()
            );
        } else if record.level() <= log::Level::Warn {
            eprintln!("[fmi crate {}] {}", record.level(), record.args());
        }
    }

    fn flush(&self) {}
}

static LOG: StderrLog = StderrLog;

fn main() -> ExitCode {
    // a panic inside a dependency is still a one-line error, not a backtrace
    std::panic::set_hook(Box::new(|info| {
        eprintln!("mechfmu-fmi-run: internal error: {info}");
    }));
    if log::set_logger(&LOG).is_ok() {
        log::set_max_level(log::LevelFilter::Trace);
    }
    let mut args = std::env::args_os().skip(1);
    let (Some(experiment), Ok(options)) = (args.next(), parse_options(&mut args)) else {
        eprintln!("{USAGE}");
        return ExitCode::from(2);
    };
    match std::panic::catch_unwind(|| run_file(&PathBuf::from(experiment), &options)) {
        Ok(Ok(())) => ExitCode::SUCCESS,
        Ok(Err(e)) => {
            eprintln!("mechfmu-fmi-run: {e}");
            ExitCode::from(1)
        }
        Err(_) => ExitCode::from(1), // the hook has said what
    }
}

/// The options after the experiment file.
#[derive(Debug, Default)]
struct Options {
    out: Option<PathBuf>,
    interface: Interface,
    /// `--substeps`, given only with `--interface me`
    substeps: Option<usize>,
}

/// `[--out FILE] [--interface cs|me] [--substeps N]` in any order, each at most once, and
/// nothing else; `--substeps` (at least 1) with `--interface me` only.
fn parse_options(args: &mut impl Iterator<Item = std::ffi::OsString>) -> Result<Options, ()> {
    let mut options = Options::default();
    let mut interface = None;
    while let Some(flag) = args.next() {
        let value = args.next().ok_or(())?;
        if flag == "--out" && options.out.is_none() {
            options.out = Some(PathBuf::from(value));
        } else if flag == "--interface" && interface.is_none() {
            interface = Some(
                value
                    .to_str()
                    .ok_or(())?
                    .parse::<Interface>()
                    .map_err(|_| ())?,
            );
        } else if flag == "--substeps" && options.substeps.is_none() {
            let n: usize = value.to_str().ok_or(())?.parse().map_err(|_| ())?;
            options.substeps = Some(n).filter(|&n| n >= 1);
            options.substeps.ok_or(())?;
        } else {
            return Err(());
        }
    }
    options.interface = interface.unwrap_or_default();
    if options.substeps.is_some() && options.interface != Interface::ModelExchange {
        return Err(());
    }
    Ok(options)
}

fn run_file(experiment: &PathBuf, options: &Options) -> Result<(), String> {
    let text = std::fs::read_to_string(experiment)
        .map_err(|e| format!("cannot read {}: {e}", experiment.display()))?;
    let exp = Experiment::from_json(&text).map_err(|e| format!("{}: {e}", experiment.display()))?;
    let table = match options.interface {
        Interface::CoSimulation => run(&exp)?,
        Interface::ModelExchange => {
            let me = MeOptions {
                substeps: options.substeps.unwrap_or(MeOptions::default().substeps),
            };
            run_me(&exp, &me)?.0
        }
    };
    let mut bytes = Vec::new();
    table
        .write_csv(&mut bytes)
        .map_err(|e| format!("cannot format the result: {e}"))?;
    match &options.out {
        Some(path) => std::fs::write(path, &bytes)
            .map_err(|e| format!("cannot write {}: {e}", path.display())),
        None => std::io::stdout()
            .lock()
            .write_all(&bytes)
            .map_err(|e| format!("cannot write the result to stdout: {e}")),
    }
}
