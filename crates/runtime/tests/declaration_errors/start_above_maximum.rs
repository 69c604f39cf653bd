use mechfmu::model::Variable;

mechfmu::mechanism! {
    /// A cart on a spring.
    pub struct Cart / CartValues {
        /// Damping ratio
        zeta: Variable::parameter("1", 1.5).min(0.0).max(1.0),
    }
}

fn main() {}
