//! Setting and getting values: which variable may be set when, all or nothing; the
//! update that checks the parameters and computes the calculated parameters and outputs
//! before any value is read or a step taken; the inputs' derivatives for the next step.

use super::{variable, Freshness, Simulation};
use crate::model::{evaluate_all, Mechanism, SetPhase, ValueSet};

impl<M: Mechanism> Simulation<M> {
    /// Whether every value reference may be set to its value in `phase`: settable then,
    /// finite, and (after initialization) a parameter's value within its bounds. Returns
    /// whether a parameter is among them.
    pub fn check_set(vrs: &[u32], values: &[f64], phase: SetPhase) -> Result<bool, String> {
        let mut sets_parameter = false;
        for (&vr, &value) in vrs.iter().zip(values) {
            let var = variable::<M>(vr)?;
            if !var.settable(phase) {
                return Err(format!(
                    "variable `{}` cannot be set {}",
                    var.name,
                    match phase {
                        SetPhase::Running =>
                            "after initialization (only inputs and tunable parameters can)",
                        SetPhase::ContinuousTime =>
                            "in continuous-time mode (only continuous inputs can; tunable parameters in event mode)",
                        _ => "(it is computed by the model)",
                    }
                ));
            }
            if !value.is_finite() {
                return Err(format!("{} = {value} is not a finite number", var.name));
            }
            if var.causality == crate::model::Causality::Parameter {
                sets_parameter = true;
                if phase.initialized() {
                    var.check_value(value)?;
                }
            }
        }
        Ok(sets_parameter)
    }

    /// Sets value references to values, checking each is settable in `phase` and finite.
    /// All or nothing: on error no value has changed.
    pub fn set_real(&mut self, vrs: &[u32], values: &[f64], phase: SetPhase) -> Result<(), String> {
        self.held = None;
        let sets_parameter = Self::check_set(vrs, values, phase)?;
        let running = phase.initialized();
        // What to go back to if the calculated parameters cannot be computed: only a
        // parameter set while running can cause that (inputs alone, set at every step by
        // most importers, need no copy of every value).
        let saved = (running && sets_parameter).then(|| self.values.clone());
        let mut parameter_changed = false;
        let mut input_changed = false;
        for (&vr, &value) in vrs.iter().zip(values) {
            if let Some(i) = self.layout.input_index(vr as usize) {
                // After initialization an input set to the value it has (and without
                // derivatives) changes nothing: nothing to recompute (importers set every
                // input at every step, changed or not).
                if running
                    && self.inputs[i].to_bits() == value.to_bits()
                    && self.input_derivatives[i] == [0.0; 2]
                    && self.values.get(vr as usize).map(f64::to_bits) == Some(value.to_bits())
                {
                    continue;
                }
                self.values.set(vr as usize, value);
                // A new value starts a new polynomial: derivatives set before it are stale.
                self.inputs[i] = value;
                self.input_derivatives[i] = [0.0; 2];
                input_changed = true;
            } else {
                self.values.set(vr as usize, value);
                parameter_changed |=
                    M::VARIABLES[vr as usize].causality == crate::model::Causality::Parameter;
                // Before initialization anything settable may have changed.
                input_changed = true;
            }
        }
        if let Some(saved) = saved {
            if parameter_changed {
                if let Err(e) = M::calculate(&mut self.values) {
                    self.values = saved;
                    for (i, &vr) in self.layout.inputs.iter().enumerate() {
                        self.inputs[i] = self.values.get(vr).unwrap_or(0.0);
                    }
                    return Err(e);
                }
            }
        }
        if running && !parameter_changed {
            // Inputs only: the parameters passed `update` and are unchanged, so the outputs
            // need an evaluation, not the whole update.
            if input_changed {
                self.freshness.point_moved();
            }
        } else {
            self.freshness = Freshness::Unchecked;
        }
        Ok(())
    }

    /// Reads value references, bringing calculated values up to date first.
    /// One pass: a reference that is no variable ends it with an error, and what was
    /// written before it is undefined, as after any call that fails.
    pub fn get_real(&mut self, vrs: &[u32], out: &mut [f64]) -> Result<(), String> {
        debug_assert_eq!(vrs.len(), out.len(), "one value per reference");
        self.update()?;
        for (&vr, o) in vrs.iter().zip(out.iter_mut()) {
            variable::<M>(vr)?;
            *o = self.values.get(vr as usize).unwrap_or(f64::NAN);
        }
        Ok(())
    }

    /// Checks every parameter against its declared bounds and the mechanism's own rules,
    /// computes the calculated parameters and the outputs.
    #[inline]
    pub fn update(&mut self) -> Result<(), String> {
        // Nothing set since the last update, the case of every step in a plain run: one
        // comparison where it is called, not a call.
        if self.freshness == Freshness::Current {
            return Ok(());
        }
        self.bring_up_to_date()
    }

    #[inline(never)]
    fn bring_up_to_date(&mut self) -> Result<(), String> {
        self.held = None;
        match self.freshness {
            Freshness::Current => return Ok(()),
            Freshness::DerivativesCurrent | Freshness::PointMoved => {
                // As the full update below, without what only parameters change.
                let before = self.values.clone();
                self.evaluate_at_point();
                if let Err(message) = self.check_computed() {
                    self.values = before;
                    return Err(message);
                }
                self.freshness = Freshness::Current;
                return Ok(());
            }
            Freshness::Unchecked => {}
        }
        for (vr, var) in M::VARIABLES.iter().enumerate() {
            let value = self.values.get(vr).unwrap_or(f64::NAN);
            if var.causality == crate::model::Causality::Parameter {
                var.check_value(value)?;
            } else if var.start.is_some() && !value.is_finite() {
                return Err(format!("{} = {value} is not a finite number", var.name));
            }
        }
        // All or nothing: computed values that are not numbers are refused, not returned.
        let before = self.values.clone();
        let result = M::calculate(&mut self.values).and_then(|()| {
            self.mark_computed_derivatives();
            self.evaluate_at_point();
            self.check_derivatives_computed()?;
            self.check_computed()
        });
        if let Err(message) = result {
            self.values = before;
            return Err(message);
        }
        self.freshness = Freshness::Current;
        Ok(())
    }

