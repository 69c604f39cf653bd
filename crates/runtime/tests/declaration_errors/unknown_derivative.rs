use mechfmu::model::Variable;

mechfmu::mechanism! {
    /// A cart on a spring.
    pub struct Cart / CartValues {
        /// Mass
        m: Variable::parameter("kg", 1.0).positive(),
        /// Position
        x: Variable::state("m", 0.1, "x_dot"),
        /// Velocity
        x_dot: Variable::state("m/s", 0.0, "x_dddot"),
        /// Acceleration
        x_ddot: Variable::output("m/s2"),
    }
}

fn main() {}
