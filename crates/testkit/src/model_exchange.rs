//! An in-process Model Exchange importer for tests: an instance instantiated as
//! `fmi2ModelExchange`, driven through the very functions the FMU exports, and integrated
//! by the importers' one Model Exchange driver (`mechfmu_host::model_exchange`: fixed-step
//! classical Runge–Kutta that locates the crossings of the event indicators by bisection,
//! stopping just past each, as CVODE does, and runs the event iteration there), as an
//! importer's solver would.

#![allow(non_upper_case_globals)]

use crate::harness::{Harness, Message};
use mechfmu::fmi2::ffi::*;
use mechfmu::fmi2::functions;
use mechfmu::model::Mechanism;
use mechfmu_host::model_exchange::{
    CallNames, Crossing, Event, Instance, Integration, Location, Options, Status, Where,
};

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

    /// Integrates from the current time to `t_end` with RK4 steps of `h` on the grid from
    /// there (the last one shortened to land on `t_end`), under the importers' one Model
    /// Exchange driver (`mechfmu_host::model_exchange`): the crossings of the event
    /// indicators located by bisection (FMPy's rule of a crossing, stopping just past each,
    /// as CVODE does), the event iteration there, step events handled.
    pub fn integrate(&mut self, t_end: f64, h: f64) -> Result<Run, String> {
        let t = self.time;
        let options = Options {
            crossing: Crossing::Strict,
            location: Location::Length { relative: 1e-13 },
            completed_integrator_step: true,
            warnings_pass: true,
        };
        let sizes = (M::STATES.len(), M::EVENT_INDICATORS.len());
        let mut me = Integration::new(&mut *self, sizes, options);
        me.at = Where::Free;
        let run = me.resume(t).and_then(|()| me.integrate_on_grid(t_end, h));
        let stats = me.stats;
        let stop = run.map_err(|e| format!("{e}: {:?}", self.messages()))?;
        Ok(Run {
            terminated_at: stop.map(|s| s.at),
            state_events: stats.state_events,
            step_events: stats.step_events,
        })
    }
}

/// An `fmi2Status` as the driver's.
fn status(s: fmi2Status) -> Status {
    match s {
        fmi2OK => Status::Ok,
        fmi2Warning => Status::Warning("fmi2Warning"),
        fmi2Discard => Status::Fail("fmi2Discard".into()),
        fmi2Error => Status::Fail("fmi2Error".into()),
        fmi2Fatal => Status::Fail("fmi2Fatal".into()),
        fmi2Pending => Status::Fail("fmi2Pending".into()),
        s => Status::Fail(format!("status {s}")),
    }
}

impl<M: Mechanism> Instance for &mut ModelExchange<M> {
    const NAMES: CallNames = CallNames::FMI2;

    fn set_time(&mut self, t: f64) -> Status {
        status(ModelExchange::set_time(self, t))
    }

    fn set_continuous_states(&mut self, x: &[f64]) -> Status {
        status(self.set_states(x))
    }

    fn get_derivatives(&mut self, dx: &mut [f64]) -> Status {
        status(self.derivatives_into(dx))
    }

    fn get_event_indicators(&mut self, z: &mut [f64]) -> Status {
        // SAFETY: live component, an array of the given length.
        status(unsafe { functions::fmi2GetEventIndicators::<M>(self.c(), z.as_mut_ptr(), z.len()) })
    }

    fn completed_integrator_step(&mut self, enter: &mut bool, terminate: &mut bool) -> Status {
        let (s, e, t) = ModelExchange::completed_integrator_step(self);
        (*enter, *terminate) = (e, t);
        status(s)
    }

    fn enter_event_mode(&mut self) -> Status {
        status(ModelExchange::enter_event_mode(self))
    }

    fn update_discrete_states(&mut self, event: &mut Event) -> Status {
        let (s, info) = self.new_discrete_states();
        *event = Event::from(&info);
        status(s)
    }

    fn enter_continuous_time_mode(&mut self) -> Status {
        status(ModelExchange::enter_continuous_time_mode(self))
    }

    fn get_continuous_states(&mut self, x: &mut [f64]) -> Status {
        // SAFETY: live component, an array of the given length.
        status(unsafe {
            functions::fmi2GetContinuousStates::<M>(self.c(), x.as_mut_ptr(), x.len())
        })
    }

    fn terminate(&mut self) -> Status {
        status(self.fmu.terminate())
    }
}
