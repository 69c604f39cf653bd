//! The callbacks the worker instantiates an FMU with, and the log of the running case their
//! logger fills.
//!
//! FMI 2.0's logger is C-variadic (`message` is a printf format), which stable Rust cannot
//! define. The logger is declared with one `const char*` after the format instead, which the
//! C calling conventions of the worker's platforms (x86-64 System V and Windows, AArch64
//! Linux) pass where a variadic callee would find its first variadic argument. It is read
//! only when the format is exactly `"%s"`, as mechfmu's FMUs and most exporters call it;
//! any other format is taken as the message itself, so another FMU's other conversions
//! (`%d`, `%g`, several `%s`) come through unformatted.

use mechfmu::fmi2::ffi::*;
use std::cell::RefCell;
use std::ffi::{c_char, c_void, CStr};

/// A case keeps the first this many messages (as the Python runner does).
pub const LOG_LIMIT: usize = 20;

/// One message of the FMU: its status, category and text.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LogMessage {
    pub status: u8,
    pub category: String,
    pub message: String,
}

/// The callbacks for `fmi2Instantiate` and the messages logged through them since the last
/// [`CaseLog::clear`]. Boxed, so the environment pointer the FMU keeps stays valid: keep
/// the log alive as long as any instance created with its callbacks.
pub struct CaseLog {
    messages: Box<RefCell<Vec<LogMessage>>>,
    callbacks: Box<fmi2CallbackFunctions>,
}

impl CaseLog {
    pub fn new() -> CaseLog {
        let messages: Box<RefCell<Vec<LogMessage>>> =
            Box::new(RefCell::new(Vec::with_capacity(LOG_LIMIT)));
        // SAFETY: `log_message` takes the fixed arguments of `fmi2CallbackLogger` plus one
        // pointer where the first variadic argument is passed (see the module's comment);
        // it reads that pointer only when the format says one `%s` argument was passed.
        let logger: unsafe extern "C" fn(
            fmi2ComponentEnvironment,
            fmi2String,
            fmi2Status,
            fmi2String,
            fmi2String,
            ...
        ) = unsafe { std::mem::transmute(log_message as *const c_void) };
        let environment = &*messages as *const RefCell<Vec<LogMessage>> as *mut c_void;
        let callbacks = Box::new(fmi2CallbackFunctions {
            logger: Some(logger),
            allocateMemory: Some(calloc),
            freeMemory: Some(free),
            stepFinished: None,
            componentEnvironment: environment,
        });
        CaseLog {
            messages,
            callbacks,
        }
    }

    /// The callbacks to pass to `fmi2Instantiate`.
    pub fn callbacks(&self) -> *const fmi2CallbackFunctions {
        &*self.callbacks
    }

    pub fn clear(&self) {
        self.messages.borrow_mut().clear();
    }

    /// The messages logged since the last clear (at most [`LOG_LIMIT`]).
    pub fn messages(&self) -> std::cell::Ref<'_, Vec<LogMessage>> {
        self.messages.borrow()
    }
}

extern "C" {
    // The C library's, which the FMU's memory callbacks are specified as.
    fn calloc(nobj: usize, size: usize) -> *mut c_void;
    fn free(obj: *mut c_void);
}

/// `fmi2CallbackLogger`, declared with the first variadic argument as a sixth parameter.
unsafe extern "C" fn log_message(
    environment: fmi2ComponentEnvironment,
    _instance_name: fmi2String,
    status: fmi2Status,
    category: fmi2String,
    format: fmi2String,
    first_argument: *const c_char,
) {
    if environment.is_null() {
        return;
    }
    // SAFETY: the FMU passes back the environment of a live `CaseLog` (the one whose
    // callbacks it was instantiated with), and NUL-terminated strings or NULL.
    unsafe {
        let messages = &*(environment as *const RefCell<Vec<LogMessage>>);
        // Called only from inside an FMI call, when the worker holds no borrow.
        let Ok(mut messages) = messages.try_borrow_mut() else {
            return;
        };
        if messages.len() >= LOG_LIMIT {
            return;
        }
        let format = text(format);
        let message = if format == "%s" {
            text(first_argument)
        } else {
            format
        };
        messages.push(LogMessage {
            status: status.min(u8::MAX as fmi2Status) as u8,
            category: text(category),
            message,
        });
    }
}

/// A C string as text (NULL as empty, invalid UTF-8 replaced).
///
/// # Safety
/// `p` is NULL or NUL-terminated.
unsafe fn text(p: *const c_char) -> String {
    if p.is_null() {
        String::new()
    } else {
        // SAFETY: the caller's promise.
        unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Calls the logger the way a C FMU calls it: through the variadic pointer type.
    fn log(log: &CaseLog, status: fmi2Status, format: &CStr, argument: &CStr) {
        // SAFETY: the callbacks of a live log, called with valid strings.
        unsafe {
            let callbacks = &*log.callbacks();
            (callbacks.logger.unwrap())(
                callbacks.componentEnvironment,
                c"sweep".as_ptr(),
                status,
                c"logStatusError".as_ptr(),
                format.as_ptr(),
                argument.as_ptr(),
            );
        }
    }

    #[test]
    fn keeps_the_first_messages_of_a_case() {
        let case_log = CaseLog::new();
        log(&case_log, fmi2Error, c"%s", c"m = -1 is not positive");
        log(&case_log, fmi2Warning, c"step %d failed", c"ignored");
        assert_eq!(
            *case_log.messages(),
            [
                LogMessage {
                    status: 3,
                    category: "logStatusError".into(),
                    message: "m = -1 is not positive".into(),
                },
                LogMessage {
                    status: 1,
                    category: "logStatusError".into(),
                    message: "step %d failed".into(),
                },
            ]
        );
        for _ in 0..30 {
            log(&case_log, fmi2OK, c"%s", c"again");
        }
        assert_eq!(case_log.messages().len(), LOG_LIMIT);
        case_log.clear();
        assert!(case_log.messages().is_empty());
    }
}
