//! A communication step: the solver over the interval, the values left at its end point
//! (or undone when they are not numbers), the inputs moved along their polynomials.

use super::system::{store_point, System};
use super::Simulation;
use crate::model::{Mechanism, ValueSet};
use crate::solver::{SolverError, StateVector, StepStats};

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

impl<M: Mechanism> Simulation<M> {
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
        // Where the equations gave no number, the values still hold the point that gave
        // none: the mechanism's account of why is taken there, before they are evaluated
        // back at the last accepted point.
        let diagnosis = match &result {
            Err(SolverError::NonFinite { .. }) => M::diagnose(system.values),
            _ => None,
        };
        if let Err(SolverError::NonFinite { .. }) = &result {
            self.no_number = first_no_number::<M>(system.values);
        }
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
            let diagnosis =
                (diagnosis.or_else(|| M::diagnose(&self.values))).map(|why| format!(": {why}"));
            self.undo(t, &start);
            self.solver.restore(memory);
            self.warning_active = warning_active;
            let why = result.err().map(|e| format!(" ({})", describe(&e)));
            return Err(StepFailure::Stopped {
                time: t,
                limit: false,
                message: format!(
                    "`{name}` became non-finite before t = {t_end}{}{}; the step is undone, the values are those at t = {t}",
                    why.unwrap_or_default(),
                    diagnosis.unwrap_or_default()
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
            Err(e) => {
                let no_number = matches!(e, SolverError::NonFinite { .. });
                Err(StepFailure::Stopped {
                    time,
                    limit: matches!(e, SolverError::Stopped { .. }),
                    message: match (diagnosis, self.no_number.take().filter(|_| no_number)) {
                        (Some(why), _) => format!("{}: {why}", describe(&e)),
                        (None, Some((vr, x))) => {
                            format!(
                                "{}: `{}` evaluated to {x}",
                                describe(&e),
                                M::VARIABLES[vr].name
                            )
                        }
                        (None, None) => describe(&e),
                    },
                })
            }
        }
    }

    /// Whether the inputs stay at their values over the next step and the values hold
    /// exactly those, so that the stages need not load them (see `System::inputs_fixed`).
    /// Known from the last step unless something was set since: a step with held inputs
    /// changes neither the inputs nor their derivatives, and one with moving inputs leaves
    /// their derivatives nonzero.
    #[inline]
    pub(super) fn inputs_held(&mut self) -> bool {
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

    /// The first of the variables `checked` that is not finite. `checked` is one of the
    /// mechanism's constants, so the common case, all finite, unrolls into straight-line
    /// vector code, no branch.
    #[inline(always)]
    pub(super) fn first_non_finite(&self, checked: &'static [usize]) -> Option<&'static str> {
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
pub(super) fn complete_point<M: Mechanism>(values: &mut M::Values<f64>) {
    if M::PROJECTED {
        M::project(values);
        M::evaluate(values);
    }
    M::outputs(values);
}

/// The first continuous variable the last evaluation gave no number for, and its value:
/// the solver stops at the first stage such a derivative makes non-finite, so the values
/// still hold it.
#[cold]
#[inline(never)]
fn first_no_number<M: Mechanism>(values: &M::Values<f64>) -> Option<(usize, f64)> {
    (M::VARIABLES.iter().enumerate())
        .filter(|(_, v)| v.variability == crate::model::Variability::Continuous)
        .find_map(|(vr, _)| values.get(vr).filter(|x| !x.is_finite()).map(|x| (vr, x)))
}

fn describe(e: &SolverError) -> String {
    match e {
        SolverError::Stopped { message, .. } => message.clone(),
        other => other.to_string(),
    }
}
