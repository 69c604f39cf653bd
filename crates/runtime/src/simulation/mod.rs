//! A mechanism being simulated: its values, its states under the ODE solver, and the rules
//! of setting and getting values. Knows nothing of C or of the FMI state machine.

mod bench;
mod derivatives;
mod model_exchange;
#[cfg(test)]
mod tests;

pub use bench::{isolate, Part, ISOLATES};

use crate::model::{evaluate_all, Layout, Mechanism, Monitor, SetPhase, ValueSet, Variable};
use crate::solver::{
    OdeSystem, Solver, SolverError, SolverMemory, StateVector, StepStats, Tolerance,
};

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

/// Why a communication step did not complete.
#[derive(Clone, Debug, PartialEq)]
pub enum StepFailure {
    /// The step cannot be done as asked (bad arguments): nothing happened.
    Rejected(String),
    /// The model or the solver stopped at `time` (the last valid time): `fmi2Discard`.
    Stopped {
        time: f64,
        message: String,
        /// The mechanism's monitor refused the next point (a limit of the model, located
        /// inside the step), not the solver or a value that is not a number.
        limit: bool,
    },
}

/// Work done by a simulation since it was created: cumulative, never reset, not part of
/// the saved state. For benchmarks and statistics (`mechfmu_counters`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Counters {
    /// Communication steps completed.
    pub steps: u64,
    /// Solver steps accepted.
    pub accepted: u64,
    /// Solver steps rejected (error too large, or NaN/inf).
    pub rejected: u64,
    /// Evaluations of the model equations on `f64` (`Mechanism::evaluate`: right-hand
    /// side, outputs, monitor). The derivative-free outputs computed once per communication
    /// point (`Mechanism::outputs`) are not counted.
    pub evaluations: u64,
}

/// A mechanism's running simulation.
pub struct Simulation<M: Mechanism> {
    layout: Layout,
    values: M::Values<f64>,
    /// Input values as set at the current communication point (by input index).
    inputs: Vec<f64>,
    /// First and second time derivatives of the inputs at the communication point.
    input_derivatives: Vec<[f64; 2]>,
    solver: Solver<M::State>,
    tolerance: Tolerance,
    /// Whether the monitor's warning condition holds (so it is logged once per episode).
    warning_active: bool,
    /// The monitor's warnings raised by the last step. Kept here rather than returned, so
    /// that a step without any (nearly all) moves no list around.
    warnings: Vec<String>,
    /// Values were set since calculated parameters and outputs were last computed.
    dirty: bool,
    /// Only inputs changed since the outputs were last computed: the parameters are as
    /// checked, the calculated parameters current; the outputs need one evaluation.
    stale: bool,
    /// With `stale`: `evaluate` has run at the point the values hold since it last moved,
    /// so the derivatives are current and only what `outputs` computes is not (Model
    /// Exchange: `fmi2GetDerivatives` evaluates no more than that). Meaningless otherwise.
    derivatives_current: bool,
    /// The event indicators' value references ([`Mechanism::EVENT_INDICATORS`]).
    indicators: Vec<usize>,
    /// Whether the inputs are held over the next step (see [`Simulation::inputs_held`]),
    /// once known: forgotten by everything that sets inputs, their derivatives or values.
    held: Option<bool>,
    counters: Counters,
}

impl<M: Mechanism> Clone for Simulation<M> {
    fn clone(&self) -> Self {
        Simulation {
            layout: self.layout.clone(),
            values: self.values.clone(),
            inputs: self.inputs.clone(),
            input_derivatives: self.input_derivatives.clone(),
            solver: self.solver.clone(),
            tolerance: self.tolerance,
            warning_active: self.warning_active,
            warnings: self.warnings.clone(),
            dirty: self.dirty,
            stale: self.stale,
            derivatives_current: self.derivatives_current,
            indicators: self.indicators.clone(),
            held: self.held,
            counters: self.counters,
        }
    }
}

