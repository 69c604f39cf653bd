//! The importer's side of logging: the callbacks an instance of either version is made
//! with, and the messages their logger records.
//!
//! FMI 2.0's logger is C-variadic (`message` is a printf format), which stable Rust cannot
//! define. The logger is declared with one `const char*` after the format instead, which the
//! C calling conventions of mechfmu's platforms (x86-64 System V and Windows, AArch64 Linux)
//! pass where a variadic callee would find its first variadic argument. It is read only when
//! the format is exactly `"%s"`, as mechfmu's FMUs and most exporters call it; any other
//! format is taken as the message itself, so another FMU's other conversions (`%d`, `%g`,
//! several `%s`) come through unformatted. FMI 3.0's logger takes the message as it is.

use mechfmu::fmi2::ffi::*;
use mechfmu::fmi3::ffi::{fmi3InstanceEnvironment, fmi3Status, fmi3String};
use std::cell::{Ref, RefCell};
use std::ffi::{c_char, c_uint, c_void, CStr};

/// One message of the FMU.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Message {
    /// The `fmi2Status` or `fmi3Status` it was logged with.
    pub status: c_uint,
    pub category: String,
    pub text: String,
}

/// What the logger appends to: the first `limit` messages.
struct Messages {
    kept: RefCell<Vec<Message>>,
    limit: usize,
}

/// The messages an FMU logged, and the callbacks it logs them through. The messages and
/// the callbacks are boxed, so the environment pointer an FMU keeps stays valid wherever
/// the log moves: keep the log alive as long as any instance made with it (the instances
/// of [`crate::fmi2`] and [`crate::fmi3`] hold on to it).
pub struct Log {
    messages: Box<Messages>,
    callbacks: Box<fmi2CallbackFunctions>,
}

impl Log {
    /// A log that keeps every message.
    pub fn new() -> Log {
        Log::keeping(usize::MAX)
    }

    /// A log that keeps the first `limit` messages (room for them taken up front, so that
    /// logging allocates nothing up to a small limit).
    pub fn keeping(limit: usize) -> Log {
        let messages = Box::new(Messages {
            kept: RefCell::new(Vec::with_capacity(limit.min(64))),
            limit,
        });
        // SAFETY: `log_fmi2` takes the fixed arguments of `fmi2CallbackLogger` plus one
        // pointer where the first variadic argument is passed (see the module's comment);
        // it reads that pointer only when the format says one `%s` argument was passed.
        let logger: unsafe extern "C" fn(
            fmi2ComponentEnvironment,
            fmi2String,
            fmi2Status,
            fmi2String,
            fmi2String,
            ...
        ) = unsafe { std::mem::transmute(log_fmi2 as *const c_void) };
        let callbacks = Box::new(fmi2CallbackFunctions {
            logger: Some(logger),
            allocateMemory: Some(calloc),
            freeMemory: Some(free),
            stepFinished: None,
            componentEnvironment: &*messages as *const Messages as *mut c_void,
        });
        Log {
            messages,
            callbacks,
        }
    }

    /// The callbacks to pass to `fmi2Instantiate`.
    pub(crate) fn fmi2_callbacks(&self) -> *const fmi2CallbackFunctions {
        &*self.callbacks
    }

    /// The `instanceEnvironment` and `logMessage` to pass to an FMI 3.0 instantiation.
    pub(crate) fn fmi3_callback(
        &self,
    ) -> (
        fmi3InstanceEnvironment,
        unsafe extern "C" fn(fmi3InstanceEnvironment, fmi3Status, fmi3String, fmi3String),
    ) {
        (self.callbacks.componentEnvironment, log_fmi3)
    }

    #[inline]
    pub fn clear(&self) {
        self.messages.kept.borrow_mut().clear();
    }

    /// The messages logged since the log was made or cleared (at most its limit).
    #[inline]
    pub fn messages(&self) -> Ref<'_, Vec<Message>> {
        self.messages.kept.borrow()
    }
}

impl Default for Log {
    fn default() -> Log {
        Log::new()
    }
}

