//! Model Exchange: the importer's solver integrates, and the simulation evaluates the
//! equations at the points it is given (the time, the states, the inputs as set), and says
//! where the model needs an event: its event indicators, the monitor's verdict at accepted
//! points, the drift off the manifold its projection restores.

use super::system::store_point;
use super::{Freshness, Simulation};
use crate::model::{copy_one_by_one, get_one_by_one, Mechanism, Monitor, ValueSet};
use crate::solver::StateVector;

/// How far off its manifold a projected mechanism may drift in Model Exchange before a step
/// event projects it back. A mechanism's equations hold off the manifold (the rigid body
/// evaluates the rotation of `q/|q|`), so the drift costs no accuracy and the projection
/// only keeps it from growing without bound; the importer's solver keeps it near its own
/// tolerance. Not tied to that tolerance: a threshold of a few tolerances is crossed every
/// few steps of CVode, and each event restarts it at order 1, so a tighter tolerance would
/// give more events and a worse answer.
pub const PROJECTION_DRIFT: f64 = 1e-3;

impl<M: Mechanism> Simulation<M> {
    /// The number of continuous states.
    pub fn state_count(&self) -> usize {
        M::STATES.len()
    }

    /// The number of event indicators.
    pub fn event_indicator_count(&self) -> usize {
        self.indicators.len()
    }

    /// `fmi2SetTime`: the point moves to time `t`.
    #[inline(always)]
    pub fn set_time(&mut self, t: f64) -> Result<(), String> {
        if !t.is_finite() {
            return Err(non_finite_time(t));
        }
        if self.values.time().to_bits() != t.to_bits() {
            self.values.set_time(t);
            self.moved();
        }
        Ok(())
    }

    /// `fmi2SetContinuousStates`: `x` holds one value per state, in the states' order. All or
    /// nothing: a value that is not finite is refused before any is set. The same states
    /// again after an evaluation of the derivatives there (an importer often sets the point
    /// it evaluated last) keep the evaluation.
    #[inline(always)]
    pub fn set_states(&mut self, x: &[f64]) -> Result<(), String> {
        debug_assert_eq!(x.len(), M::STATES.len());
        // Into a vector of the states' constant length: the loops below unroll into one
        // check, one comparison and one store per state, at known places.
        // One load per state, as the importer stored them (see `copy_one_by_one`).
        let mut states = M::State::ZERO;
        copy_one_by_one(x, states.as_mut_slice());
        // `v - v` is +0.0 for a finite `v` and NaN otherwise (see `first_non_finite`).
        #[allow(clippy::eq_op)]
        let nonfinite_bits = (states.as_slice().iter()).fold(0, |any, &v| any | (v - v).to_bits());
        if nonfinite_bits != 0 {
            return Err(non_finite_state::<M>(x));
        }
        if !matches!(
            self.freshness,
            Freshness::Current | Freshness::DerivativesCurrent
        ) {
            // No derivatives at the current point for the same states to keep (the time has
            // moved, as before most evaluations of an importer's solver): no comparison.
            for (&vr, &v) in M::STATES.iter().zip(states.as_slice()) {
                self.values.set(vr, v);
            }
            self.moved();
            return Ok(());
        }
        let mut changed = 0;
        for (&vr, &v) in M::STATES.iter().zip(states.as_slice()) {
            changed |= self.values.get(vr).map_or(u64::MAX, f64::to_bits) ^ v.to_bits();
            self.values.set(vr, v);
        }
        if changed != 0 {
            self.moved();
        }
        Ok(())
    }

    /// `fmi2GetContinuousStates`: the states, in their order.
    pub fn states(&self, x: &mut [f64]) {
        for (x, &vr) in x.iter_mut().zip(M::STATES) {
            *x = self.values.get(vr).unwrap_or(f64::NAN);
        }
    }

    /// `fmi2GetDerivatives`: the states' derivatives at the current point. `Err` when one is
    /// not a number (the point is outside the equations' domain: the importer's solver
    /// should try a smaller step).
    #[inline(always)]
    pub fn derivatives(&mut self, dx: &mut [f64]) -> Result<(), String> {
        self.evaluate_derivatives()?;
        // Straight from the values into `dx`, checked for finiteness as they pass.
        let mut nonfinite_bits = 0;
        for (d, &vr) in dx[..M::State::DIM].iter_mut().zip(M::DERIVATIVES) {
            let v = self.values.get(vr).unwrap_or(f64::NAN);
            *d = v;
            #[allow(clippy::eq_op)]
            let bits = (v - v).to_bits();
            nonfinite_bits |= bits;
        }
        if nonfinite_bits != 0 {
            return Err(self.outside_the_domain(dx, M::DERIVATIVES, "the derivative"));
        }
        Ok(())
    }

    /// `fmi2GetEventIndicators`: the indicators at the current point (as `derivatives`).
    pub fn event_indicators(&mut self, z: &mut [f64]) -> Result<(), String> {
        self.evaluate_derivatives()?;
        for (z, &vr) in z.iter_mut().zip(&self.indicators) {
            *z = self.values.get(vr).unwrap_or(f64::NAN);
        }
        self.all_finite(z, &self.indicators, "the event indicator")
    }