/// The start values of a mechanism (0 where none is declared), at time `t`.
pub fn start_values<M: Mechanism>(t: f64) -> M::Values<f64> {
    let mut values = M::zeros::<f64>();
    for (vr, v) in M::VARIABLES.iter().enumerate() {
        values.set(vr, v.start.unwrap_or(0.0));
    }
    values.set_time(t);
    values
}

impl<M: Mechanism> Simulation<M> {
    pub fn new(layout: Layout) -> Self {
        let n_inputs = layout.inputs.len();
        let mut sim = Simulation {
            layout,
            values: start_values::<M>(0.0),
            inputs: vec![0.0; n_inputs],
            input_derivatives: vec![[0.0; 2]; n_inputs],
            solver: Solver::new(),
            tolerance: default_tolerance::<M>(),
            warning_active: false,
            warnings: Vec::new(),
            dirty: true,
            stale: false,
            derivatives_current: false,
            // Checked at compile time by `export_fmu!`, and when an instance is made.
            indicators: crate::model::event_indicator_references(M::VARIABLES, M::EVENT_INDICATORS)
                .unwrap_or_default(),
            held: None,
            counters: Counters::default(),
        };
        sim.reset();
        sim
    }

    /// Back to the start values, start time 0, default tolerance, a fresh solver.
    pub fn reset(&mut self) {
        self.held = None;
        self.values = start_values::<M>(0.0);
        for (i, &vr) in self.layout.inputs.iter().enumerate() {
            self.inputs[i] = self.values.get(vr).unwrap_or(0.0);
        }
        self.input_derivatives
            .iter_mut()
            .for_each(|d| *d = [0.0; 2]);
        self.solver.forget();
        self.tolerance = default_tolerance::<M>();
        self.warning_active = false;
        self.dirty = true;
        self.stale = false;
    }

    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    pub fn time(&self) -> f64 {
        self.values.time()
    }

    /// The monitor's warnings raised by the last step (each once per episode).
    pub fn warnings(&self) -> &[String] {
        &self.warnings
    }

    pub fn values(&self) -> &M::Values<f64> {
        &self.values
    }

    /// `fmi2SetupExperiment`: the relative tolerance (None: the DefaultExperiment's) and the
    /// start time.
    pub fn setup(
        &mut self,
        relative_tolerance: Option<f64>,
        start_time: f64,
    ) -> Result<(), String> {
        if !start_time.is_finite() {
            return Err(format!("startTime = {start_time} is not a finite number"));
        }
        let tol = relative_tolerance.unwrap_or(M::EXPERIMENT.tolerance);
        self.tolerance = Tolerance::new(tol, tol)
            .filter(|_| tol > 0.0)
            .ok_or_else(|| format!("tolerance = {tol} must be a finite number > 0"))?;
        self.values.set_time(start_time);
        // The outputs (if ever computed) belong to the old time.
        self.dirty = true;
        Ok(())
    }

