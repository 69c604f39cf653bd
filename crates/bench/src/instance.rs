//! An FMI 2.0 instance of a loaded [`Binary`] as the benchmark drives it: started as an
//! importer starts one, each call that is not timed checked (its status, and the FMU's
//! messages in the error), the timed calls left to the loops that time them.

#![allow(non_upper_case_globals)]

use crate::binary::Binary;
use mechfmu::fmi2::ffi::*;
use mechfmu::simulation::Part;
use mechfmu_host::fmi2::instance::{self, ModelExchange};
use mechfmu_host::log::Log;
use std::ffi::CString;
use std::rc::Rc;

/// One instance of a loaded FMU.
pub struct Instance<'a> {
    pub binary: &'a Binary,
    fmi: instance::Instance,
    log: Rc<Log>,
}

impl<'a> Instance<'a> {
    /// A Co-Simulation instance.
    pub fn new(binary: &'a Binary) -> Result<Instance<'a>, String> {
        Self::instantiate(binary, fmi2CoSimulation)
    }

    /// A Model Exchange instance; `Err` if the binary has no Model Exchange functions.
    pub fn model_exchange(binary: &'a Binary) -> Result<Instance<'a>, String> {
        if !binary.fmi2.has_model_exchange() {
            return Err(format!(
                "{} exports no Model Exchange functions",
                binary.path.display()
            ));
        }
        Self::instantiate(binary, fmi2ModelExchange)
    }

    fn instantiate(binary: &'a Binary, fmu_type: fmi2Type) -> Result<Instance<'a>, String> {
        let log = Rc::new(Log::new());
        let d = &binary.description;
        let name = CString::new(d.model_identifier.as_str()).unwrap_or_default();
        let guid = CString::new(d.token.as_str()).unwrap_or_default();
        let resources = c"file:///tmp";
        let Some(fmi) =
            instance::Instance::instantiate(&binary.fmi2, &name, fmu_type, &guid, resources, &log)
        else {
            return Err(format!(
                "fmi2Instantiate of {} failed: {:?}",
                binary.path.display(),
                log.messages()
            ));
        };
        Ok(Instance { binary, fmi, log })
    }

    fn check(&self, status: fmi2Status, what: &str) -> Result<(), String> {
        if status == fmi2OK {
            Ok(())
        } else {
            Err(format!(
                "{what} returned {status}: {}",
                self.messages().join("; ")
            ))
        }
    }

    /// The warnings and errors the FMU logged.
    pub fn messages(&self) -> Vec<String> {
        (self.log.messages().iter())
            .filter(|m| m.status >= fmi2Warning)
            .map(|m| m.text.clone())
            .collect()
    }

    /// `fmi2Reset` (unless fresh), `fmi2SetupExperiment(tol, start)`, start values,
    /// initialization: ready to step from `start`.
    pub fn start(
        &mut self,
        tolerance: f64,
        start: f64,
        values: &[(u32, f64)],
        reset: bool,
    ) -> Result<(), String> {
        let f = &self.fmi;
        if reset {
            self.check(f.reset(), "fmi2Reset")?;
        }
        let status = f.setup_experiment(Some(tolerance), start, None);
        self.check(status, "fmi2SetupExperiment")?;
        let status = f.enter_initialization_mode();
        self.check(status, "fmi2EnterInitializationMode")?;
        for &(vr, value) in values {
            self.check(f.set_real(&[vr], &[value]), "fmi2SetReal")?;
        }
        let status = f.exit_initialization_mode();
        self.check(status, "fmi2ExitInitializationMode")
    }

    /// For a Model Exchange instance after [`Instance::start`] (in event mode): the event
    /// iteration (`fmi2NewDiscreteStates` until no new discrete states are needed), then
    /// `fmi2EnterContinuousTimeMode`.
    pub fn enter_continuous_time_mode(&mut self) -> Result<(), String> {
        let me = self.me()?;
        let mut info = fmi2EventInfo {
            newDiscreteStatesNeeded: fmi2True,
            ..fmi2EventInfo::default()
        };
        for _ in 0..100 {
            if info.newDiscreteStatesNeeded == fmi2False {
                break;
            }
            self.check(me.new_discrete_states(&mut info), "fmi2NewDiscreteStates")?;
            if info.terminateSimulation != fmi2False {
                return Err("fmi2NewDiscreteStates: terminateSimulation at the start".into());
            }
        }
        let status = me.enter_continuous_time_mode();
        self.check(status, "fmi2EnterContinuousTimeMode")
    }

    /// The Model Exchange calls (for an instance of [`Instance::model_exchange`]).
    pub fn me(&self) -> Result<ModelExchange<'_>, String> {
        self.fmi
            .model_exchange()
            .ok_or_else(|| "the binary exports no Model Exchange functions".into())
    }

    /// `fmi2GetContinuousStates` into `x` (one value per state).
    pub fn continuous_states(&mut self, x: &mut [f64]) -> Result<(), String> {
        let status = self.me()?.get_continuous_states(x);
        self.check(status, "fmi2GetContinuousStates")
    }

    #[inline]
    pub fn do_step(&self, t: f64, h: f64) -> fmi2Status {
        self.fmi.do_step(t, h)
    }

    #[inline]
    pub fn get_real(&self, vr: &[u32], out: &mut [f64]) -> fmi2Status {
        self.fmi.get_real(vr, out)
    }

    #[inline]
    pub fn set_real(&self, vr: &[u32], values: &[f64]) -> fmi2Status {
        self.fmi.set_real(vr, values)
    }

    /// Cumulative (communication steps, accepted, rejected, model evaluations), if the
    /// binary exports them.
    pub fn counters(&self) -> Option<[u64; 4]> {
        self.fmi.counters()
    }

    /// Repeats one part of a step `n` times on a copy of the instance (`mechfmu_bench`).
    pub fn bench(&self, part: Part, n: u64, h: f64) -> Result<(), String> {
        let status = (self.fmi.bench(part, n, h))
            .ok_or("the binary does not export mechfmu_bench (rebuild it)")?;
        self.check(status, "mechfmu_bench")
    }
}

/// Why a step of a timed loop failed (`call` the step function, returning `status`; the FMU's
/// `messages`): written out of the loop's way, so that the loop keeps nothing in memory for
/// it.
#[cold]
#[inline(never)]
pub(crate) fn step_failed(
    call: &str,
    t: f64,
    h: f64,
    status: impl std::fmt::Display,
    messages: impl FnOnce() -> Vec<String>,
) -> String {
    format!(
        "{call}({t}, {h}) returned {status}: {}",
        messages().join("; ")
    )
}
