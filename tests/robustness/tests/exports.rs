//! A shipped FMU's binary exports the 34 functions of FMI 2.0 Co-Simulation and the
//! documented extras the README lists, nothing else (no benchmark entry points, no Rust
//! symbols).

use mechfmu_robustness::ffi::FUNCTION_NAMES;
use mechfmu_robustness::fmu::{required_fmu_paths, Fmu};
use std::collections::BTreeSet;
use std::process::Command;

/// What the README lists besides the FMI functions.
const DOCUMENTED_EXTRAS: [&str; 3] = [
    "mechfmu_documentation",
    "mechfmu_interface",
    "mechfmu_model_description",
];

#[test]
fn a_shipped_binary_exports_the_fmi_functions_and_the_documented_extras_only() {
    let expected: BTreeSet<&str> = FUNCTION_NAMES
        .iter()
        .chain(&DOCUMENTED_EXTRAS)
        .copied()
        .collect();
    for path in required_fmu_paths() {
        let fmu = Fmu::load(&path).unwrap();
        let out = Command::new("nm")
            .args(["-D", "--defined-only", "--format=posix"])
            .arg(fmu.binary())
            .output()
            .expect("nm (binutils) runs");
        assert!(
            out.status.success(),
            "nm: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let listing = String::from_utf8_lossy(&out.stdout);
        let exported: BTreeSet<&str> = listing
            .lines()
            .filter_map(|l| l.split_whitespace().next())
            .collect();
        assert_eq!(exported, expected, "{}: exported symbols", fmu.name());
    }
}
