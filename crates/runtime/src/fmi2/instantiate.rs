//! `fmi2Instantiate` at the C boundary: the callbacks and strings of the importer checked
//! and turned into a logger and the arguments of [`calls::instantiate`](super::calls::instantiate).

use super::ffi::*;
use crate::fmi::boundary::{c_str, guarded_or, into_component};
use crate::fmi::logger::Logger;
use crate::fmi::ERROR;
use crate::model::Mechanism;

/// `fmi2Instantiate`: the callbacks and strings checked, the instance made by
/// [`calls::instantiate`](super::calls::instantiate) and handed over; NULL (with a message when
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
        let logger = Logger::new(
            functions.logger,
            functions.componentEnvironment,
            name.unwrap_or(""),
            logging_on != 0,
        );
        // SAFETY: the caller's promise (read only once the name and the type are accepted).
        let guid = || unsafe { c_str(guid) };
        match super::calls::instantiate::<M>(logger, name, fmu_type, guid) {
            Ok(instance) => into_component(instance),
            Err((logger, message)) => {
                logger.log(ERROR, &format!("fmi2Instantiate: {message}"));
                std::ptr::null_mut()
            }
        }
    })
}
