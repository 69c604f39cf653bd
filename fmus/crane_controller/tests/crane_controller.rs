//! CraneController through its FMI functions, in-process (no FMU file needed): its drives
//! against the contract's control law at random gains and measurements, the crane held still
//! at its references, its model descriptions (no state, direct feedthrough), and the checks
//! every mechfmu FMU passes.

use crane_controller::CraneController;
use mechfmu_testkit::formulas::{declares_direct_feedthrough, outputs_follow};
use mechfmu_testkit::harness::Harness;

/// At random gains, references and measurements, the drives are the control law to
/// rounding: F = (m + m_trolley) g sin θ + kp_x (x_ref - x) - kd_x ẋ + k_sway φ̇,
/// tau = (m + m_trolley) g x cos θ + kp_theta (theta_ref - θ) - kd_theta θ̇.
#[test]
fn the_drives_are_the_control_law_at_random_inputs() {
    let parameters = [
        ("x_ref", 1.0, 20.0),
        ("theta_ref", -0.2, 1.4),
        ("kp_x", 0.0, 5e3),
        ("kd_x", 0.0, 5e3),
        ("kp_theta", 0.0, 5e5),
        ("kd_theta", 0.0, 5e5),
        ("k_sway", -5e3, 5e3),
        ("m", 10.0, 5e3),
        ("m_trolley", 10.0, 1e3),
        ("g", 1.0, 25.0),
    ];
    let inputs = [
        ("x", 0.5, 20.0),
        ("x_dot", -2.0, 2.0),
        ("theta", -0.5, 1.5),
        ("theta_dot", -0.5, 0.5),
        ("phi_dot", -1.0, 1.0),
    ];
    outputs_follow::<CraneController>(&parameters, &inputs, 200, |p| {
        let weight = (p["m"] + p["m_trolley"]) * p["g"];
        let force = [
            weight * p["theta"].sin(),
            p["kp_x"] * (p["x_ref"] - p["x"]),
            -p["kd_x"] * p["x_dot"],
            p["k_sway"] * p["phi_dot"],
        ];
        let torque = [
            weight * p["x"] * p["theta"].cos(),
            p["kp_theta"] * (p["theta_ref"] - p["theta"]),
            -p["kd_theta"] * p["theta_dot"],
        ];
        let size = |terms: &[f64]| terms.iter().map(|t| t.abs()).sum::<f64>();
        vec![
            ("F", force.iter().sum(), size(&force)),
            ("tau", torque.iter().sum(), size(&torque)),
        ]
    });
}

/// At its references, with nothing moving, the controller gives the static drive loads of
/// `CraneDynamics` (section 5 of the contract): the feedback terms vanish.
#[test]
fn at_the_references_the_drives_are_the_static_loads() {
    let mut fmu = Harness::<CraneController>::new();
    let (x, theta) = (12.0, 0.6);
    fmu.initialize(None, 0.0, &[("x", x), ("theta", theta)])
        .unwrap();
    let weight = (1000.0 + 200.0) * 9.81;
    assert!((fmu.get("F") - weight * f64::sin(theta)).abs() < 1e-9);
    assert!((fmu.get("tau") - weight * x * f64::cos(theta)).abs() < 1e-7);
}

/// No state, no event indicator, and both drives depend on the inputs directly: F on x,
/// x_dot, theta and phi_dot; tau on x, theta and theta_dot.
#[test]
fn the_model_descriptions_declare_direct_feedthrough_and_no_state() {
    declares_direct_feedthrough::<CraneController>(&[
        ("F", &["x", "x_dot", "theta", "phi_dot"]),
        ("tau", &["x", "theta", "theta_dot"]),
    ]);
}

/// A payload or trolley without mass is refused at initialization, naming it.
#[test]
fn a_mass_that_is_not_positive_is_refused() {
    mechfmu_testkit::harness::assert_rejected_at_initialization::<CraneController>("m", 0.0);
    mechfmu_testkit::harness::assert_rejected_at_initialization::<CraneController>(
        "m_trolley",
        -1.0,
    );
}

mechfmu_testkit::golden_tests!(CraneController);

/// The checks every mechfmu FMU passes: reset, FMU state, serialization, derivatives,
/// Model Exchange, FMI 3.0.
#[test]
fn conforms() {
    mechfmu_testkit::conformance::check::<CraneController>();
}
