//! A shipped FMU's binary exports the 44 functions of FMI 2.0 (`fmi2Functions.h`: the
//! common ones, Model Exchange's and Co-Simulation's), the 75 of FMI 3.0
//! (`fmi3Functions.h`: one binary serves the FMU of either version), nothing else (not the
//! documented extras the `mechfmu` command reads from a describing build of its own, no
//! benchmark entry points, no Rust symbols).

use mechfmu_host::archive;
use mechfmu_host::platform::{Platform, Version};
use mechfmu_robustness::ffi::FUNCTION_NAMES;
use mechfmu_robustness::fmu::{required_fmu_paths, Fmu};
use std::collections::BTreeSet;
use std::path::Path;
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

/// The `#define fmi3X fmi3FullName(fmi3X)` lines of the official `fmi3Functions.h` (FMI
/// 3.0.x), in the header's order.
const HEADER_FUNCTIONS_FMI3: [&str; 75] = [
    "fmi3GetVersion",
    "fmi3SetDebugLogging",
    "fmi3InstantiateModelExchange",
    "fmi3InstantiateCoSimulation",
    "fmi3InstantiateScheduledExecution",
    "fmi3FreeInstance",
    "fmi3EnterInitializationMode",
    "fmi3ExitInitializationMode",
    "fmi3EnterEventMode",
    "fmi3Terminate",
    "fmi3Reset",
    "fmi3GetFloat32",
    "fmi3GetFloat64",
    "fmi3GetInt8",
    "fmi3GetUInt8",
    "fmi3GetInt16",
    "fmi3GetUInt16",
    "fmi3GetInt32",
    "fmi3GetUInt32",
    "fmi3GetInt64",
    "fmi3GetUInt64",
    "fmi3GetBoolean",
    "fmi3GetString",
    "fmi3GetBinary",
    "fmi3GetClock",
    "fmi3SetFloat32",
    "fmi3SetFloat64",
    "fmi3SetInt8",
    "fmi3SetUInt8",
    "fmi3SetInt16",
    "fmi3SetUInt16",
    "fmi3SetInt32",
    "fmi3SetUInt32",
    "fmi3SetInt64",
    "fmi3SetUInt64",
    "fmi3SetBoolean",
    "fmi3SetString",
    "fmi3SetBinary",
    "fmi3SetClock",
    "fmi3GetNumberOfVariableDependencies",
    "fmi3GetVariableDependencies",
    "fmi3GetFMUState",
    "fmi3SetFMUState",
    "fmi3FreeFMUState",
    "fmi3SerializedFMUStateSize",
    "fmi3SerializeFMUState",
    "fmi3DeserializeFMUState",
    "fmi3GetDirectionalDerivative",
    "fmi3GetAdjointDerivative",
    "fmi3EnterConfigurationMode",
    "fmi3ExitConfigurationMode",
    "fmi3GetIntervalDecimal",
    "fmi3GetIntervalFraction",
    "fmi3GetShiftDecimal",
    "fmi3GetShiftFraction",
    "fmi3SetIntervalDecimal",
    "fmi3SetIntervalFraction",
    "fmi3SetShiftDecimal",
    "fmi3SetShiftFraction",
    "fmi3EvaluateDiscreteStates",
    "fmi3UpdateDiscreteStates",
    "fmi3EnterContinuousTimeMode",
    "fmi3CompletedIntegratorStep",
    "fmi3SetTime",
    "fmi3SetContinuousStates",
    "fmi3GetContinuousStateDerivatives",
    "fmi3GetEventIndicators",
    "fmi3GetContinuousStates",
    "fmi3GetNominalsOfContinuousStates",
    "fmi3GetNumberOfEventIndicators",
    "fmi3GetNumberOfContinuousStates",
    "fmi3EnterStepMode",
    "fmi3GetOutputDerivatives",
    "fmi3DoStep",
    "fmi3ActivateModelPartition",
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
fn a_shipped_binary_exports_the_fmi_functions_only() {
    let expected: BTreeSet<&str> = HEADER_FUNCTIONS
        .iter()
        .chain(&HEADER_FUNCTIONS_FMI3)
        .copied()
        .collect();
    assert_eq!(expected.len(), 44 + 75);
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

#[test]
fn the_fmi3_fmu_carries_the_same_binary_under_its_platform_tuple() {
    for path in required_fmu_paths() {
        let fmu = Fmu::load(&path).unwrap();
        let id = fmu.name().to_string();
        let fmi3 = path
            .parent()
            .expect("in a folder")
            .join("fmi3")
            .join(path.file_name().expect("a file"));
        let binary = |fmu: &Path, version: Version| {
            let folder = Platform::X86_64Linux.folder(version);
            archive::entry(fmu, &format!("binaries/{folder}/{id}.so"))
                .unwrap_or_else(|e| panic!("{e}"))
        };
        let binary2 = binary(&path, Version::Fmi2);
        let binary3 = binary(&fmi3, Version::Fmi3);
        assert!(binary2 == binary3, "{id}: the FMI 3.0 FMU's binary differs");
        let xml = archive::model_description(&fmi3).unwrap_or_else(|e| panic!("{e}"));
        assert!(
            xml.contains("fmiVersion=\"3.0\""),
            "{id}: the FMI 3.0 FMU's model description is not FMI 3.0"
        );
    }
}
