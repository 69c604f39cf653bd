use mechfmu::model::Variable;

mechfmu::mechanism! {
    /// A cart on a spring.
    pub struct Cart / CartValues {
        /// Stroke
        s: Variable::input("m", 0.5).min(1.0).max(0.0),
    }
}

fn main() {}
