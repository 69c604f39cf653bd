//! The tutorial's mechanism without states (docs/tutorial.md, "A mechanism without
//! states"): a linear spring-damper between two ends, its force a direct function of its
//! inputs. The code between the `tutorial` lines is the tutorial's, line for line (checked
//! below), and passes the checks every FMU passes: FMI 2.0 and FMI 3.0, Co-Simulation and
//! Model Exchange.

// tutorial: begin
use mechfmu::model::{Experiment, Mechanism, Scalar, Variable};

mechfmu::mechanism! {
    /// A linear spring and a damper side by side between two ends on a line, the second at
    /// x2 > x1: the force F with which they pull the ends together.
    pub struct TensionLink / TensionLinkValues {
        /// Stiffness of the spring
        k: Variable::tunable("N/m", 100.0).min(0.0),
        /// Damping coefficient of the damper
        c: Variable::tunable("N.s/m", 2.0).min(0.0),
        /// Unstretched length of the spring
        l0: Variable::parameter("m", 1.0).positive(),
        /// Position of the first end
        x1: Variable::input("m", 0.0),
        /// Velocity of the first end
        v1: Variable::input("m/s", 0.0),
        /// Position of the second end
        x2: Variable::input("m", 1.0),
        /// Velocity of the second end
        v2: Variable::input("m/s", 0.0),
        /// Tension: the force pulling the ends together
        F: Variable::output("N"),
    }
}

impl Mechanism for TensionLink {
    const EXPERIMENT: Experiment = Experiment::until(1.0).step(0.01).tolerance(1e-8);

    // No state, so no derivative: the output, at once from the inputs.
    fn evaluate<S: Scalar>(v: &mut TensionLinkValues<S>) {
        v.F = v.k * (v.x2 - v.x1 - v.l0) + v.c * (v.v2 - v.v1);
    }
}

mechfmu::export_fmu!(TensionLink);
// tutorial: end

use mechfmu_testkit::harness::Harness;

/// F = k (x2 - x1 - l0) + c (v2 - v1), read right after the inputs are set: no step between.
#[test]
fn the_force_follows_the_inputs_at_once() {
    let mut fmu = Harness::<TensionLink>::new();
    fmu.initialize(None, 0.0, &[("k", 50.0), ("c", 3.0), ("x2", 1.2)])
        .unwrap();
    assert_eq!(fmu.get("F"), 50.0 * (1.2 - 1.0));
    for (x1, v1, x2, v2) in [(0.1, 0.5, 1.5, -0.25), (-2.0, 0.0, -0.5, 4.0)] {
        for (name, value) in [("x1", x1), ("v1", v1), ("x2", x2), ("v2", v2)] {
            fmu.set(name, value);
        }
        let want = 50.0 * (x2 - x1 - 1.0) + 3.0 * (v2 - v1);
        assert!(
            (fmu.get("F") - want).abs() <= 1e-12 * want.abs(),
            "{x1} {v1} {x2} {v2}"
        );
    }
    // A step keeps the inputs, so the force; a new input changes it at once.
    let held = fmu.get("F");
    fmu.step_to(0.5, 0.1).unwrap();
    assert_eq!(fmu.get("F"), held);
    fmu.set("v2", 1.0);
    assert!((fmu.get("F") - (50.0 * (-0.5 + 2.0 - 1.0) + 3.0 * 1.0)).abs() < 1e-12);
}

/// Both model descriptions say so: no state, and F depends on each input directly.
#[test]
fn the_model_descriptions_have_no_state_and_f_depends_on_every_input() {
    mechfmu_testkit::formulas::declares_direct_feedthrough::<TensionLink>(&[(
        "F",
        &["x1", "v1", "x2", "v2"],
    )]);
}

/// The checks every mechfmu FMU passes (reset, FMU states, serialization, derivatives,
/// threads, Model Exchange, FMI 3.0).
#[test]
fn conforms() {
    mechfmu_testkit::conformance::check::<TensionLink>();
}

/// The tutorial shows the code above, between its own `tutorial` lines.
#[test]
fn the_tutorial_shows_this_code() {
    let between = |text: &'static str, begin: &str, end: &str| {
        let from = text.find(begin).expect(begin) + begin.len();
        text[from..][..text[from..].find(end).expect(end)]
            .trim()
            .to_string()
    };
    let here = between(
        include_str!("tension_link.rs"),
        "// tutorial: begin",
        "// tutorial: end",
    );
    let tutorial = between(
        include_str!("../../../docs/tutorial.md"),
        "<!-- tension-link: begin -->\n```rust",
        "```\n<!-- tension-link: end -->",
    );
    assert_eq!(tutorial, here, "docs/tutorial.md shows other code");
}
