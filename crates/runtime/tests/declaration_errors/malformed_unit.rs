use mechfmu::model::Variable;

mechfmu::mechanism! {
    /// A cart on a spring.
    pub struct Cart / CartValues {
        /// Damping
        c: Variable::parameter("N.s//m", 0.5),
    }
}

fn main() {}
