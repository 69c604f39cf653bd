//! What an FMU state captures of a simulation: everything that determines its future, as
//! plain data, and its restoring, checked.

use super::{Freshness, Simulation};
use crate::model::{Mechanism, ValueSet};
use crate::solver::{SolverMemory, Tolerance};

/// Everything that determines a simulation's future, as plain data: what an FMU state
/// captures and what its serialized form carries.
#[derive(Clone, Debug, PartialEq)]
pub struct SavedState {
    /// Every variable's value (by value reference), then the time.
    pub values: Vec<f64>,
    /// Input values at the current communication point, by input index.
    pub inputs: Vec<f64>,
    /// Their first and second time derivatives there.
    pub input_derivatives: Vec<[f64; 2]>,
    pub solver: SolverMemory,
    pub tolerance: Tolerance,
    pub warning_active: bool,
    pub dirty: bool,
}

impl<M: Mechanism> Simulation<M> {
    /// Captures everything that determines the future.
    pub fn save(&self) -> SavedState {
        let n = M::VARIABLES.len();
        let mut values: Vec<f64> = (0..n)
            .map(|vr| self.values.get(vr).unwrap_or(f64::NAN))
            .collect();
        values.push(self.values.time());
        SavedState {
            values,
            inputs: self.inputs.clone(),
            input_derivatives: self.input_derivatives.clone(),
            solver: self.solver.memory(),
            tolerance: self.tolerance,
            warning_active: self.warning_active,
            // A state saved with stale outputs is restored for a full update: the same
            // values, one check more.
            dirty: self.freshness != Freshness::Current,
        }
    }

    /// Restores a saved state; `Err` (and nothing changed) if it was not saved from this
    /// mechanism's layout, or if it claims values up to date that do not hold: parameters
    /// the model refuses, or an evaluation that is not a number (serialized bytes can be
    /// edited). A state saved before it was checked (dirty) is checked where it is used, as
    /// the values it was saved with would have been.
    pub fn restore(&mut self, saved: &SavedState) -> Result<(), String> {
        if saved.dirty {
            return self.restore_unchecked(saved);
        }
        let before = self.clone();
        self.restore_unchecked(saved)?;
        self.freshness = Freshness::Unchecked;
        // The same values evaluated again: bit for bit what was saved, or a refusal.
        if let Err(message) = self.update() {
            *self = before;
            return Err(format!("the state's values do not hold: {message}"));
        }
        Ok(())
    }

    fn restore_unchecked(&mut self, saved: &SavedState) -> Result<(), String> {
        self.held = None;
        let n = M::VARIABLES.len();
        if saved.values.len() != n + 1
            || saved.inputs.len() != self.inputs.len()
            || saved.input_derivatives.len() != self.inputs.len()
        {
            return Err(format!(
                "the state has {} values and {} inputs; {} has {} and {}",
                saved.values.len().saturating_sub(1),
                saved.inputs.len(),
                M::NAME,
                n,
                self.inputs.len()
            ));
        }
        for (vr, &x) in saved.values[..n].iter().enumerate() {
            self.values.set(vr, x);
        }
        self.values.set_time(saved.values[n]);
        self.inputs.copy_from_slice(&saved.inputs);
        self.input_derivatives
            .copy_from_slice(&saved.input_derivatives);
        self.solver.restore(saved.solver);
        self.tolerance = saved.tolerance;
        self.warning_active = saved.warning_active;
        self.freshness = if saved.dirty {
            Freshness::Unchecked
        } else {
            Freshness::Current
        };
        Ok(())
    }
}
