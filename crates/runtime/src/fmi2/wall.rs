//! The C boundary: the only place where the importer's raw pointers become Rust references.
//!
//! Every exported function (see [`functions`](super::functions)) runs its body through
//! [`guarded`] (or [`guarded_or`] for the calls without an instance): the instance pointer is
//! checked, the call against the state table, the body runs under `catch_unwind`, and a
//! failure becomes a status and a message to the importer's logger. Each kind of pointer
//! argument has one checked conversion here ([`slice`], [`slice_mut`], [`out`], [`c_str`],
//! [`strings`], [`fmu_state`], [`StateSlot`], [`Buffer`]), with the one SAFETY argument it rests on; the
//! bodies they feed ([`api`](super::api)) are safe Rust.

#![allow(non_upper_case_globals)]

use super::ffi::*;
use super::fmu_state::{FmuState, STATE_MAGIC};
use super::instance::{Instance, MAGIC};
use super::state::{Function, ModelState};
use crate::model::Mechanism;
use std::ffi::CStr;
use std::panic::{catch_unwind, AssertUnwindSafe};

/// Largest array length accepted from an importer: beyond it a length is surely garbage.
const MAX_ARRAY: usize = 1 << 24;

/// A failed call: the status to return and the message to log.
#[derive(Debug)]
pub struct Failure {
    pub status: fmi2Status,
    pub message: String,
}

/// What a call's body returns: the status of a success, or a failure to log.
pub type Outcome = Result<fmi2Status, Failure>;

/// A failure with `fmi2Error`.
pub fn error(message: impl Into<String>) -> Failure {
    Failure {
        status: fmi2Error,
        message: message.into(),
    }
}

/// A failure with `fmi2Discard`.
pub fn discard(message: impl Into<String>) -> Failure {
    Failure {
        status: fmi2Discard,
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
/// `c` is NULL or a pointer the importer got from `fmi2Instantiate` of this binary (freed
/// or not: the magic number, cleared when an instance is freed, refuses a stale one while
/// its memory is still mapped).
pub(crate) unsafe fn instance<'a, M: Mechanism>(c: fmi2Component) -> Option<&'a mut Instance<M>> {
    let ptr = c as *mut Instance<M>;
    if ptr.is_null() || !ptr.is_aligned() {
        return None;
    }
    // SAFETY: `c` came from fmi2Instantiate (see above); the importer calls one function of
    // an instance at a time (FMI 2.0.5, section 2.1.5), so the borrow is exclusive.
    let inst = unsafe { &mut *ptr };
    (inst.magic == MAGIC).then_some(inst)
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
    inst.logger.log(fmi2Error, &message);
    false
}

/// The wall every function of an instance stands behind: `c` is checked, the call is
/// checked against `function`'s row of the state table, `body` runs under `catch_unwind`,
/// and a failure is logged through the importer's logger and returned as its status.
///
/// # Safety
/// As for [`instance`].
pub unsafe fn guarded<M: Mechanism>(
    c: fmi2Component,
    function: &Function,
    body: impl FnOnce(&mut Instance<M>) -> Outcome,
) -> fmi2Status {
    let result = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: the caller's promise.
        let Some(inst) = (unsafe { instance::<M>(c) }) else {
            return fmi2Error;
        };
        if !allowed(inst, function) {
            return fmi2Error;
        }
        match body(inst) {
            Ok(status) => status,
            Err(failure) => failed(&inst.logger, function, failure),
        }
    }));
    result.unwrap_or_else(|payload| {
        let what = payload
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| payload.downcast_ref::<String>().cloned())
            .unwrap_or_default();
        // The instance may be half-updated: it can only be reset or freed from here on.
        let _ = catch_unwind(AssertUnwindSafe(|| {
            // SAFETY: the caller's promise; the body's borrow has ended with its panic.
            if let Some(inst) = unsafe { instance::<M>(c) } {
                inst.state = ModelState::Error;
                inst.logger.log(
                    fmi2Error,
                    &format!(
                        "{}: internal error ({what}); the instance must be reset",
                        function.name
                    ),
                );
            }
        }));
        fmi2Error
    })
}

