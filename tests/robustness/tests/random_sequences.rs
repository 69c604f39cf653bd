//! Random FMI call sequences with hostile arguments, on every built FMU of each FMI version
//! (`fmus/*.fmu`, `fmus/fmi3/*.fmu`), each FMU in a child process (a crash fails this test
//! with its seed, and so does a hang: a child that has not ended after
//! `MECHFMU_ROBUSTNESS_TIMEOUT` seconds, default 600, is killed).
//!
//! CI runs 20,000 sequences of each version (split over the FMUs). A longer run:
//!
//! ```text
//! MECHFMU_SEQUENCES=1000000 cargo test --release -p mechfmu-robustness --test random_sequences -- --nocapture
//! ```
//! `MECHFMU_SEED` moves the seeds (default 0); one sequence is replayed with its call trace by
//! `cargo run --release -p mechfmu-robustness --bin robustness-driver -- sequences --fmu fmus/<Name>.fmu --first <seed> --count 1 --trace`
//! (`fmus/fmi3/<Name>.fmu` for FMI 3.0).

mod common;
use common::*;
use mechfmu_robustness::fmu::{required_fmu3_paths, required_fmu_paths};
use std::path::PathBuf;

/// Seeds of FMU number i start at `MECHFMU_SEED + i * SEED_STRIDE`.
const SEED_STRIDE: u64 = 1 << 40;

#[test]
fn random_call_sequences_never_crash_and_follow_the_standard() {
    sequences(required_fmu_paths());
}

#[test]
fn random_fmi3_call_sequences_never_crash_and_follow_the_standard() {
    sequences(required_fmu3_paths());
}

/// `MECHFMU_SEQUENCES` sequences split over the FMUs at `paths`.
fn sequences(paths: Vec<PathBuf>) {
    let total = env_u64("MECHFMU_SEQUENCES", 20_000);
    let base = env_u64("MECHFMU_SEED", 0);
    let per = total.div_ceil(paths.len() as u64);
    let started = std::time::Instant::now();
    let results = per_fmu(&paths, jobs(), |i, p| {
        let first = base + i as u64 * SEED_STRIDE;
        let (out, hung) = run_driver_within(
            p,
            &[
                "sequences",
                "--first",
                &first.to_string(),
                "--count",
                &per.to_string(),
                "--announce",
            ],
            time_limit(),
        );
        let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
        let summary = stdout
            .lines()
            .find(|l| l.starts_with("summary "))
            .map(str::to_string);
        if out.status.success() {
            return Ok(summary.unwrap_or_default());
        }
        let fails: Vec<&str> = stdout
            .lines()
            .filter(|l| l.starts_with("FAIL ") || l.contains(" sequences failed"))
            .collect();
        if out.status.code() == Some(1) && !fails.is_empty() {
            return Err(format!("{}:\n{}", name(p), fails.join("\n")));
        }
        // A crash or a hang: the last sequence begun is the culprit; replay it with its trace.
        let seed = stdout
            .lines()
            .rev()
            .find_map(|l| l.strip_prefix("begin "))
            .unwrap_or("?")
            .to_string();
        let (replay, _) = run_driver_within(
            p,
            &["sequences", "--first", &seed, "--count", "1", "--trace"],
            time_limit(),
        );
        let trace = String::from_utf8_lossy(&replay.stdout);
        let tail: Vec<&str> = trace
            .lines()
            .rev()
            .take(30)
            .collect::<Vec<_>>()
            .into_iter()
            .rev()
            .collect();
        Err(format!(
            "{}: the sequence with seed {seed} {} ({}); stderr:\n{}\nlast calls of its replay ({}):\n{}\nreplay: robustness-driver sequences --fmu {} --first {seed} --count 1 --trace",
            name(p),
            if hung {
                "HUNG (killed after the time limit)"
            } else {
                "CRASHED the process"
            },
            describe_exit(&out),
            String::from_utf8_lossy(&out.stderr),
            describe_exit(&replay),
            tail.join("\n"),
            p.display()
        ))
    });
    let mut failures = vec![];
    for r in results {
        match r {
            Ok(summary) => println!("{summary}"),
            Err(e) => failures.push(e),
        }
    }
    println!(
        "{} FMUs × {per} sequences = {} sequences in {:.1} s",
        paths.len(),
        per * paths.len() as u64,
        started.elapsed().as_secs_f64()
    );
    assert!(failures.is_empty(), "{}", failures.join("\n\n"));
}
