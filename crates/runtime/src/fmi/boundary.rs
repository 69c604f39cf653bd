//! The C boundary: the only place where the importer's raw pointers become Rust references.
//!
//! Every exported function (see [`fmi2::functions`](crate::fmi2::functions), [`fmi3::functions`](crate::fmi3::functions)) runs its body through
//! [`guarded`] (or [`guarded_or`] for the calls without an instance): the instance pointer is
//! checked, the call against the state table, the body runs under `catch_unwind`, and a
//! failure becomes a status and a message to the importer's logger. Each kind of pointer
//! argument has one checked conversion here ([`slice()`], [`slice_mut`], [`out`], [`c_str`],
//! [`strings`], [`fmu_state`], [`StateSlot`], [`Buffer`]), with the one SAFETY argument it rests on; the
//! bodies they feed ([`shared_calls`](super::shared_calls) and each layer's `calls`) are safe Rust.

#![allow(non_upper_case_globals)]

use super::fmu_state::{FmuState, STATE_MAGIC};
use super::instance::{magic, Instance};
use super::machine::{Function, ModelState};
use super::{Status, Version, DISCARD, ERROR, OK};
use crate::model::Mechanism;
use std::ffi::CStr;
use std::os::raw::{c_char, c_void};
use std::panic::{catch_unwind, AssertUnwindSafe};

/// Largest array length accepted from an importer: beyond it a length is surely garbage.
const MAX_ARRAY: usize = 1 << 24;

/// A failed call: the status to return and the message to log.
#[derive(Debug)]
pub struct Failure {
    pub status: Status,
    pub message: String,
}

/// What a call's body returns: the status of a success, or a failure to log.
pub type Outcome = Result<Status, Failure>;

/// A failure with `Error`.
pub fn error(message: impl Into<String>) -> Failure {
    Failure {
        status: ERROR,
        message: message.into(),
    }
}

/// A failure with `Discard`.
pub fn discard(message: impl Into<String>) -> Failure {
    Failure {
        status: DISCARD,
        message: message.into(),
    }
}

impl From<String> for Failure {
    fn from(message: String) -> Self {
        error(message)
    }
}

/// The instance behind `c`, if it is a live instance of this FMU.
///
/// # Safety
/// `c` is NULL or a pointer the importer got from instantiating this binary (freed or not:
/// the magic number, cleared when an instance is freed, refuses a stale one while its memory
/// is still mapped; it also refuses an instance of the other standard than `version`).
pub(crate) unsafe fn instance<'a, M: Mechanism>(
    c: *mut c_void,
    version: Version,
) -> Option<&'a mut Instance<M>> {
    let ptr = c as *mut Instance<M>;
    if ptr.is_null() || !ptr.is_aligned() {
        return None;
    }
    // SAFETY: `c` came from instantiating (see above); the importer calls one function of
    // an instance at a time (FMI 2.0.5, section 2.1.5; FMI 3.0, section 2.2.3), so the
    // borrow is exclusive.
    let inst = unsafe { &mut *ptr };
    (inst.magic == magic(version)).then_some(inst)
}

/// Whether `function` may be called in the instance's state (the standard's table); logs
/// why not when it may not.
#[inline(always)]
fn allowed<M: Mechanism>(inst: &Instance<M>, function: &Function) -> bool {
    function.allows(inst.interface, inst.state) || refused(inst, function)
}

/// Logs an illegal call sequence, or a function of the other interface type; false.
#[cold]
#[inline(never)]
fn refused<M: Mechanism>(inst: &Instance<M>, function: &Function) -> bool {
    let message = match function.interface {
        Some(interface) if interface != inst.interface => format!(
            "{}: a {} function, but the instance was instantiated for {}",
            function.name,
            interface.name(),
            inst.interface.name()
        ),
        _ => format!(
            "{}: illegal call sequence: the instance is {}",
            function.name,
            inst.state.name()
        ),
    };
    inst.logger.log(ERROR, &message);
    false
}