    /// What the monitor says about the current point (an accepted point of the importer's
    /// solver, or an event): `Ok(None)` when the model holds (a warning that starts an
    /// episode is in [`Simulation::warnings`]), `Ok(Some(reason))` when it no longer does
    /// (the simulation must stop), `Err` when the point cannot be evaluated.
    pub fn check_point(&mut self) -> Result<Option<String>, String> {
        self.warnings.clear();
        if !M::MONITORED {
            return Ok(None);
        }
        self.evaluate_derivatives()?;
        let t = self.time();
        match M::monitor(&self.values) {
            Monitor::Valid => self.warning_active = false,
            Monitor::Warning(message) => {
                if !self.warning_active {
                    self.warnings.push(format!("at t = {t}: {message}"));
                }
                self.warning_active = true;
            }
            Monitor::Invalid(message) => return Ok(Some(format!("at t = {t}: {message}"))),
        }
        Ok(None)
    }

    /// Whether [`Mechanism::project`] would move a state by more than [`PROJECTION_DRIFT`]
    /// (relative to the state, absolute below 1): then the importer is asked for a step
    /// event, where [`Simulation::project`] runs.
    pub fn projection_due(&self) -> bool {
        if !M::PROJECTED {
            return false;
        }
        let mut projected = self.values.clone();
        M::project(&mut projected);
        M::STATES.iter().any(|&vr| {
            let (x, p) = (self.values.get(vr), projected.get(vr));
            let (x, p) = (x.unwrap_or(0.0), p.unwrap_or(0.0));
            // NaN counts as drift.
            (x - p).abs() > PROJECTION_DRIFT * x.abs().max(1.0) || (x - p).is_nan()
        })
    }

    /// Projects the states back onto their manifold (at an event); whether any changed.
    pub fn project(&mut self) -> bool {
        if !M::PROJECTED {
            return false;
        }
        let before = self.state_vector();
        M::project(&mut self.values);
        let after = self.state_vector();
        let changed = (before.as_slice().iter().zip(after.as_slice()))
            .any(|(a, b)| a.to_bits() != b.to_bits());
        if changed {
            self.moved();
        }
        changed
    }

    /// The point the values hold has moved: what was evaluated there is stale.
    #[inline(always)]
    fn moved(&mut self) {
        self.freshness.point_moved();
        self.held = None;
    }

    /// Brings the derivatives up to date at the current point: the whole update when
    /// something other than the point changed (parameters, a restored state), else one
    /// evaluation of `evaluate` if the point moved. What only `outputs` computes stays
    /// stale until a value is read.
    #[inline(always)]
    fn evaluate_derivatives(&mut self) -> Result<(), String> {
        if self.freshness == Freshness::Unchecked {
            return self.update();
        }
        if self.freshness == Freshness::PointMoved {
            // The states read back one by one (forwarded from `set_states`' stores) and
            // stored again right before `evaluate`: the compiler then hands them to the
            // equations in registers, where the equations' own loads (wider, across the
            // stores of another call) could not be forwarded.
            let mut states = M::State::ZERO;
            get_one_by_one(&self.values, M::STATES, states.as_mut_slice());
            let t = self.values.time();
            store_point::<M>(&mut self.values, t, &states);
            M::evaluate(&mut self.values);
            self.counters.evaluations += 1;
            self.freshness = Freshness::DerivativesCurrent;
        }
        Ok(())
    }

    /// `Err` naming the first of `values` (read from `references`) that is not finite.
    #[inline(always)]
    fn all_finite(&self, values: &[f64], references: &[usize], what: &str) -> Result<(), String> {
        #[allow(clippy::eq_op)]
        let nonfinite_bits = values.iter().fold(0, |any, &v| any | (v - v).to_bits());
        if nonfinite_bits == 0 {
            return Ok(());
        }
        Err(self.outside_the_domain(values, references, what))
    }

    #[cold]
    #[inline(never)]
    fn outside_the_domain(&self, values: &[f64], references: &[usize], what: &str) -> String {
        let i = values.iter().position(|v| !v.is_finite()).unwrap_or(0);
        let why = M::diagnose(&self.values)
            .unwrap_or_else(|| "the point is outside the equations' domain".into());
        format!(
            "{what} `{}` is {} at t = {}: {why}",
            M::VARIABLES[references[i]].name,
            values[i],
            self.time()
        )
    }
}

/// The message for the first state of `x` that is not finite.
#[cold]
#[inline(never)]
fn non_finite_state<M: Mechanism>(x: &[f64]) -> String {
    let i = x.iter().position(|v| !v.is_finite()).unwrap_or(0);
    format!(
        "x[{i}] (`{}`) = {} is not a finite number",
        M::VARIABLES[M::STATES[i]].name,
        x[i]
    )
}

#[cold]
#[inline(never)]
fn non_finite_time(t: f64) -> String {
    format!("time = {t} is not a finite number")
}
