//! FMI 3.0's values by value reference: fmi3GetFloat64 and fmi3SetFloat64 of scalars and
//! arrays (an array's values are its elements; `nValues` counts them), the independent
//! variable, value references that are no variable (inside an array, past the end),
//! `nValues` that does not count the elements, NULL and misaligned arrays, a square matrix
//! set asymmetric.

use super::table::f;
use super::Fmi3;
use crate::ffi3::*;
use crate::fmu::{Variable, VariableExt};
use crate::sequences::core::Sequence;
use crate::sequences::machine::{Call, St, Target};

/// A value no call may write: what is left where an FMU must not write.
const CANARY: f64 = -7.5e-77;

/// How many elements to back an array of `n` with: all of them when `n` is plausible
/// (the generators' wrong counts are off by a few), none when absurd (past 2^20: the FMU
/// must refuse such a count before touching the array).
pub fn backed(n: usize) -> usize {
    if n <= 1 << 20 {
        n
    } else {
        0
    }
}

/// How an array argument is handed over.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Ptr {
    Array,
    Null,
    /// One byte past the array's start: misaligned for any element wider than a byte.
    Misaligned,
}

impl Ptr {
    /// The pointer to hand over for `p`, the array's own.
    pub(crate) fn of<T>(self, p: *const T) -> *const T {
        match self {
            Ptr::Array => p,
            Ptr::Null => std::ptr::null(),
            Ptr::Misaligned => p.cast::<u8>().wrapping_add(1).cast(),
        }
    }
    pub(crate) fn of_mut<T>(self, p: *mut T) -> *mut T {
        self.of(p.cast_const()).cast_mut()
    }
    /// Whether an array of `n` elements of `T` handed over so must be refused.
    pub(crate) fn refused<T>(self, n: usize) -> bool {
        n > 0
            && match self {
                Ptr::Array => false,
                Ptr::Null => true,
                Ptr::Misaligned => std::mem::align_of::<T>() > 1,
            }
    }
}

