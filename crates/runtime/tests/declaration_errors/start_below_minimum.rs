use mechfmu::model::Variable;

mechfmu::mechanism! {
    /// A cart on a spring.
    pub struct Cart / CartValues {
        /// Gravity
        g: Variable::parameter("m/s2", -9.81).min(0.0),
    }
}

fn main() {}
