//! Each mistake in a mechanism's generalized coordinates, a compile error that names the
//! coordinate (`mistakes.stderr`, one error for each).

include!("carts.rs");

cart!(listed_twice, x_ddot: Variable::output("m/s2"),
      2 coordinates: [Coordinate::free("x"), Coordinate::free("x")]);
cart!(velocity_as_coordinate, x_ddot: Variable::input("m/s2", 0.0),
      1 coordinates: [Coordinate::free("x_dot")]);
cart!(free_coordinate_with_an_input_acceleration, x_ddot: Variable::input("m/s2", 0.0),
      1 coordinates: [Coordinate::free("x")]);
cart!(drive_force_unknown, x_ddot: Variable::input("m/s2", 0.0),
      1 coordinates: [Coordinate::driven("x", "F")]);

/// Two carts whose drives write one force.
mod two_drives_one_force {
    use mechfmu::lagrange::{Coordinate, Lagrangian};
    use mechfmu::model::{lit, Experiment, Mechanism, Scalar, Variable};

    mechfmu::mechanism! {
        /// Two carts whose drives write one force.
        pub struct Carts / CartsValues {
            /// Mass
            m: Variable::parameter("kg", 1.0).positive(),
            /// First position
            x: Variable::state("m", 0.1, "x_dot"),
            /// First velocity
            x_dot: Variable::state("m/s", 0.0, "x_ddot"),
            /// First acceleration, prescribed
            x_ddot: Variable::input("m/s2", 0.0),
            /// Second position
            y: Variable::state("m", 0.1, "y_dot"),
            /// Second velocity
            y_dot: Variable::state("m/s", 0.0, "y_ddot"),
            /// Second acceleration, prescribed
            y_ddot: Variable::input("m/s2", 0.0),
            /// The drives' force
            F: Variable::output("N"),
        }
    }

    impl Lagrangian<2> for Carts {
        const COORDINATES: [Coordinate; 2] = [Coordinate::driven("x", "F"), Coordinate::driven("y", "F")];
        fn kinetic_energy<S: Scalar>(v: &CartsValues<S>) -> S {
            lit::<S>(0.5) * v.m * (v.x_dot * v.x_dot + v.y_dot * v.y_dot)
        }
        fn potential_energy<S: Scalar>(_: &CartsValues<S>) -> S {
            S::zero()
        }
    }

    impl Mechanism for Carts {
        const EXPERIMENT: Experiment = Experiment::until(1.0).step(0.1);
        fn evaluate<S: Scalar>(v: &mut CartsValues<S>) {
            Self::lagrange(v);
        }
    }

    pub fn compile() {
        let mut v = CartsValues::<f64>::default();
        Carts::evaluate(&mut v);
    }
}

fn main() {
    listed_twice::compile();
    velocity_as_coordinate::compile();
    free_coordinate_with_an_input_acceleration::compile();
    drive_force_unknown::compile();
    two_drives_one_force::compile();
}
