//! FMI 2.0's Co-Simulation step and status getters, and Model Exchange's event calls
//! (fmi2NewDiscreteStates, fmi2CompletedIntegratorStep).

use super::table::f;
use super::Fmi2;
use crate::ffi::*;
use crate::sequences::args::null_if;
use crate::sequences::core::Sequence;
use crate::sequences::machine::{Call, St, Target};

impl Sequence<'_, Fmi2> {
    /// The status getters: a value that is one with fmi2OK.
    pub(crate) fn status_getter(&mut self, call: Call) -> Status {
        let (function, target, c, _) = call.parts();
        let api = *self.fmu.api;
        let name = FUNCTION_NAMES[function];
        let kind: StatusKind = *self.rng.pick(&[0, 1, 2, 3, 3, 2, 4, u32::MAX]);
        let null = self.rng.chance(0.05);
        self.note(|| {
            format!(
                "{name}({target:?}, kind {kind}{})",
                if null { ", NULL value" } else { "" }
            )
        });
        let mut st: Status = 99;
        let mut real = -7.5e-77;
        let mut int: Integer = 0x5a5a;
        let mut string: CStr = std::ptr::null();
        // SAFETY: valid out pointers (or NULL).
        let s = unsafe {
            match function {
                f::GET_STATUS => {
                    (api.get_status)(c, kind, if null { std::ptr::null_mut() } else { &mut st })
                }
                f::GET_REAL_STATUS => (api.get_real_status)(c, kind, null_if(null, &mut real)),
                f::GET_INTEGER_STATUS => (api.get_integer_status)(
                    c,
                    kind,
                    if null { std::ptr::null_mut() } else { &mut int },
                ),
                f::GET_BOOLEAN_STATUS => (api.get_boolean_status)(
                    c,
                    kind,
                    if null { std::ptr::null_mut() } else { &mut int },
                ),
                _ => (api.get_string_status)(c, kind, null_if(null, &mut string)),
            }
        };
        if s == OK && !null {
            let bad = match function {
                f::GET_STATUS => st > PENDING,
                f::GET_REAL_STATUS => !real.is_finite(),
                f::GET_BOOLEAN_STATUS => !(int == 0 || int == 1),
                f::GET_STRING_STATUS => string.is_null(),
                _ => false,
            };
            if bad {
                self.fail(format!(
                    "{name}(kind {kind}) returned fmi2OK with a bad value"
                ));
            }
        }
        if !string.is_null() {
            // SAFETY: the FMU promises a NUL-terminated string.
            let _ = unsafe { std::ffi::CStr::from_ptr(string) }.to_bytes().len();
        }
        s
    }

    /// fmi2NewDiscreteStates: a NULL fmi2EventInfo refused, its booleans fmi2True or
    /// fmi2False and a finite next event time.
    pub(crate) fn new_discrete_states(&mut self, call: Call) -> Status {
        let (_, target, c, legal) = call.parts();
        let api = *self.fmu.api;
        let name = FUNCTION_NAMES[f::NEW_DISCRETE_STATES];
        let null = !self.sane && self.rng.chance(0.05);
        let mut info = unwritten_event_info();
        self.note(|| {
            format!(
                "{name}({target:?}{})",
                if null { ", NULL eventInfo" } else { "" }
            )
        });
        // SAFETY: a valid out pointer (or NULL).
        let s = unsafe { (api.new_discrete_states)(c, null_if(null, &mut info)) };
        if let (Target::Live(_), true, true) = (target, legal, null) {
            if s != ERROR {
                self.fail(format!(
                    "{name} with a NULL fmi2EventInfo returned {}",
                    status_name(s)
                ));
            }
        }
        if matches!(s, OK | WARNING) && !null {
            let flags = [
                info.newDiscreteStatesNeeded,
                info.terminateSimulation,
                info.nominalsOfContinuousStatesChanged,
                info.valuesOfContinuousStatesChanged,
                info.nextEventTimeDefined,
            ];
            if flags.iter().any(|&b| b != 0 && b != 1)
                || (info.nextEventTimeDefined == 1 && !info.nextEventTime.is_finite())
            {
                self.fail(format!("{name} returned {} with {info:?}", status_name(s)));
            }
            self.event_iterated(target, legal);
        }
        s
    }

    /// fmi2CompletedIntegratorStep: NULL out pointers refused, its booleans fmi2True or
    /// fmi2False.
    pub(crate) fn completed_integrator_step(&mut self, call: Call) -> Status {
        let (_, target, c, legal) = call.parts();
        let api = *self.fmu.api;
        let name = FUNCTION_NAMES[f::COMPLETED_INTEGRATOR_STEP];
        let no_prior: Boolean = if self.sane {
            1
        } else {
            *self.rng.pick(&[0, 1, 2])
        };
        let null_event = !self.sane && self.rng.chance(0.04);
        let null_terminate = !self.sane && self.rng.chance(0.04);
        let (mut event, mut terminate): (Boolean, Boolean) = (-1, -1);
        self.note(|| {
            format!(
                "{name}({target:?}, noSetFMUStatePriorToCurrentPoint {no_prior}{}{})",
                if null_event {
                    ", NULL enterEventMode"
                } else {
                    ""
                },
                if null_terminate {
                    ", NULL terminateSimulation"
                } else {
                    ""
                }
            )
        });
        // SAFETY: valid out pointers (or NULL).
        let s = unsafe {
            (api.completed_integrator_step)(
                c,
                no_prior,
                null_if(null_event, &mut event),
                null_if(null_terminate, &mut terminate),
            )
        };
        let null = null_event || null_terminate;
        if let (Target::Live(i), true) = (target, legal) {
            if null && s != ERROR {
                self.fail(format!(
                    "{name} with a NULL out pointer returned {}",
                    status_name(s)
                ));
            }
            if matches!(s, OK | WARNING) && !null {
                if ![event, terminate].iter().all(|&b| b == 0 || b == 1) {
                    self.fail(format!(
                        "{name} returned {} with enterEventMode = {event}, terminateSimulation = {terminate}",
                        status_name(s)
                    ));
                }
                self.insts[i].event_requested = event == 1;
            }
        }
        s
    }

    /// fmi2DoStep with sane and hostile communication points and step sizes: after
    /// fmi2OK the values are numbers; after fmi2Discard, fmi2Terminated is true and
    /// fmi2LastSuccessfulTime lies in the step.
    pub(crate) fn do_step(&mut self, call: Call) -> Status {
        let (_, target, c, legal) = call.parts();
        let e = self.fmu.md.experiment;
        let (time, stop) = self.time_and_stop(target);
        let h = match self.rng.below(20) {
            0..=8 => e.step,
            9..=11 => self.rng.log_uniform(1e-6, 1.0),
            12 => 1e-3,
            13 => *self.rng.pick(&[
                0.0,
                -0.0,
                -1.0,
                -e.step,
                f64::NAN,
                f64::INFINITY,
                f64::NEG_INFINITY,
            ]),
            14 => *self.rng.pick(&[
                5e-324,
                1e-300,
                1e-15 * time.abs().max(1e-300),
                f64::MIN_POSITIVE,
            ]),
            // Enormous steps: refused beyond a stop time, else integrated honestly (and
            // expensive), so rare.
            15 if stop.is_some_and(|s| s < 1e6) || self.rng.chance(0.01) => {
                *self.rng.pick(&[1e300, f64::MAX, 1e6, 1e3])
            }
            16 => self.rng.log_uniform(1.0, 10.0),
            _ => e.step,
        };
        let hostile = [
            f64::NAN,
            f64::INFINITY,
            f64::NEG_INFINITY,
            0.0,
            -time,
            1e308,
        ];
        let t = self.step_start(time, &hostile);
        let no_prior: Boolean = *self.rng.pick(&[0, 1, 2]);
        self.note(|| format!("fmi2DoStep({target:?}, t {t:e} (FMU at {time:e}), h {h:e}, noSetFMUStatePriorToCurrentPoint {no_prior})"));
        // SAFETY: scalar arguments.
        let s = unsafe { (self.fmu.api.do_step)(c, t, h, no_prior) };
        let Target::Live(i) = target else { return s };
        if !legal {
            return s;
        }
        match s {
            OK | WARNING => {
                self.stats.steps_ok += 1;
                self.insts[i].time = t + h;
                // The values after a successful step are numbers.
                let vrs = self.fmu.md.all_vrs();
                let mut out = vec![0.0; vrs.len()];
                // SAFETY: arrays of vrs.len() elements.
                let g = unsafe {
                    (self.fmu.api.get_real)(c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr())
                };
                self.stats.calls += 1;
                if g != OK {
                    self.fail(format!(
                        "fmi2GetReal after a successful fmi2DoStep returned {}",
                        status_name(g)
                    ));
                } else if let Some(k) = out.iter().position(|x| x.is_nan()) {
                    self.fail(format!(
                        "after fmi2DoStep(t {t:e}, h {h:e}) returned {}, `{}` is NaN",
                        status_name(s),
                        self.model.vars[k].name
                    ));
                }
            }
            DISCARD => {
                self.stats.steps_discarded += 1;
                self.insts[i].st = St::StepFailed;
                let mut last = f64::NAN;
                let mut term: Boolean = -1;
                // SAFETY: valid out pointers.
                let (a, b) = unsafe {
                    (
                        (self.fmu.api.get_real_status)(c, LAST_SUCCESSFUL_TIME, &mut last),
                        (self.fmu.api.get_boolean_status)(c, TERMINATED, &mut term),
                    )
                };
                self.stats.calls += 2;
                if a != OK
                    || !(last >= t.min(t + h) - 1e-9 * t.abs()
                        && last <= (t + h).max(t) + 1e-9 * t.abs())
                {
                    self.fail(format!("after fmi2Discard of [{t:e}, {:e}], fmi2LastSuccessfulTime = {last:e} ({})", t + h, status_name(a)));
                }
                if b != OK || term != 1 {
                    self.fail(format!(
                        "after fmi2Discard, fmi2Terminated = {term} ({})",
                        status_name(b)
                    ));
                }
                self.insts[i].time = last;
                // The values at the last successful time are numbers.
                let vrs = self.fmu.md.all_vrs();
                let mut out = vec![0.0; vrs.len()];
                // SAFETY: arrays of vrs.len() elements.
                let g = unsafe {
                    (self.fmu.api.get_real)(c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr())
                };
                self.stats.calls += 1;
                if g == OK {
                    if let Some(k) = out.iter().position(|x| x.is_nan()) {
                        self.fail(format!(
                            "after fmi2Discard (step [{t:e}, {:e}]), fmi2GetReal returned fmi2OK with `{}` = NaN",
                            t + h,
                            self.model.vars[k].name
                        ));
                    }
                }
            }
            _ => {}
        }
        s
    }
}