    /// Sets value references to values, checking each is settable in `phase` and finite.
    /// All or nothing: on error no value has changed.
    pub fn set_real(&mut self, vrs: &[u32], values: &[f64], phase: SetPhase) -> Result<(), String> {
        self.held = None;
        let mut sets_parameter = false;
        for (&vr, &value) in vrs.iter().zip(values) {
            let var = variable::<M>(vr)?;
            if !var.settable(phase) {
                return Err(format!(
                    "variable `{}` (value reference {vr}) cannot be set {}",
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
                self.stale = true;
                self.derivatives_current = false;
            }
        } else {
            self.dirty = true;
        }
        Ok(())
    }

    /// Reads value references, bringing calculated values up to date first.
    pub fn get_real(&mut self, vrs: &[u32], out: &mut [f64]) -> Result<(), String> {
        for &vr in vrs {
            variable::<M>(vr)?;
        }
        self.update()?;
        for (&vr, o) in vrs.iter().zip(out.iter_mut()) {
            *o = self.values.get(vr as usize).unwrap_or(f64::NAN);
        }
        Ok(())
    }

    /// Checks every parameter against its declared bounds and the mechanism's own rules,
    /// computes the calculated parameters and the outputs.
    #[inline]
    pub fn update(&mut self) -> Result<(), String> {
        // Nothing set since the last update, the case of every step in a plain run: a test
        // of two flags where it is called, not a call.
        if !(self.dirty || self.stale) {
            return Ok(());
        }
        self.bring_up_to_date()
    }

    #[inline(never)]
    fn bring_up_to_date(&mut self) -> Result<(), String> {
        self.held = None;
        if !self.dirty {
            if self.stale {
                // As the full update below, without what only parameters change.
                let before = self.values.clone();
                self.evaluate_at_point();
                if let Err(message) = self.check_computed() {
                    self.values = before;
                    return Err(message);
                }
                self.stale = false;
            }
            return Ok(());
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
            self.evaluate_at_point();
            self.check_computed()
        });
        if let Err(message) = result {
            self.values = before;
            return Err(message);
        }
        self.dirty = false;
        self.stale = false;
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
                return Err(format!(
                    "`{}` evaluates to {x} at t = {} with these parameters and inputs",
                    var.name,
                    self.time()
                ));
            }
        }
        Ok(())
    }

    /// Derivatives and all outputs at the current time, states and (held) inputs.
    fn evaluate_at_point(&mut self) {
        for (i, &vr) in self.layout.inputs.iter().enumerate() {
            self.values.set(vr, self.inputs[i]);
        }
        evaluate_all::<M, f64>(&mut self.values);
        self.counters.evaluations += 1;
    }

    /// Work done so far (cumulative since the simulation was created).
    pub fn counters(&self) -> Counters {
        self.counters
    }

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
            dirty: self.dirty || self.stale,
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
        self.dirty = true;
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
        self.dirty = saved.dirty;
        self.stale = false;
        Ok(())
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
            return Err(format!(
                "variable `{}` (value reference {vr}) is not an input",
                var.name
            ));
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

    /// Advances from `t` (which must be the current time) by `h`.
    ///
    /// Never inlined: `fmi2DoStep` and the benchmark's `Part::Step` then run the same
    /// machine code, so the difference of their times is the FMI layer alone (inlined into
    /// each, the two copies are compiled apart and can differ by up to 50 ns per step).
    #[inline(never)]
    // A negated comparison is how one comparison rejects NaN too (see the checks).
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    pub fn step(&mut self, t: f64, h: f64) -> Result<StepStats, StepFailure> {
        let now = self.time();
        // Each check is one comparison that NaN fails (as it fails every comparison): 30
        // instructions fewer per step than `is_finite` and NaN-aware `max` (valgrind).
        if !(h > 0.0 && h <= f64::MAX) {
            return Err(StepFailure::Rejected(format!(
                "communicationStepSize = {h} must be a finite number > 0"
            )));
        }
        // `now` and `h` are finite here: no NaN for `max` to handle.
        let larger = |a: f64, b: f64| if a > b { a } else { b };
        if !((t - now).abs() <= 1e-9 * larger(larger(now.abs(), h), 1e-300)) {
            return Err(StepFailure::Rejected(format!(
                "currentCommunicationPoint = {t} does not match the FMU's time {now}"
            )));
        }
        self.update().map_err(StepFailure::Rejected)?;
        let t_end = t + h;
        if !(t_end > t && t_end <= f64::MAX) {
            return Err(StepFailure::Rejected(format!(
                "communicationStepSize = {h} is too small to advance from t = {t}"
            )));
        }
        let mut y = self.state_vector();
        // What to go back to if the step ends on values that are not numbers: the states
        // at t are enough, the rest of the values at t is their evaluation (see `undo`).
        let (start, memory, warning_active) = (y, self.solver.memory(), self.warning_active);
        self.warnings.clear();
        let mut time = t;
        let inputs_fixed = self.inputs_held();
        let mut system = System::<M>::new(
            &mut self.values,
            &self.inputs,
            &self.input_derivatives,
            t,
            &mut self.warning_active,
            &mut self.warnings,
            inputs_fixed,
        );
        let result = self
            .solver
            .integrate(&mut system, &mut time, t_end, &mut y, self.tolerance);
        // Whatever happened, the values describe the last accepted point. After a successful
        // step they already do, without a check: the last evaluation of every accepted step
        // is its new point (Dopri5's and DOP853's first-same-as-last stage), and the last
        // step lands on `t_end` exactly. After a failed one they may hold a rejected stage.
        // (A system without states has no evaluations: its values are still at `t`.) The
        // stages computed the derivatives only: the outputs no derivative needs are computed
        // here, once per communication point, where they become visible.
        if result.is_err() || M::State::DIM == 0 {
            system.evaluate_at(time, &y);
        }
        debug_assert!(
            system.holds(time, &y),
            "the values hold the step's end point"
        );
        self.counters.evaluations += system.evaluations;
        complete_point::<M>(system.values);
        // The solver accepts only a finite end point with finite derivatives there (a
        // non-finite one rejects the step): after a successful step, the states and their
        // derivatives need no second look unless a projection has moved them.
        let non_finite = if result.is_ok() && !M::PROJECTED {
            self.first_non_finite(M::CONTINUOUS_UNCHECKED)
        } else {
            self.first_non_finite(M::CONTINUOUS)
        };
        if let Some(name) = non_finite {
            self.undo(t, &start);
            self.solver.restore(memory);
            self.warning_active = warning_active;
            let why = result.err().map(|e| format!(" ({})", describe(&e)));
            return Err(StepFailure::Stopped {
                time: t,
                limit: false,
                message: format!(
                    "`{name}` became non-finite before t = {t_end}{}; the step is undone, the values are those at t = {t}",
                    why.unwrap_or_default()
                ),
            });
        }
        // The inputs move on along their polynomials to the new communication point. Held
        // inputs (no derivatives, see `System::inputs_fixed`) stay bit for bit what they
        // were, which the values hold already: nothing to do.
        if !inputs_fixed {
            let dt = time - t;
            for (i, &vr) in self.layout.inputs.iter().enumerate() {
                let [d1, d2] = self.input_derivatives[i];
                self.inputs[i] += dt * (d1 + 0.5 * dt * d2);
                self.input_derivatives[i] = [d1 + dt * d2, d2];
                self.values.set(vr, self.inputs[i]);
            }
        }
        self.values
            .set_time(if result.is_ok() { t_end } else { time });
        match result {
            Ok(stats) => {
                self.counters.steps += 1;
                self.counters.accepted += stats.accepted;
                self.counters.rejected += stats.rejected;
                Ok(stats)
            }
            Err(e) => Err(StepFailure::Stopped {
                time,
                limit: matches!(e, SolverError::Stopped { .. }),
                message: describe(&e),
            }),
        }
    }

    /// Whether the inputs stay at their values over the next step and the values hold
    /// exactly those, so that the stages need not load them (see `System::inputs_fixed`).
    /// Known from the last step unless something was set since: a step with held inputs
    /// changes neither the inputs nor their derivatives, and one with moving inputs leaves
    /// their derivatives nonzero.
    #[inline]
    fn inputs_held(&mut self) -> bool {
        if let Some(held) = self.held {
            return held;
        }
        // `load` writes u + dt (d1 + dt d2 / 2), which is u exactly when d1 = d2 = 0 and u is
        // not -0 (-0 + 0 = +0); `evaluate` writes derivatives and outputs, never inputs.
        let held = self.input_derivatives.iter().all(|d| *d == [0.0; 2])
            && (self.layout.inputs.iter().zip(&self.inputs)).all(|(&vr, &u)| {
                u.to_bits() != (-0.0f64).to_bits()
                    && self.values.get(vr).map(f64::to_bits) == Some(u.to_bits())
            });
        self.held = Some(held);
        held
    }

    /// Back to the values at the start of a step, from its time and states: they were the
    /// complete evaluation at that point (`update` leaves them so, and so does every
    /// step), and an evaluation is a function of the states, inputs (still those at `t`),
    /// parameters and time, so evaluating again gives them back bit for bit. Cheaper than
    /// copying all the values at the start of every step for a path taken so rarely.
    fn undo(&mut self, t: f64, states: &M::State) {
        self.held = None;
        store_point::<M>(&mut self.values, t, states);
        self.evaluate_at_point();
    }

    /// The states the values hold, as the solver's vector.
    fn state_vector(&self) -> M::State {
        let mut y = M::State::ZERO;
        for (y, &vr) in y.as_mut_slice().iter_mut().zip(M::STATES) {
            *y = self.values.get(vr).unwrap_or(f64::NAN);
        }
        y
    }

    /// The first of the variables `checked` that is not finite. `checked` is one of the
    /// mechanism's constants, so the common case, all finite, unrolls into straight-line
    /// vector code, no branch.
    #[inline(always)]
    fn first_non_finite(&self, checked: &'static [usize]) -> Option<&'static str> {
        let finite = |vr: usize| self.values.get(vr).is_some_and(f64::is_finite);
        // `x - x` is +0.0 (all bits clear) for a finite `x` and NaN (some bits set) for the
        // others, and OR is associative, so the compiler pairs the variables into vector
        // instructions: 8-45 fewer instructions per step than `is_finite` on each (valgrind).
        #[allow(clippy::eq_op)]
        let nonfinite_bits = (checked.iter())
            .map(|&vr| self.values.get(vr).map_or(u64::MAX, |x| (x - x).to_bits()))
            .fold(0, |any, bits| any | bits);
        if nonfinite_bits == 0 {
            return None;
        }
        (checked.iter())
            .find(|&&vr| !finite(vr))
            .map(|&vr| M::VARIABLES[vr].name)
    }
}