/// The boundary every function of an instance stands behind: `c` is checked, the call is
/// checked against `function`'s row of the state table, `body` runs under `catch_unwind`,
/// and a failure is logged through the importer's logger and returned as its status.
///
/// # Safety
/// As for `instance`: `c` is NULL or a pointer the importer got from instantiating this binary.
pub unsafe fn guarded<M: Mechanism>(
    c: *mut c_void,
    function: &Function,
    body: impl FnOnce(&mut Instance<M>) -> Outcome,
) -> Status {
    let result = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: the caller's promise.
        let Some(inst) = (unsafe { instance::<M>(c, function.version) }) else {
            return ERROR;
        };
        if !allowed(inst, function) {
            return ERROR;
        }
        match body(inst) {
            Ok(status) => status,
            Err(failure) => failed(&inst.logger, function, failure),
        }
    }));
    result.unwrap_or_else(|payload| {
        // SAFETY: the caller's promise; the body's borrow has ended with its panic.
        unsafe { panicked::<M>(c, function, payload) }
    })
}

/// After a panic inside a call: the instance (which may be half-updated) goes to the Error
/// state, from which it can only be reset or freed, and the panic's message is logged.
/// Cold and out of line, so the exported functions carry only a call to it and keep their
/// registers for the path every successful call takes.
///
/// # Safety
/// As for [`guarded`], with no borrow of the instance left.
#[cold]
#[inline(never)]
unsafe fn panicked<M: Mechanism>(
    c: *mut c_void,
    function: &Function,
    payload: Box<dyn std::any::Any + Send>,
) -> Status {
    let what = payload
        .downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| payload.downcast_ref::<String>().cloned())
        .unwrap_or_default();
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: the caller's promise.
        if let Some(inst) = unsafe { instance::<M>(c, function.version) } {
            inst.state = ModelState::Error;
            inst.logger.log(
                ERROR,
                &format!(
                    "{}: internal error ({what}); the instance must be reset",
                    function.name
                ),
            );
        }
    }));
    ERROR
}

/// Logs a failed call; its status. Cold: off the path of every successful call.
#[cold]
#[inline(never)]
fn failed(logger: &super::logger::Logger, function: &Function, failure: Failure) -> Status {
    let Failure { status, message } = failure;
    logger.log(status, &format!("{}: {message}", function.name));
    status
}

/// `body` under `catch_unwind`, for the calls with no instance to log to: a panic gives
/// `fallback`.
pub fn guarded_or<T>(fallback: T, body: impl FnOnce() -> T) -> T {
    catch_unwind(AssertUnwindSafe(body)).unwrap_or(fallback)
}

/// Hands a new instance to the importer.
pub fn into_component<M: Mechanism>(instance: Box<Instance<M>>) -> *mut c_void {
    Box::into_raw(instance) as *mut c_void
}

/// Frees the instance behind `c` if it is live and may be freed in its state (else logs
/// why not, when there is a logger to log to).
///
/// # Safety
/// As for `instance`: `c` is NULL or a pointer the importer got from instantiating this binary. the importer does not use `c` after this call.
pub unsafe fn free_component<M: Mechanism>(c: *mut c_void, function: &Function) {
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: the caller's promise.
        let Some(inst) = (unsafe { instance::<M>(c, function.version) }) else {
            return;
        };
        if !allowed(inst, function) {
            return;
        }
        inst.magic = 0;
        // SAFETY: created by Box::into_raw in `into_component`, and live (magic checked,
        // then cleared so a second free is refused).
        drop(unsafe { Box::from_raw(c as *mut Instance<M>) });
    }));
}

/// An importer's array of `n` elements, refusing NULL (when `n > 0`), misalignment and
/// absurd lengths.
///
/// # Safety
/// When `ptr` is non-NULL, aligned and `n` plausible, `ptr` points to `n` readable
/// elements (the importer's promise in every FMI function taking an array and its length).
#[inline(always)]
pub unsafe fn slice<'a, T>(ptr: *const T, n: usize, what: &str) -> Result<&'a [T], Failure> {
    if n == 0 {
        return Ok(&[]);
    }
    if ptr.is_null() || n > MAX_ARRAY || !ptr.is_aligned() {
        return Err(bad_array(ptr, n, what));
    }
    // SAFETY: the caller's promise; NULL, misalignment and absurd lengths are refused.
    Ok(unsafe { std::slice::from_raw_parts(ptr, n) })
}

