//! An FMI 2.0 instance of a loaded binary: each call made as the header declares it, with
//! the instance's component and arrays of the lengths given, and its status returned as the
//! FMU answered (what a status means is the caller's to judge).

use super::functions::{Functions, ModelExchangeFunctions};
use crate::log::Log;
use mechfmu::fmi2::ffi::*;
use mechfmu::simulation::Part;
use std::ffi::CStr;
use std::marker::PhantomData;
use std::rc::Rc;

/// An instance, freed on drop. It holds the functions (and so the library) and the log its
/// callbacks write to.
pub struct Instance {
    f: Functions,
    component: fmi2Component,
    _log: Rc<Log>,
}

fn boolean(b: bool) -> fmi2Boolean {
    if b {
        fmi2True
    } else {
        fmi2False
    }
}

impl Instance {
    /// `fmi2Instantiate(name, kind, guid, resource_location, callbacks, visible = false,
    /// loggingOn = false)` with `log`'s callbacks; None when the FMU returns NULL (its
    /// messages are in `log`).
    pub fn instantiate(
        functions: &Functions,
        name: &CStr,
        kind: fmi2Type,
        guid: &CStr,
        resource_location: &CStr,
        log: &Rc<Log>,
    ) -> Option<Instance> {
        // SAFETY: NUL-terminated strings that outlive the call, and callbacks that outlive
        // the instance (it holds on to the log).
        let component = unsafe {
            (functions.instantiate)(
                name.as_ptr(),
                kind,
                guid.as_ptr(),
                resource_location.as_ptr(),
                log.fmi2_callbacks(),
                fmi2False,
                fmi2False,
            )
        };
        (!component.is_null()).then(|| Instance {
            f: functions.clone(),
            component,
            _log: Rc::clone(log),
        })
    }

    /// Calls `function`, one of `self.f`'s that take the component alone.
    #[inline]
    fn call(&self, function: unsafe extern "C" fn(fmi2Component) -> fmi2Status) -> fmi2Status {
        // SAFETY: a live component of the library the function comes from.
        unsafe { function(self.component) }
    }

    #[inline]
    pub fn reset(&self) -> fmi2Status {
        self.call(self.f.reset)
    }

    #[inline]
    pub fn enter_initialization_mode(&self) -> fmi2Status {
        self.call(self.f.enter_initialization_mode)
    }

    #[inline]
    pub fn exit_initialization_mode(&self) -> fmi2Status {
        self.call(self.f.exit_initialization_mode)
    }

    #[inline]
    pub fn terminate(&self) -> fmi2Status {
        self.call(self.f.terminate)
    }

    /// `fmi2SetupExperiment`: a tolerance and a stop time when given.
    #[inline]
    pub fn setup_experiment(
        &self,
        tolerance: Option<f64>,
        start: f64,
        stop: Option<f64>,
    ) -> fmi2Status {
        // SAFETY: a live component; plain values.
        unsafe {
            (self.f.setup_experiment)(
                self.component,
                boolean(tolerance.is_some()),
                tolerance.unwrap_or(0.0),
                start,
                boolean(stop.is_some()),
                stop.unwrap_or(0.0),
            )
        }
    }

    /// `fmi2SetReal` of the first `min(vrs, values)` pairs.
    #[inline]
    pub fn set_real(&self, vrs: &[u32], values: &[f64]) -> fmi2Status {
        let n = vrs.len().min(values.len());
        // SAFETY: a live component; both arrays hold `n` elements.
        unsafe { (self.f.set_real)(self.component, vrs.as_ptr(), n, values.as_ptr()) }
    }

    /// `fmi2SetInteger` of the first `min(vrs, values)` pairs.
    #[inline]
    pub fn set_integer(&self, vrs: &[u32], values: &[fmi2Integer]) -> fmi2Status {
        let n = vrs.len().min(values.len());
        // SAFETY: as for `set_real`.
        unsafe { (self.f.set_integer)(self.component, vrs.as_ptr(), n, values.as_ptr()) }
    }

    /// `fmi2SetBoolean` of the first `min(vrs, values)` pairs.
    #[inline]
    pub fn set_boolean(&self, vrs: &[u32], values: &[fmi2Boolean]) -> fmi2Status {
        let n = vrs.len().min(values.len());
        // SAFETY: as for `set_real`.
        unsafe { (self.f.set_boolean)(self.component, vrs.as_ptr(), n, values.as_ptr()) }
    }

    /// `fmi2GetReal` of the first `min(vrs, out)` value references into `out`.
    #[inline]
    pub fn get_real(&self, vrs: &[u32], out: &mut [f64]) -> fmi2Status {
        let n = vrs.len().min(out.len());
        // SAFETY: a live component; `vrs` holds `n` elements, `out` room for `n`.
        unsafe { (self.f.get_real)(self.component, vrs.as_ptr(), n, out.as_mut_ptr()) }
    }

