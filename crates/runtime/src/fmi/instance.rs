//! An FMU instance: a simulation, the importer's logger, and where it is in the state
//! machine.

use super::fmu_state::{FmuState, STATE_MAGIC};
use super::logger::Logger;
use super::machine::{Interface, ModelState};
use super::{Status, Version, OK};
use crate::model::{Layout, Mechanism, Shapes};
use crate::simulation::Simulation;

/// Marks live instances of each standard, so a stale or foreign pointer (or an instance of
/// the other standard) is refused rather than used.
pub(crate) const fn magic(version: Version) -> u64 {
    match version {
        Version::Fmi2 => 0x6d65_6368_666d_7532, // "mechfmu2"
        Version::Fmi3 => 0x6d65_6368_666d_7533, // "mechfmu3"
    }
}

pub struct Instance<M: Mechanism> {
    pub(crate) magic: u64,
    pub version: Version,
    pub logger: Logger,
    /// Model Exchange or Co-Simulation, as instantiated.
    pub interface: Interface,
    pub state: ModelState,
    pub sim: Simulation<M>,
    pub stop_time: Option<f64>,
    /// The time of the last communication point reached (after a discarded step, the last
    /// valid time).
    pub last_successful_time: f64,
    /// The model asked to stop (a discarded or early-returned step, a Model Exchange
    /// `terminateSimulation`): FMI 2.0's `fmi2Terminated` status.
    pub terminated: bool,
    pub last_step_status: Status,
    /// FMI 3.0 Co-Simulation: the importer handles events in event mode
    /// (`eventModeUsed`), and lets `fmi3DoStep` return early at one (`earlyReturnAllowed`).
    pub event_mode_used: bool,
    pub early_return_allowed: bool,
    /// FMI 3.0: its variables (arrays among them), by its value references.
    pub shapes: Option<Box<Shapes>>,
    /// Scalar value references of a call, kept so that getting and setting allocate once.
    pub scratch: Vec<u32>,
}

impl<M: Mechanism> Instance<M> {
    pub fn new(version: Version, logger: Logger, layout: Layout, interface: Interface) -> Self {
        Instance {
            magic: magic(version),
            version,
            logger,
            interface,
            state: ModelState::Instantiated,
            sim: Simulation::new(layout),
            stop_time: None,
            last_successful_time: 0.0,
            terminated: false,
            last_step_status: OK,
            event_mode_used: false,
            early_return_allowed: false,
            shapes: None,
            scratch: Vec::new(),
        }
    }

    /// Back to the state right after instantiation.
    pub fn reset(&mut self) {
        self.state = ModelState::Instantiated;
        self.sim.reset();
        self.stop_time = None;
        self.last_successful_time = 0.0;
        self.terminated = false;
        self.last_step_status = OK;
    }
}

impl<M: Mechanism> Instance<M> {
    /// Captures the instance (`fmi2GetFMUstate`, `fmi3GetFMUState`).
    pub fn save(&self) -> FmuState {
        FmuState {
            magic: STATE_MAGIC,
            version: self.version,
            interface: self.interface,
            sim: self.sim.save(),
            model_state: self.state,
            stop_time: self.stop_time,
            last_successful_time: self.last_successful_time,
            terminated: self.terminated,
            last_step_status: self.last_step_status,
        }
    }

    /// Restores a captured state (`fmi2SetFMUstate`, `fmi3SetFMUState`); refuses one saved
    /// by an instance of the other standard or interface type (its machine's states are not
    /// this one's), and one in a state this instance cannot be in (event mode without
    /// `eventModeUsed`).
    pub fn restore(&mut self, saved: &FmuState) -> Result<(), String> {
        if saved.version != self.version {
            return Err(format!(
                "the FMU state was saved by an {} instance; this instance is {}",
                saved.version.name(),
                self.version.name()
            ));
        }
        if saved.interface != self.interface {
            return Err(format!(
                "the FMU state was saved by a {} instance ({}); this instance is {}",
                saved.interface.name(),
                saved.model_state.name(),
                self.interface.name()
            ));
        }
        // Only an importer that said it uses event mode handles a Co-Simulation instance
        // there (`eventModeUsed`, which the state does not carry).
        if saved.model_state == ModelState::EventMode
            && self.interface == Interface::CoSimulation
            && !self.event_mode_used
        {
            return Err(
                "the FMU state was saved in event mode, which this Co-Simulation instance (eventModeUsed = false) has not"
                    .into(),
            );
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
