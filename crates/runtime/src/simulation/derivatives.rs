//! Exact derivatives by forward-mode automatic differentiation: the mechanism's equations
//! run once on dual numbers, seeded along the requested direction.

use super::{variable, Simulation};
use crate::model::{evaluate_all, Causality, Mechanism, ValueSet, Variability};
use num_dual::Dual64;

impl<M: Mechanism> Simulation<M> {
    /// `fmi2GetDirectionalDerivative`: the change of each unknown along the direction
    /// `dv_known` of the knowns (states and inputs) and `dt` of the time (FMI 3.0 counts the
    /// independent variable among the knowns; FMI 2.0 gives 0), at the current point.
    pub fn directional_derivative(
        &mut self,
        unknowns: &[u32],
        knowns: &[u32],
        dv_known: &[f64],
        dt: f64,
        dv_unknown: &mut [f64],
    ) -> Result<(), String> {
        for &vr in knowns {
            let v = variable::<M>(vr)?;
            if !(v.is_state() || v.causality == Causality::Input) {
                return Err(format!(
                    "known `{}` is neither a state nor an input: derivatives are taken with respect to states and inputs",
                    v.name
                ));
            }
        }
        for &vr in unknowns {
            let v = variable::<M>(vr)?;
            if v.variability != Variability::Continuous {
                return Err(format!(
                    "unknown `{}` is a parameter: it does not depend on states or inputs",
                    v.name
                ));
            }
        }
        self.update()?;
        let mut dual = M::map_values(&self.values, Dual64::from_re);
        dual.set_time(Dual64::new(self.values.time(), dt));
        for (&vr, &dv) in knowns.iter().zip(dv_known) {
            let x = dual.get(vr as usize).unwrap_or(Dual64::from_re(0.0));
            dual.set(vr as usize, Dual64::new(x.re, x.eps + dv));
        }
        evaluate_all::<M, Dual64>(&mut dual);
        for (&vr, out) in unknowns.iter().zip(dv_unknown.iter_mut()) {
            *out = dual.get(vr as usize).map_or(f64::NAN, |d| d.eps);
        }
        Ok(())
    }

    /// `fmi2GetRealOutputDerivatives` of order 1: the time derivative of each output along
    /// the motion (states moving with their derivatives, inputs along their polynomials).
    pub fn output_derivatives(
        &mut self,
        vrs: &[u32],
        orders: &[i32],
        out: &mut [f64],
    ) -> Result<(), String> {
        for (&vr, &order) in vrs.iter().zip(orders) {
            let v = variable::<M>(vr)?;
            if v.causality != Causality::Output {
                return Err(format!("`{}` is not an output", v.name));
            }
            if order != 1 {
                return Err(format!(
                    "derivative order {order} of `{}` is not available (maxOutputDerivativeOrder = 1)",
                    v.name
                ));
            }
        }
        self.update()?;
        let mut dual = M::map_values(&self.values, Dual64::from_re);
        dual.set_time(Dual64::new(self.values.time(), 1.0));
        for (&state, &derivative) in self.layout.states.iter().zip(&self.layout.derivatives) {
            let rate = self.values.get(derivative).unwrap_or(f64::NAN);
            let x = self.values.get(state).unwrap_or(f64::NAN);
            dual.set(state, Dual64::new(x, rate));
        }
        for (i, &vr) in self.layout.inputs.iter().enumerate() {
            dual.set(
                vr,
                Dual64::new(self.inputs[i], self.input_derivatives[i][0]),
            );
        }
        evaluate_all::<M, Dual64>(&mut dual);
        for (&vr, o) in vrs.iter().zip(out.iter_mut()) {
            *o = dual.get(vr as usize).map_or(f64::NAN, |d| d.eps);
        }
        Ok(())
    }
}
