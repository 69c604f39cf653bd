//! FMI 2.0's derivatives: directional derivatives, input derivatives and output
//! derivatives, with hostile value references, orders and seeds.

use super::table::f;
use super::Fmi2;
use crate::ffi::*;
use crate::fmu::VariableExt;
use crate::sequences::args::null_if;
use crate::sequences::core::Sequence;
use crate::sequences::hostile::hostile_f64;
use crate::sequences::machine::Call;

impl Sequence<'_, Fmi2> {
    /// fmi2GetDirectionalDerivative: never NaN with fmi2OK, nothing written past the
    /// unknowns.
    pub(crate) fn directional_derivative(&mut self, call: Call) -> Status {
        let (_, target, c, _) = call.parts();
        let api = *self.fmu.api;
        let name = FUNCTION_NAMES[f::DIRECTIONAL_DERIVATIVE];
        let unknowns = self.vrs();
        let knowns = self.vrs();
        let dv: Vec<f64> = knowns.iter().map(|_| self.derivative_value()).collect();
        let n = unknowns.len();
        let mut out = vec![-7.5e-77f64; n + 4];
        let (up, kp, dp) = (
            self.ptr_or_null(&unknowns),
            self.ptr_or_null(&knowns),
            self.ptr_or_null(&dv),
        );
        let op = null_if(self.rng.chance(0.04), out.as_mut_ptr());
        self.note(|| {
            format!("{name}({target:?}, unknowns {unknowns:?}, knowns {knowns:?}, dv {dv:?})")
        });
        // SAFETY: arrays of their lengths (or NULL).
        let s = unsafe { (api.get_directional_derivative)(c, up, n, kp, knowns.len(), dp, op) };
        self.check_canaries(name, &out[n..], -7.5e-77);
        if s == OK && out[..n].iter().any(|x| x.is_nan()) {
            self.fail(format!("{name} returned fmi2OK with NaN"));
        }
        s
    }

    /// fmi2SetRealInputDerivatives and fmi2GetRealOutputDerivatives: of an input or
    /// output half the time, with orders and values sane and hostile.
    pub(crate) fn input_output_derivatives(&mut self, call: Call) -> Status {
        let (function, target, c, _) = call.parts();
        let api = *self.fmu.api;
        let name = FUNCTION_NAMES[function];
        let mut vrs = self.vrs();
        if self.rng.chance(0.5) {
            let want_input = function == f::SET_INPUT_DERIVATIVES;
            if let Some(v) = self.vr_where(|v| {
                if want_input {
                    v.is("input")
                } else {
                    v.is("output")
                }
            }) {
                vrs = vec![v];
            }
        }
        let n = vrs.len();
        let orders: Vec<i32> = (0..n)
            .map(|_| *self.rng.pick(&[1, 1, 2, 2, 0, 3, -1, i32::MAX, i32::MIN]))
            .collect();
        let values: Vec<f64> = (0..n)
            .map(|_| {
                if self.rng.chance(0.7) {
                    self.rng.unit() * 4.0 - 2.0
                } else {
                    hostile_f64(&mut self.rng)
                }
            })
            .collect();
        let (vp, opp) = (self.ptr_or_null(&vrs), self.ptr_or_null(&orders));
        self.note(|| {
            format!("{name}({target:?}, vr {vrs:?}, order {orders:?}, values {values:?})")
        });
        if function == f::SET_INPUT_DERIVATIVES {
            let xp = self.ptr_or_null(&values);
            // SAFETY: arrays of n elements (or NULL).
            unsafe { (api.set_real_input_derivatives)(c, vp, n, opp, xp) }
        } else {
            let mut out = vec![-7.5e-77f64; n + 4];
            let op = null_if(self.rng.chance(0.04), out.as_mut_ptr());
            // SAFETY: arrays of n elements (or NULL).
            let s = unsafe { (api.get_real_output_derivatives)(c, vp, n, opp, op) };
            self.check_canaries(name, &out[n..], -7.5e-77);
            if s == OK && out[..n].iter().any(|x| x.is_nan()) {
                self.fail(format!("{name} returned fmi2OK with NaN"));
            }
            s
        }
    }
}