/// The model's work at a communication point, on values the solver left evaluated there:
/// the projection back onto the manifold (with the evaluation it calls for) and the
/// outputs no derivative needs (`Mechanism::outputs`), which the stages do not compute.
#[inline]
fn complete_point<M: Mechanism>(values: &mut M::Values<f64>) {
    if M::PROJECTED {
        M::project(values);
        M::evaluate(values);
    }
    M::outputs(values);
}

fn describe(e: &SolverError) -> String {
    match e {
        SolverError::Stopped { message, .. } => message.clone(),
        other => other.to_string(),
    }
}

/// The default experiment's tolerance, as relative and absolute tolerance; a mechanism
/// whose default is not a valid tolerance does not compile.
fn default_tolerance<M: Mechanism>() -> Tolerance {
    const {
        match Tolerance::new(M::EXPERIMENT.tolerance, M::EXPERIMENT.tolerance) {
            Some(tolerance) => tolerance,
            None => panic!("the default experiment's tolerance must be a finite number >= 0"),
        }
    }
}

/// The variable of value reference `vr`, or a message naming the bad reference.
pub fn variable<M: Mechanism>(vr: u32) -> Result<&'static Variable, String> {
    M::VARIABLES.get(vr as usize).ok_or_else(|| {
        format!(
            "value reference {vr} is not a variable of {} (it has {} real variables, 0..{})",
            M::NAME,
            M::VARIABLES.len(),
            M::VARIABLES.len().saturating_sub(1)
        )
    })
}

