//! The FMI 2.0 functions an importer calls, by their C names, typed as the standard's header
//! declares them (`mechfmu::fmi2::ffi`'s C types), and the benchmark entry points of a binary
//! built with the runtime's `bench` feature.

use crate::library::Library;
use mechfmu::fmi2::ffi::*;
use std::sync::Arc;

/// `fmi2Instantiate`.
pub(crate) type Instantiate = unsafe extern "C" fn(
    fmi2String,
    fmi2Type,
    fmi2String,
    fmi2String,
    *const fmi2CallbackFunctions,
    fmi2Boolean,
    fmi2Boolean,
) -> fmi2Component;
/// `fmi2FreeInstance`.
pub(crate) type FreeInstance = unsafe extern "C" fn(fmi2Component);
/// `fmi2SetupExperiment`.
pub(crate) type SetupExperiment = unsafe extern "C" fn(
    fmi2Component,
    fmi2Boolean,
    fmi2Real,
    fmi2Real,
    fmi2Boolean,
    fmi2Real,
) -> fmi2Status;
/// The calls with the instance as their only argument (`fmi2Reset`, `fmi2Terminate`, ...).
pub(crate) type Component = unsafe extern "C" fn(fmi2Component) -> fmi2Status;
/// `fmi2GetReal`.
pub(crate) type GetReal = unsafe extern "C" fn(
    fmi2Component,
    *const fmi2ValueReference,
    usize,
    *mut fmi2Real,
) -> fmi2Status;
/// `fmi2SetReal`, `fmi2SetInteger`, `fmi2SetBoolean`.
pub(crate) type Set<T> =
    unsafe extern "C" fn(fmi2Component, *const fmi2ValueReference, usize, *const T) -> fmi2Status;
/// `fmi2DoStep`.
pub(crate) type DoStep =
    unsafe extern "C" fn(fmi2Component, fmi2Real, fmi2Real, fmi2Boolean) -> fmi2Status;
/// `fmi2GetRealStatus`.
pub(crate) type GetRealStatus =
    unsafe extern "C" fn(fmi2Component, fmi2StatusKind, *mut fmi2Real) -> fmi2Status;
/// `fmi2GetBooleanStatus`.
pub(crate) type GetBooleanStatus =
    unsafe extern "C" fn(fmi2Component, fmi2StatusKind, *mut fmi2Boolean) -> fmi2Status;
/// `fmi2SetTime`.
pub(crate) type SetTime = unsafe extern "C" fn(fmi2Component, fmi2Real) -> fmi2Status;
/// `fmi2SetContinuousStates`.
pub(crate) type SetStates =
    unsafe extern "C" fn(fmi2Component, *const fmi2Real, usize) -> fmi2Status;
/// `fmi2GetContinuousStates`, `fmi2GetDerivatives`.
pub(crate) type GetStates = unsafe extern "C" fn(fmi2Component, *mut fmi2Real, usize) -> fmi2Status;
/// `fmi2NewDiscreteStates`.
pub(crate) type NewDiscreteStates =
    unsafe extern "C" fn(fmi2Component, *mut fmi2EventInfo) -> fmi2Status;
/// `mechfmu_counters`: cumulative (communication steps, accepted, rejected, model
/// evaluations) into a buffer of the given length; the number of counters.
pub(crate) type Counters = unsafe extern "C" fn(fmi2Component, *mut u64, usize) -> usize;
/// `mechfmu_bench`: a part of a step (`mechfmu::simulation::Part`) repeated on a copy of the
/// instance.
pub(crate) type Bench = unsafe extern "C" fn(fmi2Component, u32, u64, fmi2Real) -> fmi2Status;

/// The FMI 2.0 functions of a loaded binary: those of Co-Simulation, and those of Model
/// Exchange and the benchmark entry points where it exports them all. It holds the library,
/// so the pointers stay valid as long as the table lives.
#[derive(Clone)]
pub struct Functions {
    pub(crate) instantiate: Instantiate,
    pub(crate) free_instance: FreeInstance,
    pub(crate) setup_experiment: SetupExperiment,
    pub(crate) enter_initialization_mode: Component,
    pub(crate) exit_initialization_mode: Component,
    pub(crate) reset: Component,
    pub(crate) terminate: Component,
    pub(crate) set_real: Set<fmi2Real>,
    pub(crate) set_integer: Set<fmi2Integer>,
    pub(crate) set_boolean: Set<fmi2Boolean>,
    pub(crate) get_real: GetReal,
    pub(crate) do_step: DoStep,
    /// Optional: only needed after a discarded step, and some exporters leave them out.
    pub(crate) get_boolean_status: Option<GetBooleanStatus>,
    pub(crate) get_real_status: Option<GetRealStatus>,
    pub(crate) model_exchange: Option<ModelExchangeFunctions>,
    pub(crate) bench: Option<BenchFunctions>,
    _library: Arc<libloading::Library>,
}

/// The Model Exchange functions of [`Functions`].
#[derive(Clone, Copy)]
pub(crate) struct ModelExchangeFunctions {
    pub(crate) new_discrete_states: NewDiscreteStates,
    pub(crate) enter_continuous_time_mode: Component,
    pub(crate) set_time: SetTime,
    pub(crate) set_continuous_states: SetStates,
    pub(crate) get_continuous_states: GetStates,
    pub(crate) get_derivatives: GetStates,
}

/// mechfmu's own entry points of a binary built with the runtime's `bench` feature (not
/// FMI): the work counters and the parts of a step alone.
#[derive(Clone, Copy)]
pub(crate) struct BenchFunctions {
    pub(crate) counters: Counters,
    pub(crate) bench: Bench,
}

impl Functions {
    /// The functions of `library` (the messages name its path when a required one is
    /// missing).
    pub fn load(library: &Library) -> Result<Functions, String> {
        macro_rules! required {
            ($name:literal) => {
                // SAFETY: an FMI 2.0 function, typed as the standard's header declares it;
                // the table holds the library.
                unsafe { library.function($name) }
                    .map_err(|e| format!("{}: no {}: {e}", library.path().display(), $name))?
            };
        }
        macro_rules! optional {
            ($name:literal) => {
                // SAFETY: as for `required!`; mechfmu's own symbols with the signatures of
                // `export_fmu!`.
                unsafe { library.function($name) }.ok()
            };
        }
        let model_exchange = (|| {
            Some(ModelExchangeFunctions {
                new_discrete_states: optional!("fmi2NewDiscreteStates")?,
                enter_continuous_time_mode: optional!("fmi2EnterContinuousTimeMode")?,
                set_time: optional!("fmi2SetTime")?,
                set_continuous_states: optional!("fmi2SetContinuousStates")?,
                get_continuous_states: optional!("fmi2GetContinuousStates")?,
                get_derivatives: optional!("fmi2GetDerivatives")?,
            })
        })();
        let bench = (|| {
            Some(BenchFunctions {
                counters: optional!("mechfmu_counters")?,
                bench: optional!("mechfmu_bench")?,
            })
        })();
        Ok(Functions {
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
            model_exchange,
            bench,
            _library: library.shared(),
        })
    }

    /// Whether the binary exports the Model Exchange functions an importer's solver calls.
    pub fn has_model_exchange(&self) -> bool {
        self.model_exchange.is_some()
    }

    /// Whether the binary exports `mechfmu_counters` and `mechfmu_bench` (built with the
    /// runtime's `bench` feature).
    pub fn has_bench(&self) -> bool {
        self.bench.is_some()
    }
}