extern "C" {
    // The C library's, which FMI 2.0's memory callbacks are specified as.
    fn calloc(nobj: usize, size: usize) -> *mut c_void;
    fn free(obj: *mut c_void);
}

/// Appends a message to the log whose environment `environment` is.
///
/// # Safety
/// `environment` is NULL or the environment of a live [`Log`]; the strings are NULL or
/// NUL-terminated.
unsafe fn record(
    environment: *mut c_void,
    status: c_uint,
    category: *const c_char,
    text: impl FnOnce() -> String,
) {
    if environment.is_null() {
        return;
    }
    // SAFETY: the caller's promise.
    let messages = unsafe { &*(environment as *const Messages) };
    // Called only from inside an FMI call, when the importer holds no borrow.
    let Ok(mut kept) = messages.kept.try_borrow_mut() else {
        return;
    };
    if kept.len() >= messages.limit {
        return;
    }
    kept.push(Message {
        status,
        // SAFETY: the caller's promise.
        category: unsafe { c_text(category) },
        text: text(),
    });
}

/// `fmi2CallbackLogger`, declared with the first variadic argument as a sixth parameter.
unsafe extern "C" fn log_fmi2(
    environment: fmi2ComponentEnvironment,
    _instance_name: fmi2String,
    status: fmi2Status,
    category: fmi2String,
    format: fmi2String,
    first_argument: *const c_char,
) {
    // SAFETY: the FMU passes back the environment of the live `Log` whose callbacks it was
    // instantiated with, and NUL-terminated strings or NULL; `first_argument` is read only
    // when the format says it is one.
    unsafe {
        record(environment, status, category, || {
            let format = c_text(format);
            if format == "%s" {
                c_text(first_argument)
            } else {
                format
            }
        })
    }
}

/// `fmi3LogMessageCallback`.
unsafe extern "C" fn log_fmi3(
    environment: fmi3InstanceEnvironment,
    status: fmi3Status,
    category: fmi3String,
    message: fmi3String,
) {
    // SAFETY: the FMU passes back the environment of the live `Log` it was instantiated
    // with, and NUL-terminated strings or NULL.
    unsafe { record(environment, status, category, || c_text(message)) }
}

/// A C string as text (NULL as empty, invalid UTF-8 replaced).
///
/// # Safety
/// `p` is NULL or NUL-terminated.
unsafe fn c_text(p: *const c_char) -> String {
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

    fn log_through_fmi2(log: &Log, status: fmi2Status, format: &CStr, argument: &CStr) {
        // SAFETY: the callbacks' environment is `log`'s; the strings are NUL-terminated.
        unsafe {
            log_fmi2(
                (*log.fmi2_callbacks()).componentEnvironment,
                c"instance".as_ptr(),
                status,
                c"logStatusError".as_ptr(),
                format.as_ptr(),
                argument.as_ptr(),
            )
        }
    }

    #[test]
    fn a_percent_s_format_gives_its_argument_and_others_come_as_they_are() {
        let log = Log::keeping(2);
        log_through_fmi2(&log, fmi2Error, c"%s", c"the message");
        log_through_fmi2(&log, fmi2Warning, c"x = %g", c"ignored");
        log_through_fmi2(&log, fmi2Warning, c"%s", c"over the limit");
        let texts: Vec<(c_uint, String)> = (log.messages().iter())
            .map(|m| (m.status, m.text.clone()))
            .collect();
        let expected = [(fmi2Error, "the message"), (fmi2Warning, "x = %g")];
        assert_eq!(texts, expected.map(|(s, t)| (s, t.to_string())));
        assert_eq!(log.messages()[0].category, "logStatusError");
        log.clear();
        assert!(log.messages().is_empty());
    }

    #[test]
    fn the_fmi3_logger_records_the_message() {
        let log = Log::new();
        let (environment, logger) = log.fmi3_callback();
        // SAFETY: the environment is `log`'s; the strings are NUL-terminated.
        unsafe { logger(environment, 1, c"logEvents".as_ptr(), c"a warning".as_ptr()) };
        assert_eq!(
            log.messages().as_slice(),
            [Message {
                status: 1,
                category: "logEvents".into(),
                text: "a warning".into()
            }]
        );
    }
}
