use mechfmu::model::Variable;

mechfmu::mechanism! {
    /// A cart on a spring.
    pub struct Cart / CartValues {
        /// Velocity
        v: Variable::output("m/s"),
        /// Position
        x: Variable::state("m", 0.1, "v"),
        /// The same position
        y: Variable::state("m", 0.1, "v"),
    }
}

fn main() {}
