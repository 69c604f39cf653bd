//! An FMU instance: a simulation, the importer's logger, and where it is in the state
//! machine.

use super::ffi::*;
use super::fmu_state::{FmuState, STATE_MAGIC};
use super::logger::Logger;
use super::state::{Interface, ModelState};
use crate::model::{Layout, Mechanism};
use crate::simulation::Simulation;

/// Marks live instances, so a stale or foreign pointer is refused rather than used.
pub(crate) const MAGIC: u64 = 0x6d65_6368_666d_7532; // "mechfmu2"

pub struct Instance<M: Mechanism> {
    pub(crate) magic: u64,
    pub logger: Logger,
    /// Model Exchange or Co-Simulation, as instantiated.
    pub interface: Interface,
    pub state: ModelState,
    pub sim: Simulation<M>,
    pub stop_time: Option<f64>,
    /// The time of the last communication point reached (after a discarded step, the last
    /// valid time).
    pub last_successful_time: f64,
    /// The model asked to stop (a discarded step): `fmi2Terminated` status.
    pub terminated: bool,
    pub last_step_status: fmi2Status,
}

impl<M: Mechanism> Instance<M> {
    pub fn new(logger: Logger, layout: Layout, interface: Interface) -> Self {
        Instance {
            magic: MAGIC,
            logger,
            interface,
            state: ModelState::Instantiated,
            sim: Simulation::new(layout),
            stop_time: None,
            last_successful_time: 0.0,
            terminated: false,
            last_step_status: fmi2OK,
        }
    }

    /// Back to the state right after `fmi2Instantiate`.
    pub fn reset(&mut self) {
        self.state = ModelState::Instantiated;
        self.sim.reset();
        self.stop_time = None;
        self.last_successful_time = 0.0;
        self.terminated = false;
        self.last_step_status = fmi2OK;
    }
}

impl<M: Mechanism> Instance<M> {
    /// Captures the instance for `fmi2GetFMUstate`.
    pub fn save(&self) -> FmuState {
        FmuState {
            magic: STATE_MAGIC,
            sim: self.sim.save(),
            model_state: self.state,
            stop_time: self.stop_time,
            last_successful_time: self.last_successful_time,
            terminated: self.terminated,
            last_step_status: self.last_step_status,
        }
    }

    /// Restores a captured state (`fmi2SetFMUstate`); refuses one saved in a state of the
    /// other interface type's machine.
    pub fn restore(&mut self, saved: &FmuState) -> Result<(), String> {
        if let Some(other) = saved
            .model_state
            .interface()
            .filter(|&i| i != self.interface)
        {
            return Err(format!(
                "the FMU state was saved by a {} instance ({}); this instance is {}",
                other.name(),
                saved.model_state.name(),
                self.interface.name()
            ));
        }
        self.sim.restore(&saved.sim)?;
        self.state = saved.model_state;
        self.stop_time = saved.stop_time;
        self.last_successful_time = saved.last_successful_time;
        self.terminated = saved.terminated;
        self.last_step_status = saved.last_step_status;
        Ok(())
    }
}
