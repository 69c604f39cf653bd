//! The FMI 2.0 functions a well-behaved importer calls, by their C names, typed as the
//! standard's header declares them ([`super::api`]'s types), and the benchmark entry points
//! of a binary built with the runtime's `bench` feature.

use super::api::*;
use crate::library::Library;
use mechfmu::fmi2::ffi::*;
use std::sync::Arc;

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
    pub(crate) instantiate: fmi2InstantiateTYPE,
    pub(crate) free_instance: fmi2FreeInstanceTYPE,
    pub(crate) setup_experiment: fmi2SetupExperimentTYPE,
    pub(crate) enter_initialization_mode: fmi2EnterInitializationModeTYPE,
    pub(crate) exit_initialization_mode: fmi2ExitInitializationModeTYPE,
    pub(crate) reset: fmi2ResetTYPE,
    pub(crate) terminate: fmi2TerminateTYPE,
    pub(crate) set_real: fmi2SetRealTYPE,
    pub(crate) set_integer: fmi2SetIntegerTYPE,
    pub(crate) set_boolean: fmi2SetBooleanTYPE,
    pub(crate) get_real: fmi2GetRealTYPE,
    pub(crate) do_step: fmi2DoStepTYPE,
    /// Optional: only needed after a discarded step, and some exporters leave them out.
    pub(crate) get_boolean_status: Option<fmi2GetBooleanStatusTYPE>,
    pub(crate) get_real_status: Option<fmi2GetRealStatusTYPE>,
    pub(crate) model_exchange: Option<ModelExchangeFunctions>,
    pub(crate) bench: Option<BenchFunctions>,
    _library: Arc<libloading::Library>,
}

/// The Model Exchange functions of [`Functions`].
#[derive(Clone, Copy)]
pub(crate) struct ModelExchangeFunctions {
    pub(crate) new_discrete_states: fmi2NewDiscreteStatesTYPE,
    pub(crate) enter_continuous_time_mode: fmi2EnterContinuousTimeModeTYPE,
    pub(crate) set_time: fmi2SetTimeTYPE,
    pub(crate) set_continuous_states: fmi2SetContinuousStatesTYPE,
    pub(crate) get_continuous_states: fmi2GetContinuousStatesTYPE,
    pub(crate) get_derivatives: fmi2GetDerivativesTYPE,
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
