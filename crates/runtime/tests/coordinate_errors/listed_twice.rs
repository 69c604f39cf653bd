use mechfmu::lagrange::{Coordinate, Lagrangian};
use mechfmu::model::{lit, Experiment, Mechanism, Scalar, Variable};

mechfmu::mechanism! {
    /// A coordinate listed twice.
    pub struct Cart / CartValues {
        /// Mass
        m: Variable::parameter("kg", 1.0).positive(),
        /// Position
        x: Variable::state("m", 0.1, "x_dot"),
        /// Velocity
        x_dot: Variable::state("m/s", 0.0, "x_ddot"),
        /// Acceleration
        x_ddot: Variable::output("m/s2"),
    }
}

impl Lagrangian<2> for Cart {
    const COORDINATES: [Coordinate; 2] = [Coordinate::free("x"), Coordinate::free("x")];
    fn kinetic_energy<S: Scalar>(v: &CartValues<S>) -> S {
        lit::<S>(0.5) * v.m * v.x_dot * v.x_dot
    }
    fn potential_energy<S: Scalar>(_: &CartValues<S>) -> S {
        S::zero()
    }
}

impl Mechanism for Cart {
    const EXPERIMENT: Experiment = Experiment { start: 0.0, stop: 1.0, step: 0.1, tolerance: 1e-6 };
    fn evaluate<S: Scalar>(v: &mut CartValues<S>) {
        Self::lagrange(v);
    }
}

fn main() {
    // The coordinates are resolved where the equations are compiled for a scalar.
    let mut v = CartValues::<f64>::default();
    Cart::evaluate(&mut v);
}
