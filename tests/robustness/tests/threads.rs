//! Instances in threads, through the loaded binaries (conformance checks the same
//! in-process through `Harness`): two FMU binaries loaded in one process, eight instances stepped in
//! eight threads at once give results bit-identical to sequential runs.

use mechfmu_robustness::fmu::{required_fmu_paths, Fmu};
use mechfmu_robustness::scenarios::fingerprint;

#[test]
fn two_binaries_eight_threads_match_sequential_runs() {
    let paths = required_fmu_paths();
    // Two different FMUs if there are two; else the same one unpacked twice (two images
    // of one library in one process).
    let a = Fmu::load(&paths[0]).unwrap();
    let b = Fmu::load(paths.get(1).unwrap_or(&paths[0])).unwrap();
    let fmus = [&a, &b];
    let job = |i: usize| {
        let fmu = fmus[i % 2];
        let tol = fmu.md.experiment.tolerance * 10f64.powi(-((i / 2) as i32));
        fingerprint(fmu, tol, 20_000 + 1000 * (i / 2))
            .unwrap_or_else(|e| panic!("{} (job {i}): {e}", fmu.name()))
    };
    let sequential: Vec<Vec<u64>> = (0..8).map(job).collect();
    for round in 0..3 {
        let parallel: Vec<Vec<u64>> = std::thread::scope(|s| {
            let handles: Vec<_> = (0..8).map(|i| s.spawn(move || job(i))).collect();
            handles
                .into_iter()
                .map(|h| h.join().expect("a thread panicked"))
                .collect()
        });
        for i in 0..8 {
            assert!(
                parallel[i] == sequential[i],
                "round {round}: {} instance {i} in a thread differs from its sequential run",
                fmus[i % 2].name()
            );
        }
    }
    // The runs differ from each other (tolerances, lengths), so equality means something.
    assert_ne!(sequential[0], sequential[2]);
    assert_ne!(sequential[1], sequential[3]);
    println!(
        "{} and {}: 8 threads × 3 rounds bit-identical to sequential runs",
        a.name(),
        b.name()
    );
}
