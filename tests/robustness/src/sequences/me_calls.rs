//! Model Exchange's calls on the continuous states, alike in both standards: SetTime,
//! SetContinuousStates and the four array getters, with wrong lengths, NULL arrays and
//! non-finite values, or as an importer's integrator makes them ([`Sequence::sane`]).

use super::core::{MeArray, Sequence, Standard};
use super::hostile::hostile_f64;
use super::machine::{Call, Target};
use crate::ffi::{Status, ERROR, OK, WARNING};
use crate::sequences::args::null_if;

impl<S: Standard> Sequence<'_, S> {
    /// The Model Exchange calls both standards share (SetTime, SetContinuousStates, the
    /// array getters), made with their checks; `None` for any other function.
    pub(crate) fn shared_me_call(&mut self, call: Call) -> Option<Status> {
        let [states, derivatives, set_time, set_states, _, indicators] = S::ME_STEP;
        let function = call.parts().0;
        let s = match function {
            _ if function == set_time => self.set_time_call(call),
            _ if function == set_states => self.set_continuous_states_call(call),
            _ if function == derivatives => self.me_array_call(call, MeArray::Derivatives),
            _ if function == indicators => self.me_array_call(call, MeArray::EventIndicators),
            _ if function == states => self.me_array_call(call, MeArray::ContinuousStates),
            _ if function == S::GET_NOMINALS => self.me_array_call(call, MeArray::Nominals),
            _ => return None,
        };
        Some(s)
    }

    /// A step of the event iteration went through: an event counted, and what the
    /// importer knew of the states gone.
    pub(crate) fn event_iterated(&mut self, target: Target, legal: bool) {
        if let (Target::Live(i), true) = (target, legal) {
            self.stats.events += 1;
            let inst = &mut self.insts[i];
            inst.x.clear();
            inst.dx.clear();
        }
    }

    /// SetTime: a time ahead of the instance's (an integrator's step when sane), the same,
    /// behind it, huge, tiny or not finite; a finite time is accepted, no other.
    pub(crate) fn set_time_call(&mut self, call: Call) -> Status {
        let (function, target, c, legal) = call.parts();
        let name = S::NAMES[function];
        let time = match target {
            Target::Live(i) => self.insts[i].time,
            _ => 0.0,
        };
        let t = if self.sane {
            time + self.h_me
        } else {
            match self.rng.below(12) {
                0..=5 => time + self.rng.log_uniform(1e-6, 0.1),
                6 => time,
                // Backwards: after a rejected step, an importer goes back.
                7 => time - self.rng.unit(),
                8 => *self
                    .rng
                    .pick(&[1e308, -1e308, f64::MAX, f64::MIN, 1e15, -1e15]),
                9 => *self.rng.pick(&[5e-324, -0.0, 0.0, time * (1.0 + 1e-15)]),
                _ => *self
                    .rng
                    .pick(&[f64::NAN, -f64::NAN, f64::INFINITY, f64::NEG_INFINITY]),
            }
        };
        self.note(|| format!("{name}({target:?}, time {t:e} (FMU at {time:e}))"));
        // SAFETY: scalar arguments.
        let s = unsafe { S::set_time(self.fmu, c, t) };
        if let (Target::Live(i), true) = (target, legal) {
            if t.is_finite() != (s == OK) {
                self.fail(format!(
                    "{name}(time {t:e}) returned {} (a finite time is accepted, no other)",
                    S::status_name(s)
                ));
            }
            if s == OK {
                self.insts[i].time = t;
            }
        }
        s
    }

    /// SetContinuousStates: from what the importer knows of the instance (an Euler step
    /// from the last states read, those states, or the start values), perturbed, with a
    /// hostile element, a wrong length or NULL sometimes.
    pub(crate) fn set_continuous_states_call(&mut self, call: Call) -> Status {
        let (function, target, c, legal) = call.parts();
        let name = S::NAMES[function];
        let n = self.model.nx;
        let len = self.array_len(n);
        let cap = len.min(n + 8);
        // From what the importer knows of the instance: an Euler step from the last
        // states read, those states, or the start values.
        let (x, dx) = match target {
            Target::Live(i) => (self.insts[i].x.clone(), self.insts[i].dx.clone()),
            _ => (vec![], vec![]),
        };
        let mut values: Vec<f64> = if x.len() == n && dx.len() == n {
            x.iter().zip(&dx).map(|(x, d)| x + self.h_me * d).collect()
        } else if x.len() == n {
            x
        } else {
            self.model.x_start.clone()
        };
        if !self.sane && self.rng.chance(0.2) {
            for v in values.iter_mut() {
                *v *= 1.0 + 0.1 * (self.rng.unit() - 0.5);
            }
        }
        values.resize(cap, 0.5);
        if !self.sane && cap > 0 && self.rng.chance(0.25) {
            let k = self.rng.below(cap);
            values[k] = hostile_f64(&mut self.rng);
        }
        let null = !self.sane && self.rng.chance(0.04);
        self.note(|| {
            format!(
                "{name}({target:?}, x {values:?}{}, nx {len})",
                if null { " at NULL" } else { "" }
            )
        });
        // SAFETY: `cap` readable elements (or NULL); a longer `len` is one the FMU
        // must refuse before reading (nx is in its modelDescription).
        let s = unsafe {
            S::set_continuous_states(
                self.fmu,
                c,
                if null {
                    std::ptr::null()
                } else {
                    values.as_ptr()
                },
                len,
            )
        };
        if let (Target::Live(i), true) = (target, legal) {
            let right = len == n && !(null && n > 0);
            let finite = values[..cap.min(len)].iter().all(|x| x.is_finite());
            if !right && s != ERROR {
                self.fail(format!(
                    "{name} with nx = {len}{} (the FMU has {n} states) returned {}",
                    if null { " and x = NULL" } else { "" },
                    S::status_name(s)
                ));
            } else if right && !finite && s != ERROR {
                self.fail(format!(
                    "{name} with non-finite states {values:?} returned {}",
                    S::status_name(s)
                ));
            } else if right && finite && s != OK {
                self.fail(format!(
                    "{name} refused finite states {values:?} ({})",
                    S::status_name(s)
                ));
            }
            if s == OK {
                let inst = &mut self.insts[i];
                values.truncate(n);
                inst.x_set = Some(values.clone());
                inst.x = values;
                inst.dx.clear();
            }
        }
        s
    }

    /// One of the four array getters (`which`): a wrong length or NULL refused, nothing
    /// written past the elements, finite values (nominals > 0), the states given back
    /// bit for bit, the same numbers as the variables they are.
    pub(crate) fn me_array_call(&mut self, call: Call, which: MeArray) -> Status {
        let (function, target, c, legal) = call.parts();
        let name = S::NAMES[function];
        let n = if which == MeArray::EventIndicators {
            self.model.ni
        } else {
            self.model.nx
        };
        let len = self.array_len(n);
        let cap = len.min(n + 8);
        let canary = -7.5e-77f64;
        let mut out = vec![canary; cap + 4];
        let null = !self.sane && self.rng.chance(0.04);
        self.note(|| {
            format!(
                "{name}({target:?}, n {len}{})",
                if null { ", NULL array" } else { "" }
            )
        });
        // SAFETY: `cap` writable elements (or NULL); a longer `len` is one the FMU
        // must refuse before writing.
        let out_ptr: *mut f64 = null_if(null, out.as_mut_ptr());
        let s = unsafe { S::get_me_array(self.fmu, which, c, out_ptr, len) };
        self.check_canaries(name, &out[cap.min(len)..], canary);
        let right = len == n && !(null && n > 0);
        if let (Target::Live(_), true, false, false) = (target, legal, right, s == ERROR) {
            self.fail(format!(
                "{name} with n = {len}{} (the FMU has {n}) returned {}",
                if null { " and a NULL array" } else { "" },
                S::status_name(s)
            ));
        }
        if matches!(s, OK | WARNING) && right && !null {
            let got = &out[..n];
            let bad = if which == MeArray::Nominals {
                got.iter().position(|x| !(x.is_finite() && *x > 0.0))
            } else {
                got.iter().position(|x| !x.is_finite())
            };
            if let Some(k) = bad {
                self.fail(format!(
                    "{name} returned {} with element {k} = {} ({got:?})",
                    S::status_name(s),
                    got[k]
                ));
            }
            if let (Target::Live(i), true) = (target, legal) {
                let got = got.to_vec();
                match which {
                    MeArray::ContinuousStates => {
                        if let Some(set) = &self.insts[i].x_set {
                            if set
                                .iter()
                                .zip(&got)
                                .any(|(a, b)| a.to_bits() != b.to_bits())
                            {
                                let set = set.clone();
                                self.fail(format!(
                                "{name} returned {got:?}, not the states {set:?} SetContinuousStates was given"
                            ));
                            }
                        }
                        self.insts[i].x = got.clone();
                    }
                    MeArray::Derivatives => self.insts[i].dx = got.clone(),
                    _ => {}
                }
                // The same numbers as the variables they are: checked once this
                // call's messages are (reading them may log its own).
                let vrs = match which {
                    MeArray::ContinuousStates => self.model.state_vrs.clone(),
                    MeArray::Derivatives => self.model.derivative_vrs.clone(),
                    _ => vec![],
                };
                if !vrs.is_empty() {
                    self.same_as_variables = Some((c, vrs, got));
                }
            }
        }
        s
    }
}