impl Sequence<'_, Fmi3> {
    /// Mostly the array, NULL or misaligned sometimes.
    pub(crate) fn ptr(&mut self) -> Ptr {
        match self.rng.below(50) {
            0 | 1 => Ptr::Null,
            2 => Ptr::Misaligned,
            _ => Ptr::Array,
        }
    }

    /// Value references for a getter: as FMI 2.0's (a quarter of them no variable), time's
    /// sometimes, or every variable's.
    fn vrs3(&mut self) -> Vec<u32> {
        match self.rng.below(10) {
            0 => self.model.vars.iter().map(|v| v.vr).collect(),
            1 => {
                let mut vrs = self.vrs();
                vrs.push(self.model.time_vr.unwrap_or(0));
                vrs
            }
            _ => self.vrs(),
        }
    }

    /// `nValues` for arrays that have `n` values: mostly `n`.
    pub(crate) fn n_values(&mut self, n: usize) -> usize {
        if self.rng.chance(0.85) {
            n
        } else {
            self.array_len(n)
        }
    }

    pub(crate) fn get_float64(&mut self, call: Call) -> Status {
        let (_, target, c, legal) = call.parts();
        let name = FUNCTION_NAMES_FMI3[f::GET_FLOAT64];
        let mut vrs = self.vrs3();
        let expected = self.model.len_of(&vrs);
        let n = self.n_values(expected.unwrap_or(vrs.len()));
        let cap = backed(n);
        let mut out = vec![CANARY; cap + 4];
        let (vp, op) = (self.ptr(), self.ptr());
        let nvr = vrs.len();
        vrs.push(0); // room for a misaligned pointer's last element
        self.note(|| {
            format!(
                "{name}({target:?}, vr {:?} ({vp:?}), nValues {n} ({op:?}))",
                &vrs[..nvr]
            )
        });
        // SAFETY: `nvr` value references and `cap` writable values (or NULL, or misaligned
        // within the arrays); a longer `n` is one the FMU must refuse before writing.
        let s = unsafe {
            (self.fmu.api.get_float64)(c, vp.of(vrs.as_ptr()), nvr, op.of_mut(out.as_mut_ptr()), n)
        };
        let written = if op == Ptr::Array { cap.min(n) } else { 0 };
        self.check_canaries(name, &out[written..], CANARY);
        let wrong = vp.refused::<u32>(nvr) || op.refused::<f64>(n) || expected != Some(n);
        if matches!(target, Target::Live(_)) && legal && wrong && s != ERROR {
            self.fail(format!(
                "{name} of {:?} with nValues = {n} ({expected:?} values; arrays {vp:?}, {op:?}) returned {}",
                &vrs[..nvr],
                status_name(s)
            ));
        }
        if matches!(s, OK | WARNING) {
            if let Some(k) = out[..written].iter().position(|x| x.is_nan()) {
                self.fail(format!(
                    "{name} returned {} with NaN at value {k} of {:?}",
                    status_name(s),
                    &vrs[..nvr]
                ));
            }
        }
        s
    }

    /// Value references and values to set: mostly variables' (every element near its start
    /// value, a quarter hostile); sometimes any value references, time's, a square matrix
    /// asymmetric (one element off its transpose), or every continuous input.
    fn values_to_set(&mut self) -> (Vec<u32>, Vec<f64>) {
        let square: Vec<(u32, usize)> = (self.model.vars.iter())
            .filter(|v| v.is_square_matrix())
            .map(|v| (v.vr, v.len()))
            .collect();
        let mut vrs: Vec<u32> = match self.rng.below(10) {
            0..=2 => self.vrs(),
            3 if !square.is_empty() => {
                let (vr, len) = *self.rng.pick(&square);
                let d = (len as f64).sqrt() as usize;
                let mut x: Vec<f64> = (0..len).map(|k| self.value_for(vr, k)).collect();
                for i in 0..d {
                    for j in 0..i {
                        x[i * d + j] = x[j * d + i];
                    }
                }
                let (i, j) = (self.rng.below(d), self.rng.below(d));
                if i != j {
                    x[i * d + j] = x[j * d + i] * 1.5 + 0.25;
                }
                return (vec![vr], x);
            }
            4 => {
                let mut vrs = self.vrs();
                vrs.push(self.model.time_vr.unwrap_or(0));
                vrs
            }
            5 => (self.model.vars.iter())
                .filter(|v| v.is("input") && v.variability == "continuous")
                .map(|v| v.vr)
                .collect(),
            _ => (0..1 + self.rng.below(3))
                .filter_map(|_| self.vr_where(|v| !v.is("independent")))
                .collect(),
        };
        if vrs.is_empty() && self.rng.chance(0.5) {
            vrs = self.vrs();
        }
        let mut values = vec![];
        for &vr in &vrs {
            let len = self.model.var(vr).map_or(1, Variable::len);
            for k in 0..len {
                values.push(self.value_for(vr, k));
            }
        }
        (vrs, values)
    }

    pub(crate) fn set_float64(&mut self, call: Call) -> Status {
        let (_, target, c, legal) = call.parts();
        let name = FUNCTION_NAMES_FMI3[f::SET_FLOAT64];
        let (mut vrs, mut values) = self.values_to_set();
        let expected = self.model.len_of(&vrs);
        let n = self.n_values(values.len());
        values.resize(backed(n), 0.5);
        let (nvr, cap) = (vrs.len(), values.len());
        let (vp, xp) = (self.ptr(), self.ptr());
        vrs.push(0);
        values.push(0.5);
        self.note(|| {
            format!(
                "{name}({target:?}, vr {:?} ({vp:?}), values {:?} ({xp:?}), nValues {n})",
                &vrs[..nvr],
                &values[..cap]
            )
        });
        // SAFETY: `nvr` value references and `cap` values (or NULL, or misaligned within
        // the arrays); a longer `n` is one the FMU must refuse before reading.
        let s = unsafe {
            (self.fmu.api.set_float64)(c, vp.of(vrs.as_ptr()), nvr, xp.of(values.as_ptr()), n)
        };
        vrs.truncate(nvr);
        values.truncate(cap);
        let Target::Live(i) = target else { return s };
        if !legal {
            return s;
        }
        let time = self.model.time_vr.is_some_and(|t| vrs.contains(&t));
        let wrong = vp.refused::<u32>(nvr) || xp.refused::<f64>(n) || expected != Some(n);
        if (wrong || time) && s != ERROR {
            self.fail(format!(
                "{name} of {vrs:?} with nValues = {n} ({expected:?} values{}; arrays {vp:?}, {xp:?}) returned {}",
                if time { ", time among them" } else { "" },
                status_name(s)
            ));
        }
        if !matches!(s, OK | WARNING) || wrong {
            return s;
        }
        if self.insts[i].st == St::ContinuousTimeMode {
            let continuous_input = |vr: &u32| {
                self.model
                    .var(*vr)
                    .is_some_and(|v| v.is("input") && v.variability == "continuous")
            };
            if let Some(vr) = vrs.iter().find(|vr| !continuous_input(vr)) {
                self.fail(format!(
                    "{name} in continuous-time mode returned {} for value reference {vr}, which is not a continuous input",
                    status_name(s)
                ));
            }
        }
        // What was set with OK reads back bit for bit (a matrix stored symmetric cannot
        // have taken an asymmetric one, a value cannot have been dropped): checked once
        // this call's messages are (reading may log its own).
        self.same_as_variables = Some((c, vrs, values));
        s
    }
}
