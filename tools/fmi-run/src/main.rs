//! `mechfmu-fmi-run EXPERIMENT.json [--out FILE]`: runs one experiment on an FMU through the
//! `fmi` crate and writes the result as CSV (to stdout, or FILE). See the library's
//! documentation ([`mechfmu_fmi_run`]) for why this importer exists and how it drives the FMU.
//!
//! Exit status: 0 on success; 1 when the run fails (import, unknown variable, an FMI call
//! not returning `fmi2OK`), with one message on stderr naming the call and the variables;
//! 2 for a usage error. The FMU's log messages go to stderr, prefixed with `[FMU ...]`.

use mechfmu_fmi_run::{run, Experiment};
use std::io::Write;
use std::path::PathBuf;
use std::process::ExitCode;

const USAGE: &str = "usage: mechfmu-fmi-run EXPERIMENT.json [--out FILE]";

/// Writes the FMU's messages (the `fmi` crate forwards its logger callback to `log`) and the
/// crate's own warnings and errors to stderr.
struct StderrLog;

impl log::Log for StderrLog {
    fn enabled(&self, _: &log::Metadata) -> bool {
        true
    }

    fn log(&self, record: &log::Record) {
        // fmi-sys gives the FMU's messages the module path "logger", the instance as target
        if record.module_path() == Some("logger") {
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
    let (Some(experiment), out) = (args.next(), parse_out(&mut args)) else {
        eprintln!("{USAGE}");
        return ExitCode::from(2);
    };
    let Ok(out) = out else {
        eprintln!("{USAGE}");
        return ExitCode::from(2);
    };
    match std::panic::catch_unwind(|| run_file(&PathBuf::from(experiment), out.as_ref())) {
        Ok(Ok(())) => ExitCode::SUCCESS,
        Ok(Err(e)) => {
            eprintln!("mechfmu-fmi-run: {e}");
            ExitCode::from(1)
        }
        Err(_) => ExitCode::from(1), // the hook has said what
    }
}

/// `[--out FILE]`, and nothing else.
fn parse_out(args: &mut impl Iterator<Item = std::ffi::OsString>) -> Result<Option<PathBuf>, ()> {
    match (args.next(), args.next(), args.next()) {
        (None, _, _) => Ok(None),
        (Some(flag), Some(file), None) if flag == "--out" => Ok(Some(PathBuf::from(file))),
        _ => Err(()),
    }
}

fn run_file(experiment: &PathBuf, out: Option<&PathBuf>) -> Result<(), String> {
    let text = std::fs::read_to_string(experiment)
        .map_err(|e| format!("cannot read {}: {e}", experiment.display()))?;
    let exp = Experiment::from_json(&text).map_err(|e| format!("{}: {e}", experiment.display()))?;
    let table = run(&exp)?;
    let mut bytes = Vec::new();
    table
        .write_csv(&mut bytes)
        .map_err(|e| format!("cannot format the result: {e}"))?;
    match out {
        Some(path) => std::fs::write(path, &bytes)
            .map_err(|e| format!("cannot write {}: {e}", path.display())),
        None => std::io::stdout()
            .lock()
            .write_all(&bytes)
            .map_err(|e| format!("cannot write the result to stdout: {e}")),
    }
}