    /// `fmi2DoStep(t, h, noSetFMUStatePriorToCurrentPoint = true)`.
    #[inline]
    pub fn do_step(&self, t: f64, h: f64) -> fmi2Status {
        // SAFETY: a live component; plain values.
        unsafe { (self.f.do_step)(self.component, t, h, fmi2True) }
    }

    /// `fmi2GetBooleanStatus(kind)`: its status and value; None where the binary does not
    /// export it.
    #[inline]
    pub fn boolean_status(&self, kind: fmi2StatusKind) -> Option<(fmi2Status, bool)> {
        let get = self.f.get_boolean_status?;
        let mut value = fmi2False;
        // SAFETY: a live component; one writable value.
        let status = unsafe { get(self.component, kind, &mut value) };
        Some((status, value != fmi2False))
    }

    /// `fmi2GetRealStatus(kind)`: its status and value; None where the binary does not
    /// export it.
    #[inline]
    pub fn real_status(&self, kind: fmi2StatusKind) -> Option<(fmi2Status, f64)> {
        let get = self.f.get_real_status?;
        let mut value = 0.0;
        // SAFETY: a live component; one writable value.
        let status = unsafe { get(self.component, kind, &mut value) };
        Some((status, value))
    }

    /// The Model Exchange calls on this instance; None where the binary lacks them.
    #[inline]
    pub fn model_exchange(&self) -> Option<ModelExchange<'_>> {
        Some(ModelExchange {
            f: self.f.model_exchange?,
            component: self.component,
            _instance: PhantomData,
        })
    }

    /// Cumulative (communication steps, accepted, rejected, model evaluations): the FMU's
    /// own counters (`mechfmu_counters`); None where the binary does not export them.
    #[inline]
    pub fn counters(&self) -> Option<[u64; 4]> {
        let f = self.f.bench?.counters;
        let mut out = [0u64; 4];
        // SAFETY: a live component; room for 4 counters.
        let n = unsafe { f(self.component, out.as_mut_ptr(), out.len()) };
        (n >= 4).then_some(out)
    }

    /// One part of a step repeated `n` times on a copy of the instance (`mechfmu_bench`);
    /// None where the binary does not export it.
    #[inline]
    pub fn bench(&self, part: Part, n: u64, h: f64) -> Option<fmi2Status> {
        let f = self.f.bench?.bench;
        // SAFETY: a live component; plain values.
        Some(unsafe { f(self.component, part as u32, n, h) })
    }
}

impl Drop for Instance {
    fn drop(&mut self) {
        // SAFETY: a live component, freed once, its library still loaded (held by `f`).
        unsafe { (self.f.free_instance)(self.component) }
    }
}

/// The Model Exchange calls of an [`Instance`], resolved once: what an importer's solver
/// calls per right-hand side. The functions are copied in, so that a loop over a borrowed
/// `ModelExchange` keeps them in registers; it borrows the instance, which holds the
/// library.
#[derive(Clone, Copy)]
pub struct ModelExchange<'a> {
    f: ModelExchangeFunctions,
    component: fmi2Component,
    _instance: PhantomData<&'a Instance>,
}

impl ModelExchange<'_> {
    /// `fmi2NewDiscreteStates` into `info`.
    #[inline]
    pub fn new_discrete_states(&self, info: &mut fmi2EventInfo) -> fmi2Status {
        // SAFETY: a live component; `info` is writable.
        unsafe { (self.f.new_discrete_states)(self.component, info) }
    }

    #[inline]
    pub fn enter_continuous_time_mode(&self) -> fmi2Status {
        // SAFETY: a live component.
        unsafe { (self.f.enter_continuous_time_mode)(self.component) }
    }

    #[inline]
    pub fn set_time(&self, t: f64) -> fmi2Status {
        // SAFETY: a live component; a plain value.
        unsafe { (self.f.set_time)(self.component, t) }
    }

    /// `fmi2SetContinuousStates` of all of `x`.
    #[inline]
    pub fn set_continuous_states(&self, x: &[f64]) -> fmi2Status {
        // SAFETY: a live component; `x` holds `x.len()` values.
        unsafe { (self.f.set_continuous_states)(self.component, x.as_ptr(), x.len()) }
    }

    /// `fmi2GetContinuousStates` into all of `x`.
    #[inline]
    pub fn get_continuous_states(&self, x: &mut [f64]) -> fmi2Status {
        // SAFETY: a live component; `x` has room for `x.len()` values.
        unsafe { (self.f.get_continuous_states)(self.component, x.as_mut_ptr(), x.len()) }
    }

    /// `fmi2GetDerivatives` into all of `dx`.
    #[inline]
    pub fn get_derivatives(&self, dx: &mut [f64]) -> fmi2Status {
        // SAFETY: a live component; `dx` has room for `dx.len()` values.
        unsafe { (self.f.get_derivatives)(self.component, dx.as_mut_ptr(), dx.len()) }
    }
}
