//! One FMU instance and the FMI calls a case makes on it (through `mechfmu-host`). Each
//! call's status is checked as FMPy checks it: above `fmi2Warning` the case fails with that
//! status and the function's name.

use crate::setup::{Setup, Start, StartKind};
use mechfmu::fmi2::ffi::*;
use mechfmu_host::fmi2::functions::Functions;
use mechfmu_host::fmi2::instance;
use mechfmu_host::log::Log;
use std::rc::Rc;

/// The FMI call a case failed at.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Failure {
    pub status: fmi2Status,
    pub function: &'static str,
    /// For a discarded `fmi2DoStep`: the step's start time and the last successful time.
    pub discarded: Option<(f64, f64)>,
}

impl Failure {
    pub fn at(status: fmi2Status, function: &'static str) -> Failure {
        Failure {
            status,
            function,
            discarded: None,
        }
    }
}

fn check(status: fmi2Status, function: &'static str) -> Result<(), Failure> {
    if status > fmi2Warning {
        Err(Failure::at(status, function))
    } else {
        Ok(())
    }
}

/// A Co-Simulation instance, freed on drop.
pub struct Instance {
    fmi: instance::Instance,
    /// Not yet used by a case: its first case runs without `fmi2Reset`.
    pub fresh: bool,
}

impl Instance {
    /// `fmi2Instantiate` as FMPy's `FMU2Slave.instantiate` calls it (Co-Simulation,
    /// invisible, logging off), with `log`'s callbacks; None when the FMU returns NULL.
    pub fn instantiate(functions: &Functions, log: &Rc<Log>, setup: &Setup) -> Option<Instance> {
        let fmi = instance::Instance::instantiate(
            functions,
            &setup.instance_name,
            fmi2CoSimulation,
            &setup.guid,
            &setup.resource_location,
            log,
        )?;
        Some(Instance { fmi, fresh: true })
    }

    pub fn reset(&self) -> Result<(), Failure> {
        check(self.fmi.reset(), "fmi2Reset")
    }

    pub fn enter_initialization_mode(&self) -> Result<(), Failure> {
        let status = self.fmi.enter_initialization_mode();
        check(status, "fmi2EnterInitializationMode")
    }

    pub fn exit_initialization_mode(&self) -> Result<(), Failure> {
        let status = self.fmi.exit_initialization_mode();
        check(status, "fmi2ExitInitializationMode")
    }

    pub fn terminate(&self) -> Result<(), Failure> {
        check(self.fmi.terminate(), "fmi2Terminate")
    }

    /// `fmi2SetupExperiment` as FMPy's `setupExperiment(tolerance, start, stop or None)`.
    pub fn setup_experiment(&self, setup: &Setup) -> Result<(), Failure> {
        let stop = setup.set_stop_time.then_some(setup.stop_time);
        let status = self
            .fmi
            .setup_experiment(setup.tolerance, setup.start_time, stop);
        check(status, "fmi2SetupExperiment")
    }

    /// One start value, by its own `fmi2Set<Type>` call, as FMPy's `apply_start_values`.
    /// An Integer arrives truncated already; `as` saturates what an `int` cannot hold.
    pub fn set_start(&self, start: &Start, value: f64) -> Result<(), Failure> {
        let vr = &[start.vr];
        let (status, function) = match start.kind {
            StartKind::Real => (self.fmi.set_real(vr, &[value]), "fmi2SetReal"),
            StartKind::Integer => {
                let integer = value as fmi2Integer;
                (self.fmi.set_integer(vr, &[integer]), "fmi2SetInteger")
            }
            StartKind::Boolean => {
                let boolean = if value != 0.0 { fmi2True } else { fmi2False };
                (self.fmi.set_boolean(vr, &[boolean]), "fmi2SetBoolean")
            }
        };
        check(status, function)
    }

    /// `fmi2SetReal` of all inputs in one call.
    pub fn set_real(&self, vrs: &[u32], values: &[f64]) -> Result<(), Failure> {
        check(self.fmi.set_real(vrs, values), "fmi2SetReal")
    }

    /// `fmi2GetReal` of `vrs` into `out`.
    pub fn get_real(&self, vrs: &[u32], out: &mut [f64]) -> Result<(), Failure> {
        check(self.fmi.get_real(vrs, out), "fmi2GetReal")
    }

    /// `fmi2DoStep(time, h, noSetFMUStatePriorToCurrentPoint = true)`. A discarded step
    /// reports where it started and the FMU's last successful time, which FMPy's loop asks
    /// for only when the FMU says it terminated (the failures of those queries ignored).
    pub fn do_step(&self, time: f64, h: f64) -> Result<(), Failure> {
        let status = self.fmi.do_step(time, h);
        if status <= fmi2Warning {
            return Ok(());
        }
        let discarded =
            (status == fmi2Discard).then(|| (time, self.last_successful_time().unwrap_or(time)));
        Err(Failure {
            status,
            function: "fmi2DoStep",
            discarded,
        })
    }

    /// `fmi2LastSuccessfulTime` if `fmi2Terminated` is true, both answered without error.
    fn last_successful_time(&self) -> Option<f64> {
        let (status, terminated) = self.fmi.boolean_status(fmi2Terminated)?;
        if status > fmi2Warning || !terminated {
            return None;
        }
        let (status, last) = self.fmi.real_status(fmi2LastSuccessfulTime)?;
        (status <= fmi2Warning).then_some(last)
    }
}