/// `y` (which the solver passes with exactly `V::DIM` entries) as a fixed-size vector. A
/// copy of constant length is a few moves; one of the slice's length would be a call of
/// `memcpy` where the length is not known at compile time.
#[inline(always)]
fn fixed_size<V: StateVector>(y: &[f64]) -> V {
    let mut v = V::ZERO;
    v.as_mut_slice().copy_from_slice(&y[..V::DIM]);
    v
}

/// Stores the time and the states into the values (nothing else: not the inputs).
#[inline(always)]
fn store_point<M: Mechanism>(values: &mut M::Values<f64>, t: f64, states: &M::State) {
    values.set_time(t);
    for (&vr, &x) in M::STATES.iter().zip(states.as_slice()) {
        values.set(vr, x);
    }
}

/// The mechanism seen by the ODE solver: states in, derivatives out, inputs interpolated
/// from the communication point.
struct System<'a, M: Mechanism> {
    values: &'a mut M::Values<f64>,
    inputs: &'a [f64],
    input_derivatives: &'a [[f64; 2]],
    t0: f64,
    warning_active: &'a mut bool,
    warnings: &'a mut Vec<String>,
    /// Model evaluations so far. A count of its own, not a reference to the simulation's:
    /// a store through a reference could, as far as the compiler knows, change the values,
    /// which it would then read back from memory after every evaluation.
    evaluations: u64,
    /// The inputs stay at their values over the step (no derivatives) and the values hold
    /// exactly those: loading them at every stage would write what is there.
    inputs_fixed: bool,
}

