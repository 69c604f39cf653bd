//! Long runs without drift in time and without growing memory. Each FMU runs in a child
//! process (its own RSS): n communication steps of h = 1e-3 with the importer's time
//! t0 + k·h; at the end fmi2LastSuccessfulTime must be t0 + n·h exactly and the resident set
//! must not have grown (sampled from /proc/self/statm after a warm-up and at the end).
//!
//! CI runs 10^5 steps; the 10^6-step run is ignored by default:
//!
//! ```text
//! cargo test --release -p mechfmu-robustness --test long_runs -- --ignored --nocapture
//! ```

mod common;
use common::*;
use mechfmu_robustness::fmu::required_fmu_paths;

/// RSS growth allowed between the warm-up and the end: a few pages of allocator noise,
/// far below what a leak of even a few bytes per step would show over 10^5 steps.
const RSS_SLACK: u64 = 256 * 1024;

fn long_runs(steps: u64) {
    let paths = required_fmu_paths();
    let results = per_fmu(&paths, jobs(), |_, p| {
        (
            name(p),
            run_driver(
                p,
                &["long-run", "--steps", &steps.to_string(), "--h", "1e-3"],
            ),
        )
    });
    let mut failures = vec![];
    for (name, out) in results {
        let stdout = String::from_utf8_lossy(&out.stdout);
        if !out.status.success() {
            failures.push(format!(
                "{name}: {} {}",
                describe_exit(&out),
                String::from_utf8_lossy(&out.stderr)
            ));
            continue;
        }
        print!("{stdout}");
        let r: Vec<&str> = stdout
            .lines()
            .find_map(|l| l.strip_prefix("result "))
            .expect("result line")
            .split(' ')
            .collect();
        let (last, expected): (f64, f64) = (r[1].parse().unwrap(), r[2].parse().unwrap());
        let (before, after): (u64, u64) = (r[3].parse().unwrap(), r[4].parse().unwrap());
        if last.to_bits() != expected.to_bits() {
            failures.push(format!("{name}: after {steps} steps fmi2LastSuccessfulTime = {last:?}, t0 + n·h = {expected:?}"));
        }
        if after > before + RSS_SLACK {
            failures.push(format!(
                "{name}: RSS grew from {} KiB to {} KiB over {steps} steps",
                before / 1024,
                after / 1024
            ));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn hundred_thousand_steps_without_drift_or_growth() {
    long_runs(env_u64("MECHFMU_LONG_STEPS", 100_000));
}

#[test]
#[ignore = "10^6 steps per FMU: run with --ignored (seconds to a minute in release)"]
fn million_steps_without_drift_or_growth() {
    long_runs(1_000_000);
}