/// An importer's output array of `n` elements (checked as [`slice`]).
///
/// # Safety
/// As for [`slice`], with the elements writable and not aliased by another argument.
#[inline(always)]
pub unsafe fn slice_mut<'a, T>(ptr: *mut T, n: usize, what: &str) -> Result<&'a mut [T], Failure> {
    if n == 0 {
        return Ok(&mut []);
    }
    if ptr.is_null() || n > MAX_ARRAY || !ptr.is_aligned() {
        return Err(bad_array(ptr, n, what));
    }
    // SAFETY: the caller's promise; NULL, misalignment and absurd lengths are refused.
    Ok(unsafe { std::slice::from_raw_parts_mut(ptr, n) })
}

/// Why an importer's array was refused.
#[cold]
#[inline(never)]
fn bad_array<T>(ptr: *const T, n: usize, what: &str) -> Failure {
    if ptr.is_null() {
        error(format!("{what} is NULL but its length is {n}"))
    } else if n > MAX_ARRAY {
        error(format!("{what} has an implausible length {n}"))
    } else {
        misaligned(what)
    }
}

/// A pointer not aligned for what it points to: not one the importer's C code can have
/// made for that type.
#[cold]
#[inline(never)]
fn misaligned(what: &str) -> Failure {
    error(format!("{what} is misaligned for its type"))
}

/// A NULL argument the call needs.
#[cold]
#[inline(never)]
fn null(what: &str) -> Failure {
    error(format!("{what} is NULL"))
}

/// An importer's output argument (a single value), refusing NULL and misalignment.
/// Inlined with its messages out of line: a communication step checks four of them.
///
/// # Safety
/// When non-NULL and aligned, `ptr` points to a writable `T`.
#[inline(always)]
pub unsafe fn out<'a, T>(ptr: *mut T, what: &str) -> Result<&'a mut T, Failure> {
    if ptr.is_null() {
        return Err(null(what));
    }
    if !ptr.is_aligned() {
        return Err(misaligned(what));
    }
    // SAFETY: the caller's promise; NULL and misalignment are refused.
    Ok(unsafe { &mut *ptr })
}

/// An importer's optional out argument: `None` when NULL (the importer does not want it);
/// a misaligned pointer is refused.
///
/// # Safety
/// As for [`out`].
pub unsafe fn out_or_null<'a, T>(ptr: *mut T, what: &str) -> Result<Option<&'a mut T>, Failure> {
    if ptr.is_null() {
        return Ok(None);
    }
    // SAFETY: the caller's promise.
    unsafe { out(ptr, what) }.map(Some)
}

/// An importer's string: `None` when NULL or not UTF-8.
///
/// # Safety
/// When non-NULL, `ptr` points to a NUL-terminated string.
pub unsafe fn c_str<'a>(ptr: *const c_char) -> Option<&'a str> {
    if ptr.is_null() {
        return None;
    }
    // SAFETY: the caller's promise.
    unsafe { CStr::from_ptr(ptr) }.to_str().ok()
}

/// An importer's array of `n` strings, each non-NULL and UTF-8 (`element` names one in the
/// message when it is not).
///
/// # Safety
/// As for [`slice`] and, for each element, [`c_str`].
pub unsafe fn strings<'a>(
    ptr: *const *const c_char,
    n: usize,
    what: &str,
    element: &str,
) -> Result<Vec<&'a str>, Failure> {
    // SAFETY: the caller's promise.
    let pointers = unsafe { slice(ptr, n, what) }?;
    pointers
        .iter()
        // SAFETY: the caller's promise.
        .map(|&p| {
            unsafe { c_str(p) }.ok_or_else(|| error(format!("{element} is NULL or not UTF-8")))
        })
        .collect()
}

