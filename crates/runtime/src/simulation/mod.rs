//! A mechanism being simulated: its values, its states under the ODE solver, and the rules
//! of setting and getting values. Knows nothing of C or of the FMI state machine.
//!
//! Here the simulation, its start and reset; `values`: setting and getting values, the
//! update of what the model computes; `step`: a communication step; `system`: the mechanism
//! as the solver sees it; `saved_state`: what an FMU state captures; `model_exchange`: the
//! points an importer's solver gives; `derivatives`: exact derivatives; `bench`: the parts
//! of a step, for `mechfmu bench`.

mod bench;
mod derivatives;
mod model_exchange;
mod saved_state;
mod step;
mod system;
#[cfg(test)]
mod tests;
mod values;

pub use bench::{isolate, Part, ISOLATES};
pub use model_exchange::PROJECTION_DRIFT;
pub use saved_state::SavedState;
pub use step::StepFailure;

use crate::model::{Layout, Mechanism, ValueSet, Variable};
use crate::solver::{Solver, StateVector, Tolerance};

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

/// How much of what the model computes (calculated parameters, derivatives, outputs) is
/// that of the values the simulation holds, from the least that needs computing to the most.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Freshness {
    /// All of it: nothing to compute before a value is read or a step taken.
    Current,
    /// `evaluate` has run at the point since it last moved (Model Exchange:
    /// `fmi2GetDerivatives` evaluates no more than that): the derivatives are current, what
    /// only `outputs` computes is not.
    DerivativesCurrent,
    /// Only the point (time, states) or the inputs changed: the parameters are as checked,
    /// the calculated parameters current; the derivatives and outputs need one evaluation.
    PointMoved,
    /// Values were set since the parameters were checked and the calculated parameters and
    /// outputs computed (or never were): the whole update.
    Unchecked,
}

impl Freshness {
    /// The point or the inputs changed: the evaluation is to be done again, and nothing
    /// less than what was already due.
    fn point_moved(&mut self) {
        if *self != Freshness::Unchecked {
            *self = Freshness::PointMoved;
        }
    }
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
    /// How much of what the model computes is that of the values as they are.
    freshness: Freshness,
    /// The event indicators' value references ([`Mechanism::EVENT_INDICATORS`]).
    indicators: Vec<usize>,
    /// Whether the inputs are held over the next step (see [`Simulation::inputs_held`]),
    /// once known: forgotten by everything that sets inputs, their derivatives or values.
    held: Option<bool>,
    counters: Counters,
    /// The variable the last failed step's equations gave no number for, and its value:
    /// kept here, set only on that path, so that a step that succeeds carries nothing more.
    no_number: Option<(usize, f64)>,
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
            freshness: self.freshness,
            indicators: self.indicators.clone(),
            held: self.held,
            counters: self.counters,
            no_number: self.no_number,
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
            freshness: Freshness::Unchecked,
            // Checked at compile time by `export_fmu!`, and when an instance is made.
            indicators: crate::model::event_indicator_references(M::VARIABLES, M::EVENT_INDICATORS)
                .unwrap_or_default(),
            held: None,
            counters: Counters::default(),
            no_number: None,
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
        self.freshness = Freshness::Unchecked;
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
        self.freshness = Freshness::Unchecked;
        Ok(())
    }

    /// Work done so far (cumulative since the simulation was created).
    pub fn counters(&self) -> Counters {
        self.counters
    }

    /// The states the values hold, as the solver's vector.
    fn state_vector(&self) -> M::State {
        let mut y = M::State::ZERO;
        for (y, &vr) in y.as_mut_slice().iter_mut().zip(M::STATES) {
            *y = self.values.get(vr).unwrap_or(f64::NAN);
        }
        y
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
    M::VARIABLES
        .get(vr as usize)
        .ok_or_else(|| not_a_variable::<M>(vr))
}

/// Why `vr` is refused: it is no variable of the mechanism.
#[cold]
#[inline(never)]
fn not_a_variable<M: Mechanism>(vr: u32) -> String {
    format!(
        "value reference {vr} is not a variable of {} (it has {} real variables, 0..{})",
        M::NAME,
        M::VARIABLES.len(),
        M::VARIABLES.len().saturating_sub(1)
    )
}
