//! FMI 3.0's dispatch of every function (the shared ones to the generator's machinery),
//! SetDebugLogging, the instance's life cycle (initialization with its experiment, event
//! mode, step mode, continuous-time mode, terminate, reset, free), the FMU states of the
//! other standard, and the functions of features not offered.

use super::table::f;
use super::Fmi3;
use crate::ffi3::*;
use crate::sequences::core::Sequence;
use crate::sequences::fmu_states::Restore;
use crate::sequences::hostile::hostile_f64;
use crate::sequences::machine::{Call, Inst, Kind, Snap, St, Target};
use crate::sequences::state_bytes::{forge_state, forge_token};

impl Sequence<'_, Fmi3> {
    pub(crate) fn dispatch(&mut self, call: Call) -> Option<Status> {
        let (function, target, c, legal) = call.parts();
        let api = *self.fmu.api;
        let name = FUNCTION_NAMES_FMI3[function];
        let live = matches!(target, Target::Live(_)) && legal;
        if let Some(s) = self.shared_me_call(call) {
            return Some(s);
        }
        let s = match function {
            f::SET_DEBUG_LOGGING => {
                let on = self.rng.chance(0.5);
                let (names, null_array, nc) = self.logging_categories();
                let ptrs: Vec<CStr> = names
                    .iter()
                    .map(|n| n.as_ref().map_or(std::ptr::null(), |c| c.as_ptr()))
                    .collect();
                self.note(|| format!("{name}(on {on}, {nc} categories {names:?})"));
                let array = if null_array {
                    std::ptr::null()
                } else {
                    ptrs.as_ptr()
                };
                // SAFETY: `nc` strings at `ptrs` (or a NULL array).
                let s = unsafe { (api.set_debug_logging)(c, on, nc, array) };
                self.apply_logging(target, legal, on, &names, null_array, nc);
                s
            }
            f::FREE_INSTANCE => {
                self.note(|| format!("{name}({target:?})"));
                // SAFETY: NULL, foreign or misaligned memory, an instance of either
                // standard of this binary.
                unsafe { (api.free_instance)(c) };
                self.stats.calls += 1;
                if let (Target::Live(i), true) = (target, legal) {
                    let inst = self.insts.remove(i);
                    for v in inst.sink.take_violations() {
                        self.fail(format!("{name}: {v}"));
                    }
                }
                return None;
            }
            f::ENTER_INIT => self.enter_initialization_mode(call),
            f::EXIT_INIT
            | f::ENTER_EVENT_MODE
            | f::TERMINATE
            | f::RESET
            | f::EVALUATE_DISCRETE_STATES
            | f::ENTER_CONTINUOUS_TIME_MODE
            | f::ENTER_STEP_MODE => self.mode_change(call),
            f::GET_FLOAT64 => self.get_float64(call),
            f::SET_FLOAT64 => self.set_float64(call),
            f::GET_FLOAT32..=f::GET_BINARY => self.get_other_type(call),
            f::SET_FLOAT32..=f::SET_BINARY => self.set_other_type(call),
            f::GET_FMU_STATE => self.get_fmu_state_call(call),
            f::SET_FMU_STATE if self.extra.other.is_some() && self.rng.chance(0.1) => {
                let state = self
                    .extra
                    .other
                    .as_ref()
                    .map_or(std::ptr::null_mut(), |o| o.state);
                self.note(|| format!("{name}({target:?}, the FMI 2.0 instance's state)"));
                // SAFETY: a live FMU state of this binary (of the other standard).
                let s = unsafe { (api.set_fmu_state)(c, state) };
                if live && s != ERROR {
                    self.fail(format!(
                        "{name} of an FMI 2.0 instance's FMU state returned {}",
                        status_name(s)
                    ));
                }
                s
            }
            f::SET_FMU_STATE => self.state_handle_call(call, 0, restore),
            f::SERIALIZED_SIZE => self.state_handle_call(call, 1, restore),
            f::SERIALIZE => self.state_handle_call(call, 2, restore),
            f::FREE_FMU_STATE => self.free_fmu_state_call(call),
            f::DESERIALIZE => {
                let (bytes, snap) = self.serialized_bytes3();
                let foreign = snap.is_some_and(|s| s.other_standard);
                let s = self.deserialize_call(function, target, c, (bytes, snap));
                if live && foreign && s != ERROR {
                    self.fail(format!(
                        "{name} of an FMI 2.0 instance's serialized state returned {}",
                        status_name(s)
                    ));
                }
                s
            }
            f::DIRECTIONAL_DERIVATIVE | f::ADJOINT_DERIVATIVE => self.directional_or_adjoint(call),
            f::GET_OUTPUT_DERIVATIVES => self.output_derivatives(call),
            f::DO_STEP => self.do_step(call),
            f::UPDATE_DISCRETE_STATES => self.update_discrete_states(call),
            f::COMPLETED_INTEGRATOR_STEP => self.completed_integrator_step(call),
            f::GET_NUMBER_OF_EVENT_INDICATORS | f::GET_NUMBER_OF_CONTINUOUS_STATES => {
                self.get_number_of(call)
            }
            _ if f::unsupported(function) => self.unsupported(call),
            _ => unreachable!("function {function}"),
        };
        Some(s)
    }

    /// fmi3EnterInitializationMode with the experiment's tolerance, start and stop time,
    /// sane and hostile.
    fn enter_initialization_mode(&mut self, call: Call) -> Status {
        let (_, target, c, legal) = call.parts();
        let e = self.model.experiment;
        let tol_defined = self.rng.chance(0.8);
        let tol = match self.rng.below(6) {
            0 | 5 => e.tolerance,
            1 => self.rng.log_uniform(1e-10, 1e-2),
            2 => 1e-6,
            3 => *self
                .rng
                .pick(&[0.0, -1.0, f64::NAN, f64::INFINITY, 1e300, 10.0, 1e-14]),
            _ => 1e-300,
        };
        let start = match self.rng.below(6) {
            0..=2 => e.start,
            3 => self.rng.unit() * 100.0 - 50.0,
            4 => hostile_f64(&mut self.rng),
            _ => 0.0,
        };
        let stop_defined = self.rng.chance(0.4);
        let stop = match self.rng.below(4) {
            0 => start + e.stop - e.start,
            1 => start + self.rng.unit() * 10.0,
            2 => hostile_f64(&mut self.rng),
            _ => start - 1.0,
        };
        self.note(|| format!("fmi3EnterInitializationMode({target:?}, tol {tol_defined}:{tol:e}, start {start:e}, stop {stop_defined}:{stop:e})"));
        // SAFETY: scalar arguments.
        let s = unsafe {
            (self.fmu.api.enter_initialization_mode)(c, tol_defined, tol, start, stop_defined, stop)
        };
        if let (Some(inst), true, OK) = (self.inst(target), legal, s) {
            inst.st = St::Init;
            inst.time = start;
            inst.stop = stop_defined.then_some(stop);
        }
        s
    }

    /// A call of the instance alone that moves its state machine: the oracle moves with it.
    fn mode_change(&mut self, call: Call) -> Status {
        let (function, target, c, legal) = call.parts();
        let api = *self.fmu.api;
        let name = FUNCTION_NAMES_FMI3[function];
        self.note(|| format!("{name}({target:?})"));
        let g = match function {
            f::EXIT_INIT => api.exit_initialization_mode,
            f::ENTER_EVENT_MODE => api.enter_event_mode,
            f::TERMINATE => api.terminate,
            f::RESET => api.reset,
            f::EVALUATE_DISCRETE_STATES => api.evaluate_discrete_states,
            f::ENTER_CONTINUOUS_TIME_MODE => api.enter_continuous_time_mode,
            _ => api.enter_step_mode,
        };
        // SAFETY: NULL, foreign or misaligned memory, or an instance of this binary.
        let s = unsafe { g(c) };
        let Some(inst) = self.inst(target).filter(|_| legal) else {
            return s;
        };
        let without_event_mode = inst.kind == Kind::CoSimulation && !inst.event_mode_used;
        match (function, s) {
            (f::ENTER_EVENT_MODE, _) if without_event_mode && s != ERROR => self.fail(format!(
                "{name} of a Co-Simulation instance without eventModeUsed returned {}",
                status_name(s)
            )),
            (f::ENTER_EVENT_MODE, _) if without_event_mode => {}
            (f::EXIT_INIT, OK | WARNING) => {
                inst.st = if inst.kind == Kind::ModelExchange || inst.event_mode_used {
                    St::EventMode
                } else {
                    St::StepComplete
                }
            }
            // A model failure at initialization: the Error state.
            (f::EXIT_INIT, _) => inst.st = St::Error,
            (f::ENTER_EVENT_MODE, OK) => inst.enter_event_mode(),
            (f::ENTER_CONTINUOUS_TIME_MODE, OK) => inst.st = St::ContinuousTimeMode,
            (f::ENTER_STEP_MODE, OK) => inst.st = St::StepComplete,
            (f::TERMINATE, OK) => inst.st = St::Terminated,
            (f::RESET, OK) => inst.reset(),
            (f::EVALUATE_DISCRETE_STATES, _) if s != OK => self.fail(format!(
                "{name} in event mode returned {} (there is nothing discrete to evaluate)",
                status_name(s)
            )),
            _ => {}
        }
        s
    }

    /// Clocks, intervals and shifts, per-element dependencies, configuration mode, model
    /// partitions: called with NULL arguments (the FMU must refuse before reading them),
    /// always fmi3Error.
    fn unsupported(&mut self, call: Call) -> Status {
        let (function, target, c, _) = call.parts();
        let api = *self.fmu.api;
        let name = FUNCTION_NAMES_FMI3[function];
        self.note(|| format!("{name}({target:?}, NULL arguments)"));
        let vr = self.vr();
        let n = *self.rng.pick(&[0, 1, 3]);
        let (vrs, null) = (std::ptr::null(), std::ptr::null_mut::<u64>());
        // SAFETY: NULL arrays of length `n` (0 or not), which the FMU must not read.
        let s = unsafe {
            match function {
                f::GET_CLOCK => (api.get_clock)(c, vrs, n, null.cast()),
                f::SET_CLOCK => (api.set_clock)(c, vrs, n, null.cast()),
                f::GET_NUMBER_OF_VARIABLE_DEPENDENCIES => {
                    (api.get_number_of_variable_dependencies)(c, vr, null.cast())
                }
                f::GET_VARIABLE_DEPENDENCIES => (api.get_variable_dependencies)(
                    c,
                    vr,
                    null.cast(),
                    null.cast(),
                    null.cast(),
                    null.cast(),
                    n,
                ),
                f::ENTER_CONFIGURATION_MODE => (api.enter_configuration_mode)(c),
                f::EXIT_CONFIGURATION_MODE => (api.exit_configuration_mode)(c),
                f::GET_INTERVAL_DECIMAL => {
                    (api.get_interval_decimal)(c, vrs, n, null.cast(), null.cast())
                }
                f::GET_INTERVAL_FRACTION => {
                    (api.get_interval_fraction)(c, vrs, n, null.cast(), null.cast(), null.cast())
                }
                f::GET_SHIFT_DECIMAL => (api.get_shift_decimal)(c, vrs, n, null.cast()),
                f::GET_SHIFT_FRACTION => {
                    (api.get_shift_fraction)(c, vrs, n, null.cast(), null.cast())
                }
                f::SET_INTERVAL_DECIMAL => (api.set_interval_decimal)(c, vrs, n, null.cast()),
                f::SET_INTERVAL_FRACTION => {
                    (api.set_interval_fraction)(c, vrs, n, null.cast(), null.cast())
                }
                f::SET_SHIFT_DECIMAL => (api.set_shift_decimal)(c, vrs, n, null.cast()),
                f::SET_SHIFT_FRACTION => {
                    (api.set_shift_fraction)(c, vrs, n, null.cast(), null.cast())
                }
                _ => (api.activate_model_partition)(c, vr, hostile_f64(&mut self.rng)),
            }
        };
        if s != ERROR {
            self.fail(format!(
                "{name} (a feature this FMU does not offer) returned {}",
                status_name(s)
            ));
        }
        s
    }

    /// Bytes to deserialize: as FMI 2.0's sequences draw them, or (one in five when there
    /// is one) the FMI 2.0 instance's serialized state, raw or forged into FMI 3.0's, or an
    /// FMI 3.0 state with its interface type or instance state forged.
    pub(crate) fn serialized_bytes3(&mut self) -> (Vec<u8>, Option<Snap>) {
        if self.rng.chance(0.8) {
            return self.serialized_bytes();
        }
        let token = self.fmu.md.instantiation_token.clone();
        match (self.rng.below(3), &self.extra.other) {
            (0, Some(other)) => (other.bytes.clone(), Some(self.other_standard_snap())),
            (1, Some(other)) => {
                let mut b = other.bytes.clone();
                forge_token(&mut b, &token);
                (b, None)
            }
            _ if !self.serialized.is_empty() => {
                let k = self.rng.below(self.serialized.len());
                let mut b = self.serialized[k].0.clone();
                forge_state(&mut self.rng, &mut b);
                (b, None)
            }
            _ => self.serialized_bytes(),
        }
    }
}

/// What restoring `snap` into `inst` must do: refused if saved by the other standard, by
/// the other interface type, or in event mode for a Co-Simulation instance without it;
/// accepted if this sequence saved it (it was not read from forged bytes); either for
/// forged bytes the FMU accepted.
fn restore(snap: &Snap, inst: &Inst) -> Restore {
    if snap.other_standard {
        Restore::Refused("saved by an FMI 2.0 instance".into())
    } else if snap.kind != inst.kind {
        Restore::Refused(format!("saved by a {} instance", snap.kind.name()))
    } else if snap.st == St::EventMode && inst.kind == Kind::CoSimulation && !inst.event_mode_used {
        Restore::Refused("saved in event mode (the instance has no eventModeUsed)".into())
    } else if snap.forged {
        Restore::Either
    } else {
        Restore::Accepted
    }
}