/// The live FMU state behind an importer's handle.
///
/// # Safety
/// `s` is NULL or a handle from getting or deserializing an FMU state of this binary
/// (freed or not: its magic number is cleared when it is freed).
pub unsafe fn fmu_state<'a>(s: *mut c_void) -> Result<&'a mut FmuState, Failure> {
    let ptr = s as *mut FmuState;
    if ptr.is_null() {
        return Err(error("the FMU state is NULL"));
    }
    if !ptr.is_aligned() {
        return Err(misaligned("the FMU state"));
    }
    // SAFETY: the caller's promise; one call at a time, so the borrow is exclusive.
    let state = unsafe { &mut *ptr };
    if state.magic != STATE_MAGIC {
        return Err(error(
            "the FMU state is not a live state of this FMU (freed, or not from getting or deserializing one)",
        ));
    }
    Ok(state)
}

/// The importer's `fmi2FMUstate*` (`fmi3FMUState*`) argument: where a state is handed
/// over, or freed from. Checked when used, so a call checks its other arguments first.
pub struct StateSlot {
    ptr: *mut *mut c_void,
    /// The argument's name in messages (`FMUstate`, FMI 3.0's `FMUState`).
    what: &'static str,
}

impl StateSlot {
    /// FMI 2.0's `FMUstate`.
    ///
    /// # Safety
    /// `ptr` is NULL or points to a writable FMU state handle that is NULL or a handle as
    /// for [`fmu_state`].
    pub unsafe fn new(ptr: *mut *mut c_void) -> Self {
        StateSlot {
            ptr,
            what: "FMUstate",
        }
    }

    /// The argument named `what` (FMI 3.0's `FMUState`).
    ///
    /// # Safety
    /// As for [`new`](Self::new).
    pub unsafe fn named(ptr: *mut *mut c_void, what: &'static str) -> Self {
        StateSlot { ptr, what }
    }

    fn get<'a>(&self) -> Result<&'a mut *mut c_void, Failure> {
        // SAFETY: `new`'s promise.
        unsafe { out(self.ptr, self.what) }
    }

    /// Hands `state` to the importer, reusing the state the slot holds if any.
    pub fn store(self, state: FmuState) -> Outcome {
        let slot = self.get()?;
        if slot.is_null() {
            *slot = Box::into_raw(Box::new(state)) as *mut c_void;
        } else {
            // SAFETY: `new`'s promise about what the slot holds.
            *unsafe { fmu_state(*slot) }? = state;
        }
        Ok(OK)
    }

    /// Frees the state the slot holds (nothing if NULL) and sets the slot to NULL.
    pub fn free(self) -> Outcome {
        let slot = self.get()?;
        if slot.is_null() {
            return Ok(OK);
        }
        // SAFETY: `new`'s promise about what the slot holds.
        unsafe { fmu_state(*slot) }?.magic = 0;
        // SAFETY: a live state (magic checked, then cleared) that `store` created with
        // Box::into_raw.
        drop(unsafe { Box::from_raw(*slot as *mut FmuState) });
        *slot = std::ptr::null_mut();
        Ok(OK)
    }
}

/// The importer's output buffer of `len` bytes (serializing an FMU state), checked when it is
/// filled, so a call checks its length first.
pub struct Buffer {
    ptr: *mut u8,
    len: usize,
}

impl Buffer {
    /// # Safety
    /// As for [`slice_mut`]: when `ptr` is non-NULL and `len` plausible, `ptr` points to `len`
    /// writable bytes.
    pub unsafe fn new(ptr: *mut u8, len: usize) -> Self {
        Buffer { ptr, len }
    }

    /// Its length in bytes, as the importer gave it.
    pub fn size(&self) -> usize {
        self.len
    }

    /// Copies `bytes` into the buffer, which must be exactly as long.
    pub fn fill(self, bytes: &[u8], what: &str) -> Result<(), Failure> {
        if bytes.len() != self.len {
            return Err(error(format!(
                "{what} has {} bytes, not the {} given",
                self.len,
                bytes.len()
            )));
        }
        // SAFETY: `new`'s promise.
        unsafe { slice_mut(self.ptr, self.len, what) }?.copy_from_slice(bytes);
        Ok(())
    }
}
