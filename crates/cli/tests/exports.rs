//! A shipped FMU's binary exports the 34 functions of FMI 2.0 Co-Simulation and the
//! documented extras, nothing else (no benchmark entry points, no Rust symbols). Reads the
//! FMUs `mechfmu build` wrote into `fmus/` (the test command builds them first).

use std::collections::BTreeSet;
use std::io::Read;
use std::path::Path;
use std::process::Command;

/// FMI 2.0.5, `fmi2Functions.h`: the common functions and those of Co-Simulation.
const FMI2_CO_SIMULATION: [&str; 34] = [
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

/// The extras the README lists.
const DOCUMENTED_EXTRAS: [&str; 3] = [
    "mechfmu_documentation",
    "mechfmu_interface",
    "mechfmu_model_description",
];

#[test]
fn a_shipped_binary_exports_the_fmi_functions_and_the_documented_extras_only() {
    let fmus = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fmus");
    let expected: BTreeSet<&str> = FMI2_CO_SIMULATION
        .iter()
        .chain(&DOCUMENTED_EXTRAS)
        .copied()
        .collect();
    let mut checked = 0;
    for entry in std::fs::read_dir(&fmus).expect("fmus/ (run `mechfmu build` first)") {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "fmu") {
            continue;
        }
        let model = path.file_stem().unwrap().to_str().unwrap().to_string();
        let mut archive = zip::ZipArchive::new(std::fs::File::open(&path).unwrap()).unwrap();
        let mut binary = Vec::new();
        archive
            .by_name(&format!("binaries/linux64/{model}.so"))
            .unwrap_or_else(|e| panic!("{}: no linux64 binary: {e}", path.display()))
            .read_to_end(&mut binary)
            .unwrap();
        let so =
            std::env::temp_dir().join(format!("mechfmu-exports-{}-{model}.so", std::process::id()));
        std::fs::write(&so, &binary).unwrap();
        let out = Command::new("nm")
            .args(["-D", "--defined-only", "--format=posix"])
            .arg(&so)
            .output()
            .expect("nm (binutils) runs");
        let _ = std::fs::remove_file(&so);
        assert!(
            out.status.success(),
            "nm: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let exported: BTreeSet<String> = String::from_utf8_lossy(&out.stdout)
            .lines()
            .filter_map(|l| l.split_whitespace().next().map(String::from))
            .collect();
        let exported: BTreeSet<&str> = exported.iter().map(String::as_str).collect();
        assert_eq!(exported, expected, "{model}: exported symbols");
        checked += 1;
    }
    assert!(checked >= 6, "only {checked} FMUs in {}", fmus.display());
}
