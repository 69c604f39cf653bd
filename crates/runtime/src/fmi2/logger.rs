//! Messages to the importer's logger, filtered by log category.
#![allow(non_upper_case_globals)]

use super::ffi::*;
use crate::contract::LOG_CATEGORIES;
use std::ffi::CString;

/// The category a message of a given status belongs to.
pub fn category_of(status: fmi2Status) -> usize {
    match status {
        fmi2OK => 0,
        fmi2Warning => 1,
        fmi2Discard => 2,
        fmi2Error => 3,
        _ => 4,
    }
}

/// The importer's logger and which categories it wants.
pub struct Logger {
    callback: fmi2CallbackLogger,
    environment: fmi2ComponentEnvironment,
    instance_name: CString,
    /// Per category of [`LOG_CATEGORIES`] except `logAll`.
    enabled: [bool; 5],
}

// The environment pointer is the importer's; it is handed back to the importer's own
// logger and never dereferenced here.
unsafe impl Send for Logger {}

impl Logger {
    /// Status messages are on from the start (an importer needs to know why a call failed);
    /// `logEvents` follows `loggingOn`.
    pub fn new(
        callback: fmi2CallbackLogger,
        environment: fmi2ComponentEnvironment,
        instance_name: &str,
        logging_on: bool,
    ) -> Self {
        Logger {
            callback,
            environment,
            instance_name: to_cstring(instance_name),
            enabled: [logging_on, true, true, true, true],
        }
    }

    /// `fmi2SetDebugLogging`: no categories means all of them.
    pub fn set_categories(&mut self, on: bool, categories: &[&str]) -> Result<(), String> {
        if categories.is_empty() {
            self.enabled = [on; 5];
            return Ok(());
        }
        for name in categories {
            match LOG_CATEGORIES.iter().position(|(c, _)| c == name) {
                Some(5) => self.enabled = [on; 5],
                Some(i) => self.enabled[i] = on,
                None => {
                    let known: Vec<&str> = LOG_CATEGORIES.iter().map(|c| c.0).collect();
                    return Err(format!(
                        "unknown log category \"{name}\" (known: {})",
                        known.join(", ")
                    ));
                }
            }
        }
        Ok(())
    }

    pub fn enabled(&self, status: fmi2Status) -> bool {
        self.enabled[category_of(status)]
    }

    /// Sends `message` with the category matching `status`, if that category is on. The
    /// text goes through `"%s"`, so a `%` in it is printed, not interpreted.
    pub fn log(&self, status: fmi2Status, message: &str) {
        let Some(callback) = self.callback else {
            return;
        };
        let category = category_of(status);
        if !self.enabled[category] {
            return;
        }
        let category = to_cstring(LOG_CATEGORIES[category].0);
        let message = to_cstring(message);
        // SAFETY: the importer gave this logger for this instance; all strings are valid
        // NUL-terminated C strings that outlive the call.
        unsafe {
            callback(
                self.environment,
                self.instance_name.as_ptr(),
                status,
                category.as_ptr(),
                c"%s".as_ptr(),
                message.as_ptr(),
            );
        }
    }
}

/// A C string of `s`, with any interior NUL replaced (a message is never lost to one).
pub fn to_cstring(s: &str) -> CString {
    CString::new(s.replace('\0', "\u{FFFD}")).unwrap_or_default()
}
