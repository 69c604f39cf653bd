//! Memory use without valgrind (`scripts/valgrind` runs the same cycles under valgrind):
//! instantiate/initialize/step/free cycles of every FMU, with importer callbacks for
//! allocateMemory/freeMemory that abort the process if called; and of every FMI 3.0 FMU
//! (which has no memory callbacks: its intermediateUpdate callback aborts if called).

mod common;
use common::*;
use mechfmu_robustness::fmu::{required_fmu3_paths, required_fmu_paths, Fmu};
use std::path::PathBuf;

#[test]
fn every_fmu_declares_the_memory_callbacks_unused() {
    for p in required_fmu_paths() {
        let fmu = Fmu::load(&p).unwrap();
        assert!(
            fmu.md.can_not_use_memory_management_functions,
            "{}: canNotUseMemoryManagementFunctions is not \"true\", yet the runtime allocates with Rust's allocator",
            fmu.name()
        );
    }
}

/// The cycles `scripts/valgrind` runs, here without valgrind (fewer of them): every FMU
/// survives them, and never calls the importer's memory functions (they abort).
#[test]
fn instantiate_free_cycles_never_call_the_memory_callbacks() {
    cycles(required_fmu_paths());
}

/// The FMI 3.0 cycles `scripts/valgrind` runs (Co-Simulation with and without event mode
/// and early return, Model Exchange), here without valgrind.
#[test]
fn fmi3_instantiate_free_cycles_survive() {
    cycles(required_fmu3_paths());
}

fn cycles(paths: Vec<PathBuf>) {
    let results = per_fmu(&paths, jobs(), |_, p| {
        let out = run_driver(p, &["cycles", "--count", "200"]);
        (name(p), out)
    });
    for (name, out) in results {
        assert!(
            out.status.success(),
            "{name}: cycles failed ({}):\n{}{}",
            describe_exit(&out),
            String::from_utf8_lossy(&out.stdout),
            String::from_utf8_lossy(&out.stderr)
        );
        print!("{}", String::from_utf8_lossy(&out.stdout));
    }
}
