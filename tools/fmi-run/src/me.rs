//! Model Exchange under this crate's fixed-step RK4, with events: the same integrator for
//! FMI 2.0 and FMI 3.0 instances, each seen through [`MeInstance`] (see the crate's
//! documentation, "Model Exchange").

use crate::{Experiment, MeOptions, MeStats, Table, EVENT_LOCATION_TOLERANCE};
use fmi::EventFlags;

/// The outcome of an FMI call, of either version.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Status {
    Ok,
    /// `fmi2Warning` or `fmi3Warning` (its name).
    Warning(&'static str),
    /// Any other status, named (`fmi3Discard`, ...).
    Fail(String),
}

impl Status {
    /// OK or Warning: the call's outputs are defined.
    pub(crate) fn is_ok(&self) -> bool {
        !matches!(self, Status::Fail(_))
    }
}

impl From<Result<fmi::fmi2::Fmi2Res, fmi::fmi2::Fmi2Error>> for Status {
    fn from(r: Result<fmi::fmi2::Fmi2Res, fmi::fmi2::Fmi2Error>) -> Self {
        use fmi::fmi2::{Fmi2Error as E, Fmi2Res as R};
        match r {
            Ok(R::OK) => Status::Ok,
            Ok(R::Warning) => Status::Warning("fmi2Warning"),
            Ok(R::Pending) => {
                Status::Fail("fmi2Pending (asynchronous steps are not supported)".into())
            }
            Err(E::Discard) => Status::Fail("fmi2Discard".into()),
            Err(E::Error) => Status::Fail("fmi2Error".into()),
            Err(E::Fatal) => Status::Fail("fmi2Fatal".into()),
            Err(e) => Status::Fail(e.to_string()),
        }
    }
}

impl From<Result<fmi::fmi3::Fmi3Res, fmi::fmi3::Fmi3Error>> for Status {
    fn from(r: Result<fmi::fmi3::Fmi3Res, fmi::fmi3::Fmi3Error>) -> Self {
        use fmi::fmi3::{Fmi3Error as E, Fmi3Res as R};
        match r {
            Ok(R::OK) => Status::Ok,
            Ok(R::Warning) => Status::Warning("fmi3Warning"),
            Err(E::Discard) => Status::Fail("fmi3Discard".into()),
            Err(E::Error) => Status::Fail("fmi3Error".into()),
            Err(E::Fatal) => Status::Fail("fmi3Fatal".into()),
        }
    }
}

/// `Ok` for an OK status only; else an error naming the call (`call()`) and the status.
pub(crate) fn ok(call: impl FnOnce() -> String, status: impl Into<Status>) -> Result<(), String> {
    match status.into() {
        Status::Ok => Ok(()),
        Status::Warning(name) => Err(format!("{} returned {name}", call())),
        Status::Fail(name) => Err(format!("{} returned {name}", call())),
    }
}

/// The names of a version's functions and flags, for messages.
pub(crate) struct CallNames {
    /// `fmi2` or `fmi3`.
    pub prefix: &'static str,
    pub get_derivatives: &'static str,
    pub update_discrete_states: &'static str,
    pub discrete_states_need_update: &'static str,
    pub set_inputs: &'static str,
}

/// What the RK4 integrator needs of a Model Exchange instance, FMI 2.0 or 3.0, initialized
/// and with the experiment's variables resolved.
pub(crate) trait MeInstance {
    const NAMES: CallNames;
    fn set_time(&mut self, t: f64) -> Status;
    fn set_continuous_states(&mut self, x: &[f64]) -> Status;
    fn get_derivatives(&mut self, dx: &mut [f64]) -> Status;
    /// Discard when the FMU cannot compute them (the fmi crate's `Ok(false)`).
    fn get_event_indicators(&mut self, z: &mut [f64]) -> Status;
    fn completed_integrator_step(&mut self, enter: &mut bool, terminate: &mut bool) -> Status;
    fn enter_event_mode(&mut self) -> Status;
    fn update_discrete_states(&mut self, flags: &mut EventFlags) -> Status;
    fn enter_continuous_time_mode(&mut self) -> Status;
    fn get_continuous_states(&mut self, x: &mut [f64]) -> Status;
    fn terminate(&mut self) -> Status;
    /// Sets the inputs to `row` (one value per input of the experiment).
    fn set_inputs(&mut self, row: &[f64]) -> Status;
    /// The inputs' names, for messages.
    fn input_list(&self) -> &str;
    /// One row of the result at `t`: `t`, then the recorded variables now.
    fn record(&mut self, t: f64) -> Result<Vec<f64>, String>;
}

