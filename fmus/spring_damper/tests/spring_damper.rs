//! SpringDamper through its FMI functions, in-process (no FMU file needed): its outputs
//! against the contract's formulas at random inputs and parameters, its model descriptions
//! (no state, every output depending on the inputs directly), its refusals, and the checks
//! every mechfmu FMU passes.

use mechfmu_testkit::formulas::{declares_direct_feedthrough, outputs_follow};
use mechfmu_testkit::harness::{assert_rejected_at_initialization, Harness};
use spring_damper::SpringDamper;

/// At random parameters and inputs, the outputs are the contract's formulas to rounding:
/// F_a = k (x_b - x_a - l0) + c (v_b - v_a), F_b = -F_a, E = ½ k (x_b - x_a - l0)².
#[test]
fn the_outputs_are_the_formulas_at_random_inputs() {
    let parameters = [("k", 0.0, 1e3), ("c", 0.0, 50.0), ("l0", -1.0, 2.0)];
    let inputs = [
        ("x_a", -5.0, 5.0),
        ("x_b", -5.0, 5.0),
        ("v_a", -10.0, 10.0),
        ("v_b", -10.0, 10.0),
    ];
    outputs_follow::<SpringDamper>(&parameters, &inputs, 200, |p| {
        let stretch = p["x_b"] - p["x_a"] - p["l0"];
        let (spring, damper) = (p["k"] * stretch, p["c"] * (p["v_b"] - p["v_a"]));
        let size = spring.abs() + damper.abs();
        let energy = 0.5 * p["k"] * stretch * stretch;
        vec![
            ("F_a", spring + damper, size),
            ("F_b", -(spring + damper), size),
            ("E", energy, energy),
        ]
    });
}

/// No state, no event indicator, and each output depends on the inputs directly: the
/// forces on all four (the damping's velocities too, though c starts at 0), the energy on
/// the positions.
#[test]
fn the_model_descriptions_declare_direct_feedthrough_and_no_state() {
    let all = ["x_a", "x_b", "v_a", "v_b"];
    declares_direct_feedthrough::<SpringDamper>(&[
        ("F_a", &all),
        ("F_b", &all),
        ("E", &["x_a", "x_b"]),
    ]);
}

/// A negative stiffness or damping is refused at initialization, naming it; zero is not.
#[test]
fn a_negative_stiffness_or_damping_is_refused() {
    assert_rejected_at_initialization::<SpringDamper>("k", -1.0);
    assert_rejected_at_initialization::<SpringDamper>("c", -0.1);
    let mut fmu = Harness::<SpringDamper>::new();
    fmu.initialize(None, 0.0, &[("k", 0.0), ("c", 0.0), ("x_b", 2.0)])
        .unwrap();
    assert_eq!((fmu.get("F_a"), fmu.get("E")), (0.0, 0.0));
}

mechfmu_testkit::golden_tests!(SpringDamper);

/// The checks every mechfmu FMU passes: reset, FMU state, serialization, derivatives,
/// Model Exchange, FMI 3.0.
#[test]
fn conforms() {
    mechfmu_testkit::conformance::check::<SpringDamper>();
}
