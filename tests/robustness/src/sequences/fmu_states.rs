//! The FMU state functions, alike in both standards: get (into a fresh slot or over a
//! live state), set, free, size, serialize, deserialize, with hostile handles, slots,
//! buffers and bytes; the oracle follows what each handle holds.

use super::core::{Sequence, Standard};
use super::machine::{Call, Handle, Inst, Snap, Target};
use super::state_bytes::decode_snap;
use crate::ffi::{Component, FmuState, Status, ERROR, OK};
use crate::sequences::args::null_if;

/// What restoring a saved state into an instance must do.
pub enum Restore {
    /// Be refused with an error, for the reason given.
    Refused(String),
    /// Succeed.
    Accepted,
    /// Either (the oracle cannot tell).
    Either,
}

impl<S: Standard> Sequence<'_, S> {
    /// GetFMUState: a fresh slot, or one holding a live state (which is then overwritten).
    pub(crate) fn get_fmu_state_call(&mut self, call: Call) -> Status {
        let (function, target, c, _) = call.parts();
        let name = S::NAMES[function];
        let reuse = (!self.handles.is_empty() && self.rng.chance(0.3))
            .then(|| self.rng.below(self.handles.len()));
        let mut slot: FmuState = reuse.map_or(std::ptr::null_mut(), |k| self.handles[k].ptr);
        let null_slot = self.rng.chance(0.05);
        self.note(|| {
            format!(
                "{name}({target:?}, slot {}{})",
                if reuse.is_some() { "reused" } else { "NULL" },
                if null_slot { ", NULL slot pointer" } else { "" }
            )
        });
        let slot_ptr: *mut FmuState = null_if(null_slot, &mut slot);
        // SAFETY: a valid slot (or NULL) holding NULL or a live state.
        let s = unsafe { S::get_fmu_state(self.fmu, c, slot_ptr) };
        if let (Target::Live(i), OK) = (target, s) {
            let snap = self.insts[i].snap();
            match reuse {
                Some(k) => {
                    if slot != self.handles[k].ptr {
                        self.fail(format!("{name} replaced a reused state's handle"));
                    }
                    self.handles[k].snap = snap;
                }
                None if slot.is_null() => self.fail(format!(
                    "{name} returned {} and no state",
                    S::status_name(OK)
                )),
                None => self.handles.push(Handle { ptr: slot, snap }),
            }
        }
        s
    }

    /// SetFMUState, SerializedFMUStateSize or SerializeFMUState (`which`: 0, 1, 2) of a
    /// handle of this sequence, NULL or foreign memory; `restore` says what restoring a
    /// state into an instance must do.
    pub(crate) fn state_handle_call(
        &mut self,
        call: Call,
        which: usize,
        restore: impl Fn(&Snap, &Inst) -> Restore,
    ) -> Status {
        let (function, target, c, legal) = call.parts();
        let name = S::NAMES[function];
        let (k, h) = self.state_handle();
        self.note(|| format!("{name}({target:?}, state {k:?})"));
        match which {
            0 => {
                // SAFETY: a live state, NULL, or foreign memory.
                let s = unsafe { S::set_fmu_state(self.fmu, c, h) };
                if let (Target::Live(i), true, Some(k)) = (target, legal, k) {
                    let snap = self.handles[k].snap;
                    match restore(&snap, &self.insts[i]) {
                        Restore::Refused(why) if s != ERROR => self.fail(format!(
                            "{name} of a state {why} into a {} instance returned {}",
                            self.insts[i].kind.name(),
                            S::status_name(s)
                        )),
                        Restore::Accepted if s != OK => self.fail(format!(
                            "{name} of a state saved in {:?} by a {} instance into one returned {}",
                            snap.st,
                            snap.kind.name(),
                            S::status_name(s)
                        )),
                        Restore::Refused(_) => {}
                        _ if s == OK => {
                            self.insts[i].restore(&snap);
                            self.stats.states_restored += 1;
                        }
                        _ => {}
                    }
                }
                s
            }
            1 => {
                let mut size = usize::MAX;
                let null = self.rng.chance(0.05);
                let size_ptr: *mut usize = null_if(null, &mut size);
                // SAFETY: a valid out pointer (or NULL).
                let s = unsafe { S::serialized_size(self.fmu, c, h, size_ptr) };
                if s == OK && !null && !(16..1 << 20).contains(&size) {
                    self.fail(format!(
                        "{name} returned {} with an implausible size {size}",
                        S::status_name(s)
                    ));
                }
                s
            }
            _ => self.serialize_call(name, k, h, c),
        }
    }

    /// SerializeFMUState into a buffer of the right size, one byte more or less, none, or
    /// NULL; the bytes of a state it serializes are kept for deserializing.
    fn serialize_call(
        &mut self,
        name: &str,
        k: Option<usize>,
        h: FmuState,
        c: Component,
    ) -> Status {
        let mut size = 0usize;
        // SAFETY: a valid out pointer.
        let s0 = unsafe { S::serialized_size(self.fmu, c, h, &mut size) };
        self.stats.calls += 1;
        let ask = match self.rng.below(8) {
            0 => size.wrapping_add(1),
            1 => size.saturating_sub(1),
            2 => 0,
            _ => size,
        };
        let mut buf = vec![0x77u8; ask + 8];
        let null = self.rng.chance(0.05);
        let buf_ptr: *mut u8 = null_if(null, buf.as_mut_ptr());
        // SAFETY: `ask` writable bytes (or NULL).
        let s = unsafe { S::serialize(self.fmu, c, h, buf_ptr, ask) };
        if buf[ask..].iter().any(|&b| b != 0x77) {
            self.fail(format!("{name} wrote past the {ask} bytes it was given"));
        }
        if s == OK {
            if s0 != OK || ask != size {
                self.fail(format!(
                    "{name} returned {} for a buffer of {ask} bytes; the size is {size}",
                    S::status_name(s)
                ));
            }
            if let Some(k) = k {
                buf.truncate(ask);
                let snap = self.handles[k].snap;
                self.serialized.push((buf, snap));
            }
        }
        s
    }

    /// FreeFMUState of a handle of this sequence, NULL or foreign memory, through a valid
    /// slot or NULL.
    pub(crate) fn free_fmu_state_call(&mut self, call: Call) -> Status {
        let (function, target, c, legal) = call.parts();
        let name = S::NAMES[function];
        let (k, h) = self.state_handle();
        let mut slot = h;
        let null_slot = self.rng.chance(0.05);
        self.note(|| {
            format!(
                "{name}({target:?}, state {k:?}{})",
                if null_slot { ", NULL slot pointer" } else { "" }
            )
        });
        let slot_ptr: *mut FmuState = null_if(null_slot, &mut slot);
        // SAFETY: a valid slot (or NULL) holding a live state, NULL or foreign memory.
        let s = unsafe { S::free_fmu_state(self.fmu, c, slot_ptr) };
        if s == OK {
            if let (Some(k), false) = (k, null_slot) {
                if !slot.is_null() {
                    self.fail(format!(
                        "{name} returned {} but did not set the slot to NULL",
                        S::status_name(s)
                    ));
                }
                self.handles.remove(k);
            }
        } else if let (Some(_), false, true) =
            (k, null_slot, matches!(target, Target::Live(_)) && legal)
        {
            self.fail(format!(
                "{name} of a live state returned {}",
                S::status_name(s)
            ));
        }
        s
    }

    /// DeserializeFMUState of `bytes` (what they capture, when known) into a fresh slot or
    /// over a live state; NULL bytes sometimes, with a size or absurdly long.
    pub(crate) fn deserialize_call(
        &mut self,
        function: usize,
        target: Target,
        c: Component,
        (bytes, snap): (Vec<u8>, Option<Snap>),
    ) -> Status {
        let name = S::NAMES[function];
        let reuse = (!self.handles.is_empty() && self.rng.chance(0.2))
            .then(|| self.rng.below(self.handles.len()));
        let mut slot: FmuState = reuse.map_or(std::ptr::null_mut(), |k| self.handles[k].ptr);
        let null_bytes = self.rng.chance(0.04);
        let size = if null_bytes && self.rng.chance(0.5) {
            usize::MAX
        } else {
            bytes.len()
        };
        self.note(|| {
            format!(
                "{name}({target:?}, {} bytes{}, slot {})",
                size,
                if null_bytes { " at NULL" } else { "" },
                if reuse.is_some() { "reused" } else { "NULL" }
            )
        });
        let bytes_ptr: *const u8 = if null_bytes {
            std::ptr::null()
        } else {
            bytes.as_ptr()
        };
        // SAFETY: `size` readable bytes (or NULL); a valid slot.
        let s = unsafe { S::deserialize(self.fmu, c, bytes_ptr, size, &mut slot) };
        if let (Target::Live(_), OK) = (target, s) {
            self.stats.deserialized += 1;
            let snap = snap.or_else(|| decode_snap(&bytes));
            match (snap, reuse) {
                (None, _) => self.fail(format!("{name} accepted bytes this oracle cannot read")),
                (Some(snap), Some(k)) => self.handles[k].snap = snap,
                (Some(snap), None) => self.handles.push(Handle { ptr: slot, snap }),
            }
        }
        s
    }
}
