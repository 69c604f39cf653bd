//! The FMI 3.0 Co-Simulation functions an importer calls to step an FMU, by their C names,
//! typed as the standard's headers declare them ([`super::api`]'s types).

use super::api::*;
use crate::library::Library;
use std::sync::Arc;

/// The FMI 3.0 Co-Simulation functions of a loaded binary. It holds the library, so the
/// pointers stay valid as long as the table lives.
#[derive(Clone)]
pub struct Functions {
    pub(crate) instantiate: fmi3InstantiateCoSimulationTYPE,
    pub(crate) free_instance: fmi3FreeInstanceTYPE,
    pub(crate) enter_initialization_mode: fmi3EnterInitializationModeTYPE,
    pub(crate) exit_initialization_mode: fmi3ExitInitializationModeTYPE,
    pub(crate) reset: fmi3ResetTYPE,
    pub(crate) get_float64: fmi3GetFloat64TYPE,
    pub(crate) do_step: fmi3DoStepTYPE,
    _library: Arc<libloading::Library>,
}

impl Functions {
    /// The functions of `library`; None where it does not export them all.
    pub fn load(library: &Library) -> Option<Functions> {
        macro_rules! get {
            ($name:literal) => {
                // SAFETY: an FMI 3.0 function, typed as the standard's headers declare it;
                // the table holds the library.
                unsafe { library.function($name) }.ok()?
            };
        }
        Some(Functions {
            instantiate: get!("fmi3InstantiateCoSimulation"),
            free_instance: get!("fmi3FreeInstance"),
            enter_initialization_mode: get!("fmi3EnterInitializationMode"),
            exit_initialization_mode: get!("fmi3ExitInitializationMode"),
            reset: get!("fmi3Reset"),
            get_float64: get!("fmi3GetFloat64"),
            do_step: get!("fmi3DoStep"),
            _library: library.shared(),
        })
    }
}
