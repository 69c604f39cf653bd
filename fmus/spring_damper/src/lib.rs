//! `SpringDamper`: a massless spring and damper between two points on a line, the coupling
//! element that joins two mechanisms (a system's component, not a body: it has no state).
//!
//! `F_a = k (x_b - x_a - l0) + c (v_b - v_a)`, `F_b = -F_a`, `E = ½ k (x_b - x_a - l0)²`

#![forbid(unsafe_code)]

use mechfmu::model::{lit, Experiment, Mechanism, Scalar, Terminal, Variable, TRANSLATIONAL};

mechfmu::mechanism! {
    /// A massless spring and damper between points a and b on a line: the forces on its ends
    /// from their positions and velocities, F_a = k (x_b - x_a - l0) + c (v_b - v_a) = -F_b.
    pub struct SpringDamper / SpringDamperValues {
        /// Spring stiffness
        k: Variable::tunable("N/m", 1.0).min(0.0),
        /// Damping coefficient
        c: Variable::tunable("N.s/m", 0.0).min(0.0),
        /// Unstretched length of the spring
        l0: Variable::tunable("m", 0.0),
        /// Position of point a
        x_a: Variable::input("m", 0.0),
        /// Position of point b
        x_b: Variable::input("m", 0.0),
        /// Velocity of point a
        v_a: Variable::input("m/s", 0.0),
        /// Velocity of point b
        v_b: Variable::input("m/s", 0.0),
        /// Force on point a, positive along the line
        F_a: Variable::output("N"),
        /// Force on point b, positive along the line
        F_b: Variable::output("N"),
        /// Energy stored in the spring
        E: Variable::output("J"),
    }
}

impl Mechanism for SpringDamper {
    const EXPERIMENT: Experiment = Experiment::until(1.0).step(0.01).tolerance(1e-6);

    const TERMINALS: &'static [Terminal] = &[
        Terminal::new(
            "a",
            TRANSLATIONAL,
            "End a: its position and velocity, and the force the spring exerts on it",
            &[("s", "x_a"), ("v", "v_a"), ("f", "F_a")],
        ),
        Terminal::new(
            "b",
            TRANSLATIONAL,
            "End b: its position and velocity, and the force the spring exerts on it",
            &[("s", "x_b"), ("v", "v_b"), ("f", "F_b")],
        ),
    ];

    const NOTES: &'static str = "
        A coupling element: it joins two mechanisms in a system (as the third spring and
        damper of `TwoMassOscillator` joins its masses), and has no mass and no state. With
        the stretch `s = x_b - x_a - l0`:

            F_a = k s + c (v_b - v_a)      force on point a, positive along the line
            F_b = -F_a                     force on point b
            E   = ½ k s²                   energy stored in the spring

        Every output depends directly on the inputs (direct feedthrough): an importer that
        sets an input reads the new forces at once, without a step. `k` and `c` may be 0; a
        negative one is refused at initialization.

        The references `mechfmu validate` runs are these formulas, at random inputs.
    ";

    // No state, so no derivative: the outputs, at once from the inputs.
    fn evaluate<S: Scalar>(v: &mut SpringDamperValues<S>) {
        let stretch = v.x_b - v.x_a - v.l0;
        v.F_a = v.k * stretch + v.c * (v.v_b - v.v_a);
        v.F_b = -v.F_a;
        v.E = lit::<S>(0.5) * v.k * stretch * stretch;
    }
}

// The FMU's functions; none when the crate is compiled into a system's FMU.
#[cfg(not(feature = "component"))]
mechfmu::export_fmu!(SpringDamper);
