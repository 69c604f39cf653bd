//! The mechanism as the ODE solver sees it over a communication step: states in,
//! derivatives out, inputs interpolated from the communication point, the monitor asked at
//! accepted points.

use crate::model::{Mechanism, Monitor, ValueSet};
use crate::solver::{OdeSystem, StateVector};

/// `y` (which the solver passes with exactly `V::DIM` entries) as a fixed-size vector. A
/// copy of constant length is a few moves; one of the slice's length would be a call of
/// `memcpy` where the length is not known at compile time.
#[inline(always)]
pub(super) fn fixed_size<V: StateVector>(y: &[f64]) -> V {
    let mut v = V::ZERO;
    v.as_mut_slice().copy_from_slice(&y[..V::DIM]);
    v
}

/// Stores the time and the states into the values (nothing else: not the inputs).
#[inline(always)]
pub(super) fn store_point<M: Mechanism>(values: &mut M::Values<f64>, t: f64, states: &M::State) {
    values.set_time(t);
    for (&vr, &x) in M::STATES.iter().zip(states.as_slice()) {
        values.set(vr, x);
    }
}

/// The mechanism seen by the ODE solver: states in, derivatives out, inputs interpolated
/// from the communication point.
pub(super) struct System<'a, M: Mechanism> {
    pub(super) values: &'a mut M::Values<f64>,
    inputs: &'a [f64],
    input_derivatives: &'a [[f64; 2]],
    pub(super) t0: f64,
    warning_active: &'a mut bool,
    warnings: &'a mut Vec<String>,
    /// Model evaluations so far. A count of its own, not a reference to the simulation's:
    /// a store through a reference could, as far as the compiler knows, change the values,
    /// which it would then read back from memory after every evaluation.
    pub(super) evaluations: u64,
    /// The inputs stay at their values over the step (no derivatives) and the values hold
    /// exactly those: loading them at every stage would write what is there.
    inputs_fixed: bool,
}

impl<'a, M: Mechanism> System<'a, M> {
    #[allow(clippy::too_many_arguments)]
    pub(super) fn new(
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
    pub(super) fn holds(&self, t: f64, y: &M::State) -> bool {
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
    pub(super) fn evaluate_at(&mut self, t: f64, y: &M::State) {
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
    pub(super) fn derivatives_at(&mut self, t: f64, states: &M::State) -> M::State {
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