    /// The derivatives the equations compute (not a state, an input or a parameter) before
    /// they do: [`UNCOMPUTED`], which only a derivative the equations never set still holds.
    fn mark_computed_derivatives(&mut self) {
        for &d in &self.layout.derivatives {
            if computed::<M>(d) {
                self.values.set(d, UNCOMPUTED);
            }
        }
    }

    /// Every derivative the equations compute was set by them: one forgotten would hold what
    /// it held before every evaluation, a silent constant.
    fn check_derivatives_computed(&self) -> Result<(), String> {
        let layout = &self.layout;
        for (&state, &d) in layout.states.iter().zip(&layout.derivatives) {
            let held = self.values.get(d).map(f64::to_bits);
            if computed::<M>(d) && held == Some(UNCOMPUTED.to_bits()) {
                return Err(format!(
                    "the equations never set `{}`, the derivative of `{}`: `evaluate` must compute the derivative of every state",
                    M::VARIABLES[d].name,
                    M::VARIABLES[state].name
                ));
            }
        }
        Ok(())
    }

    /// The values computed at the current point are numbers: continuous variables finite
    /// (as a step requires), calculated parameters not NaN (an infinite one, such as the
    /// damping ratio of a free mass, means something).
    fn check_computed(&self) -> Result<(), String> {
        for (vr, var) in M::VARIABLES.iter().enumerate() {
            let x = self.values.get(vr).unwrap_or(f64::NAN);
            let bad = if var.variability == crate::model::Variability::Continuous {
                !x.is_finite()
            } else {
                x.is_nan()
            };
            if bad {
                // The mechanism's account of why, else the point: the states.
                let why = match M::diagnose(&self.values) {
                    Some(why) => format!(": {why}"),
                    None => self.states_said(),
                };
                return Err(format!(
                    "`{}` evaluates to {x} at t = {} with these parameters and inputs{why}",
                    var.name,
                    self.time(),
                ));
            }
        }
        Ok(())
    }

    /// `, where r = 0, theta = 0.8`: the states' values, as a message continues.
    fn states_said(&self) -> String {
        let said: Vec<String> = (self.layout.states.iter())
            .map(|&vr| {
                let x = self.values.get(vr).unwrap_or(f64::NAN);
                format!("{} = {x}", M::VARIABLES[vr].name)
            })
            .collect();
        if said.is_empty() {
            String::new()
        } else {
            format!(", where {}", said.join(", "))
        }
    }

    /// Derivatives and all outputs at the current time, states and (held) inputs.
    pub(super) fn evaluate_at_point(&mut self) {
        for (i, &vr) in self.layout.inputs.iter().enumerate() {
            self.values.set(vr, self.inputs[i]);
        }
        evaluate_all::<M, f64>(&mut self.values);
        self.counters.evaluations += 1;
    }

    /// Sets derivatives of inputs for the next step (`orders` 1 or 2). All or nothing: every
    /// entry is checked before any is set.
    pub fn set_input_derivatives(
        &mut self,
        vrs: &[u32],
        orders: &[i32],
        values: &[f64],
    ) -> Result<(), String> {
        for ((&vr, &order), &value) in vrs.iter().zip(orders).zip(values) {
            self.input_derivative_slot(vr, order, value)?;
        }
        self.held = None;
        for ((&vr, &order), &value) in vrs.iter().zip(orders).zip(values) {
            let (i, k) = self.input_derivative_slot(vr, order, value)?;
            self.input_derivatives[i][k] = value;
        }
        Ok(())
    }

    /// Where the derivative of order `order` of input `vr` is kept, if `value` may go there.
    fn input_derivative_slot(
        &self,
        vr: u32,
        order: i32,
        value: f64,
    ) -> Result<(usize, usize), String> {
        let var = variable::<M>(vr)?;
        let Some(i) = self.layout.input_index(vr as usize) else {
            return Err(format!("variable `{}` is not an input", var.name));
        };
        if !(1..=2).contains(&order) {
            return Err(format!(
                "derivative order {order} of `{}` is not supported (1 or 2)",
                var.name
            ));
        }
        if !value.is_finite() {
            return Err(format!(
                "derivative of `{}` = {value} is not a finite number",
                var.name
            ));
        }
        Ok((i, order as usize - 1))
    }
}

/// A NaN no arithmetic makes (its payload spells "uncomp"): what a derivative the equations
/// compute holds before the first evaluation with new parameters.
const UNCOMPUTED: f64 = f64::from_bits(0x7ffc_756e_636f_6d70);

/// Whether the equations compute variable `vr`, a derivative: it is no state, input or
/// parameter, whose values come from elsewhere.
fn computed<M: Mechanism>(vr: usize) -> bool {
    let var = &M::VARIABLES[vr];
    !var.is_state()
        && matches!(
            var.causality,
            crate::model::Causality::Local | crate::model::Causality::Output
        )
}
