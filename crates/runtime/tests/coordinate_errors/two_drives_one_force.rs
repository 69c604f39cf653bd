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
    const EXPERIMENT: Experiment = Experiment { start: 0.0, stop: 1.0, step: 0.1, tolerance: 1e-6 };
    fn evaluate<S: Scalar>(v: &mut CartsValues<S>) {
        Self::lagrange(v);
    }
}

fn main() {
    // The coordinates are resolved where the equations are compiled for a scalar.
    let mut v = CartsValues::<f64>::default();
    Carts::evaluate(&mut v);
}
