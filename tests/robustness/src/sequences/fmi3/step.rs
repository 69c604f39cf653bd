//! FMI 3.0's communication step and events: fmi3DoStep with its out arguments (early
//! return, terminateSimulation, the last successful time), fmi3UpdateDiscreteStates,
//! fmi3CompletedIntegratorStep, the numbers of states and indicators.

use super::table::f;
use super::values::Ptr;
use super::Fmi3;
use crate::ffi3::*;
use crate::sequences::args::null_if;
use crate::sequences::core::{Sequence, Standard};
use crate::sequences::machine::{Call, St, Target};

/// Every byte an FMU writes for a boolean is 0 or 1; `0xa5` is left where it wrote none.
fn boolean(b: u8) -> bool {
    b == 0 || b == 1
}

impl Sequence<'_, Fmi3> {
    /// fmi3DoStep: sane and hostile communication points and step sizes (as FMI 2.0's),
    /// out arguments NULL or misaligned sometimes (refused).
    pub(crate) fn do_step(&mut self, call: Call) -> Status {
        let (_, target, c, legal) = call.parts();
        let e = self.model.experiment;
        let (time, stop) = self.time_and_stop(target);
        let h = match self.rng.below(20) {
            0..=9 => e.step,
            10..=12 => self.rng.log_uniform(1e-6, 1.0),
            13 => *self
                .rng
                .pick(&[0.0, -0.0, -1.0, -e.step, f64::NAN, f64::INFINITY]),
            14 => *self
                .rng
                .pick(&[5e-324, 1e-300, 1e-15 * time.abs().max(1e-300)]),
            15 if stop.is_some_and(|s| s < 1e6) || self.rng.chance(0.01) => {
                *self.rng.pick(&[1e300, f64::MAX, 1e6, 1e3])
            }
            16 => self.rng.log_uniform(1.0, 10.0),
            _ => e.step,
        };
        let t = self.step_start(time, &[f64::NAN, f64::INFINITY, 0.0, -time, 1e308]);
        let no_prior = self.rng.chance(0.5);
        // Booleans are bytes, never misaligned: NULL or not. The time: NULL or misaligned
        // (within `last`) sometimes.
        let nulls: [bool; 3] = std::array::from_fn(|_| self.rng.chance(0.02));
        let time_ptr = self.ptr();
        let mut flags = [0xa5u8; 3];
        let mut last = [f64::NAN; 2];
        self.note(|| format!("fmi3DoStep({target:?}, t {t:e} (FMU at {time:e}), h {h:e}, NULL booleans {nulls:?}, lastSuccessfulTime {time_ptr:?})"));
        let [event, terminate, early] = &mut flags;
        let b = |null: bool, p: &mut u8| null_if(null, p as *mut u8);
        // SAFETY: valid out pointers (or NULL, or misaligned within `last`).
        let s = unsafe {
            (self.fmu.api.do_step)(
                c,
                t,
                h,
                no_prior,
                b(nulls[0], event).cast(),
                b(nulls[1], terminate).cast(),
                b(nulls[2], early).cast(),
                time_ptr.of_mut(last.as_mut_ptr()),
            )
        };
        let Target::Live(i) = target else { return s };
        if !legal {
            return s;
        }
        if nulls.iter().any(|&n| n) || time_ptr != Ptr::Array {
            if s != ERROR {
                self.fail(format!(
                    "fmi3DoStep with NULL booleans {nulls:?} and lastSuccessfulTime {time_ptr:?} returned {}",
                    status_name(s)
                ));
            }
            return s;
        }
        let [event, terminate, early] = flags;
        let (inst, md) = (&self.insts[i], &self.fmu.md);
        let last = last[0];
        let ends =
            |x: f64| x >= t.min(t + h) - 1e-9 * t.abs() && x <= (t + h).max(t) + 1e-9 * t.abs();
        let bad = if matches!(s, OK | WARNING | DISCARD) && !flags.iter().all(|&b| boolean(b)) {
            Some("a boolean that is neither 0 nor 1")
        } else if matches!(s, OK | WARNING)
            && early == 1
            && !(inst.early_return_allowed && md.might_return_early_from_do_step)
        {
            Some("an early return the instance or the modelDescription does not allow")
        } else if matches!(s, OK | WARNING) && event == 1 && !inst.event_mode_used {
            Some("eventHandlingNeeded without eventModeUsed")
        } else if matches!(s, OK | WARNING)
            && early == 0
            && terminate == 0
            && last.to_bits() != (t + h).to_bits()
        {
            Some("a lastSuccessfulTime other than t + h")
        } else if (s == DISCARD || early == 1) && !(terminate == 1 && ends(last)) {
            Some("a stop without terminateSimulation at a lastSuccessfulTime in the step")
        } else {
            None
        };
        if let Some(what) = bad {
            self.fail(format!(
                "fmi3DoStep(t {t:e}, h {h:e}) returned {} with {what}: eventHandlingNeeded {event}, terminateSimulation {terminate}, earlyReturn {early}, lastSuccessfulTime {last:e}",
                status_name(s)
            ));
        }
        if !matches!(s, OK | WARNING | DISCARD) {
            return s;
        }
        let stopped = terminate == 1;
        let inst = &mut self.insts[i];
        inst.time = if stopped { last } else { t + h };
        if stopped {
            inst.st = St::StepFailed;
        }
        if s == DISCARD {
            self.stats.steps_discarded += 1;
        } else {
            self.stats.steps_ok += 1;
            self.stats.early_returns += early as u64;
        }
        // The values after the step (or where it stopped) are numbers.
        let vrs = self.fmu.md.all_vrs();
        let mut out = vec![0.0; self.fmu.md.len_of(&vrs).unwrap_or(0)];
        // SAFETY: the live instance just stepped.
        let g = unsafe { Fmi3::get_values(self.fmu, c, &vrs, &mut out) };
        self.stats.calls += 1;
        if s != DISCARD && g != OK {
            self.fail(format!(
                "fmi3GetFloat64 after a successful fmi3DoStep returned {}",
                status_name(g)
            ));
        } else if let (OK, Some(k)) = (g, out.iter().position(|x| x.is_nan())) {
            self.fail(format!(
                "after fmi3DoStep(t {t:e}, h {h:e}) returned {}, value {k} of every variable is NaN",
                status_name(s)
            ));
        }
        s
    }

    /// fmi3UpdateDiscreteStates: out arguments NULL sometimes (the FMU may skip them or
    /// refuse), booleans 0 or 1, a finite next event time where one is defined.
    pub(crate) fn update_discrete_states(&mut self, call: Call) -> Status {
        let (_, target, c, legal) = call.parts();
        let name = FUNCTION_NAMES_FMI3[f::UPDATE_DISCRETE_STATES];
        let nulls: [bool; 6] = std::array::from_fn(|_| !self.sane && self.rng.chance(0.05));
        let mut flags = [0xa5u8; 5];
        let mut next = f64::NAN;
        self.note(|| format!("{name}({target:?}, NULL out arguments {nulls:?})"));
        let p = |k: usize, b: &mut u8| null_if(nulls[k], b as *mut u8);
        let [a, b, cc, d, e] = &mut flags;
        let (a, b, cc, d, e) = (p(0, a), p(1, b), p(2, cc), p(3, d), p(4, e));
        let next_p = null_if(nulls[5], &mut next as *mut f64);
        // SAFETY: valid out pointers or NULL.
        let s = unsafe {
            (self.fmu.api.update_discrete_states)(
                c,
                a.cast(),
                b.cast(),
                cc.cast(),
                d.cast(),
                e.cast(),
                next_p,
            )
        };
        if matches!(s, OK | WARNING) {
            let given: Vec<u8> = (0..5).filter(|&k| !nulls[k]).map(|k| flags[k]).collect();
            if !given.iter().all(|&b| boolean(b))
                || (!nulls[4] && !nulls[5] && flags[4] == 1 && !next.is_finite())
            {
                self.fail(format!(
                    "{name} returned {} with {flags:?}, next event time {next}",
                    status_name(s)
                ));
            }
            self.event_iterated(target, legal);
        }
        s
    }

    /// fmi3CompletedIntegratorStep: NULL out pointers refused, booleans 0 or 1, no event
    /// asked by an FMU that says it needs no completed integrator steps.
    pub(crate) fn completed_integrator_step(&mut self, call: Call) -> Status {
        let (_, target, c, legal) = call.parts();
        let name = FUNCTION_NAMES_FMI3[f::COMPLETED_INTEGRATOR_STEP];
        let no_prior = self.sane || self.rng.chance(0.5);
        let null_event = !self.sane && self.rng.chance(0.04);
        let null_terminate = !self.sane && self.rng.chance(0.04);
        let (mut event, mut terminate) = (0xa5u8, 0xa5u8);
        self.note(|| format!("{name}({target:?}, noSetFMUStatePriorToCurrentPoint {no_prior}, NULL {null_event} {null_terminate})"));
        let ep = null_if(null_event, &mut event as *mut u8);
        let tp = null_if(null_terminate, &mut terminate as *mut u8);
        // SAFETY: valid out pointers (or NULL).
        let s =
            unsafe { (self.fmu.api.completed_integrator_step)(c, no_prior, ep.cast(), tp.cast()) };
        let Target::Live(i) = target else { return s };
        if !legal {
            return s;
        }
        if (null_event || null_terminate) && s != ERROR {
            self.fail(format!(
                "{name} with a NULL out pointer returned {}",
                status_name(s)
            ));
        }
        if matches!(s, OK | WARNING) && !null_event && !null_terminate {
            if !boolean(event) || !boolean(terminate) {
                self.fail(format!("{name} returned {} with enterEventMode = {event}, terminateSimulation = {terminate}", status_name(s)));
            }
            if event == 1 && !self.fmu.md.needs_completed_integrator_step {
                self.fail(format!(
                    "{name} asked for an event, but needsCompletedIntegratorStep is false"
                ));
            }
            self.insts[i].event_requested = event == 1;
        }
        s
    }

    /// fmi3GetNumberOfContinuousStates, fmi3GetNumberOfEventIndicators: the
    /// modelDescription's count (of elements), NULL refused.
    pub(crate) fn get_number_of(&mut self, call: Call) -> Status {
        let (function, target, c, legal) = call.parts();
        let name = FUNCTION_NAMES_FMI3[function];
        let null = self.rng.chance(0.1);
        let mut n = usize::MAX;
        let p = null_if(null, &mut n as *mut usize);
        self.note(|| format!("{name}({target:?}{})", if null { ", NULL" } else { "" }));
        let (g, expected) = if function == f::GET_NUMBER_OF_CONTINUOUS_STATES {
            (self.fmu.api.get_number_of_continuous_states, self.model.nx)
        } else {
            (self.fmu.api.get_number_of_event_indicators, self.model.ni)
        };
        // SAFETY: a valid out pointer (or NULL).
        let s = unsafe { g(c, p) };
        if matches!(target, Target::Live(_))
            && legal
            && (null != (s == ERROR) || (s == OK && n != expected))
        {
            self.fail(format!(
                "{name}{} returned {} with {n} (the modelDescription has {expected})",
                if null { " of NULL" } else { "" },
                status_name(s)
            ));
        }
        s
    }
}
