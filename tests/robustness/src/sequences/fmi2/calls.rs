//! FMI 2.0's calls of its own: SetDebugLogging, the instance's life cycle, values of the
//! four types, and the dispatch of every function (the shared ones to the generator's
//! machinery).

use super::table::f;
use super::Fmi2;
use crate::ffi::*;
use crate::fmu::VariableExt;
use crate::sequences::args::null_if;
use crate::sequences::core::Sequence;
use crate::sequences::fmu_states::Restore;
use crate::sequences::hostile::hostile_f64;
use crate::sequences::machine::{Call, St, Target};
use std::ffi::CString;

impl Sequence<'_, Fmi2> {
    pub(crate) fn dispatch(&mut self, call: Call) -> Option<Status> {
        let (function, target, c, _) = call.parts();
        if let Some(s) = self.shared_me_call(call) {
            return Some(s);
        }
        let s = match function {
            f::SET_DEBUG_LOGGING => self.set_debug_logging_call(call),
            f::FREE_INSTANCE => {
                self.free_instance_call(call);
                return None;
            }
            f::SETUP_EXPERIMENT => self.setup_experiment_call(call),
            f::ENTER_INIT
            | f::EXIT_INIT
            | f::TERMINATE
            | f::RESET
            | f::CANCEL_STEP
            | f::ENTER_EVENT_MODE
            | f::ENTER_CONTINUOUS_TIME_MODE => self.life_cycle_call(call),
            f::GET_REAL => self.get_real_call(call),
            f::GET_INTEGER | f::GET_BOOLEAN | f::GET_STRING => self.get_other_type_call(call),
            f::SET_REAL => self.set_real_call(call),
            f::SET_INTEGER | f::SET_BOOLEAN | f::SET_STRING => self.set_other_type_call(call),
            f::GET_FMU_STATE => self.get_fmu_state_call(call),
            f::SET_FMU_STATE => self.state_handle_call(call, 0, restore),
            f::SERIALIZED_SIZE => self.state_handle_call(call, 1, restore),
            f::SERIALIZE => self.state_handle_call(call, 2, restore),
            f::FREE_FMU_STATE => self.free_fmu_state_call(call),
            f::DESERIALIZE => {
                let bytes = self.serialized_bytes();
                self.deserialize_call(function, target, c, bytes)
            }
            f::DIRECTIONAL_DERIVATIVE => self.directional_derivative(call),
            f::SET_INPUT_DERIVATIVES | f::GET_OUTPUT_DERIVATIVES => {
                self.input_output_derivatives(call)
            }
            f::DO_STEP => self.do_step(call),
            f::GET_STATUS
            | f::GET_REAL_STATUS
            | f::GET_INTEGER_STATUS
            | f::GET_BOOLEAN_STATUS
            | f::GET_STRING_STATUS => self.status_getter(call),
            f::NEW_DISCRETE_STATES => self.new_discrete_states(call),
            f::COMPLETED_INTEGRATOR_STEP => self.completed_integrator_step(call),
            _ => unreachable!("function {function}"),
        };
        Some(s)
    }

    /// SetDebugLogging with categories drawn sane or hostile; the oracle's categories follow.
    fn set_debug_logging_call(&mut self, call: Call) -> Status {
        let (function, target, c, legal) = call.parts();
        let api = *self.fmu.api;
        let name = FUNCTION_NAMES[function];
        let on: Boolean = *self.rng.pick(&[0, 1, 2, -1]);
        let (names, null_array, nc) = self.logging_categories();
        let ptrs: Vec<CStr> = names
            .iter()
            .map(|n| n.as_ref().map_or(std::ptr::null(), |c| c.as_ptr()))
            .collect();
        self.note(|| {
            format!(
                "{name}(on {on}, {nc} categories {names:?}{})",
                if null_array { ", NULL array" } else { "" }
            )
        });
        let array = if null_array {
            std::ptr::null()
        } else {
            ptrs.as_ptr()
        };
        // SAFETY: `nc` strings at `ptrs` (or a NULL array).
        let s = unsafe { (api.set_debug_logging)(c, on, nc, array) };
        self.apply_logging(target, legal, on != 0, &names, null_array, nc);
        s
    }

    /// FreeInstance; a live instance freed legally leaves the sequence, its logger checked a
    /// last time.
    fn free_instance_call(&mut self, call: Call) {
        let (function, target, c, legal) = call.parts();
        let api = *self.fmu.api;
        let name = FUNCTION_NAMES[function];
        self.note(|| format!("{name}({target:?})"));
        // SAFETY: NULL, foreign memory, or a live instance.
        unsafe { (api.free_instance)(c) };
        self.stats.calls += 1;
        if let Target::Live(i) = target {
            if legal {
                let inst = self.insts.remove(i);
                for v in inst.sink.take_violations() {
                    self.fail(format!("{name}: {v}"));
                }
            }
        }
    }

    /// SetupExperiment with a tolerance, start and stop time drawn sane or hostile.
    fn setup_experiment_call(&mut self, call: Call) -> Status {
        let (function, target, c, legal) = call.parts();
        let api = *self.fmu.api;
        let name = FUNCTION_NAMES[function];
        let e = self.fmu.md.experiment;
        let tol_defined: Boolean = *self.rng.pick(&[0, 1, 1, 1, 7]);
        let tol = match self.rng.below(6) {
            0 => e.tolerance,
            1 => self.rng.log_uniform(1e-10, 1e-2),
            2 => 1e-6,
            3 => *self
                .rng
                .pick(&[0.0, -1.0, f64::NAN, f64::INFINITY, 1e300, 10.0, 1e-14]),
            4 if self.rng.chance(0.05) => 1e-300,
            _ => e.tolerance,
        };
        let start = match self.rng.below(6) {
            0..=2 => e.start,
            3 => self.rng.unit() * 100.0 - 50.0,
            4 => hostile_f64(&mut self.rng),
            _ => 0.0,
        };
        let stop_defined: Boolean = *self.rng.pick(&[0, 0, 1, 1, -3]);
        let stop = match self.rng.below(4) {
            0 => start + e.stop - e.start,
            1 => start + self.rng.unit() * 10.0,
            2 => hostile_f64(&mut self.rng),
            _ => start - 1.0,
        };
        self.note(|| format!("{name}({target:?}, tol {tol_defined}:{tol:e}, start {start:e}, stop {stop_defined}:{stop:e})"));
        // SAFETY: scalar arguments.
        let s = unsafe { (api.setup_experiment)(c, tol_defined, tol, start, stop_defined, stop) };
        if let (Some(inst), true, OK) = (self.inst(target), legal, s) {
            inst.time = start;
            inst.stop = (stop_defined != 0).then_some(stop);
        }
        s
    }

    /// A function of the instance's life cycle without arguments (initialization, terminate,
    /// reset, cancel, the Model Exchange modes); the oracle's state follows.
    fn life_cycle_call(&mut self, call: Call) -> Status {
        let (function, target, c, legal) = call.parts();
        let api = *self.fmu.api;
        let name = FUNCTION_NAMES[function];
        self.note(|| format!("{name}({target:?})"));
        let g = match function {
            f::ENTER_INIT => api.enter_initialization_mode,
            f::EXIT_INIT => api.exit_initialization_mode,
            f::TERMINATE => api.terminate,
            f::RESET => api.reset,
            f::ENTER_EVENT_MODE => api.enter_event_mode,
            f::ENTER_CONTINUOUS_TIME_MODE => api.enter_continuous_time_mode,
            _ => api.cancel_step,
        };
        // SAFETY: NULL, foreign memory, or a live instance.
        let s = unsafe { g(c) };
        if let (Some(inst), true) = (self.inst(target), legal) {
            match (function, s) {
                (f::ENTER_INIT, OK) => inst.st = St::Init,
                (f::EXIT_INIT, OK | WARNING) => inst.st = inst.kind.initialized(),
                (f::ENTER_EVENT_MODE, OK) => inst.enter_event_mode(),
                (f::ENTER_CONTINUOUS_TIME_MODE, OK) => inst.st = St::ContinuousTimeMode,
                // A model failure at initialization: the Error state.
                (f::EXIT_INIT, _) => inst.st = St::Error,
                (f::TERMINATE, OK) => inst.st = St::Terminated,
                (f::RESET, OK) => inst.reset(),
                _ => {}
            }
        }
        s
    }

    /// GetReal: nothing written past the values asked, no NaN with OK or Warning.
    fn get_real_call(&mut self, call: Call) -> Status {
        let (function, target, c, _) = call.parts();
        let api = *self.fmu.api;
        let name = FUNCTION_NAMES[function];
        let vrs = self.vrs();
        let n = vrs.len();
        let mut out = vec![-7.5e-77f64; n + 4];
        let vp = self.ptr_or_null(&vrs);
        let op = null_if(self.rng.chance(0.04), out.as_mut_ptr());
        self.note(|| {
            format!(
                "{name}({target:?}, vr {vrs:?}{}{})",
                if vp.is_null() { ", NULL vr" } else { "" },
                if op.is_null() { ", NULL value" } else { "" }
            )
        });
        // SAFETY: arrays of n elements (or NULL).
        let s = unsafe { (api.get_real)(c, vp, n, op) };
        self.check_canaries(name, &out[n..], -7.5e-77);
        if matches!(s, OK | WARNING) {
            if let Some(k) = out[..n].iter().position(|x| x.is_nan()) {
                self.fail(format!(
                    "{name} returned {} with NaN for value reference {}",
                    status_name(s),
                    vrs[k]
                ));
            }
        }
        s
    }

    /// GetInteger, GetBoolean or GetString, of types this FMU has no variables of: nothing
    /// written past the values asked, no OK for a value reference.
    fn get_other_type_call(&mut self, call: Call) -> Status {
        let (function, target, c, legal) = call.parts();
        let api = *self.fmu.api;
        let name = FUNCTION_NAMES[function];
        let vrs = self.vrs();
        let n = vrs.len();
        let mut ints = vec![0x5a5a_5a5a_i32; n + 4];
        let mut strs: Vec<CStr> = vec![std::ptr::null(); n + 4];
        let vp = self.ptr_or_null(&vrs);
        let null_out = self.rng.chance(0.04);
        self.note(|| format!("{name}({target:?}, vr {vrs:?})"));
        // SAFETY: arrays of n elements (or NULL).
        let s = unsafe {
            match function {
                f::GET_INTEGER => (api.get_integer)(c, vp, n, null_if(null_out, ints.as_mut_ptr())),
                f::GET_BOOLEAN => (api.get_boolean)(c, vp, n, null_if(null_out, ints.as_mut_ptr())),
                _ => (api.get_string)(c, vp, n, null_if(null_out, strs.as_mut_ptr())),
            }
        };
        if ints[n..].iter().any(|&x| x != 0x5a5a_5a5a) || strs[n..].iter().any(|p| !p.is_null()) {
            self.fail(format!("{name} wrote past the {n} elements it was given"));
        }
        if n > 0 && s == OK && matches!(target, Target::Live(_)) && legal {
            self.fail(format!(
                "{name} of Real variables {vrs:?} returned fmi2OK (this FMU has no such variables)"
            ));
        }
        s
    }

    /// SetReal: in continuous-time mode only continuous inputs are accepted.
    fn set_real_call(&mut self, call: Call) -> Status {
        let (function, target, c, legal) = call.parts();
        let api = *self.fmu.api;
        let name = FUNCTION_NAMES[function];
        let vrs = self.vrs();
        let values: Vec<f64> = vrs.iter().map(|&v| self.value_for(v, 0)).collect();
        let vp = self.ptr_or_null(&vrs);
        let xp = self.ptr_or_null(&values);
        self.note(|| format!("{name}({target:?}, vr {vrs:?}, values {values:?})"));
        // SAFETY: arrays of n elements (or NULL).
        let s = unsafe { (api.set_real)(c, vp, vrs.len(), xp) };
        if let (Target::Live(i), true, OK | WARNING) = (target, legal, s) {
            if self.insts[i].st == St::ContinuousTimeMode {
                let continuous_input = |vr: &u32| {
                    self.model
                        .vars
                        .iter()
                        .any(|v| v.vr == *vr && v.is("input") && v.variability == "continuous")
                };
                if let Some(vr) = vrs.iter().find(|vr| !continuous_input(vr)) {
                    self.fail(format!(
                        "{name} in continuous-time mode returned {} for value reference {vr}, which is not a continuous input",
                        status_name(s)
                    ));
                }
            }
        }
        s
    }

    /// SetInteger, SetBoolean or SetString, of types this FMU has no variables of: no OK for a
    /// value reference.
    fn set_other_type_call(&mut self, call: Call) -> Status {
        let (function, target, c, legal) = call.parts();
        let api = *self.fmu.api;
        let name = FUNCTION_NAMES[function];
        let vrs = self.vrs();
        let n = vrs.len();
        let ints: Vec<i32> = (0..n).map(|_| self.rng.next_u64() as i32).collect();
        let cstrings: Vec<CString> = (0..n)
            .map(|i| CString::new(format!("s{i}%s")).unwrap())
            .collect();
        let strs: Vec<CStr> = cstrings
            .iter()
            .map(|s| {
                if self.rng.chance(0.2) {
                    std::ptr::null()
                } else {
                    s.as_ptr()
                }
            })
            .collect();
        let vp = self.ptr_or_null(&vrs);
        self.note(|| format!("{name}({target:?}, vr {vrs:?})"));
        // SAFETY: arrays of n elements (or NULL).
        let s = unsafe {
            match function {
                f::SET_INTEGER => (api.set_integer)(c, vp, n, self.ptr_or_null(&ints)),
                f::SET_BOOLEAN => (api.set_boolean)(c, vp, n, self.ptr_or_null(&ints)),
                _ => (api.set_string)(c, vp, n, self.ptr_or_null(&strs)),
            }
        };
        if n > 0 && s == OK && matches!(target, Target::Live(_)) && legal {
            self.fail(format!("{name} of value references {vrs:?} returned fmi2OK (this FMU has no such variables)"));
        }
        s
    }
}

/// A state saved in a state only the other interface type's machine has must be refused
/// (FMI 2.0 has no other check the oracle can make).
fn restore(
    snap: &crate::sequences::machine::Snap,
    inst: &crate::sequences::machine::Inst,
) -> Restore {
    match snap.st.kind().filter(|&other| other != inst.kind) {
        Some(other) => {
            Restore::Refused(format!("saved in {:?} (a {} state)", snap.st, other.name()))
        }
        None => Restore::Either,
    }
}
