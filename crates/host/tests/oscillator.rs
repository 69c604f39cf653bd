//! The host side on a real FMU: `fmus/Oscillator.fmu` and its FMI 3.0 sibling as `mechfmu
//! build` wrote them, opened, loaded and stepped through each version's functions.

use mechfmu::contract::Version;
use mechfmu::fmi2::ffi::{fmi2CoSimulation, fmi2OK};
use mechfmu::fmi3::ffi::fmi3OK;
use mechfmu_host::archive;
use mechfmu_host::description::ModelDescription;
use mechfmu_host::library::{Extra, Library};
use mechfmu_host::log::Log;
use mechfmu_host::{fmi2, fmi3};
use std::ffi::CString;
use std::path::{Path, PathBuf};
use std::rc::Rc;

/// The Oscillator FMU of `version`, taken apart into a folder of its own: its model
/// description and its loaded binary.
fn oscillator(version: Version) -> (ModelDescription, Library) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let fmu = match version {
        Version::Fmi2 => root.join("fmus/Oscillator.fmu"),
        Version::Fmi3 => root.join("fmus/fmi3/Oscillator.fmu"),
    };
    assert!(
        fmu.is_file(),
        "{} is missing: build the FMUs first (`cargo run --release -- build`)",
        fmu.display()
    );
    let dir: PathBuf = std::env::temp_dir().join(format!(
        "mechfmu-host-{}-{}",
        version.name().replace(' ', ""),
        std::process::id()
    ));
    let files = archive::extract(&fmu, &dir).unwrap();
    let xml = std::fs::read_to_string(&files.model_description).unwrap();
    let description = ModelDescription::parse(&xml).unwrap();
    assert_eq!(description.version, version);
    let library = Library::open(&files.binary).unwrap();
    // loaded: the files are no longer needed
    let _ = std::fs::remove_dir_all(&dir);
    (description, library)
}

#[test]
fn an_fmi2_instance_steps_and_its_messages_reach_the_log() {
    let (d, library) = oscillator(Version::Fmi2);
    let functions = fmi2::functions::Functions::load(&library).unwrap();
    assert!(functions.has_model_exchange());
    let log = Rc::new(Log::new());
    let name = CString::new(d.model_identifier.as_str()).unwrap();
    let guid = CString::new(d.token.as_str()).unwrap();
    let wrong = fmi2::instance::Instance::instantiate(
        &functions,
        &name,
        fmi2CoSimulation,
        c"{not-the-guid}",
        c"",
        &log,
    );
    assert!(wrong.is_none());
    assert!(!log.messages().is_empty(), "the refusal is logged");
    let instance = fmi2::instance::Instance::instantiate(
        &functions,
        &name,
        fmi2CoSimulation,
        &guid,
        c"",
        &log,
    )
    .unwrap();
    assert_eq!(instance.setup_experiment(Some(1e-8), d.start, None), fmi2OK);
    assert_eq!(instance.enter_initialization_mode(), fmi2OK);
    assert_eq!(instance.exit_initialization_mode(), fmi2OK);
    let x = d.variable("x").unwrap();
    for k in 0..10 {
        assert_eq!(instance.do_step(k as f64 * d.step, d.step), fmi2OK);
    }
    let mut value = [0.0];
    assert_eq!(instance.get_real(&[x.vr], &mut value), fmi2OK);
    assert!(value[0].is_finite() && value[0] != x.start.unwrap());
    assert_eq!(instance.terminate(), fmi2OK);
}

#[test]
fn an_fmi3_instance_steps_from_the_same_binary() {
    let (d, library) = oscillator(Version::Fmi3);
    let functions = fmi3::functions::Functions::load(&library).unwrap();
    let log = Rc::new(Log::new());
    let name = CString::new(d.model_identifier.as_str()).unwrap();
    let token = CString::new(d.token.as_str()).unwrap();
    let mut instance =
        fmi3::instance::Instance::instantiate(&functions, &name, &token, c"", &log).unwrap();
    assert_eq!(
        instance.enter_initialization_mode(None, d.start, None),
        fmi3OK
    );
    assert_eq!(instance.exit_initialization_mode(), fmi3OK);
    assert_eq!(instance.do_step(d.start, d.step), fmi3OK);
    let x = d.variable("x").unwrap();
    let mut value = [0.0];
    assert_eq!(instance.get_float64(&[x.vr], &mut value), fmi3OK);
    assert!(value[0].is_finite());
}

#[test]
fn the_shipped_binary_exports_the_fmi_functions_and_renders_no_text() {
    for version in [Version::Fmi2, Version::Fmi3] {
        let (_, library) = oscillator(version);
        assert!(library.exports("fmi2DoStep") && library.exports("fmi3DoStep"));
        assert!(!library.exports("no_such_symbol"));
        for extra in [
            Extra::ModelDescription(version),
            Extra::Documentation(version),
            Extra::Interface,
        ] {
            assert!(!library.exports(extra.symbol()), "{}", extra.symbol());
            let err = library.text(extra).unwrap_err();
            assert!(err.contains("a shipped FMU binary"), "{err}");
        }
    }
}
