//! What the importers' Model Exchange driver (`mechfmu_host::model_exchange`) calls,
//! alike in both standards: one trait over [`Instance`] (FMI 2.0) and [`Instance3`] (FMI
//! 3.0), so the same driver integrates either.

use super::{Instance, Instance3};
use crate::ffi::Status;
use mechfmu_host::model_exchange::{CallNames, Event};

/// A Model Exchange instance as an importer's integrator sees it (statuses are the same
/// numbers in both standards).
pub trait ModelExchangeInstance {
    /// The standard's names of the calls, for messages.
    const NAMES: CallNames;
    /// The continuous states and event indicators the modelDescription declares.
    fn counts(&self) -> (usize, usize);
    /// The default experiment's start time.
    fn start_time(&self) -> f64;
    /// The last messages, for error texts.
    fn log_tail(&self) -> String;
    fn set_time(&mut self, t: f64) -> Status;
    fn set_continuous_states(&mut self, x: &[f64]) -> Status;
    fn get_continuous_states(&mut self, x: &mut [f64]) -> Status;
    fn get_derivatives(&mut self, dx: &mut [f64]) -> Status;
    fn get_event_indicators(&mut self, z: &mut [f64]) -> Status;
    /// The status, enterEventMode, terminateSimulation.
    fn completed_integrator_step(&mut self, no_set_prior: bool) -> (Status, bool, bool);
    fn enter_event_mode(&mut self) -> Status;
    fn enter_continuous_time_mode(&mut self) -> Status;
    /// One step of the event iteration (fmi2NewDiscreteStates, fmi3UpdateDiscreteStates):
    /// the status and what it reported.
    fn update_discrete_states(&mut self) -> (Status, Event);
}

impl ModelExchangeInstance for Instance<'_> {
    const NAMES: CallNames = CallNames::FMI2;
    fn counts(&self) -> (usize, usize) {
        (self.fmu.md.nx(), self.fmu.md.number_of_event_indicators)
    }
    fn start_time(&self) -> f64 {
        self.fmu.md.experiment.start
    }
    fn log_tail(&self) -> String {
        Instance::log_tail(self)
    }
    fn set_time(&mut self, t: f64) -> Status {
        Instance::set_time(self, t)
    }
    fn set_continuous_states(&mut self, x: &[f64]) -> Status {
        Instance::set_continuous_states(self, x)
    }
    fn get_continuous_states(&mut self, x: &mut [f64]) -> Status {
        Instance::get_continuous_states(self, x)
    }
    fn get_derivatives(&mut self, dx: &mut [f64]) -> Status {
        Instance::get_derivatives(self, dx)
    }
    fn get_event_indicators(&mut self, z: &mut [f64]) -> Status {
        Instance::get_event_indicators(self, z)
    }
    fn completed_integrator_step(&mut self, no_set_prior: bool) -> (Status, bool, bool) {
        Instance::completed_integrator_step(self, no_set_prior)
    }
    fn enter_event_mode(&mut self) -> Status {
        Instance::enter_event_mode(self)
    }
    fn enter_continuous_time_mode(&mut self) -> Status {
        Instance::enter_continuous_time_mode(self)
    }
    fn update_discrete_states(&mut self) -> (Status, Event) {
        let (s, info) = self.new_discrete_states();
        (s, Event::from(&info))
    }
}

impl ModelExchangeInstance for Instance3<'_> {
    const NAMES: CallNames = CallNames::FMI3;
    fn counts(&self) -> (usize, usize) {
        (self.fmu.md.nx(), self.fmu.md.ni())
    }
    fn start_time(&self) -> f64 {
        self.fmu.md.experiment.start
    }
    fn log_tail(&self) -> String {
        Instance3::log_tail(self)
    }
    fn set_time(&mut self, t: f64) -> Status {
        Instance3::set_time(self, t)
    }
    fn set_continuous_states(&mut self, x: &[f64]) -> Status {
        Instance3::set_continuous_states(self, x)
    }
    fn get_continuous_states(&mut self, x: &mut [f64]) -> Status {
        Instance3::get_continuous_states(self, x)
    }
    fn get_derivatives(&mut self, dx: &mut [f64]) -> Status {
        Instance3::get_derivatives(self, dx)
    }
    fn get_event_indicators(&mut self, z: &mut [f64]) -> Status {
        Instance3::get_event_indicators(self, z)
    }
    fn completed_integrator_step(&mut self, no_set_prior: bool) -> (Status, bool, bool) {
        Instance3::completed_integrator_step(self, no_set_prior)
    }
    fn enter_event_mode(&mut self) -> Status {
        Instance3::enter_event_mode(self)
    }
    fn enter_continuous_time_mode(&mut self) -> Status {
        Instance3::enter_continuous_time_mode(self)
    }
    fn update_discrete_states(&mut self) -> (Status, Event) {
        let (s, d) = Instance3::update_discrete_states(self);
        let event = Event {
            discrete_states_need_update: d.discrete_states_need_update != 0,
            terminate_simulation: d.terminate_simulation != 0,
            values_of_continuous_states_changed: d.values_changed != 0,
            next_event_time: (d.next_event_time_defined != 0).then_some(d.next_event_time),
        };
        (s, event)
    }
}
