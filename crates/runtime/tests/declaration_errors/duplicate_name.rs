use mechfmu::model::Variable;

mechfmu::mechanism! {
    /// A cart on a spring.
    pub struct Cart / CartValues {
        /// Mass
        m: Variable::parameter("kg", 1.0),
        /// Position
        x: Variable::state("m", 0.1, "v"),
        /// Velocity
        v: Variable::output("m/s"),
        /// Mass again
        m: Variable::parameter("kg", 2.0),
    }
}

fn main() {}
