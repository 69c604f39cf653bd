//! An in-process Model Exchange importer for tests: an instance instantiated as
//! `fmi2ModelExchange`, driven through the very functions the FMU exports, and a
//! fixed-step classical Runge–Kutta integrator of its own that locates the crossings of the
//! event indicators (by bisection, stopping just past each, as CVODE does) and runs the
//! event iteration there, as an importer's solver would.

#![allow(non_upper_case_globals)]

use crate::harness::{Harness, Message};
use mechfmu::fmi2::ffi::*;
use mechfmu::fmi2::functions;
use mechfmu::model::Mechanism;

/// One Model Exchange instance of mechanism `M`.
pub struct ModelExchange<M: Mechanism> {
    /// The instance, for the calls both interface types share (`get`, `set`, FMU states).
    pub fmu: Harness<M>,
    time: f64,
}

/// How an integration ended.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Run {
    /// The time the FMU asked to stop at (`terminateSimulation`), if it did.
    pub terminated_at: Option<f64>,
    /// State events (indicator crossings) located and handled.
    pub state_events: usize,
    /// Step events (`enterEventMode` from `fmi2CompletedIntegratorStep`).
    pub step_events: usize,
}

/// Whether an indicator went from `before` to `after` across zero (FMPy's rule).
fn crossed(before: f64, after: f64) -> bool {
    (before > 0.0 && after <= 0.0) || (before < 0.0 && after >= 0.0)
}

impl<M: Mechanism> Default for ModelExchange<M> {
    fn default() -> Self {
        Self::new()
    }
}

impl<M: Mechanism> ModelExchange<M> {
    /// Instantiates as Model Exchange with the right GUID, logging on.
    pub fn new() -> Self {
        let fmu = Harness::instantiate(M::NAME, fmi2ModelExchange, &mechfmu::contract::guid::<M>())
            .unwrap_or_else(|log| panic!("fmi2Instantiate(fmi2ModelExchange) failed: {log:?}"));
        ModelExchange { fmu, time: 0.0 }
    }

    fn c(&self) -> fmi2Component {
        self.fmu.component()
    }

    /// Every message logged so far.
    pub fn messages(&self) -> Vec<Message> {
        self.fmu.messages()
    }

    /// The time of the point the instance was last given.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Setup, start values, initialization, the event iteration, continuous-time mode: the
    /// usual importer sequence.
    pub fn initialize(
        &mut self,
        tolerance: Option<f64>,
        start: f64,
        values: &[(&str, f64)],
    ) -> Result<(), String> {
        self.fmu.initialize(tolerance, start, values)?;
        self.time = start;
        let (status, info) = self.new_discrete_states();
        if status > fmi2Warning || info.terminateSimulation != 0 {
            return Err(format!(
                "initial event iteration: status {status}, {info:?}: {:?}",
                self.messages()
            ));
        }
        match self.enter_continuous_time_mode() {
            fmi2OK => Ok(()),
            s => Err(format!("fmi2EnterContinuousTimeMode returned {s}")),
        }
    }

    pub fn set_time(&mut self, t: f64) -> fmi2Status {
        self.time = t;
        // SAFETY: live component.
        unsafe { functions::fmi2SetTime::<M>(self.c(), t) }
    }

    pub fn set_states(&mut self, x: &[f64]) -> fmi2Status {
        // SAFETY: live component, an array of the given length.
        unsafe { functions::fmi2SetContinuousStates::<M>(self.c(), x.as_ptr(), x.len()) }
    }

    pub fn states(&mut self) -> Result<Vec<f64>, fmi2Status> {
        let mut x = vec![f64::NAN; M::STATES.len()];
        // SAFETY: live component, an array of the given length.
        match unsafe { functions::fmi2GetContinuousStates::<M>(self.c(), x.as_mut_ptr(), x.len()) }
        {
            fmi2OK => Ok(x),
            s => Err(s),
        }
    }

