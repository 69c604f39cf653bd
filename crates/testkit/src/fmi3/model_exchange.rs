//! The calls of FMI 3.0's Model Exchange, of event mode (both interface types) and of step
//! mode, on an [`Fmi3Harness`].

use super::{ok, Fmi3Harness};
use mechfmu::fmi3::ffi::*;
use mechfmu::fmi3::functions;
use mechfmu::model::Mechanism;

/// What `fmi3UpdateDiscreteStates` returned through its out arguments.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct DiscreteStates {
    pub discrete_states_need_update: bool,
    pub terminate_simulation: bool,
    pub nominals_of_continuous_states_changed: bool,
    pub values_of_continuous_states_changed: bool,
    pub next_event_time_defined: bool,
    pub next_event_time: f64,
}

/// The getters of one array of the Model Exchange values (states, derivatives, event
/// indicators, nominals).
type ArrayGetter = unsafe extern "C" fn(fmi3Instance, *mut fmi3Float64, usize) -> fmi3Status;

impl<M: Mechanism> Fmi3Harness<M> {
    pub fn set_time(&mut self, t: f64) -> fmi3Status {
        self.time = t;
        // SAFETY: live instance.
        unsafe { functions::fmi3SetTime::<M>(self.instance, t) }
    }

    pub fn set_continuous_states(&mut self, x: &[f64]) -> fmi3Status {
        // SAFETY: live instance, an array of the given length.
        unsafe { functions::fmi3SetContinuousStates::<M>(self.instance, x.as_ptr(), x.len()) }
    }

    pub fn continuous_states(&mut self) -> Result<Vec<f64>, fmi3Status> {
        self.array(functions::fmi3GetContinuousStates::<M>, M::STATES.len())
    }

    pub fn derivatives(&mut self) -> Result<Vec<f64>, fmi3Status> {
        self.array(
            functions::fmi3GetContinuousStateDerivatives::<M>,
            M::STATES.len(),
        )
    }

    pub fn event_indicators(&mut self) -> Result<Vec<f64>, fmi3Status> {
        self.array(
            functions::fmi3GetEventIndicators::<M>,
            M::EVENT_INDICATORS.len(),
        )
    }

    pub fn nominals(&mut self) -> Result<Vec<f64>, fmi3Status> {
        self.array(
            functions::fmi3GetNominalsOfContinuousStates::<M>,
            M::STATES.len(),
        )
    }

    /// The `len` values a getter of one array fills in.
    fn array(&mut self, getter: ArrayGetter, len: usize) -> Result<Vec<f64>, fmi3Status> {
        let mut values = vec![f64::NAN; len];
        // SAFETY: live instance, an array of the given length.
        let status = unsafe { getter(self.instance, values.as_mut_ptr(), values.len()) };
        ok(status, values)
    }

    pub fn number_of_continuous_states(&mut self) -> Result<usize, fmi3Status> {
        let mut n = usize::MAX;
        // SAFETY: live instance, a valid out-pointer.
        let status =
            unsafe { functions::fmi3GetNumberOfContinuousStates::<M>(self.instance, &mut n) };
        ok(status, n)
    }

    pub fn number_of_event_indicators(&mut self) -> Result<usize, fmi3Status> {
        let mut n = usize::MAX;
        // SAFETY: live instance, a valid out-pointer.
        let status =
            unsafe { functions::fmi3GetNumberOfEventIndicators::<M>(self.instance, &mut n) };
        ok(status, n)
    }

    pub fn enter_event_mode(&mut self) -> fmi3Status {
        // SAFETY: live instance.
        unsafe { functions::fmi3EnterEventMode::<M>(self.instance) }
    }

    pub fn update_discrete_states(&mut self) -> (fmi3Status, DiscreteStates) {
        let mut d = DiscreteStates {
            next_event_time: f64::NAN,
            ..DiscreteStates::default()
        };
        // SAFETY: live instance, valid out-pointers.
        let status = unsafe {
            functions::fmi3UpdateDiscreteStates::<M>(
                self.instance,
                &mut d.discrete_states_need_update,
                &mut d.terminate_simulation,
                &mut d.nominals_of_continuous_states_changed,
                &mut d.values_of_continuous_states_changed,
                &mut d.next_event_time_defined,
                &mut d.next_event_time,
            )
        };
        (status, d)
    }

    pub fn enter_continuous_time_mode(&mut self) -> fmi3Status {
        // SAFETY: live instance.
        unsafe { functions::fmi3EnterContinuousTimeMode::<M>(self.instance) }
    }

    pub fn enter_step_mode(&mut self) -> fmi3Status {
        // SAFETY: live instance.
        unsafe { functions::fmi3EnterStepMode::<M>(self.instance) }
    }

    /// `(status, enterEventMode, terminateSimulation)`.
    pub fn completed_integrator_step(&mut self) -> (fmi3Status, bool, bool) {
        let (mut enter, mut terminate) = (false, false);
        // SAFETY: live instance, valid out-pointers.
        let status = unsafe {
            functions::fmi3CompletedIntegratorStep::<M>(
                self.instance,
                true,
                &mut enter,
                &mut terminate,
            )
        };
        (status, enter, terminate)
    }

    /// Initialization as [`initialize`](Self::initialize), then the event iteration and
    /// continuous-time mode: a Model Exchange instance ready for an importer's solver.
    pub fn initialize_model_exchange(
        &mut self,
        tolerance: Option<f64>,
        start: f64,
        values: &[(&str, f64)],
    ) -> Result<(), String> {
        self.initialize(tolerance, start, values)?;
        let (status, update) = self.update_discrete_states();
        if status > fmi3Warning || update.terminate_simulation {
            return Err(format!(
                "initial event iteration: status {status}, {update:?}: {:?}",
                self.messages()
            ));
        }
        let status = self.enter_continuous_time_mode();
        self.check(status, "fmi3EnterContinuousTimeMode")
    }
}