/// Logs a failed call; its status. Cold: off the path of every successful call.
#[cold]
#[inline(never)]
fn failed(logger: &super::logger::Logger, function: &Function, failure: Failure) -> fmi2Status {
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
pub fn into_component<M: Mechanism>(instance: Box<Instance<M>>) -> fmi2Component {
    Box::into_raw(instance) as fmi2Component
}

/// Frees the instance behind `c` if it is live and may be freed in its state (else logs
/// why not, when there is a logger to log to).
///
/// # Safety
/// As for [`instance`]; the importer does not use `c` after this call.
pub unsafe fn free_component<M: Mechanism>(c: fmi2Component, function: &Function) {
    let _ = catch_unwind(AssertUnwindSafe(|| {
        // SAFETY: the caller's promise.
        let Some(inst) = (unsafe { instance::<M>(c) }) else {
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
        return Err(bad_array(ptr.is_null(), n, what));
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
        return Err(bad_array(ptr.is_null(), n, what));
    }
    // SAFETY: the caller's promise; NULL, misalignment and absurd lengths are refused.
    Ok(unsafe { std::slice::from_raw_parts_mut(ptr, n) })
}

/// Why an importer's array was refused.
#[cold]
#[inline(never)]
fn bad_array(null: bool, n: usize, what: &str) -> Failure {
    if null {
        error(format!("{what} is NULL but its length is {n}"))
    } else {
        error(format!("{what} has an implausible length {n}"))
    }
}

/// An importer's output argument (a single value), refusing NULL and misalignment.
///
/// # Safety
/// When non-NULL and aligned, `ptr` points to a writable `T`.
pub unsafe fn out<'a, T>(ptr: *mut T, what: &str) -> Result<&'a mut T, Failure> {
    if ptr.is_null() || !ptr.is_aligned() {
        return Err(error(format!("{what} is NULL")));
    }
    // SAFETY: the caller's promise; NULL and misalignment are refused.
    Ok(unsafe { &mut *ptr })
}

/// An importer's string: `None` when NULL or not UTF-8.
///
/// # Safety
/// When non-NULL, `ptr` points to a NUL-terminated string.
pub unsafe fn c_str<'a>(ptr: fmi2String) -> Option<&'a str> {
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
    ptr: *const fmi2String,
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
/// `s` is NULL or a handle from `fmi2GetFMUstate`/`fmi2DeSerializeFMUstate` of this binary
/// (freed or not: its magic number is cleared when it is freed).
pub unsafe fn fmu_state<'a>(s: fmi2FMUstate) -> Result<&'a mut FmuState, Failure> {
    let ptr = s as *mut FmuState;
    if ptr.is_null() || !ptr.is_aligned() {
        return Err(error("the FMU state is NULL"));
    }
    // SAFETY: the caller's promise; one call at a time, so the borrow is exclusive.
    let state = unsafe { &mut *ptr };
    if state.magic != STATE_MAGIC {
        return Err(error(
            "the FMU state is not a live state of this FMU (freed, or not from fmi2GetFMUstate)",
        ));
    }
    Ok(state)
}

/// The importer's `fmi2FMUstate*` argument: where a state is handed over, or freed from.
/// Checked when used, so a call checks its other arguments first.
pub struct StateSlot(*mut fmi2FMUstate);

impl StateSlot {
    /// # Safety
    /// `ptr` is NULL or points to a writable `fmi2FMUstate` that is NULL or a handle as for
    /// [`fmu_state`].
    pub unsafe fn new(ptr: *mut fmi2FMUstate) -> Self {
        StateSlot(ptr)
    }

    fn get<'a>(&self) -> Result<&'a mut fmi2FMUstate, Failure> {
        // SAFETY: `new`'s promise.
        unsafe { out(self.0, "FMUstate") }
    }

    /// Hands `state` to the importer, reusing the state the slot holds if any.
    pub fn store(self, state: FmuState) -> Outcome {
        let slot = self.get()?;
        if slot.is_null() {
            *slot = Box::into_raw(Box::new(state)) as fmi2FMUstate;
        } else {
            // SAFETY: `new`'s promise about what the slot holds.
            *unsafe { fmu_state(*slot) }? = state;
        }
        Ok(fmi2OK)
    }

    /// Frees the state the slot holds (nothing if NULL) and sets the slot to NULL.
    pub fn free(self) -> Outcome {
        let slot = self.get()?;
        if slot.is_null() {
            return Ok(fmi2OK);
        }
        // SAFETY: `new`'s promise about what the slot holds.
        unsafe { fmu_state(*slot) }?.magic = 0;
        // SAFETY: a live state (magic checked, then cleared) that `store` created with
        // Box::into_raw.
        drop(unsafe { Box::from_raw(*slot as *mut FmuState) });
        *slot = std::ptr::null_mut();
        Ok(fmi2OK)
    }
}

/// The importer's output buffer of `len` bytes (`fmi2SerializeFMUstate`), checked when it is
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

/// `fmi2Instantiate`: the callbacks and strings checked, the instance made by
/// [`api::instantiate`](super::api::instantiate) and handed over; NULL (with a message when
/// there is a logger) on any failure.
///
/// # Safety
/// `functions` is NULL or points to the importer's callback table; the strings are NULL or
/// NUL-terminated.
pub unsafe fn instantiate<M: Mechanism>(
    instance_name: fmi2String,
    fmu_type: fmi2Type,
    guid: fmi2String,
    functions: *const fmi2CallbackFunctions,
    logging_on: fmi2Boolean,
) -> fmi2Component {
    guarded_or(std::ptr::null_mut(), || {
        // Without callbacks there is no one to tell what went wrong.
        if functions.is_null() || !functions.is_aligned() {
            return std::ptr::null_mut();
        }
        // SAFETY: the caller's promise; NULL and misalignment are refused.
        let functions = unsafe { *functions };
        // SAFETY: the caller's promise.
        let name = unsafe { c_str(instance_name) };
        let logger = super::logger::Logger::new(
            functions.logger,
            functions.componentEnvironment,
            name.unwrap_or(""),
            logging_on != 0,
        );
        // SAFETY: the caller's promise (read only once the name and the type are accepted).
        let guid = || unsafe { c_str(guid) };
        match super::api::instantiate::<M>(logger, name, fmu_type, guid) {
            Ok(instance) => into_component(instance),
            Err((logger, message)) => {
                logger.log(fmi2Error, &format!("fmi2Instantiate: {message}"));
                std::ptr::null_mut()
            }
        }
    })
}