    pub fn derivatives(&mut self) -> Result<Vec<f64>, fmi2Status> {
        let mut dx = vec![f64::NAN; M::STATES.len()];
        // SAFETY: live component, an array of the given length.
        match unsafe { functions::fmi2GetDerivatives::<M>(self.c(), dx.as_mut_ptr(), dx.len()) } {
            fmi2OK => Ok(dx),
            s => Err(s),
        }
    }

    /// The derivatives into `dx` (one per state), without allocating: for counting the
    /// instructions of an evaluation.
    pub fn derivatives_into(&mut self, dx: &mut [f64]) -> fmi2Status {
        // SAFETY: live component, an array of the given length.
        unsafe { functions::fmi2GetDerivatives::<M>(self.c(), dx.as_mut_ptr(), dx.len()) }
    }

    pub fn event_indicators(&mut self) -> Result<Vec<f64>, fmi2Status> {
        let mut z = vec![f64::NAN; M::EVENT_INDICATORS.len()];
        // SAFETY: live component, an array of the given length.
        match unsafe { functions::fmi2GetEventIndicators::<M>(self.c(), z.as_mut_ptr(), z.len()) } {
            fmi2OK => Ok(z),
            s => Err(s),
        }
    }

    pub fn nominals(&mut self) -> Result<Vec<f64>, fmi2Status> {
        let mut n = vec![f64::NAN; M::STATES.len()];
        // SAFETY: live component, an array of the given length.
        match unsafe {
            functions::fmi2GetNominalsOfContinuousStates::<M>(self.c(), n.as_mut_ptr(), n.len())
        } {
            fmi2OK => Ok(n),
            s => Err(s),
        }
    }

    pub fn enter_event_mode(&mut self) -> fmi2Status {
        // SAFETY: live component.
        unsafe { functions::fmi2EnterEventMode::<M>(self.c()) }
    }

    pub fn new_discrete_states(&mut self) -> (fmi2Status, fmi2EventInfo) {
        let mut info = fmi2EventInfo::default();
        // SAFETY: live component, a valid out-pointer.
        let status = unsafe { functions::fmi2NewDiscreteStates::<M>(self.c(), &mut info) };
        (status, info)
    }

    pub fn enter_continuous_time_mode(&mut self) -> fmi2Status {
        // SAFETY: live component.
        unsafe { functions::fmi2EnterContinuousTimeMode::<M>(self.c()) }
    }

    /// `(status, enterEventMode, terminateSimulation)`.
    pub fn completed_integrator_step(&mut self) -> (fmi2Status, bool, bool) {
        let (mut enter, mut terminate) = (fmi2False, fmi2False);
        // SAFETY: live component, valid out-pointers.
        let status = unsafe {
            functions::fmi2CompletedIntegratorStep::<M>(
                self.c(),
                fmi2True,
                &mut enter,
                &mut terminate,
            )
        };
        (status, enter != 0, terminate != 0)
    }

    /// The derivatives at (t, x).
    fn rhs(&mut self, t: f64, x: &[f64]) -> Result<Vec<f64>, String> {
        let statuses = [self.set_time(t), self.set_states(x)];
        if let Some(s) = statuses.iter().find(|&&s| s != fmi2OK) {
            return Err(format!(
                "setting the point ({t}, {x:?}) returned {s}: {:?}",
                self.messages()
            ));
        }
        self.derivatives().map_err(|s| {
            format!(
                "fmi2GetDerivatives at t = {t} returned {s}: {:?}",
                self.messages()
            )
        })
    }

