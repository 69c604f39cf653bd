use mechfmu::model::Variable;

mechfmu::mechanism! {
    /// A cart on a spring.
    pub struct Cart / CartValues {
        /// Position
        x: Variable::state("m", 0.1, "v"),
        /// Velocity
        v: Variable::output("m/ss"),
    }
}

fn main() {}
