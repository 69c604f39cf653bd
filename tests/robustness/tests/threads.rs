//! Instances in threads, through the loaded binaries (conformance checks the same
//! in-process through `Harness`): two FMU binaries loaded in one process, eight
//! Co-Simulation instances stepped and four Model Exchange instances integrated (by the
//! importer's fixed-step RK4 through fmi2SetTime, fmi2SetContinuousStates and
//! fmi2GetDerivatives, with fmi2CompletedIntegratorStep, the event indicators and events)
//! in twelve threads at once give results bit-identical to sequential runs. The same for
//! FMI 3.0: two FMI 3.0 binaries, eight Co-Simulation instances (half of them through event
//! mode, with the status and out arguments of every step) and four Model Exchange
//! instances (fmi3SetTime, fmi3SetContinuousStates, fmi3GetContinuousStateDerivatives,
//! fmi3UpdateDiscreteStates) in twelve threads.

use mechfmu_robustness::fmu::{required_fmu3_paths, required_fmu_paths, Fmu, Fmu3};
use mechfmu_robustness::scenarios::{fingerprint, fingerprint3, me_fingerprint, me_fingerprint3};

/// Jobs 0..8 are Co-Simulation runs, 8..12 Model Exchange runs.
const CS_JOBS: usize = 8;
const JOBS: usize = 12;

/// The [`JOBS`] runs of `job` one after the other, then 3 rounds of all of them in as
/// many threads at once, each bit-identical to its sequential run (`instance` says which
/// run differed); the sequential runs.
fn sequential_then_in_threads(
    job: impl Fn(usize) -> Vec<u64> + Copy + Send + Sync,
    instance: impl Fn(usize) -> String,
) -> Vec<Vec<u64>> {
    let sequential: Vec<Vec<u64>> = (0..JOBS).map(job).collect();
    for round in 0..3 {
        let parallel: Vec<Vec<u64>> = std::thread::scope(|s| {
            let handles: Vec<_> = (0..JOBS).map(|i| s.spawn(move || job(i))).collect();
            handles
                .into_iter()
                .map(|h| h.join().expect("a thread panicked"))
                .collect()
        });
        for i in 0..JOBS {
            assert!(
                parallel[i] == sequential[i],
                "round {round}: {} instance {i} in a thread differs from its sequential run",
                instance(i)
            );
        }
    }
    sequential
}

#[test]
fn two_binaries_twelve_threads_match_sequential_runs() {
    let paths = required_fmu_paths();
    // Two different FMUs if there are two; else the same one unpacked twice (two images
    // of one library in one process).
    let a = Fmu::load(&paths[0]).unwrap();
    let b = Fmu::load(paths.get(1).unwrap_or(&paths[0])).unwrap();
    let fmus = [&a, &b];
    for fmu in fmus {
        assert!(
            fmu.md.model_exchange.is_some(),
            "{} does not declare Model Exchange",
            fmu.name()
        );
    }
    let job = |i: usize| {
        let fmu = fmus[i % 2];
        if i < CS_JOBS {
            let tol = fmu.md.experiment.tolerance * 10f64.powi(-((i / 2) as i32));
            fingerprint(fmu, tol, 20_000 + 1000 * (i / 2))
        } else {
            // Different step sizes and lengths: h = step/2, step/4 over 4,000 and 8,000 steps.
            let k = (i - CS_JOBS) / 2;
            let h = fmu.md.experiment.step / (2 << k) as f64;
            me_fingerprint(fmu, fmu.md.experiment.tolerance, 4_000 << k, h)
        }
        .unwrap_or_else(|e| panic!("{} (job {i}): {e}", fmu.name()))
    };
    let sequential = sequential_then_in_threads(job, |i| {
        let kind = if i < CS_JOBS {
            "Co-Simulation"
        } else {
            "Model Exchange"
        };
        format!("{} {kind}", fmus[i % 2].name())
    });
    // The runs differ from each other (tolerances, step sizes, lengths), so equality
    // means something.
    assert_ne!(sequential[0], sequential[2]);
    assert_ne!(sequential[1], sequential[3]);
    assert_ne!(sequential[8], sequential[10]);
    assert_ne!(sequential[9], sequential[11]);
    println!(
        "{} and {}: 8 Co-Simulation and 4 Model Exchange instances in 12 threads × 3 rounds bit-identical to sequential runs",
        a.name(),
        b.name()
    );
}

#[test]
fn two_fmi3_binaries_twelve_threads_match_sequential_runs() {
    let paths = required_fmu3_paths();
    let a = Fmu3::load(&paths[0]).unwrap();
    let b = Fmu3::load(paths.get(1).unwrap_or(&paths[0])).unwrap();
    let fmus = [&a, &b];
    for fmu in fmus {
        assert!(
            fmu.md.model_exchange.is_some(),
            "{} does not declare Model Exchange",
            fmu.name()
        );
    }
    let job = |i: usize| {
        let fmu = fmus[i % 2];
        if i < CS_JOBS {
            // Jobs 0, 1 and 4, 5 without event mode, 2, 3 and 6, 7 through it.
            let tol = fmu.md.experiment.tolerance * 10f64.powi(-((i / 4) as i32));
            fingerprint3(fmu, tol, 10_000 + 1000 * (i / 2), (i / 2) % 2 == 1)
        } else {
            let k = (i - CS_JOBS) / 2;
            let h = fmu.md.experiment.step / (2 << k) as f64;
            me_fingerprint3(fmu, fmu.md.experiment.tolerance, 2_000 << k, h)
        }
        .unwrap_or_else(|e| panic!("{} (job {i}): {e}", fmu.name()))
    };
    let sequential = sequential_then_in_threads(job, |i| format!("{} FMI 3.0", fmus[i % 2].name()));
    // The runs differ from each other, so equality means something.
    for (x, y) in [(0, 2), (1, 3), (0, 4), (8, 10), (9, 11)] {
        assert_ne!(sequential[x], sequential[y], "jobs {x} and {y}");
    }
    println!(
        "{} and {}: 8 Co-Simulation and 4 Model Exchange FMI 3.0 instances in 12 threads × 3 rounds bit-identical to sequential runs",
        a.name(),
        b.name()
    );
}
