//! FMI 3.0's getters and setters of the types the FMU has no variables of (Float32, the
//! integers, Boolean, String, Binary): value references, counts and arrays sane and
//! hostile; only a call asking for nothing succeeds, and nothing is written.

use super::table::f;
use super::values::{backed, Ptr};
use super::Fmi3;
use crate::ffi3::*;
use crate::sequences::core::Sequence;
use crate::sequences::machine::{Call, Target};

impl Sequence<'_, Fmi3> {
    /// A getter of a type the FMU has no variables of (Float32, the integers, Boolean,
    /// String, Binary): only a call asking for nothing succeeds, and nothing is written.
    pub(crate) fn get_other_type(&mut self, call: Call) -> Status {
        let (function, target, c, legal) = call.parts();
        let api = *self.fmu.api;
        let name = FUNCTION_NAMES_FMI3[function];
        let (vrs, nvr, n, vp, op) = self.no_variables_args();
        let cap = backed(n);
        // Room for `cap` values of any type (8 bytes at most; Binary's sizes and pointers
        // in two halves), one more for a misaligned pointer, untouched if nothing is written.
        let mut buf = vec![0x5a5a_5a5a_5a5a_5a5au64; 2 * cap + 2];
        let out = op.of_mut(buf.as_mut_ptr());
        let second = op.of_mut(buf[cap + 1..].as_mut_ptr());
        let vp_ = vp.of(vrs.as_ptr());
        self.note_no_variables(name, target, &vrs[..nvr], vp, n, op);
        // SAFETY: `nvr` value references and room for `cap` values (or NULL, or misaligned
        // within the buffers); a longer `n` is one the FMU must refuse before writing.
        let s = unsafe {
            match function {
                f::GET_FLOAT32 => (api.get_float32)(c, vp_, nvr, out.cast(), n),
                f::GET_INT8 => (api.get_int8)(c, vp_, nvr, out.cast(), n),
                f::GET_UINT8 => (api.get_uint8)(c, vp_, nvr, out.cast(), n),
                f::GET_INT16 => (api.get_int16)(c, vp_, nvr, out.cast(), n),
                f::GET_UINT16 => (api.get_uint16)(c, vp_, nvr, out.cast(), n),
                f::GET_INT32 => (api.get_int32)(c, vp_, nvr, out.cast(), n),
                f::GET_UINT32 => (api.get_uint32)(c, vp_, nvr, out.cast(), n),
                f::GET_INT64 => (api.get_int64)(c, vp_, nvr, out.cast(), n),
                f::GET_UINT64 => (api.get_uint64)(c, vp_, nvr, out.cast(), n),
                f::GET_BOOLEAN => (api.get_boolean)(c, vp_, nvr, out.cast(), n),
                f::GET_STRING => (api.get_string)(c, vp_, nvr, out.cast(), n),
                _ => (api.get_binary)(c, vp_, nvr, out.cast(), second.cast(), n),
            }
        };
        if buf.iter().any(|&x| x != 0x5a5a_5a5a_5a5a_5a5a) {
            self.fail(format!(
                "{name} wrote values of variables this FMU does not have"
            ));
        }
        self.check_no_variables(name, target, legal, nvr, n, s);
        s
    }

    /// A setter of a type the FMU has no variables of: only a call setting nothing
    /// succeeds. The values are bytes of every kind (booleans other than 0 and 1 too).
    pub(crate) fn set_other_type(&mut self, call: Call) -> Status {
        let (function, target, c, legal) = call.parts();
        let api = *self.fmu.api;
        let name = FUNCTION_NAMES_FMI3[function];
        let (vrs, nvr, n, vp, xp) = self.no_variables_args();
        let cap = backed(n);
        let mut buf: Vec<u64> = (0..2 * cap + 2).map(|_| self.rng.next_u64()).collect();
        if matches!(function, f::SET_STRING | f::SET_BINARY) {
            // Pointers to strings (or NULL), to bytes; Binary's sizes in the second half.
            let pointers = [c"s0".as_ptr(), c"%s%n".as_ptr(), std::ptr::null()];
            for (k, x) in buf.iter_mut().enumerate() {
                *x = if k <= cap {
                    pointers[k % 3] as u64
                } else {
                    k as u64 % 5
                };
            }
        }
        let values = xp.of(buf.as_ptr());
        let second = xp.of(buf[cap + 1..].as_ptr());
        let vp_ = vp.of(vrs.as_ptr());
        self.note_no_variables(name, target, &vrs[..nvr], vp, n, xp);
        // SAFETY: `nvr` value references and `cap` values (or NULL, or misaligned within
        // the buffer; strings NUL-terminated or NULL); a longer `n` is one the FMU must
        // refuse before reading.
        let s = unsafe {
            match function {
                f::SET_FLOAT32 => (api.set_float32)(c, vp_, nvr, values.cast(), n),
                f::SET_INT8 => (api.set_int8)(c, vp_, nvr, values.cast(), n),
                f::SET_UINT8 => (api.set_uint8)(c, vp_, nvr, values.cast(), n),
                f::SET_INT16 => (api.set_int16)(c, vp_, nvr, values.cast(), n),
                f::SET_UINT16 => (api.set_uint16)(c, vp_, nvr, values.cast(), n),
                f::SET_INT32 => (api.set_int32)(c, vp_, nvr, values.cast(), n),
                f::SET_UINT32 => (api.set_uint32)(c, vp_, nvr, values.cast(), n),
                f::SET_INT64 => (api.set_int64)(c, vp_, nvr, values.cast(), n),
                f::SET_UINT64 => (api.set_uint64)(c, vp_, nvr, values.cast(), n),
                f::SET_BOOLEAN => (api.set_boolean)(c, vp_, nvr, values.cast(), n),
                f::SET_STRING => (api.set_string)(c, vp_, nvr, values.cast(), n),
                _ => (api.set_binary)(c, vp_, nvr, second.cast(), values.cast(), n),
            }
        };
        self.check_no_variables(name, target, legal, nvr, n, s);
        s
    }

    /// The arguments of a get or set of a type without variables: value references (none a
    /// fifth of the time), their count, nValues (0 a fifth of the time) and the kinds of the
    /// two array pointers; a 0 pushed past the value references, so their pointer is never
    /// dangling.
    fn no_variables_args(&mut self) -> (Vec<u32>, usize, usize, Ptr, Ptr) {
        let mut vrs = if self.rng.chance(0.2) {
            vec![]
        } else {
            self.vrs()
        };
        let n = if self.rng.chance(0.2) {
            0
        } else {
            self.n_values(vrs.len())
        };
        let (vp, values) = (self.ptr(), self.ptr());
        let nvr = vrs.len();
        vrs.push(0);
        (vrs, nvr, n, vp, values)
    }

    fn note_no_variables(
        &mut self,
        name: &str,
        target: Target,
        vrs: &[u32],
        vp: Ptr,
        n: usize,
        values: Ptr,
    ) {
        self.note(|| format!("{name}({target:?}, vr {vrs:?} ({vp:?}), nValues {n} ({values:?}))"));
    }

    /// A get or set of a type without variables succeeds when it asks for nothing
    /// (`nValueReferences` and `nValues` 0) and only then.
    fn check_no_variables(
        &mut self,
        name: &str,
        target: Target,
        legal: bool,
        nvr: usize,
        n: usize,
        s: Status,
    ) {
        if !matches!(target, Target::Live(_)) || !legal {
            return;
        }
        let nothing = nvr == 0 && n == 0;
        if nothing != (s == OK) {
            self.fail(format!(
                "{name} with {nvr} value references and nValues = {n} (this FMU has no such variables) returned {}",
                status_name(s)
            ));
        }
    }
}
