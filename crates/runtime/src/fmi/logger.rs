//! Messages to the importer's logger, filtered by log category: FMI 2.0's callback (with
//! the instance name and a format string) or FMI 3.0's.

use super::{Status, DISCARD, ERROR, OK, WARNING};
use crate::contract::LOG_CATEGORIES;
use std::ffi::CString;
use std::os::raw::{c_char, c_void};

/// The category a message of a given status belongs to.
pub fn category_of(status: Status) -> usize {
    match status {
        OK => 0,
        WARNING => 1,
        DISCARD => 2,
        ERROR => 3,
        _ => 4,
    }
}

/// FMI 2.0's `fmi2CallbackLogger` (environment, instance name, status, category, format, ...).
pub type Fmi2Callback =
    unsafe extern "C" fn(*mut c_void, *const c_char, Status, *const c_char, *const c_char, ...);

/// FMI 3.0's `fmi3LogMessageCallback` (environment, status, category, message).
pub type Fmi3Callback = unsafe extern "C" fn(*mut c_void, Status, *const c_char, *const c_char);

/// Where messages go: the importer's callback of either standard, or nowhere.
pub enum Sink {
    Fmi2 {
        callback: Fmi2Callback,
        environment: *mut c_void,
        instance_name: CString,
    },
    Fmi3 {
        callback: Fmi3Callback,
        environment: *mut c_void,
    },
    None,
}

/// The importer's logger and which categories it wants.
pub struct Logger {
    sink: Sink,
    /// Per category of [`LOG_CATEGORIES`] except `logAll`.
    enabled: [bool; 5],
}

// The environment pointer is the importer's; it is handed back to the importer's own
// logger and never dereferenced here.
unsafe impl Send for Logger {}

impl Logger {
    /// FMI 2.0's logger (none when `callback` is NULL). Status messages are on from the
    /// start (an importer needs to know why a call failed); `logEvents` follows `loggingOn`.
    pub fn new(
        callback: Option<Fmi2Callback>,
        environment: *mut c_void,
        instance_name: &str,
        logging_on: bool,
    ) -> Self {
        let sink = match callback {
            Some(callback) => Sink::Fmi2 {
                callback,
                environment,
                instance_name: to_cstring(instance_name),
            },
            None => Sink::None,
        };
        Logger::with_sink(sink, logging_on)
    }

    /// FMI 3.0's logger (none when `callback` is NULL), as [`Logger::new`].
    pub fn fmi3(
        callback: Option<Fmi3Callback>,
        environment: *mut c_void,
        logging_on: bool,
    ) -> Self {
        let sink = match callback {
            Some(callback) => Sink::Fmi3 {
                callback,
                environment,
            },
            None => Sink::None,
        };
        Logger::with_sink(sink, logging_on)
    }

    fn with_sink(sink: Sink, logging_on: bool) -> Self {
        Logger {
            sink,
            enabled: [logging_on, true, true, true, true],
        }
    }

    /// `fmi2SetDebugLogging`: no categories means all of them. All or nothing: with an
    /// unknown name among them no category changes, so the error it returns is logged as
    /// the categories were before (an error category switched off by the same call would
    /// swallow it).
    pub fn set_categories(&mut self, on: bool, categories: &[&str]) -> Result<(), String> {
        let mut enabled = self.enabled;
        if categories.is_empty() {
            enabled = [on; 5];
        }
        for name in categories {
            match LOG_CATEGORIES.iter().position(|(c, _)| c == name) {
                Some(5) => enabled = [on; 5],
                Some(i) => enabled[i] = on,
                None => {
                    let known: Vec<&str> = LOG_CATEGORIES.iter().map(|c| c.0).collect();
                    return Err(format!(
                        "unknown log category \"{name}\" (known: {}); no category changed",
                        known.join(", ")
                    ));
                }
            }
        }
        self.enabled = enabled;
        Ok(())
    }

    pub fn enabled(&self, status: Status) -> bool {
        self.enabled[category_of(status)]
    }

    /// Sends `message` with the category matching `status`, if that category is on. FMI
    /// 2.0's text goes through `"%s"`, so a `%` in it is printed, not interpreted.
    pub fn log(&self, status: Status, message: &str) {
        let category = category_of(status);
        if matches!(self.sink, Sink::None) || !self.enabled[category] {
            return;
        }
        let category = to_cstring(LOG_CATEGORIES[category].0);
        let message = to_cstring(message);
        // SAFETY: the importer gave this callback for this instance; all strings are valid
        // NUL-terminated C strings that outlive the call.
        unsafe {
            match &self.sink {
                Sink::Fmi2 {
                    callback,
                    environment,
                    instance_name,
                } => callback(
                    *environment,
                    instance_name.as_ptr(),
                    status,
                    category.as_ptr(),
                    c"%s".as_ptr(),
                    message.as_ptr(),
                ),
                Sink::Fmi3 {
                    callback,
                    environment,
                } => callback(*environment, status, category.as_ptr(), message.as_ptr()),
                Sink::None => {}
            }
        }
    }
}

/// A C string of `s`, with any interior NUL replaced (a message is never lost to one).
pub fn to_cstring(s: &str) -> CString {
    CString::new(s.replace('\0', "\u{FFFD}")).unwrap_or_default()
}