/// The most events handled within one communication step before the run is declared stuck
/// (an event indicator that keeps changing sign: chattering).
const MAX_EVENTS_PER_STEP: usize = 100;

/// The indicators whose domain (`z > 0` or `z <= 0`, the standard's definition of a state
/// event) differs between `before` and `after`.
pub(crate) fn sign_changes(before: &[f64], after: &[f64]) -> Vec<usize> {
    before
        .iter()
        .zip(after)
        .enumerate()
        .filter(|(_, (a, b))| (**a > 0.0) != (**b > 0.0))
        .map(|(i, _)| i)
        .collect()
}

/// "state event of event indicator 0" (or "indicators [0, 1]").
fn state_event(which: &[usize]) -> String {
    match which {
        [i] => format!("state event of event indicator {i}"),
        _ => format!("state event of event indicators {which:?}"),
    }
}

/// How an event iteration ended.
enum Iteration {
    Done,
    /// `terminateSimulation`: the message saying which call asked, when.
    Terminate(String),
}

/// A Model Exchange instance being integrated, with its accepted point.
struct MeIntegration<I: MeInstance> {
    fmu: I,
    /// `completedIntegratorStepNotNeeded` is false (or absent), or FMI 3.0's
    /// `needsCompletedIntegratorStep`.
    needs_completed_integrator_step: bool,
    /// The accepted time, states and event indicators (the FMU is at this point between
    /// steps).
    t: f64,
    x: Vec<f64>,
    z: Vec<f64>,
    /// `nextEventTime` of the last event iteration, if defined.
    next_event_time: Option<f64>,
    /// The RK4 stages and scratch.
    k: [Vec<f64>; 4],
    stage: Vec<f64>,
    stats: MeStats,
    /// Where the run is, for messages: the communication step (1-based), their number, and
    /// the step's start.
    step: usize,
    steps: usize,
    step_start: f64,
}

impl<I: MeInstance> MeIntegration<I> {
    fn at(&self, t: f64) -> String {
        if self.step == 0 {
            return format!("at t = {t:?} (initialization)");
        }
        format!(
            "at t = {t:?} (in step {} of {}, from t = {:?})",
            self.step, self.steps, self.step_start
        )
    }

    fn call(name: &str) -> String {
        format!("{}{name}", I::NAMES.prefix)
    }

    /// `SetTime(t)` and `SetContinuousStates(x)`.
    fn set_point(&mut self, t: f64, x: &[f64]) -> Result<(), String> {
        ok(
            || format!("{}({t:?})", Self::call("SetTime")),
            self.fmu.set_time(t),
        )?;
        let r = self.fmu.set_continuous_states(x);
        ok(
            || format!("{} {}", Self::call("SetContinuousStates"), self.at(t)),
            r,
        )
    }

    /// The event indicators at the FMU's current point, into `z` (none: no call).
    fn read_indicators(fmu: &mut I, z: &mut [f64]) -> Status {
        if z.is_empty() {
            return Status::Ok;
        }
        fmu.get_event_indicators(z)
    }

