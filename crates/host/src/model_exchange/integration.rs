//! An instance being integrated: its accepted point, the RK4 step, the location of a state
//! event, the events, and the loops over them.

use super::{ok, Event, Instance, Location, Options, Status, MAX_EVENTS_PER_STEP};

/// What happened during a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Stats {
    /// Accepted RK4 steps (a step cut short at an event counts as one).
    pub steps: usize,
    /// Derivative evaluations (4 per RK4 step, bisection trials included).
    pub derivative_evaluations: usize,
    /// State events: a crossing of an event indicator, located by bisection.
    pub state_events: usize,
    /// Step events: `CompletedIntegratorStep` returned `enterEventMode`.
    pub step_events: usize,
    /// Time events: the time an event iteration announced (`nextEventTime`) reached.
    pub time_events: usize,
    /// Input events: the inputs changed at a communication point (counted by the importer
    /// that sets them).
    pub input_events: usize,
    /// Event iterations that set `valuesOfContinuousStatesChanged`.
    pub state_changes: usize,
}

/// Where the run is, for messages.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Where {
    /// Before the first step: "at t = 0.0 (initialization)".
    Initialization,
    /// In communication step `step` (1-based) of `steps`, from `start`.
    Step {
        step: usize,
        steps: usize,
        start: f64,
    },
    /// The time alone.
    Free,
}

/// The FMU asked to stop (`terminateSimulation`): when, and the message saying which call
/// asked, where.
#[derive(Clone, Debug, PartialEq)]
pub struct Stop {
    pub at: f64,
    pub why: String,
}

/// How one step ended.
#[derive(Clone, Debug, PartialEq)]
pub enum Step {
    /// Accepted, cut short at a state event or not.
    Accepted {
        state_event: bool,
    },
    Stopped(Stop),
}

/// How an event iteration ended.
enum Iteration {
    Done,
    /// `terminateSimulation`: the message saying which call asked, when.
    Terminate(String),
}

/// A Model Exchange instance being integrated, with its accepted point.
pub struct Integration<I: Instance> {
    pub fmu: I,
    options: Options,
    /// The accepted time, states and event indicators (the FMU is at this point between
    /// steps).
    pub t: f64,
    pub x: Vec<f64>,
    pub z: Vec<f64>,
    /// `nextEventTime` of the last event iteration, if defined.
    next_event_time: Option<f64>,
    /// The RK4 stages and scratch.
    k: [Vec<f64>; 4],
    stage: Vec<f64>,
    pub stats: Stats,
    /// Where the run is, for messages.
    pub at: Where,
    /// Events since the last target was reached.
    events: usize,
}

impl<I: Instance> Integration<I> {
    /// `fmu` with `nx` states and `nz` event indicators, at t = 0 before its first event
    /// iteration.
    pub fn new(fmu: I, (nx, nz): (usize, usize), options: Options) -> Integration<I> {
        Integration {
            fmu,
            options,
            t: 0.0,
            x: vec![0.0; nx],
            z: vec![0.0; nz],
            next_event_time: None,
            k: std::array::from_fn(|_| vec![0.0; nx]),
            stage: vec![0.0; nx],
            stats: Stats::default(),
            at: Where::Initialization,
            events: 0,
        }
    }

    /// "at t = ..." and where in the run, for messages.
    pub fn at(&self, t: f64) -> String {
        match self.at {
            Where::Initialization => format!("at t = {t:?} (initialization)"),
            Where::Step { step, steps, start } => {
                format!("at t = {t:?} (in step {step} of {steps}, from t = {start:?})")
            }
            Where::Free => format!("at t = {t:?}"),
        }
    }

    /// The function `name` of the instance's version (`fmi2SetTime`, ...).
    pub fn call(name: &str) -> String {
        format!("{}{name}", I::NAMES.prefix)
    }

    /// `Ok` for OK, and for a Warning where [`Options::warnings_pass`]; else the error.
    fn passes(&self, call: impl FnOnce() -> String, status: Status) -> Result<(), String> {
        match status {
            Status::Warning(_) if self.options.warnings_pass => Ok(()),
            status => ok(call, status),
        }
    }

