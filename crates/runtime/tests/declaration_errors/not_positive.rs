use mechfmu::model::Variable;

mechfmu::mechanism! {
    /// A cart on a spring.
    pub struct Cart / CartValues {
        /// Mass
        m: Variable::parameter("kg", 0.0).positive(),
    }
}

fn main() {}
