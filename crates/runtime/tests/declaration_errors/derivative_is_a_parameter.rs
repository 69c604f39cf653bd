use mechfmu::model::Variable;

mechfmu::mechanism! {
    /// A cart on a spring.
    pub struct Cart / CartValues {
        /// Stiffness
        k: Variable::parameter("N/m", 10.0),
        /// Position
        x: Variable::state("m", 0.1, "k"),
    }
}

fn main() {}
