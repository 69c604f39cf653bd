//! The generator's machinery both standards' sequences share: instances, value
//! references, values and array lengths drawn sane or hostile, FMU state handles and
//! serialized bytes (valid, corrupted, random, forged with a repaired checksum).

use super::core::{Sequence, Standard};
use super::hostile::hostile_f64;
use super::machine::{Snap, Target};
use super::state_bytes::{fix_checksum, mutate_semantically};
use crate::ffi::{Component, FmuState};
use crate::fmu::{Variable, VariableExt};
use std::ffi::CString;

/// Instance names an importer might give.
pub const SANE_NAMES: [&str; 4] = ["instance", "Oscillator", "x%s%n%d %p", "ünïcødé name"];

impl<S: Standard> Sequence<'_, S> {
    /// A seed or input derivative: mostly within [-1, 1), hostile sometimes.
    pub(crate) fn derivative_value(&mut self) -> f64 {
        if self.rng.chance(0.8) {
            self.rng.unit() * 2.0 - 1.0
        } else {
            hostile_f64(&mut self.rng)
        }
    }

    /// The oracle's time and stop time of the instance (time 0 and none for no instance).
    pub(crate) fn time_and_stop(&self, target: Target) -> (f64, Option<f64>) {
        match target {
            Target::Live(i) => (self.insts[i].time, self.insts[i].stop),
            _ => (0.0, None),
        }
    }

    /// The time a step starts at: mostly the instance's, sometimes off it by a rounding, a
    /// second or a millisecond, or one of `hostile`.
    pub(crate) fn step_start(&mut self, time: f64, hostile: &[f64]) -> f64 {
        match self.rng.below(20) {
            0..=15 => time,
            16 => time * (1.0 + 1e-13) + 1e-300,
            17 => time + *self.rng.pick(&[1.0, -1.0, 1e-3, -1e-3]),
            _ => *self.rng.pick(hostile),
        }
    }

    /// The instance of a call: mostly a live one, sometimes NULL or foreign memory.
    pub(crate) fn target(&mut self) -> (Target, Component) {
        let r = self.rng.unit();
        if self.insts.is_empty() || r < 0.04 {
            return (Target::Null, std::ptr::null_mut());
        }
        if r < 0.07 {
            return (Target::Foreign, self.foreign_memory());
        }
        let i = self.rng.below(self.insts.len());
        (Target::Live(i), self.insts[i].c)
    }

    /// Memory that is no instance: zeros or noise.
    pub(crate) fn foreign_memory(&mut self) -> Component {
        let p = if self.rng.chance(0.5) {
            self.zeros.as_mut_ptr()
        } else {
            self.noise.as_mut_ptr()
        };
        p.cast()
    }

    pub(crate) fn vr(&mut self) -> u32 {
        if self.rng.chance(0.85) && self.model.vr_end > 0 {
            self.rng.below(self.model.vr_end as usize) as u32
        } else {
            *self.rng.pick(&[
                self.model.vr_end,
                self.model.vr_end + 1,
                1000,
                1 << 31,
                u32::MAX,
            ])
        }
    }

    pub(crate) fn vrs(&mut self) -> Vec<u32> {
        let n = match self.rng.below(10) {
            0 => 0,
            1..=6 => 1 + self.rng.below(4),
            7 | 8 => self.model.vr_end as usize + self.rng.below(4),
            _ => 1 + self.rng.below(64),
        };
        (0..n).map(|_| self.vr()).collect()
    }

    /// A value reference of a variable of the given kinds, if there is one.
    pub(crate) fn vr_where(&mut self, pred: impl Fn(&Variable) -> bool) -> Option<u32> {
        let c: Vec<u32> = self
            .model
            .vars
            .iter()
            .filter(|v| pred(v))
            .map(|v| v.vr)
            .collect();
        (!c.is_empty()).then(|| *self.rng.pick(&c))
    }

    /// A value for element `k` of variable `vr`: near its start value (above its min),
    /// sometimes hostile.
    pub(crate) fn value_for(&mut self, vr: u32, k: usize) -> f64 {
        if self.rng.chance(0.25) {
            return hostile_f64(&mut self.rng);
        }
        let var = self.model.var(vr);
        let start = var.and_then(|v| v.start_at(k)).unwrap_or(1.0);
        let lo = var.and_then(|v| v.min);
        let x = start * (0.5 + self.rng.unit())
            + if self.rng.chance(0.3) {
                self.rng.unit() - 0.5
            } else {
                0.0
            };
        match lo {
            Some(lo) if x < lo => lo + self.rng.unit(),
            _ => x,
        }
    }

    pub(crate) fn ptr_or_null<T>(&mut self, v: &[T]) -> *const T {
        if self.rng.chance(0.04) {
            std::ptr::null()
        } else {
            v.as_ptr()
        }
    }

    // -----------------------------------------------------------------------------------
    // Calls

    /// A length for an array of `n` elements: mostly right, sometimes wrong, rarely absurd
    /// (always right for an importer's integrator step).
    pub(crate) fn array_len(&mut self, n: usize) -> usize {
        if self.sane {
            return n;
        }
        match self.rng.below(20) {
            0..=14 => n,
            15 => 0,
            16 => n + 1 + self.rng.below(3),
            17 => n.saturating_sub(1),
            18 => n.wrapping_sub(1),
            _ => *self.rng.pick(&[usize::MAX, 1 << 40, (1 << 24) + 1]),
        }
    }

    pub(crate) fn check_canaries(&mut self, name: &str, tail: &[f64], canary: f64) {
        if tail.iter().any(|x| x.to_bits() != canary.to_bits()) {
            self.fail(format!("{name} wrote past the elements it was given"));
        }
    }

    /// An FMU state handle: a live one of this sequence (`Some(index)`), NULL, or foreign
    /// memory.
    pub(crate) fn state_handle(&mut self) -> (Option<usize>, FmuState) {
        let r = self.rng.unit();
        if !self.handles.is_empty() && r < 0.85 {
            let k = self.rng.below(self.handles.len());
            return (Some(k), self.handles[k].ptr);
        }
        if r < 0.92 {
            return (None, std::ptr::null_mut());
        }
        let p = if self.rng.chance(0.5) {
            self.zeros.as_mut_ptr()
        } else {
            self.noise.as_mut_ptr()
        };
        (None, p.cast())
    }

    /// Bytes to deserialize, and what they capture when known.
    pub(crate) fn serialized_bytes(&mut self) -> (Vec<u8>, Option<Snap>) {
        let have = !self.serialized.is_empty();
        let r = self.rng.below(10);
        if have && r < 4 {
            let k = self.rng.below(self.serialized.len());
            let (b, s) = &self.serialized[k];
            return (b.clone(), Some(*s));
        }
        if have && r < 7 {
            let k = self.rng.below(self.serialized.len());
            let mut b = self.serialized[k].0.clone();
            match self.rng.below(4) {
                0 => {
                    let i = self.rng.below(b.len());
                    b[i] ^= 1 << self.rng.below(8);
                }
                1 => b.truncate(self.rng.below(b.len())),
                2 => b.push(self.rng.next_u64() as u8),
                _ => {
                    // Corrupt the body, then repair the checksum (FNV-1a 64 of the body, as
                    // the format documents): what only a deliberate forger could send.
                    mutate_semantically(&mut self.rng, &mut b);
                    fix_checksum(&mut b);
                }
            }
            return (b, None);
        }
        let n = if self.rng.chance(0.2) {
            0
        } else {
            self.rng.below(600)
        };
        let mut b: Vec<u8> = (0..n).map(|_| self.rng.next_u64() as u8).collect();
        if n >= 8 && self.rng.chance(0.5) {
            b[..8].copy_from_slice(b"mechfmuS");
        }
        (b, None)
    }

    /// Log categories for SetDebugLogging: up to three, mostly known ones, sometimes
    /// unknown, empty, not UTF-8 or NULL; whether the array is NULL; its length (absurd
    /// with a NULL array sometimes).
    pub(crate) fn logging_categories(&mut self) -> (Vec<Option<CString>>, bool, usize) {
        let pool: [&[u8]; 9] = [
            b"logEvents",
            b"logStatusWarning",
            b"logStatusDiscard",
            b"logStatusError",
            b"logStatusFatal",
            b"logAll",
            b"logUnknown",
            b"",
            b"\xff\xfe",
        ];
        let n = self.rng.below(4);
        let mut names: Vec<Option<CString>> = (0..n)
            .map(|_| {
                if self.rng.chance(0.05) {
                    None
                } else {
                    let i = if self.rng.chance(0.8) {
                        self.rng.below(6)
                    } else {
                        self.rng.below(9)
                    };
                    Some(CString::new(pool[i]).unwrap())
                }
            })
            .collect();
        if n == 0 && self.rng.chance(0.5) {
            names.clear();
        }
        let null_array = self.rng.chance(0.05);
        let nc = if null_array && self.rng.chance(0.5) {
            usize::MAX
        } else {
            names.len()
        };
        (names, null_array, nc)
    }

    /// The oracle's copy of the category logic: what SetDebugLogging(`on`, `names`) did to
    /// the categories of the instance `target` (when legal).
    pub(crate) fn apply_logging(
        &mut self,
        target: Target,
        legal: bool,
        on: bool,
        names: &[Option<CString>],
        null_array: bool,
        nc: usize,
    ) {
        let Some(inst) = self.inst(target).filter(|_| legal) else {
            return;
        };
        if (null_array && nc > 0)
            || !names
                .iter()
                .all(|n| n.as_ref().is_some_and(|c| c.to_str().is_ok()))
        {
            return;
        }
        if names.is_empty() {
            inst.categories = [on; 5];
            return;
        }
        // All or nothing: an unknown name leaves every category as it was.
        let mut categories = inst.categories;
        for n in names.iter().flatten() {
            match crate::importer::CATEGORIES
                .iter()
                .position(|c| c.as_bytes() == n.as_bytes())
            {
                Some(5) => categories = [on; 5],
                Some(k) => categories[k] = on,
                None => return,
            }
        }
        inst.categories = categories;
    }
}

/// `p`, or NULL where `null`: an out argument handed over or withheld.
pub(crate) fn null_if<T>(null: bool, p: *mut T) -> *mut T {
    if null {
        std::ptr::null_mut()
    } else {
        p
    }
}
