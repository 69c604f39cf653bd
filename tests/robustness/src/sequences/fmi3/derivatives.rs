//! FMI 3.0's derivatives by value reference (arrays count their elements): directional
//! derivatives (`nSeed` the elements of the knowns, `nSensitivity` the unknowns'),
//! adjoint derivatives (the other way round) and output derivatives (an order per
//! variable, `nValues` its elements), with hostile value references, counts, seeds and
//! pointers.

use super::table::f;
use super::values::{backed, Ptr};
use super::Fmi3;
use crate::ffi3::*;
use crate::fmu::VariableExt;
use crate::sequences::core::Sequence;
use crate::sequences::machine::{Call, Target};

const CANARY: f64 = -7.5e-77;

impl Sequence<'_, Fmi3> {
    /// fmi3GetDirectionalDerivative or fmi3GetAdjointDerivative: wrong counts, value
    /// references that are no variable, time among the unknowns (it is a known only) or
    /// hand-overs refused; never NaN with OK, nothing written past the sensitivities.
    pub(crate) fn directional_or_adjoint(&mut self, call: Call) -> Status {
        let (function, target, c, legal) = call.parts();
        let name = FUNCTION_NAMES_FMI3[function];
        let mut unknowns = self.vrs();
        let mut knowns = self.vrs();
        let (nu, nk) = (unknowns.len(), knowns.len());
        let time = self.model.time_vr;
        let eu =
            (self.model.len_of(&unknowns)).filter(|_| !unknowns.iter().any(|v| Some(*v) == time));
        let ek = self.model.len_of(&knowns);
        // The seed runs along the knowns (directional) or the unknowns (adjoint).
        let (seed_of, sens_of) = if function == f::DIRECTIONAL_DERIVATIVE {
            (ek, eu)
        } else {
            (eu, ek)
        };
        let n_seed = if self.rng.chance(0.85) {
            seed_of.unwrap_or(nk)
        } else {
            self.array_len(nk)
        };
        let n_sens = if self.rng.chance(0.85) {
            sens_of.unwrap_or(nu)
        } else {
            self.array_len(nu)
        };
        let mut seed: Vec<f64> = (0..backed(n_seed) + 1)
            .map(|_| self.derivative_value())
            .collect();
        let cap = backed(n_sens);
        let mut out = vec![CANARY; cap + 4];
        let (up, kp, sp, op) = (self.ptr(), self.ptr(), self.ptr(), self.ptr());
        unknowns.push(0);
        knowns.push(0);
        self.note(|| {
            format!(
                "{name}({target:?}, unknowns {:?}, knowns {:?}, nSeed {n_seed}, nSensitivity {n_sens}, arrays {up:?} {kp:?} {sp:?} {op:?})",
                &unknowns[..nu],
                &knowns[..nk]
            )
        });
        let g = if function == f::DIRECTIONAL_DERIVATIVE {
            self.fmu.api.get_directional_derivative
        } else {
            self.fmu.api.get_adjoint_derivative
        };
        // SAFETY: arrays of their lengths (or NULL, or misaligned within them); a longer
        // count is one the FMU must refuse before reading or writing.
        let s = unsafe {
            g(
                c,
                up.of(unknowns.as_ptr()),
                nu,
                kp.of(knowns.as_ptr()),
                nk,
                sp.of(seed.as_mut_ptr()),
                n_seed,
                op.of_mut(out.as_mut_ptr()),
                n_sens,
            )
        };
        let written = if op == Ptr::Array { cap.min(n_sens) } else { 0 };
        self.check_canaries(name, &out[written..], CANARY);
        let wrong = up.refused::<u32>(nu)
            || kp.refused::<u32>(nk)
            || sp.refused::<f64>(n_seed)
            || op.refused::<f64>(n_sens)
            || seed_of != Some(n_seed)
            || sens_of != Some(n_sens);
        if matches!(target, Target::Live(_)) && legal && wrong && s != ERROR {
            self.fail(format!(
                "{name} with unknowns {:?} ({eu:?} values), knowns {:?} ({ek:?}), nSeed {n_seed}, nSensitivity {n_sens}, arrays {up:?} {kp:?} {sp:?} {op:?} returned {}",
                &unknowns[..nu],
                &knowns[..nk],
                status_name(s)
            ));
        }
        if s == OK && out[..written].iter().any(|x| x.is_nan()) {
            self.fail(format!("{name} returned fmi3OK with NaN"));
        }
        seed.clear();
        s
    }

    /// fmi3GetOutputDerivatives: of an output half the time, an order per variable (sane
    /// and hostile), `nValues` its elements; never NaN with OK.
    pub(crate) fn output_derivatives(&mut self, call: Call) -> Status {
        let (_, target, c, legal) = call.parts();
        let name = FUNCTION_NAMES_FMI3[f::GET_OUTPUT_DERIVATIVES];
        let mut vrs = self.vrs();
        if self.rng.chance(0.5) {
            if let Some(v) = self.vr_where(|v| v.is("output")) {
                vrs = vec![v];
            }
        }
        let nvr = vrs.len();
        let mut orders: Vec<i32> = (0..nvr + 1)
            .map(|_| *self.rng.pick(&[1, 1, 2, 2, 0, 3, -1, i32::MAX, i32::MIN]))
            .collect();
        let expected = self.model.len_of(&vrs);
        let n = if self.rng.chance(0.85) {
            expected.unwrap_or(nvr)
        } else {
            self.array_len(nvr)
        };
        let cap = backed(n);
        let mut out = vec![CANARY; cap + 4];
        let (vp, orp, op) = (self.ptr(), self.ptr(), self.ptr());
        vrs.push(0);
        self.note(|| {
            format!(
                "{name}({target:?}, vr {:?}, orders {:?}, nValues {n}, arrays {vp:?} {orp:?} {op:?})",
                &vrs[..nvr],
                &orders[..nvr]
            )
        });
        // SAFETY: arrays of their lengths (or NULL, or misaligned within them); a longer
        // `n` is one the FMU must refuse before writing.
        let s = unsafe {
            (self.fmu.api.get_output_derivatives)(
                c,
                vp.of(vrs.as_ptr()),
                nvr,
                orp.of(orders.as_mut_ptr()),
                op.of_mut(out.as_mut_ptr()),
                n,
            )
        };
        let written = if op == Ptr::Array { cap.min(n) } else { 0 };
        self.check_canaries(name, &out[written..], CANARY);
        let wrong = vp.refused::<u32>(nvr)
            || orp.refused::<i32>(nvr)
            || op.refused::<f64>(n)
            || expected != Some(n);
        if matches!(target, Target::Live(_)) && legal && wrong && s != ERROR {
            self.fail(format!(
                "{name} of {:?} with nValues {n} ({expected:?} values), arrays {vp:?} {orp:?} {op:?} returned {}",
                &vrs[..nvr],
                status_name(s)
            ));
        }
        if s == OK && out[..written].iter().any(|x| x.is_nan()) {
            self.fail(format!("{name} returned fmi3OK with NaN"));
        }
        orders.clear();
        s
    }
}
