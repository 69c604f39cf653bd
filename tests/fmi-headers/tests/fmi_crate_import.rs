//! A second, independent importer: the `fmi` crate (rust-fmi) unpacks the packaged
//! `fmus/Oscillator.fmu`, parses its modelDescription with its own schema, loads the binary
//! and runs it; the result must match the closed-form solution.

use fmi::fmi2::import::Fmi2Import;
use fmi::fmi2::instance::{CoSimulation, Common};
use fmi::traits::FmiImport;
use std::path::PathBuf;

fn fmu_path(name: &str) -> PathBuf {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("../../fmus/{name}.fmu"));
    assert!(
        path.exists(),
        "{} is missing: build the FMUs first with `cargo run --release -- build`",
        path.display()
    );
    path
}

#[test]
fn fmi_crate_runs_the_oscillator_and_matches_the_closed_form() {
    let import: Fmi2Import =
        fmi::import::from_path(fmu_path("Oscillator")).expect("import Oscillator.fmu");
    let md = import.model_description();
    assert_eq!(md.model_name, "Oscillator");
    let vr = |name: &str| md.model_variable_by_name(name).expect(name).value_reference;
    let (x, c, k) = (vr("x"), vr("c"), vr("k"));
    let exp = md.default_experiment.as_ref().expect("DefaultExperiment");
    assert_eq!(exp.stop_time(), 20.0);

    let mut fmu = import
        .instantiate_cs("Oscillator", false, true)
        .expect("instantiate");
    assert_eq!(fmu.get_version(), "2.0");
    fmu.setup_experiment(Some(1e-8), 0.0, None).expect("setup");
    fmu.enter_initialization_mode().expect("enter init");
    // ζ = 0.1, ωn = 2: underdamped, from x0 = 1, v0 = 0.
    fmu.set_real(&[c, k], &[0.4, 4.0]).expect("set");
    fmu.exit_initialization_mode().expect("exit init");

    let (wn, zeta) = (2.0f64, 0.1f64);
    let wd = wn * (1.0 - zeta * zeta).sqrt();
    let exact =
        |t: f64| (-zeta * wn * t).exp() * ((wd * t).cos() + zeta * wn / wd * (wd * t).sin());
    let h = 0.01;
    let mut max_err = 0.0f64;
    let mut value = [0.0];
    for n in 0..2000 {
        let t = n as f64 * h;
        fmu.do_step(t, h, true).expect("step");
        fmu.get_real(&[x], &mut value).expect("get");
        max_err = max_err.max((value[0] - exact(t + h)).abs());
    }
    // The free response spans [-0.73, 1]: 1e-6 of its range.
    assert!(max_err < 1.7e-6, "max error {max_err:e}");
    fmu.terminate().expect("terminate");
}
