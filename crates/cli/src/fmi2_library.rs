//! An FMU binary loaded the way an importer loads it: the shared library through
//! `libloading`, its FMI 2.0 Co-Simulation functions by their C names, typed as the
//! standard's header declares them (`mechfmu::fmi2::ffi`'s C types). `mechfmu bench` and
//! `mechfmu sweep-worker` both call FMUs through these.

use mechfmu::fmi2::ffi::*;
use std::path::Path;

/// `fmi2Instantiate`.
pub type Instantiate = unsafe extern "C" fn(
    fmi2String,
    fmi2Type,
    fmi2String,
    fmi2String,
    *const fmi2CallbackFunctions,
    fmi2Boolean,
    fmi2Boolean,
) -> fmi2Component;
/// `fmi2FreeInstance`.
pub type FreeInstance = unsafe extern "C" fn(fmi2Component);
/// `fmi2SetupExperiment`.
pub type SetupExperiment = unsafe extern "C" fn(
    fmi2Component,
    fmi2Boolean,
    fmi2Real,
    fmi2Real,
    fmi2Boolean,
    fmi2Real,
) -> fmi2Status;
/// The calls with the instance as their only argument (`fmi2Reset`, `fmi2Terminate`, ...).
pub type Component = unsafe extern "C" fn(fmi2Component) -> fmi2Status;
/// `fmi2GetReal`.
pub type GetReal = unsafe extern "C" fn(
    fmi2Component,
    *const fmi2ValueReference,
    usize,
    *mut fmi2Real,
) -> fmi2Status;
/// `fmi2SetReal`.
pub type SetReal = unsafe extern "C" fn(
    fmi2Component,
    *const fmi2ValueReference,
    usize,
    *const fmi2Real,
) -> fmi2Status;
/// `fmi2SetInteger`.
pub type SetInteger = unsafe extern "C" fn(
    fmi2Component,
    *const fmi2ValueReference,
    usize,
    *const fmi2Integer,
) -> fmi2Status;
/// `fmi2SetBoolean`.
pub type SetBoolean = unsafe extern "C" fn(
    fmi2Component,
    *const fmi2ValueReference,
    usize,
    *const fmi2Boolean,
) -> fmi2Status;
/// `fmi2DoStep`.
pub type DoStep =
    unsafe extern "C" fn(fmi2Component, fmi2Real, fmi2Real, fmi2Boolean) -> fmi2Status;
/// `fmi2GetRealStatus`.
pub type GetRealStatus =
    unsafe extern "C" fn(fmi2Component, fmi2StatusKind, *mut fmi2Real) -> fmi2Status;
/// `fmi2GetBooleanStatus`.
pub type GetBooleanStatus =
    unsafe extern "C" fn(fmi2Component, fmi2StatusKind, *mut fmi2Boolean) -> fmi2Status;
/// `fmi2SetTime`.
pub type SetTime = unsafe extern "C" fn(fmi2Component, fmi2Real) -> fmi2Status;
/// `fmi2SetContinuousStates`.
pub type SetStates = unsafe extern "C" fn(fmi2Component, *const fmi2Real, usize) -> fmi2Status;
/// `fmi2GetContinuousStates`, `fmi2GetDerivatives`.
pub type GetStates = unsafe extern "C" fn(fmi2Component, *mut fmi2Real, usize) -> fmi2Status;
/// `fmi2NewDiscreteStates`.
pub type NewDiscreteStates = unsafe extern "C" fn(fmi2Component, *mut fmi2EventInfo) -> fmi2Status;

/// Loads the shared library at `path` (a message naming it when it cannot be loaded).
pub fn open(path: &Path) -> Result<libloading::Library, String> {
    // SAFETY: loading an FMU binary runs its initializers, which an importer has to trust
    // (mechfmu's are Rust's: none).
    unsafe { libloading::Library::new(path) }
        .map_err(|e| format!("cannot load {}: {e}", path.display()))
}

/// The FMI 2.0 Co-Simulation functions an importer calls, resolved from a loaded library.
/// The pointers stay valid as long as that library stays loaded: keep them beside it.
#[derive(Clone, Copy)]
pub struct CoSimulation {
    pub instantiate: Instantiate,
    pub free_instance: FreeInstance,
    pub setup_experiment: SetupExperiment,
    pub enter_initialization_mode: Component,
    pub exit_initialization_mode: Component,
    pub reset: Component,
    pub terminate: Component,
    pub set_real: SetReal,
    pub set_integer: SetInteger,
    pub set_boolean: SetBoolean,
    pub get_real: GetReal,
    pub do_step: DoStep,
    /// Optional: only needed after a discarded step, and some exporters leave them out.
    pub get_boolean_status: Option<GetBooleanStatus>,
    pub get_real_status: Option<GetRealStatus>,
}

impl CoSimulation {
    /// The functions of `library` (loaded from `path`, which the messages name).
    pub fn load(library: &libloading::Library, path: &Path) -> Result<CoSimulation, String> {
        macro_rules! required {
            ($name:literal) => {
                // SAFETY: an FMI 2.0 function, typed as the standard's header declares it.
                *unsafe { library.get(concat!($name, "\0").as_bytes()) }
                    .map_err(|e| format!("{}: no {}: {e}", path.display(), $name))?
            };
        }
        macro_rules! optional {
            ($name:literal) => {
                // SAFETY: as for `required!`.
                unsafe { library.get(concat!($name, "\0").as_bytes()) }
                    .ok()
                    .map(|symbol| *symbol)
            };
        }
        Ok(CoSimulation {
            instantiate: required!("fmi2Instantiate"),
            free_instance: required!("fmi2FreeInstance"),
            setup_experiment: required!("fmi2SetupExperiment"),
            enter_initialization_mode: required!("fmi2EnterInitializationMode"),
            exit_initialization_mode: required!("fmi2ExitInitializationMode"),
            reset: required!("fmi2Reset"),
            terminate: required!("fmi2Terminate"),
            set_real: required!("fmi2SetReal"),
            set_integer: required!("fmi2SetInteger"),
            set_boolean: required!("fmi2SetBoolean"),
            get_real: required!("fmi2GetReal"),
            do_step: required!("fmi2DoStep"),
            get_boolean_status: optional!("fmi2GetBooleanStatus"),
            get_real_status: optional!("fmi2GetRealStatus"),
        })
    }
}
