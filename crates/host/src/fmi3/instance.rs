//! An FMI 3.0 Co-Simulation instance of a loaded binary: each call made as the headers
//! declare it, its status returned as the FMU answered.

use super::functions::Functions;
use crate::log::Log;
use mechfmu::fmi3::ffi::*;
use std::ffi::CStr;
use std::rc::Rc;

/// The out arguments of `fmi3DoStep`: eventHandlingNeeded, terminateSimulation,
/// earlyReturn, lastSuccessfulTime.
#[derive(Default)]
struct Outs(bool, bool, bool, f64);

/// A Co-Simulation instance, freed on drop. It holds the functions (and so the library) and
/// the log its logger writes to.
pub struct Instance {
    f: Functions,
    instance: fmi3Instance,
    /// Where `fmi3DoStep` writes its out arguments (every call writes them all, so a loop
    /// of steps does not reset them: what an importer's loop does per call is passing them).
    outs: Outs,
    _log: Rc<Log>,
}

impl Instance {
    /// `fmi3InstantiateCoSimulation(name, token, resource_path)`: invisible, logging off, no
    /// event mode, no early return, no intermediate update, with `log`'s logger; None when
    /// the FMU returns NULL (its messages are in `log`).
    pub fn instantiate(
        functions: &Functions,
        name: &CStr,
        token: &CStr,
        resource_path: &CStr,
        log: &Rc<Log>,
    ) -> Option<Instance> {
        let (environment, logger) = log.fmi3_callback();
        // SAFETY: NUL-terminated strings that outlive the call, no required intermediate
        // variables, and a logger whose environment outlives the instance (it holds on to
        // the log).
        let instance = unsafe {
            (functions.instantiate)(
                name.as_ptr(),
                token.as_ptr(),
                resource_path.as_ptr(),
                false,
                false,
                false,
                false,
                std::ptr::null(),
                0,
                environment,
                Some(logger),
                None,
            )
        };
        (!instance.is_null()).then(|| Instance {
            f: functions.clone(),
            instance,
            outs: Outs::default(),
            _log: Rc::clone(log),
        })
    }

    #[inline]
    pub fn reset(&self) -> fmi3Status {
        // SAFETY: a live instance of the library the function comes from.
        unsafe { (self.f.reset)(self.instance) }
    }

    /// `fmi3EnterInitializationMode`: a tolerance and a stop time when given.
    #[inline]
    pub fn enter_initialization_mode(
        &self,
        tolerance: Option<f64>,
        start: f64,
        stop: Option<f64>,
    ) -> fmi3Status {
        // SAFETY: a live instance; plain values.
        unsafe {
            (self.f.enter_initialization_mode)(
                self.instance,
                tolerance.is_some(),
                tolerance.unwrap_or(0.0),
                start,
                stop.is_some(),
                stop.unwrap_or(0.0),
            )
        }
    }

    #[inline]
    pub fn exit_initialization_mode(&self) -> fmi3Status {
        // SAFETY: as for `reset`.
        unsafe { (self.f.exit_initialization_mode)(self.instance) }
    }

    /// `fmi3DoStep(t, h, noSetFMUStatePriorToCurrentPoint = true)`, its out arguments kept
    /// by the instance.
    #[inline]
    pub fn do_step(&mut self, t: f64, h: f64) -> fmi3Status {
        let o = &mut self.outs;
        // SAFETY: a live instance; the out arguments are writable fields.
        unsafe {
            (self.f.do_step)(
                self.instance,
                t,
                h,
                true,
                &mut o.0,
                &mut o.1,
                &mut o.2,
                &mut o.3,
            )
        }
    }

    /// `fmi3GetFloat64` of the value references `vrs` (scalars) into `out`, of the same
    /// length.
    #[inline]
    pub fn get_float64(&self, vrs: &[u32], out: &mut [f64]) -> fmi3Status {
        let n = vrs.len().min(out.len());
        // SAFETY: a live instance; `vrs` holds `n` elements, `out` room for `n`.
        unsafe { (self.f.get_float64)(self.instance, vrs.as_ptr(), n, out.as_mut_ptr(), n) }
    }
}

impl Drop for Instance {
    fn drop(&mut self) {
        // SAFETY: live, freed once, its library still loaded (held by `f`) and before its
        // log.
        unsafe { (self.f.free_instance)(self.instance) }
    }
}