impl<'a, M: Mechanism> System<'a, M> {
    #[allow(clippy::too_many_arguments)]
    fn new(
        values: &'a mut M::Values<f64>,
        inputs: &'a [f64],
        input_derivatives: &'a [[f64; 2]],
        t0: f64,
        warning_active: &'a mut bool,
        warnings: &'a mut Vec<String>,
        inputs_fixed: bool,
    ) -> Self {
        System {
            values,
            inputs,
            input_derivatives,
            t0,
            warning_active,
            warnings,
            evaluations: 0,
            inputs_fixed,
        }
    }
}

impl<M: Mechanism> System<'_, M> {
    /// Whether the values hold exactly the point (t, y) with the inputs there. The values
    /// are always evaluated at the point they hold (every load is followed by an
    /// evaluation, and `Simulation::update` leaves them so), so then there is nothing to
    /// evaluate: this is how the solver's first stage reuses the evaluation at the end of
    /// the previous step (FSAL across communication steps), and how the evaluation after
    /// the last stage and the monitor's are saved. Bit-for-bit: the same point gives the
    /// same evaluation (`Mechanism::evaluate` is a function of the values it reads).
    #[inline(always)]
    fn holds(&self, t: f64, y: &M::State) -> bool {
        if self.values.time().to_bits() != t.to_bits() {
            return false;
        }
        let same = |vr: usize, x: f64| self.values.get(vr).map(f64::to_bits) == Some(x.to_bits());
        // M::STATES is a constant: this unrolls into one comparison per state.
        if !M::STATES
            .iter()
            .zip(y.as_slice())
            .fold(true, |all, (&vr, &x)| all & same(vr, x))
        {
            return false;
        }
        if self.inputs_fixed {
            return true;
        }
        let dt = t - self.t0;
        M::INPUTS
            .iter()
            .zip(self.inputs)
            .zip(self.input_derivatives)
            .all(|((&vr, &u), d)| same(vr, u + dt * (d[0] + 0.5 * dt * d[1])))
    }

    /// Loads (t, y) and evaluates the model there, unless the values already hold it.
    #[inline(always)]
    fn evaluate_at(&mut self, t: f64, y: &M::State) {
        if !self.holds(t, y) {
            self.load(t, y);
            M::evaluate(self.values);
            self.evaluations += 1;
        }
    }

    /// Stores the point into the values. The states are read from the solver's vector
    /// before this (`fixed_size`): as far as the compiler knows the values may overlap it,
    /// and a store first would make it read back from memory the stage it has just
    /// computed in registers, on the stages' critical path.
    #[inline(always)]
    fn load(&mut self, t: f64, states: &M::State) {
        store_point::<M>(self.values, t, states);
        if !self.inputs_fixed {
            let dt = t - self.t0;
            // `M::INPUTS` is a constant: stores into known fields, which the compiler can
            // tell from the states' (with the layout's list it could not, and the equations
            // would read the states back from memory).
            for ((&vr, &u), d) in M::INPUTS
                .iter()
                .zip(self.inputs)
                .zip(self.input_derivatives)
            {
                self.values.set(vr, u + dt * (d[0] + 0.5 * dt * d[1]));
            }
        }
    }
}