    /// `Ok` for OK; else the error naming the call `name` of the instance's version, the
    /// event `what` and the accepted point.
    fn ok_at(&self, name: &str, what: &str, status: Status) -> Result<(), String> {
        let call = || format!("{} ({what}) {}", Self::call(name), self.at(self.t));
        ok(call, status)
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

    /// Takes the instance's point at `t` as the accepted one: its states, and its event
    /// indicators there.
    pub fn resume(&mut self, t: f64) -> Result<(), String> {
        self.t = t;
        let r = self.fmu.get_continuous_states(&mut self.x);
        ok(
            || format!("{} {}", Self::call("GetContinuousStates"), self.at(t)),
            r,
        )?;
        let x = std::mem::take(&mut self.x);
        let set = self.set_point(t, &x);
        self.x = x;
        set?;
        let r = Self::read_indicators(&mut self.fmu, &mut self.z);
        ok(
            || format!("{} {}", Self::call("GetEventIndicators"), self.at(t)),
            r,
        )
    }

    /// One classical RK4 step of length `h` from (`t0`, `x0`), its last stage at `t4`: for
    /// each stage `SetTime`, `SetContinuousStates` and the derivatives; then the FMU is set
    /// to (`t1`, `x1`) and its event indicators read into `z1`.
    #[allow(clippy::too_many_arguments)]
    fn rk4(
        &mut self,
        (t0, x0): (f64, &[f64]),
        h: f64,
        t4: f64,
        t1: f64,
        x1: &mut [f64],
        z1: &mut [f64],
    ) -> Result<(), String> {
        let mid = t0 + 0.5 * h;
        let stages = [(t0, 0.0), (mid, 0.5 * h), (mid, 0.5 * h), (t4, h)];
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

    /// Locates the first crossing in the step from (`t0`, `x0`) to `t1`, whose end
    /// (`x1`, `z1`) is past it: bisection, each trial one RK4 step from `t0`; `x1` and `z1`
    /// left at the bracket's end, past the crossing, whose time is returned.
    fn locate(
        &mut self,
        (t0, x0): (f64, &[f64]),
        t1: f64,
        x1: &mut Vec<f64>,
        z1: &mut Vec<f64>,
    ) -> Result<f64, String> {
        let (mut xm, mut zm) = (x1.clone(), z1.clone());
        let (crossing, location) = (self.options.crossing, self.options.location);
        // the bracket: end times, or lengths from t0
        let (mut lo, mut hi) = match location {
            Location::Time { .. } => (t0, t1),
            Location::Length { .. } => (0.0, t1 - t0),
        };
        loop {
            // the trial's middle, and the length and end of its step from t0
            let (mid, h, end) = match location {
                Location::Time { tolerance } => {
                    let mid = lo + 0.5 * (hi - lo);
                    if hi - lo <= tolerance || mid <= lo || mid >= hi {
                        break;
                    }
                    (mid, mid - t0, mid)
                }
                Location::Length { relative } => {
                    if hi - lo <= relative * t0.abs().max(1.0) {
                        break;
                    }
                    let mid = 0.5 * (lo + hi);
                    (mid, mid, t0 + mid)
                }
            };
            self.rk4((t0, x0), h, end, end, &mut xm, &mut zm)?;
            if crossing.changes(&self.z, &zm).is_empty() {
                lo = mid;
            } else {
                hi = mid;
                std::mem::swap(x1, &mut xm);
                std::mem::swap(z1, &mut zm);
            }
        }
        Ok(match location {
            Location::Time { .. } => hi,
            Location::Length { .. } => t0 + hi,
        })
    }

    /// The FMU asked to stop: `Terminate`, and the message that ends the run.
    pub fn terminate_there(&mut self, why: String) -> String {
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
        let mut event = Event::default();
        let call = I::NAMES.update_discrete_states;
        for iteration in 1.. {
            event = Event::default();
            let r = self.fmu.update_discrete_states(&mut event);
            if event.terminate_simulation && r.is_ok() {
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
            self.passes(
                || format!("{call} ({what}, iteration {iteration}) {}", self.at(self.t)),
                r,
            )?;
            changed |= event.values_of_continuous_states_changed;
            if !event.discrete_states_need_update {
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
        self.next_event_time = event.next_event_time;
        Ok((Iteration::Done, changed))
    }

    /// `EnterEventMode` at the accepted point, for the event `what`.
    pub fn enter_event_mode(&mut self, what: &str) -> Result<(), String> {
        let r = self.fmu.enter_event_mode();
        self.ok_at("EnterEventMode", what, r)
    }

    /// In event mode at the accepted point: the event iteration, `EnterContinuousTimeMode`,
    /// the states again if they changed, the event indicators again; or the stop the FMU
    /// asked for.
    pub fn finish_event(&mut self, what: &str) -> Result<Option<Stop>, String> {
        let (outcome, changed) = self.event_iteration(what)?;
        if let Iteration::Terminate(why) = outcome {
            return Ok(Some(Stop { at: self.t, why }));
        }
        let r = self.fmu.enter_continuous_time_mode();
        self.ok_at("EnterContinuousTimeMode", what, r)?;
        if changed {
            self.stats.state_changes += 1;
            let r = self.fmu.get_continuous_states(&mut self.x);
            self.ok_at("GetContinuousStates", what, r)?;
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
        )?;
        Ok(None)
    }

    /// One RK4 step from the accepted point towards `limit` (or to a time event announced
    /// before it): the step, the location of a state event in it, `CompletedIntegratorStep`
    /// at the point accepted, and the events there.
    pub fn step(&mut self, limit: f64) -> Result<Step, String> {
        let (mut x1, mut z1) = (vec![0.0; self.x.len()], vec![0.0; self.z.len()]);
        // a time event announced up to the limit ends the step there
        let time_event = self.next_event_time.filter(|&te| te <= limit);
        let target = time_event.map_or(limit, |te| te.max(self.t));
        let (t0, x0) = (self.t, self.x.clone());
        if target > t0 {
            let h = target - t0;
            // the last stage at the step's end, or at its start plus its length
            let t4 = match self.options.location {
                Location::Time { .. } => target,
                Location::Length { .. } => t0 + h,
            };
            self.rk4((t0, &x0), h, t4, target, &mut x1, &mut z1)?;
        } else {
            x1.copy_from_slice(&x0);
            z1.copy_from_slice(&self.z);
        }
        let crossing = self.options.crossing;
        let mut accepted = target;
        if !crossing.changes(&self.z, &z1).is_empty() {
            accepted = self.locate((t0, &x0), target, &mut x1, &mut z1)?;
            // the FMU is at the last trial: back to the point accepted
            self.set_point(accepted, &x1)?;
        }
        let which = crossing.changes(&self.z, &z1);
        self.t = accepted;
        self.x.copy_from_slice(&x1);
        self.z.copy_from_slice(&z1);
        self.stats.steps += 1;
        self.stats.state_events += !which.is_empty() as usize;

        let mut step_event = false;
        if self.options.completed_integrator_step {
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
                return Ok(Step::Stopped(Stop { at: self.t, why }));
            }
            self.passes(|| format!("{call} {point}"), r)?;
            step_event = enter;
        }
        let time_event = time_event.is_some() && accepted == target && which.is_empty();
        let mut kinds = Vec::new();
        if !which.is_empty() {
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
            self.events += 1;
            if self.events > MAX_EVENTS_PER_STEP {
                return Err(format!(
                    "more than {MAX_EVENTS_PER_STEP} events {}: the last a {}",
                    self.at(self.t),
                    kinds.join(", ")
                ));
            }
            if time_event {
                self.next_event_time = None;
            }
            let what = kinds.join(", ");
            self.enter_event_mode(&what)?;
            if let Some(stop) = self.finish_event(&what)? {
                return Ok(Step::Stopped(stop));
            }
        }
        Ok(Step::Accepted {
            state_event: !which.is_empty(),
        })
    }

    /// Integrates from the accepted point to `t_end` with RK4 steps of at most `t_end - t`,
    /// handling every event on the way; the FMU ends at (`t_end`, its states), unless it
    /// asked to stop before.
    pub fn integrate_to(&mut self, t_end: f64) -> Result<Option<Stop>, String> {
        self.events = 0;
        while self.t < t_end {
            if let Step::Stopped(stop) = self.step(t_end)? {
                return Ok(Some(stop));
            }
        }
        Ok(None)
    }

    /// Integrates from the accepted point `t0` to `t_end` with RK4 steps of `h` on the grid
    /// t0 + n·h (the last one shortened to land on `t_end`), handling every event on the
    /// way: after a state event, the rest of the grid's step follows.
    pub fn integrate_on_grid(&mut self, t_end: f64, h: f64) -> Result<Option<Stop>, String> {
        let t0 = self.t;
        let mut n = 0u64;
        self.events = 0;
        while self.t < t_end - 1e-12 * t_end.abs().max(1.0) {
            let target = (t0 + (n + 1) as f64 * h).min(t_end);
            match self.step(target)? {
                Step::Stopped(stop) => return Ok(Some(stop)),
                Step::Accepted { state_event: false } => {
                    n += 1;
                    self.events = 0;
                }
                // go on from the event with the rest of the grid's step
                Step::Accepted { state_event: true } => n = ((self.t - t0) / h).floor() as u64,
            }
        }
        Ok(None)
    }
}

/// "state event of event indicator 0" (or "indicators [0, 1]").
fn state_event(which: &[usize]) -> String {
    match which {
        [i] => format!("state event of event indicator {i}"),
        _ => format!("state event of event indicators {which:?}"),
    }
}
