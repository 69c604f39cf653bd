//! Runs one robustness scenario on one FMU; the tests in `tests/` run it as a child
//! process (a crash then fails a test instead of killing the test runner), and
//! `scripts/valgrind` runs it under valgrind.
//!
//! ```text
//! robustness-driver sequences --fmu fmus/Oscillator.fmu [--first SEED] [--count N] [--announce] [--trace]
//! robustness-driver cycles    --fmu fmus/Oscillator.fmu [--count 1000]
//! robustness-driver long-run  --fmu fmus/Oscillator.fmu [--steps 1000000] [--h 1e-3]   (FMI 2.0)
//! robustness-driver tour      --fmu fmus/Oscillator.fmu      (prints nothing unless it fails)
//! robustness-driver dump-state --fmu fmus/Oscillator.fmu --out FILE [--steps 10] [--me event|continuous] [--cs-event]
//! ```
//! Each command runs on an FMU of either version (`fmus/fmi3/<Name>.fmu`: FMI 3.0), by the
//! `fmiVersion` of its modelDescription.xml; `--cs-event` (FMI 3.0) dumps the state of a
//! Co-Simulation instance in event mode.
//! Exit status: 0 success, 1 a check failed (the failure on stderr), 2 bad usage.

use mechfmu_robustness::fmu::{fmi_version, Fmu, Fmu3};
use mechfmu_robustness::sequences::{Fmi2, Fmi3};
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
    let loaded = match fmi_version(&path) {
        Ok(v) if v == "3.0" => Fmu3::load(&path).map(|f| Loaded::Fmi3(Box::new(f))),
        Ok(_) => Fmu::load(&path).map(|f| Loaded::Fmi2(Box::new(f))),
        Err(e) => Err(e),
    };
    let fmu = match loaded {
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
            let (announce, trace) = (flag("--announce"), flag("--trace"));
            let (stats, failures) = match &fmu {
                Loaded::Fmi2(fmu) => {
                    sequences::run_many::<Fmi2>(fmu, first, count, announce, trace)
                }
                Loaded::Fmi3(fmu) => {
                    sequences::run_many::<Fmi3>(fmu, first, count, announce, trace)
                }
            };
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
            let (cycles, me) = match &fmu {
                Loaded::Fmi2(fmu) => (
                    scenarios::cycles(fmu, count),
                    fmu.md.model_exchange.is_some(),
                ),
                Loaded::Fmi3(fmu) => (
                    scenarios::cycles3(fmu, count),
                    fmu.md.model_exchange.is_some(),
                ),
            };
            match cycles {
                Ok(calls) => {
                    let me = if me {
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
            let Loaded::Fmi2(fmu) = &fmu else {
                eprintln!("robustness-driver: long-run drives FMI 2.0 FMUs");
                return ExitCode::from(2);
            };
            match scenarios::long_run(fmu, steps, h) {
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
                None if flag("--cs-event") => scenarios::Dump::CoSimulationEventMode,
                None => scenarios::Dump::CoSimulation,
                Some("event") => scenarios::Dump::EventMode,
                Some("continuous") => scenarios::Dump::ContinuousTimeMode,
                Some(other) => {
                    eprintln!("robustness-driver: --me {other}: event or continuous");
                    return ExitCode::from(2);
                }
            };
            let steps = number("--steps", 10) as usize;
            let dumped = match &fmu {
                Loaded::Fmi2(fmu) => scenarios::serialized_state(fmu, steps, how),
                Loaded::Fmi3(fmu) => scenarios::serialized_state3(fmu, steps, how),
            };
            match dumped {
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
        "tour" => match match &fmu {
            Loaded::Fmi2(fmu) => scenarios::tour(fmu),
            Loaded::Fmi3(fmu) => scenarios::tour3(fmu),
        } {
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

/// The FMU of either version.
enum Loaded {
    Fmi2(Box<Fmu>),
    Fmi3(Box<Fmu3>),
}

impl Loaded {
    fn name(&self) -> &str {
        match self {
            Loaded::Fmi2(f) => f.name(),
            Loaded::Fmi3(f) => f.name(),
        }
    }
}