impl<M: Mechanism> System<'_, M> {
    /// The derivatives the values hold at the point `states`.
    ///
    /// All are read before any is written: a store into the caller's vector could, as far
    /// as the compiler knows, change the values, and the derivatives written after it would
    /// be read back from memory instead of taken from the registers `evaluate` computed
    /// them in. A derivative that is a state (x' = v) is taken from `states`, the same
    /// number without a round trip through memory.
    #[inline(always)]
    fn read_derivatives(&self, states: &M::State) -> M::State {
        let mut derivatives = M::State::ZERO;
        for ((&vr, &state), d) in M::DERIVATIVES
            .iter()
            .zip(M::DERIVATIVES_AMONG_STATES)
            .zip(derivatives.as_mut_slice())
        {
            *d = match state {
                Some(j) => states.as_slice()[j],
                None => self.values.get(vr).unwrap_or(f64::NAN),
            };
        }
        derivatives
    }

    /// The model at a stage: the point into the values, `evaluate`, the derivatives out.
    /// What the callback ([`OdeSystem::rhs`]) does beyond this is its interface: the
    /// solver's slices in and out, and the count. The benchmark's walk of evaluations runs
    /// this very code (`Part::Evaluate`), so the two differ by exactly that.
    #[inline(always)]
    fn derivatives_at(&mut self, t: f64, states: &M::State) -> M::State {
        self.load(t, states);
        M::evaluate(self.values);
        self.read_derivatives(states)
    }
}

impl<M: Mechanism> OdeSystem for System<'_, M> {
    /// A stage: a point the values do not hold (stages are new points), so no check for it.
    #[inline(always)]
    fn rhs(&mut self, t: f64, y: &[f64], dydt: &mut [f64]) {
        let derivatives = self.derivatives_at(t, &fixed_size(y));
        dydt[..M::State::DIM].copy_from_slice(derivatives.as_slice());
        // Counted last, for the reason `read_derivatives` reads before it writes.
        self.evaluations += 1;
    }

    /// The start of a communication step (the values hold it already, evaluated, unless
    /// something was set since) or the new point of a solver step (the values hold it when
    /// the system is at rest: every stage was the same point).
    #[inline(always)]
    fn rhs_reusing(&mut self, t: f64, y: &[f64], dydt: &mut [f64]) {
        let states: M::State = fixed_size(y);
        self.evaluate_at(t, &states);
        let derivatives = self.read_derivatives(&states);
        dydt[..M::State::DIM].copy_from_slice(derivatives.as_slice());
    }

    fn accepted(&mut self, t: f64, y: &[f64]) -> Result<(), String> {
        if !M::MONITORED {
            return Ok(());
        }
        self.evaluate_at(t, &fixed_size(y));
        match M::monitor(self.values) {
            Monitor::Valid => *self.warning_active = false,
            Monitor::Warning(message) => {
                if !*self.warning_active {
                    self.warnings.push(format!("at t = {t}: {message}"));
                }
                *self.warning_active = true;
            }
            Monitor::Invalid(message) => {
                return Err(format!("the next point, t = {t}, is not valid: {message}"))
            }
        }
        Ok(())
    }

    fn valid_at(&mut self, t: f64, y: &[f64]) -> bool {
        if !M::MONITORED {
            return true;
        }
        self.evaluate_at(t, &fixed_size(y));
        !matches!(M::monitor(self.values), Monitor::Invalid(_))
    }
}