    /// One classical Runge–Kutta step from (t, x) of size h.
    pub fn rk4(&mut self, t: f64, x: &[f64], h: f64) -> Result<Vec<f64>, String> {
        let along = |x: &[f64], k: &[f64], a: f64| -> Vec<f64> {
            x.iter().zip(k).map(|(x, k)| x + a * k).collect()
        };
        let k1 = self.rhs(t, x)?;
        let k2 = self.rhs(t + h / 2.0, &along(x, &k1, h / 2.0))?;
        let k3 = self.rhs(t + h / 2.0, &along(x, &k2, h / 2.0))?;
        let k4 = self.rhs(t + h, &along(x, &k3, h))?;
        Ok((0..x.len())
            .map(|i| x[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]))
            .collect())
    }

    /// The indicators at (t, x).
    fn indicators_at(&mut self, t: f64, x: &[f64]) -> Result<Vec<f64>, String> {
        self.set_time(t);
        self.set_states(x);
        self.event_indicators().map_err(|s| {
            format!(
                "fmi2GetEventIndicators at t = {t} returned {s}: {:?}",
                self.messages()
            )
        })
    }

    /// The event iteration at the current point; `Some(time)` if the FMU asks to stop.
    fn handle_event(&mut self) -> Result<Option<f64>, String> {
        let status = self.enter_event_mode();
        if status != fmi2OK {
            return Err(format!("fmi2EnterEventMode returned {status}"));
        }
        loop {
            let (status, info) = self.new_discrete_states();
            if status > fmi2Warning {
                return Err(format!(
                    "fmi2NewDiscreteStates returned {status}: {:?}",
                    self.messages()
                ));
            }
            if info.terminateSimulation != 0 {
                return Ok(Some(self.time));
            }
            if info.newDiscreteStatesNeeded == 0 {
                break;
            }
        }
        match self.enter_continuous_time_mode() {
            fmi2OK => Ok(None),
            s => Err(format!("fmi2EnterContinuousTimeMode returned {s}")),
        }
    }

    /// Integrates from the current time to `t_end` with RK4 steps of `h` (the last one
    /// shortened to land on `t_end`), handling state and step events.
    pub fn integrate(&mut self, t_end: f64, h: f64) -> Result<Run, String> {
        let mut run = Run::default();
        let mut t = self.time;
        let mut x = self
            .states()
            .map_err(|s| format!("fmi2GetContinuousStates returned {s}"))?;
        let mut z = self.indicators_at(t, &x)?;
        let t0 = t;
        let mut n = 0u64;
        while t < t_end - 1e-12 * t_end.abs().max(1.0) {
            let t_next = (t0 + (n + 1) as f64 * h).min(t_end);
            let mut x_next = self.rk4(t, &x, t_next - t)?;
            let mut z_next = self.indicators_at(t_next, &x_next)?;
            let mut t_reached = t_next;
            let state_event = z.iter().zip(&z_next).any(|(&a, &b)| crossed(a, b));
            if state_event {
                // Bisection on the step's length, keeping the end past the crossing.
                let (mut lo, mut hi) = (0.0, t_next - t);
                while hi - lo > 1e-13 * t.abs().max(1.0) {
                    let mid = 0.5 * (lo + hi);
                    let x_mid = self.rk4(t, &x, mid)?;
                    let z_mid = self.indicators_at(t + mid, &x_mid)?;
                    if z.iter().zip(&z_mid).any(|(&a, &b)| crossed(a, b)) {
                        (hi, x_next, z_next) = (mid, x_mid, z_mid);
                    } else {
                        lo = mid;
                    }
                }
                t_reached = t + hi;
                self.set_time(t_reached);
                self.set_states(&x_next);
            } else {
                n += 1;
            }
            run.state_events += state_event as usize;
            let (status, step_event, terminate) = self.completed_integrator_step();
            if status > fmi2Warning {
                return Err(format!(
                    "fmi2CompletedIntegratorStep returned {status}: {:?}",
                    self.messages()
                ));
            }
            if terminate {
                run.terminated_at = Some(t_reached);
                return Ok(run);
            }
            (t, x, z) = (t_reached, x_next, z_next);
            if state_event || step_event {
                run.step_events += step_event as usize;
                if let Some(time) = self.handle_event()? {
                    run.terminated_at = Some(time);
                    return Ok(run);
                }
                x = self
                    .states()
                    .map_err(|s| format!("fmi2GetContinuousStates returned {s}"))?;
                z = self.indicators_at(t, &x)?;
                if state_event {
                    // Go on from the event with the remainder of the regular step.
                    n = ((t - t0) / h).floor() as u64;
                }
            }
        }
        Ok(run)
    }
}
