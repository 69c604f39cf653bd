//! One FMU instance and the FMI calls a case makes on it: the worker's only `unsafe` calls
//! into the FMU. Each call's status is checked as FMPy checks it: above `fmi2Warning` the
//! case fails with that status and the function's name.

use super::log::CaseLog;
use super::setup::{Setup, Start, StartKind};
use crate::fmi2_library::{self, CoSimulation};
use mechfmu::fmi2::ffi::*;
use std::path::Path;
use std::rc::Rc;

/// What the instances' functions and callbacks live in: the loaded library and the log.
/// Every instance holds on to it, so neither goes while an instance could call them.
pub struct Loaded {
    fmi: CoSimulation,
    log: CaseLog,
    _library: libloading::Library,
}

impl Loaded {
    /// Loads the library at `path` and its FMI 2.0 Co-Simulation functions.
    pub fn open(path: &Path) -> Result<Rc<Loaded>, String> {
        let library = fmi2_library::open(path)?;
        Ok(Rc::new(Loaded {
            fmi: CoSimulation::load(&library, path)?,
            log: CaseLog::new(),
            _library: library,
        }))
    }

    /// The log of the running case.
    pub fn log(&self) -> &CaseLog {
        &self.log
    }
}

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
    fmi: CoSimulation,
    component: fmi2Component,
    /// Dropped after `fmi2FreeInstance` (`Drop::drop` runs before the fields go).
    _loaded: Rc<Loaded>,
    /// Not yet used by a case: its first case runs without `fmi2Reset`.
    pub fresh: bool,
}

impl Instance {
    /// `fmi2Instantiate` as FMPy's `FMU2Slave.instantiate` calls it (Co-Simulation,
    /// invisible, logging off), with the log's callbacks; None when the FMU returns NULL.
    pub fn instantiate(loaded: &Rc<Loaded>, setup: &Setup) -> Option<Instance> {
        let fmi = loaded.fmi;
        // SAFETY: NUL-terminated strings that outlive the call, and callbacks that outlive
        // the instance (it holds on to `loaded`).
        let component = unsafe {
            (fmi.instantiate)(
                setup.instance_name.as_ptr(),
                fmi2CoSimulation,
                setup.guid.as_ptr(),
                setup.resource_location.as_ptr(),
                loaded.log.callbacks(),
                fmi2False,
                fmi2False,
            )
        };
        (!component.is_null()).then(|| Instance {
            fmi,
            component,
            _loaded: Rc::clone(loaded),
            fresh: true,
        })
    }

    /// A call with the component as its only argument (`fmi2Reset`, `fmi2Terminate`, ...).
    fn simple(&self, call: fmi2_library::Component, function: &'static str) -> Result<(), Failure> {
        // SAFETY: a live component of the (loaded) library `call` comes from.
        check(unsafe { call(self.component) }, function)
    }

    pub fn reset(&self) -> Result<(), Failure> {
        self.simple(self.fmi.reset, "fmi2Reset")
    }

    pub fn enter_initialization_mode(&self) -> Result<(), Failure> {
        self.simple(
            self.fmi.enter_initialization_mode,
            "fmi2EnterInitializationMode",
        )
    }

    pub fn exit_initialization_mode(&self) -> Result<(), Failure> {
        self.simple(
            self.fmi.exit_initialization_mode,
            "fmi2ExitInitializationMode",
        )
    }

    pub fn terminate(&self) -> Result<(), Failure> {
        self.simple(self.fmi.terminate, "fmi2Terminate")
    }

    /// `fmi2SetupExperiment` as FMPy's `setupExperiment(tolerance, start, stop or None)`.
    pub fn setup_experiment(&self, setup: &Setup) -> Result<(), Failure> {
        let boolean = |b: bool| if b { fmi2True } else { fmi2False };
        let stop = if setup.set_stop_time {
            setup.stop_time
        } else {
            0.0
        };
        // SAFETY: a live component; plain values.
        let status = unsafe {
            (self.fmi.setup_experiment)(
                self.component,
                boolean(setup.tolerance.is_some()),
                setup.tolerance.unwrap_or(0.0),
                setup.start_time,
                boolean(setup.set_stop_time),
                stop,
            )
        };
        check(status, "fmi2SetupExperiment")
    }

    /// One start value, by its own `fmi2Set<Type>` call, as FMPy's `apply_start_values`.
    /// An Integer arrives truncated already; `as` saturates what an `int` cannot hold.
    pub fn set_start(&self, start: &Start, value: f64) -> Result<(), Failure> {
        let vr = &start.vr;
        let c = self.component;
        // SAFETY: a live component; one value reference and one value.
        let (status, function) = unsafe {
            match start.kind {
                StartKind::Real => ((self.fmi.set_real)(c, vr, 1, &value), "fmi2SetReal"),
                StartKind::Integer => {
                    let integer = value as fmi2Integer;
                    ((self.fmi.set_integer)(c, vr, 1, &integer), "fmi2SetInteger")
                }
                StartKind::Boolean => {
                    let boolean = if value != 0.0 { fmi2True } else { fmi2False };
                    ((self.fmi.set_boolean)(c, vr, 1, &boolean), "fmi2SetBoolean")
                }
            }
        };
        check(status, function)
    }

    /// `fmi2SetReal` of all inputs in one call.
    pub fn set_real(&self, vrs: &[u32], values: &[f64]) -> Result<(), Failure> {
        let n = vrs.len().min(values.len());
        // SAFETY: a live component; both arrays hold `n` elements.
        let status =
            unsafe { (self.fmi.set_real)(self.component, vrs.as_ptr(), n, values.as_ptr()) };
        check(status, "fmi2SetReal")
    }

    /// `fmi2GetReal` of `vrs` into `out`.
    pub fn get_real(&self, vrs: &[u32], out: &mut [f64]) -> Result<(), Failure> {
        let n = vrs.len().min(out.len());
        // SAFETY: a live component; `vrs` holds `n` elements, `out` room for `n`.
        let status =
            unsafe { (self.fmi.get_real)(self.component, vrs.as_ptr(), n, out.as_mut_ptr()) };
        check(status, "fmi2GetReal")
    }

    /// `fmi2DoStep(time, h, noSetFMUStatePriorToCurrentPoint = true)`. A discarded step
    /// reports where it started and the FMU's last successful time, which FMPy's loop asks
    /// for only when the FMU says it terminated (the failures of those queries ignored).
    pub fn do_step(&self, time: f64, h: f64) -> Result<(), Failure> {
        // SAFETY: a live component; plain values.
        let status = unsafe { (self.fmi.do_step)(self.component, time, h, fmi2True) };
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
        let (get_boolean, get_real) = (self.fmi.get_boolean_status?, self.fmi.get_real_status?);
        let mut terminated = fmi2False;
        // SAFETY: a live component; one writable value.
        let status = unsafe { get_boolean(self.component, fmi2Terminated, &mut terminated) };
        if status > fmi2Warning || terminated == fmi2False {
            return None;
        }
        let mut last = 0.0;
        // SAFETY: as above.
        let status = unsafe { get_real(self.component, fmi2LastSuccessfulTime, &mut last) };
        (status <= fmi2Warning).then_some(last)
    }
}

impl Drop for Instance {
    fn drop(&mut self) {
        // SAFETY: a live component, freed once, its library still loaded (`_loaded`).
        unsafe { (self.fmi.free_instance)(self.component) }
    }
}