    /// One classical RK4 step from (`t0`, `x0`) to `t1`: for each stage `SetTime`,
    /// `SetContinuousStates` and the derivatives; then the FMU is set to (`t1`, `x1`) and its
    /// event indicators read into `z1`.
    fn rk4(
        &mut self,
        t0: f64,
        x0: &[f64],
        t1: f64,
        x1: &mut [f64],
        z1: &mut [f64],
    ) -> Result<(), String> {
        let h = t1 - t0;
        let mid = t0 + 0.5 * h;
        let stages = [(t0, 0.0), (mid, 0.5 * h), (mid, 0.5 * h), (t1, h)];
        for (s, &(ts, a)) in stages.iter().enumerate() {
            // the stage's states: x0 + a k[s-1]
            if s == 0 {
                self.stage.copy_from_slice(x0);
            } else {
                let (done, _) = self.k.split_at(s);
                for ((y, &x), &k) in self.stage.iter_mut().zip(x0).zip(&done[s - 1]) {
                    *y = x + a * k;
                }
            }
            let stage = std::mem::take(&mut self.stage);
            let set = self.set_point(ts, &stage);
            self.stage = stage;
            set?;
            let r = self.fmu.get_derivatives(&mut self.k[s]);
            ok(
                || {
                    format!(
                        "{} {} (RK4 stage {} of 4)",
                        I::NAMES.get_derivatives,
                        self.at(ts),
                        s + 1
                    )
                },
                r,
            )?;
            self.stats.derivative_evaluations += 1;
        }
        for (i, y) in x1.iter_mut().enumerate() {
            let [k1, k2, k3, k4] = &self.k;
            *y = x0[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
        self.set_point(t1, x1)?;
        let r = Self::read_indicators(&mut self.fmu, z1);
        ok(
            || format!("{} {}", Self::call("GetEventIndicators"), self.at(t1)),
            r,
        )
    }

    /// The FMU asked to stop: `Terminate`, and the message that ends the run.
    fn terminate_there(&mut self, why: String) -> String {
        match self.fmu.terminate() {
            Status::Ok => why,
            r => {
                let also = ok(|| Self::call("Terminate"), r).err().unwrap_or_default();
                format!("{why}; then {also}")
            }
        }
    }

    /// The event iteration at the current point: `fmi2NewDiscreteStates` (or
    /// `fmi3UpdateDiscreteStates`) until no further update is needed. Whether the states
    /// changed, or the stop.
    fn event_iteration(&mut self, what: &str) -> Result<(Iteration, bool), String> {
        let mut changed = false;
        let mut flags = EventFlags::default();
        let call = I::NAMES.update_discrete_states;
        for iteration in 1.. {
            flags.reset();
            let r = self.fmu.update_discrete_states(&mut flags);
            if flags.terminate_simulation && r.is_ok() {
                return Ok((
                    Iteration::Terminate(format!(
                        "{call} ({what}, iteration {iteration}) {} returned terminateSimulation = true: \
                         the simulation stopped at t = {:?}",
                        self.at(self.t),
                        self.t
                    )),
                    changed,
                ));
            }
            ok(
                || format!("{call} ({what}, iteration {iteration}) {}", self.at(self.t)),
                r,
            )?;
            changed |= flags.values_of_continuous_states_changed;
            if !flags.discrete_states_need_update {
                break;
            }
            if iteration >= MAX_EVENTS_PER_STEP {
                return Err(format!(
                    "{call} ({what}) {} still returns {} after {iteration} iterations",
                    self.at(self.t),
                    I::NAMES.discrete_states_need_update
                ));
            }
        }
        self.next_event_time = flags.next_event_time;
        Ok((Iteration::Done, changed))
    }

    /// An event at the accepted point: `EnterEventMode` (unless already in event mode), the
    /// inputs `row` set in event mode, the event iteration, `EnterContinuousTimeMode`, the
    /// states again if they changed, the event indicators again.
    fn event(&mut self, what: &str, enter: bool, row: Option<&[f64]>) -> Result<(), String> {
        if enter {
            let r = self.fmu.enter_event_mode();
            ok(
                || {
                    format!(
                        "{} ({what}) {}",
                        Self::call("EnterEventMode"),
                        self.at(self.t)
                    )
                },
                r,
            )?;
        }
        if let Some(row) = row {
            let r = self.fmu.set_inputs(row);
            ok(
                || {
                    format!(
                        "{}({}) in event mode {}",
                        I::NAMES.set_inputs,
                        self.fmu.input_list(),
                        self.at(self.t)
                    )
                },
                r,
            )?;
        }
        let (outcome, changed) = self.event_iteration(what)?;
        if let Iteration::Terminate(why) = outcome {
            return Err(self.terminate_there(why));
        }
        let r = self.fmu.enter_continuous_time_mode();
        ok(
            || {
                format!(
                    "{} ({what}) {}",
                    Self::call("EnterContinuousTimeMode"),
                    self.at(self.t)
                )
            },
            r,
        )?;
        if changed {
            self.stats.state_changes += 1;
            let r = self.fmu.get_continuous_states(&mut self.x);
            ok(
                || {
                    format!(
                        "{} ({what}) {}",
                        Self::call("GetContinuousStates"),
                        self.at(self.t)
                    )
                },
                r,
            )?;
        }
        let r = Self::read_indicators(&mut self.fmu, &mut self.z);
        ok(
            || {
                format!(
                    "{} {} ({what})",
                    Self::call("GetEventIndicators"),
                    self.at(self.t)
                )
            },
            r,
        )
    }

    /// Integrates from the accepted point to `t_end` with RK4 steps of at most `t_end - t`,
    /// handling every event on the way; the FMU ends at (`t_end`, its states).
    fn integrate_to(&mut self, t_end: f64) -> Result<(), String> {
        let n = self.x.len();
        let (mut x1, mut z1) = (vec![0.0; n], vec![0.0; self.z.len()]);
        let (mut xm, mut zm) = (x1.clone(), z1.clone());
        let mut events = 0;
        while self.t < t_end {
            // a time event announced up to t_end ends the step there
            let time_event = self.next_event_time.filter(|&te| te <= t_end);
            let target = time_event.map_or(t_end, |te| te.max(self.t));
            let (t0, x0) = (self.t, self.x.clone());
            if target > t0 {
                self.rk4(t0, &x0, target, &mut x1, &mut z1)?;
            } else {
                x1.copy_from_slice(&x0);
                z1.copy_from_slice(&self.z);
            }
            let mut accepted = target;
            let crossed = sign_changes(&self.z, &z1);
            if !crossed.is_empty() {
                // bisection on the step's length: re-integrate from t0 with the shorter
                // step; `hi` always ends past a sign change, `lo` before any
                let (mut lo, mut hi) = (t0, target);
                while hi - lo > EVENT_LOCATION_TOLERANCE {
                    let mid = lo + 0.5 * (hi - lo);
                    if mid <= lo || mid >= hi {
                        break;
                    }
                    self.rk4(t0, &x0, mid, &mut xm, &mut zm)?;
                    if sign_changes(&self.z, &zm).is_empty() {
                        lo = mid;
                    } else {
                        hi = mid;
                        std::mem::swap(&mut x1, &mut xm);
                        std::mem::swap(&mut z1, &mut zm);
                    }
                }
                accepted = hi;
                // the FMU is at the last trial: back to the point accepted
                self.set_point(hi, &x1)?;
            }
            let which = sign_changes(&self.z, &z1);
            self.t = accepted;
            self.x.copy_from_slice(&x1);
            self.z.copy_from_slice(&z1);
            self.stats.steps += 1;

            let mut step_event = false;
            if self.needs_completed_integrator_step {
                let (mut enter, mut terminate) = (false, false);
                let r = self
                    .fmu
                    .completed_integrator_step(&mut enter, &mut terminate);
                // where, and why the step ended there
                let point = if which.is_empty() {
                    self.at(self.t)
                } else {
                    format!("{} ({})", self.at(self.t), state_event(&which))
                };
                let call = Self::call("CompletedIntegratorStep");
                if terminate && r.is_ok() {
                    let why = format!(
                        "{call} {point} returned terminateSimulation = true: \
                         the simulation stopped at t = {:?}",
                        self.t
                    );
                    return Err(self.terminate_there(why));
                }
                ok(|| format!("{call} {point}"), r)?;
                step_event = enter;
            }
            let time_event = time_event.is_some() && accepted == target && which.is_empty();
            let mut kinds = Vec::new();
            if !which.is_empty() {
                self.stats.state_events += 1;
                kinds.push(state_event(&which));
            }
            if step_event {
                self.stats.step_events += 1;
                kinds.push("step event".to_string());
            }
            if time_event {
                self.stats.time_events += 1;
                kinds.push("time event".to_string());
            }
            if !kinds.is_empty() {
                events += 1;
                if events > MAX_EVENTS_PER_STEP {
                    return Err(format!(
                        "more than {MAX_EVENTS_PER_STEP} events {}: the last a {}",
                        self.at(self.t),
                        kinds.join(", ")
                    ));
                }
                if time_event {
                    self.next_event_time = None;
                }
                self.event(&kinds.join(", "), true, None)?;
            }
        }
        Ok(())
    }
}

/// Integrates an instance just out of `ExitInitializationMode` (in event mode), with `nx`
/// states and `nz` event indicators, through the experiment: the initial event iteration,
/// then every communication step (input events, RK4 substeps, events), recording each
/// communication point; `Terminate` at the end.
pub(crate) fn integrate<I: MeInstance>(
    fmu: I,
    needs_completed_integrator_step: bool,
    (nx, nz): (usize, usize),
    exp: &Experiment,
    options: &MeOptions,
) -> Result<(Table, MeStats), String> {
    let mut me = MeIntegration {
        fmu,
        needs_completed_integrator_step,
        t: 0.0,
        x: vec![0.0; nx],
        z: vec![0.0; nz],
        next_event_time: None,
        k: std::array::from_fn(|_| vec![0.0; nx]),
        stage: vec![0.0; nx],
        stats: MeStats::default(),
        step: 0,
        steps: exp.steps,
        step_start: 0.0,
    };
    // ExitInitializationMode left the FMU in event mode
    me.event("the initial event iteration", false, None)?;
    let r = me.fmu.get_continuous_states(&mut me.x);
    ok(
        || {
            format!(
                "{} at t = 0.0",
                MeIntegration::<I>::call("GetContinuousStates")
            )
        },
        r,
    )?;

    let h = exp.step_size;
    let time = |k: usize| k as f64 * h;
    let mut rows = Vec::with_capacity(exp.steps + 1);
    rows.push(me.fmu.record(0.0)?);
    for k in 1..=exp.steps {
        me.step = k;
        me.step_start = time(k - 1);
        // the inputs of the step from t_{k-1}: row 0 was set in initialization mode; a
        // change is an input event at t_{k-1}
        if k > 1 && !exp.inputs.is_empty() {
            let (old, new) = (&exp.input_values[k - 2], &exp.input_values[k - 1]);
            if old.iter().zip(new).any(|(a, b)| a.to_bits() != b.to_bits()) {
                me.stats.input_events += 1;
                me.event("input event", true, Some(new))?;
            }
        }
        let (t0, t1) = (time(k - 1), time(k));
        let m = options.substeps;
        for j in 1..=m {
            // the substeps' ends, the last exactly t_k
            let tj = if j == m {
                t1
            } else {
                t0 + (t1 - t0) * (j as f64 / m as f64)
            };
            me.integrate_to(tj)?;
        }
        rows.push(me.fmu.record(t1)?);
    }
    let r = me.fmu.terminate();
    ok(|| MeIntegration::<I>::call("Terminate"), r)?;
    Ok((
        Table {
            names: crate::column_names(exp),
            rows,
        },
        me.stats,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_state_event_is_a_change_of_domain_z_positive_or_not() {
        assert_eq!(
            sign_changes(&[1.0, -1.0], &[0.5, -2.0]),
            Vec::<usize>::new()
        );
        assert_eq!(sign_changes(&[1.0, -1.0], &[-0.5, -2.0]), [0]);
        assert_eq!(sign_changes(&[1.0, -1.0], &[-0.5, 2.0]), [0, 1]);
        // z = 0 belongs to z <= 0
        assert_eq!(sign_changes(&[1e-300], &[0.0]), [0]);
        assert_eq!(sign_changes(&[0.0], &[-1.0]), Vec::<usize>::new());
        assert_eq!(sign_changes(&[-0.0], &[1e-300]), [0]);
    }

    #[test]
    fn statuses_are_named_by_version() {
        let warning: Status = Ok::<_, fmi::fmi3::Fmi3Error>(fmi::fmi3::Fmi3Res::Warning).into();
        assert!(warning.is_ok());
        assert_eq!(
            ok(|| "fmi3DoStep".into(), warning),
            Err("fmi3DoStep returned fmi3Warning".into())
        );
        let discard: Status = Err::<fmi::fmi2::Fmi2Res, _>(fmi::fmi2::Fmi2Error::Discard).into();
        assert!(!discard.is_ok());
        assert_eq!(
            ok(|| "fmi2DoStep".into(), discard),
            Err("fmi2DoStep returned fmi2Discard".into())
        );
    }
}
