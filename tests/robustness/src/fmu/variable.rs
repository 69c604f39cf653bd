//! What this importer asks of a variable as `mechfmu_host::description`'s parser gives it
//! (either standard's: FMI 2.0's `derivative` a 1-based index, FMI 3.0's a value
//! reference).

use mechfmu_host::description::Variable;

/// Questions about a [`Variable`] the importer's checks and calls ask.
pub trait VariableExt {
    fn is(&self, causality: &str) -> bool;
    fn is_tunable_parameter(&self) -> bool;
    /// A mass, a length or an inertia (by unit or quantity) declared with `min="0"`: a
    /// parameter that must be strictly positive.
    fn must_be_positive(&self) -> bool;
    /// The number of values the variable has (an FMI 3.0 array's elements; 1 for a scalar).
    fn len(&self) -> usize;
    fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// A square matrix (two equal dimensions of at least 2).
    fn is_square_matrix(&self) -> bool;
    /// The start value of element `k` (FMI 3.0's per element, a real scalar's at 0), if
    /// one is declared.
    fn start_at(&self, k: usize) -> Option<f64>;
}

impl VariableExt for Variable {
    fn is(&self, causality: &str) -> bool {
        self.causality == causality
    }
    fn is_tunable_parameter(&self) -> bool {
        self.causality == "parameter" && self.variability == "tunable"
    }
    fn must_be_positive(&self) -> bool {
        let physical = matches!(self.unit.as_deref(), Some("kg" | "m" | "kg.m2"))
            || matches!(
                self.quantity.as_deref(),
                Some("Mass" | "Length" | "MomentOfInertia" | "Inertia")
            );
        self.causality == "parameter" && physical && self.min == Some(0.0)
    }
    fn len(&self) -> usize {
        self.dimensions.iter().product()
    }
    fn is_square_matrix(&self) -> bool {
        matches!(self.dimensions[..], [a, b] if a == b && a > 1)
    }
    fn start_at(&self, k: usize) -> Option<f64> {
        (self.start_values.get(k).copied()).or(self.start.filter(|_| k == 0))
    }
}
