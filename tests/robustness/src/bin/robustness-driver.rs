//! Runs one robustness scenario on one FMU; the tests in `tests/` run it as a child
//! process (a crash then fails a test instead of killing the test runner), and
//! `scripts/valgrind` runs it under valgrind.
//!
//! ```text
//! robustness-driver sequences --fmu fmus/Oscillator.fmu [--first SEED] [--count N] [--announce] [--trace]
//! robustness-driver cycles    --fmu fmus/Oscillator.fmu [--count 1000]
//! robustness-driver long-run  --fmu fmus/Oscillator.fmu [--steps 1000000] [--h 1e-3]
//! robustness-driver tour      --fmu fmus/Oscillator.fmu      (prints nothing unless it fails)
//! robustness-driver dump-state --fmu fmus/Oscillator.fmu --out FILE [--steps 10] [--me event|continuous]
//! ```
//! Exit status: 0 success, 1 a check failed (the failure on stderr), 2 bad usage.

use mechfmu_robustness::fmu::Fmu;
use mechfmu_robustness::{scenarios, sequences};
use std::path::PathBuf;
use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let Some(command) = args.first().cloned() else {
        eprintln!("usage: robustness-driver sequences|cycles|long-run|tour --fmu PATH [options]");
        return ExitCode::from(2);
    };
    let value = |flag: &str| -> Option<String> {
        args.iter()
            .position(|a| a == flag)
            .and_then(|i| args.get(i + 1))
            .cloned()
    };
    let flag = |name: &str| args.iter().any(|a| a == name);
    let number = |name: &str, default: u64| -> u64 {
        value(name).map_or(default, |v| {
            v.parse()
                .unwrap_or_else(|_| panic!("{name} {v}: not a number"))
        })
    };
    let Some(path) = value("--fmu").map(PathBuf::from) else {
        eprintln!("robustness-driver: --fmu PATH is required");
        return ExitCode::from(2);
    };
    let fmu = match Fmu::load(&path) {
        Ok(f) => f,
        Err(e) => {
            eprintln!("robustness-driver: {e}");
            return ExitCode::from(1);
        }
    };
    match command.as_str() {
        "sequences" => {
            let first = number("--first", 0);
            let count = number("--count", 1000);
            let (stats, failures) =
                sequences::run_many(&fmu, first, count, flag("--announce"), flag("--trace"));
            println!("summary {}: {stats}", fmu.name());
            for f in failures.iter().take(20) {
                println!("FAIL {f}");
            }
            if failures.is_empty() {
                ExitCode::SUCCESS
            } else {
                println!("{} of {} sequences failed", failures.len(), stats.sequences);
                ExitCode::from(1)
            }
        }
        "cycles" => {
            let count = number("--count", 1000) as usize;
            match scenarios::cycles(&fmu, count) {
                Ok(calls) => {
                    let me = if fmu.md.model_exchange.is_some() {
                        count.div_ceil(scenarios::ME_EVERY)
                    } else {
                        0
                    };
                    println!(
                        "{}: {count} instantiate/initialize/step/free cycles ({me} with a Model Exchange run), {calls} FMI calls",
                        fmu.name()
                    );
                    ExitCode::SUCCESS
                }
                Err(e) => {
                    eprintln!("{}: {e}", fmu.name());
                    ExitCode::from(1)
                }
            }
        }
        "long-run" => {
            let steps = number("--steps", 1_000_000);
            let h = value("--h").map_or(1e-3, |v| v.parse().expect("--h: a number"));
            match scenarios::long_run(&fmu, steps, h) {
                Ok(r) => {
                    println!("{}: {r}", fmu.name());
                    println!(
                        "rss-samples-kib {}",
                        r.rss_samples
                            .iter()
                            .map(|x| (x / 1024).to_string())
                            .collect::<Vec<_>>()
                            .join(" ")
                    );
                    println!(
                        "result {} {:e} {:e} {} {} {}",
                        r.steps,
                        r.last_successful_time,
                        r.expected_time,
                        r.rss_before,
                        r.rss_after,
                        r.seconds
                    );
                    ExitCode::SUCCESS
                }
                Err(e) => {
                    eprintln!("{}: {e}", fmu.name());
                    ExitCode::from(1)
                }
            }
        }
        "dump-state" => {
            // A serialized FMU state after `--steps` default steps: seeds for fuzz/corpus.
            // `--me event` / `--me continuous`: of a Model Exchange instance in that mode.
            let out = value("--out").expect("--out FILE");
            let how = match value("--me").as_deref() {
                None => scenarios::Dump::CoSimulation,
                Some("event") => scenarios::Dump::EventMode,
                Some("continuous") => scenarios::Dump::ContinuousTimeMode,
                Some(other) => {
                    eprintln!("robustness-driver: --me {other}: event or continuous");
                    return ExitCode::from(2);
                }
            };
            match scenarios::serialized_state(&fmu, number("--steps", 10) as usize, how) {
                Ok(bytes) => {
                    std::fs::write(&out, bytes).expect("write --out");
                    ExitCode::SUCCESS
                }
                Err(e) => {
                    eprintln!("{}: {e}", fmu.name());
                    ExitCode::from(1)
                }
            }
        }
        "tour" => match scenarios::tour(&fmu) {
            Ok(_) => ExitCode::SUCCESS,
            Err(e) => {
                // The test checks stderr is empty: a failure is the exit status, and its
                // text goes to a file the test reads.
                if let Some(p) = value("--report") {
                    let _ = std::fs::write(p, e);
                }
                ExitCode::from(1)
            }
        },
        other => {
            eprintln!("robustness-driver: unknown command {other}");
            ExitCode::from(2)
        }
    }
}
