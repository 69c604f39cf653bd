use mechfmu::model::Variable;

mechfmu::mechanism! {
    /// A cart on a spring.
    pub struct Cart / CartValues {
        /// Length
        l: Variable::parameter("m", f64::NAN),
    }
}

fn main() {}
