//! A shipped FMU's binary exports the 44 functions of FMI 2.0 (`fmi2Functions.h`: the
//! common ones, Model Exchange's and Co-Simulation's) and the documented extras the README
//! lists, nothing else (no benchmark entry points, no Rust symbols).

use mechfmu_robustness::ffi::FUNCTION_NAMES;
use mechfmu_robustness::fmu::{required_fmu_paths, Fmu};
use std::collections::BTreeSet;
use std::process::Command;

/// The `#define fmi2X fmi2FullName(fmi2X)` lines of the official `fmi2Functions.h`
/// (FMI 2.0.x), in the header's order: what an FMU binary must export.
const HEADER_FUNCTIONS: [&str; 44] = [
    // Common functions
    "fmi2GetTypesPlatform",
    "fmi2GetVersion",
    "fmi2SetDebugLogging",
    "fmi2Instantiate",
    "fmi2FreeInstance",
    "fmi2SetupExperiment",
    "fmi2EnterInitializationMode",
    "fmi2ExitInitializationMode",
    "fmi2Terminate",
    "fmi2Reset",
    "fmi2GetReal",
    "fmi2GetInteger",
    "fmi2GetBoolean",
    "fmi2GetString",
    "fmi2SetReal",
    "fmi2SetInteger",
    "fmi2SetBoolean",
    "fmi2SetString",
    "fmi2GetFMUstate",
    "fmi2SetFMUstate",
    "fmi2FreeFMUstate",
    "fmi2SerializedFMUstateSize",
    "fmi2SerializeFMUstate",
    "fmi2DeSerializeFMUstate",
    "fmi2GetDirectionalDerivative",
    // Functions for FMI2 for Model Exchange
    "fmi2EnterEventMode",
    "fmi2NewDiscreteStates",
    "fmi2EnterContinuousTimeMode",
    "fmi2CompletedIntegratorStep",
    "fmi2SetTime",
    "fmi2SetContinuousStates",
    "fmi2GetDerivatives",
    "fmi2GetEventIndicators",
    "fmi2GetContinuousStates",
    "fmi2GetNominalsOfContinuousStates",
    // Functions for FMI2 for Co-Simulation
    "fmi2SetRealInputDerivatives",
    "fmi2GetRealOutputDerivatives",
    "fmi2DoStep",
    "fmi2CancelStep",
    "fmi2GetStatus",
    "fmi2GetRealStatus",
    "fmi2GetIntegerStatus",
    "fmi2GetBooleanStatus",
    "fmi2GetStringStatus",
];

/// What the README lists besides the FMI functions.
const DOCUMENTED_EXTRAS: [&str; 3] = [
    "mechfmu_documentation",
    "mechfmu_interface",
    "mechfmu_model_description",
];

#[test]
fn the_importer_resolves_exactly_the_header_functions() {
    let header: BTreeSet<&str> = HEADER_FUNCTIONS.iter().copied().collect();
    let resolved: BTreeSet<&str> = FUNCTION_NAMES.iter().copied().collect();
    assert_eq!(header.len(), 44, "a name twice in HEADER_FUNCTIONS");
    assert_eq!(
        resolved.len(),
        FUNCTION_NAMES.len(),
        "a name twice in FUNCTION_NAMES"
    );
    assert_eq!(resolved, header);
}

#[test]
fn a_shipped_binary_exports_the_fmi_functions_and_the_documented_extras_only() {
    let expected: BTreeSet<&str> = HEADER_FUNCTIONS
        .iter()
        .chain(&DOCUMENTED_EXTRAS)
        .copied()
        .collect();
    assert_eq!(expected.len(), 47);
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
        let missing: Vec<_> = expected.difference(&exported).collect();
        let extra: Vec<_> = exported.difference(&expected).collect();
        assert!(
            missing.is_empty() && extra.is_empty(),
            "{}: exported symbols: missing {missing:?}, not expected {extra:?}",
            fmu.name()
        );
    }
}
