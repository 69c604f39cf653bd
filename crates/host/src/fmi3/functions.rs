//! The FMI 3.0 Co-Simulation functions an importer calls to step an FMU, by their C names,
//! typed as the standard's headers declare them (`mechfmu::fmi3::ffi`'s C types).

use crate::library::Library;
use mechfmu::fmi3::ffi::*;
use std::sync::Arc;

/// `fmi3InstantiateCoSimulation`.
pub(crate) type Instantiate = unsafe extern "C" fn(
    fmi3String,
    fmi3String,
    fmi3String,
    fmi3Boolean,
    fmi3Boolean,
    fmi3Boolean,
    fmi3Boolean,
    *const fmi3ValueReference,
    usize,
    fmi3InstanceEnvironment,
    fmi3LogMessageCallback,
    fmi3IntermediateUpdateCallback,
) -> fmi3Instance;
/// `fmi3FreeInstance`.
pub(crate) type FreeInstance = unsafe extern "C" fn(fmi3Instance);
/// `fmi3EnterInitializationMode`.
pub(crate) type EnterInitializationMode = unsafe extern "C" fn(
    fmi3Instance,
    fmi3Boolean,
    fmi3Float64,
    fmi3Float64,
    fmi3Boolean,
    fmi3Float64,
) -> fmi3Status;
/// The calls with the instance as their only argument (`fmi3Reset`, ...).
pub(crate) type Call = unsafe extern "C" fn(fmi3Instance) -> fmi3Status;
/// `fmi3GetFloat64`.
pub(crate) type GetFloat64 = unsafe extern "C" fn(
    fmi3Instance,
    *const fmi3ValueReference,
    usize,
    *mut fmi3Float64,
    usize,
) -> fmi3Status;
/// `fmi3DoStep`.
pub(crate) type DoStep = unsafe extern "C" fn(
    fmi3Instance,
    fmi3Float64,
    fmi3Float64,
    fmi3Boolean,
    *mut fmi3Boolean,
    *mut fmi3Boolean,
    *mut fmi3Boolean,
    *mut fmi3Float64,
) -> fmi3Status;

/// The FMI 3.0 Co-Simulation functions of a loaded binary. It holds the library, so the
/// pointers stay valid as long as the table lives.
#[derive(Clone)]
pub struct Functions {
    pub(crate) instantiate: Instantiate,
    pub(crate) free_instance: FreeInstance,
    pub(crate) enter_initialization_mode: EnterInitializationMode,
    pub(crate) exit_initialization_mode: Call,
    pub(crate) reset: Call,
    pub(crate) get_float64: GetFloat64,
    pub(crate) do_step: DoStep,
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
