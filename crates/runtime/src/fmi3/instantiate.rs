//! FMI 3.0's three instantiation functions at the C boundary: the strings and the logger
//! callback of the importer checked and turned into the arguments of
//! [`calls::instantiate`](super::calls::instantiate).

use super::ffi::*;
use crate::fmi::boundary::{c_str, guarded_or, into_component, slice};
use crate::fmi::logger::Logger;
use crate::fmi::machine::Interface;
use crate::fmi::ERROR;
use crate::model::Mechanism;

/// What the importer asks of a Co-Simulation instance beyond a Model Exchange one.
#[derive(Clone, Copy, Debug)]
pub struct CoSimulationOptions {
    pub event_mode_used: bool,
    pub early_return_allowed: bool,
    pub required_intermediate_variables: *const fmi3ValueReference,
    pub n_required_intermediate_variables: usize,
}

/// `fmi3InstantiateModelExchange` (`options` None) and `fmi3InstantiateCoSimulation`: the
/// instance, or NULL (with a message when there is a logger) on any failure.
///
/// # Safety
/// The strings are NULL or NUL-terminated; `options`' array is NULL or holds its length
/// of value references.
pub unsafe fn instantiate<M: Mechanism>(
    function: &str,
    instance_name: fmi3String,
    instantiation_token: fmi3String,
    logging_on: fmi3Boolean,
    instance_environment: fmi3InstanceEnvironment,
    log_message: fmi3LogMessageCallback,
    options: Option<CoSimulationOptions>,
) -> fmi3Instance {
    guarded_or(std::ptr::null_mut(), || {
        let logger = Logger::fmi3(log_message, instance_environment, logging_on);
        // SAFETY: the caller's promise.
        let name = unsafe { c_str(instance_name) };
        let interface = match options {
            None => Interface::ModelExchange,
            Some(_) => Interface::CoSimulation,
        };
        // SAFETY: the caller's promise (read only once the name is accepted).
        let token = || unsafe { c_str(instantiation_token) };
        let required = match options {
            // SAFETY: the caller's promise.
            Some(o) => unsafe {
                slice(
                    o.required_intermediate_variables,
                    o.n_required_intermediate_variables,
                    "requiredIntermediateVariables[]",
                )
            }
            .map(<[u32]>::len)
            .map_err(|failure| failure.message),
            None => Ok(0),
        };
        let made = match required {
            Ok(n) => super::calls::instantiate::<M>(
                logger,
                name,
                interface,
                token,
                options.is_some_and(|o| o.event_mode_used),
                options.is_some_and(|o| o.early_return_allowed),
                n,
            ),
            Err(message) => Err((logger, message)),
        };
        match made {
            Ok(instance) => into_component(instance),
            Err((logger, message)) => {
                logger.log(ERROR, &format!("{function}: {message}"));
                std::ptr::null_mut()
            }
        }
    })
}

/// `fmi3InstantiateScheduledExecution`: not offered (the model description declares no
/// `<ScheduledExecution>`); NULL, with the reason logged.
pub fn instantiate_scheduled_execution(
    logging_on: fmi3Boolean,
    instance_environment: fmi3InstanceEnvironment,
    log_message: fmi3LogMessageCallback,
) -> fmi3Instance {
    guarded_or(std::ptr::null_mut(), || {
        Logger::fmi3(log_message, instance_environment, logging_on).log(
            ERROR,
            "fmi3InstantiateScheduledExecution: this FMU offers Model Exchange and Co-Simulation, not Scheduled Execution",
        );
        std::ptr::null_mut()
    })
}
