use mechfmu::model::{Experiment, Mechanism, Scalar, Terminal, Variable, TRANSLATIONAL};

mechfmu::mechanism! {
    /// A mass pushed by a force.
    pub struct Body / BodyValues {
        /// Mass
        m: Variable::parameter("kg", 1.0).positive(),
        /// Force
        F: Variable::input("N", 0.0),
        /// Position
        x: Variable::state("m", 0.0, "v"),
        /// Velocity
        v: Variable::state("m/s", 0.0, "a"),
        /// Acceleration
        a: Variable::output("m/s2"),
    }
}

impl Mechanism for Body {
    const EXPERIMENT: Experiment = Experiment::until(1.0);
    const TERMINALS: &'static [Terminal] =
        &[Terminal::new("flange", TRANSLATIONAL, "", &[("s", "x"), ("v", "v"), ("f", "F")])];
    fn evaluate<S: Scalar>(v: &mut BodyValues<S>) {
        v.a = v.F / v.m;
    }
}

mechfmu::mechanism! {
    /// A spring pulling a point back to the origin.
    pub struct Anchor / AnchorValues {
        /// Stiffness
        k: Variable::tunable("N/m", 1.0).min(0.0),
        /// Position
        x: Variable::input("m", 0.0),
        /// Force
        F: Variable::output("N"),
    }
}

impl Mechanism for Anchor {
    const EXPERIMENT: Experiment = Experiment::until(1.0);
    const TERMINALS: &'static [Terminal] =
        &[Terminal::new("end", TRANSLATIONAL, "", &[("s", "x"), ("f", "F")])];
    fn evaluate<S: Scalar>(v: &mut AnchorValues<S>) {
        v.F = -v.k * v.x;
    }
}

mechfmu::system! {
    /// Every mistake once.
    pub struct Mistaken {
        components {
            body: Body,
            anchor: Anchor,
            anchor: Anchor,
            file: fmu("parts/Part.zip"),
        }
        connections {
            body.x => anchr.x,
            body.position => anchor.x,
            body.F => anchor.x,
            body.v => anchor.x,
            anchor.F => body.a,
            anchor.F => body.F,
            anchor.F => body.F,
        }
        terminals {
            body.flange <=> anchor.end,
            body.flange <=> body.flange,
            body.flange <=> anchor.start,
        }
        parameter_sets {
            default { body.a = 1.0, body.m = 0.0, anchor.k = -1.0, body.m = 2.0 }
            default { anchor.k = 2.0 }
        }
        experiment: Experiment::until(1.0),
    }
}

fn main() {}
