//! The importer's Model Exchange driver: a fixed-step classical Runge-Kutta (RK4)
//! integrator that locates the state events by bisection and runs the event iteration
//! there, over any Model Exchange instance of either FMI version ([`Instance`]). The
//! importers of the tests (the test kit's in-process one, the robustness suite's) and of
//! `mechfmu validate` (`tools/fmi-run`, over the `fmi` crate's instances) all drive their
//! instances with it.
//!
//! - [`Instance`]: the calls the driver makes, with their statuses ([`Status`]) and the
//!   names a version gives them ([`CallNames`]);
//! - [`Integration`]: an instance being integrated from an accepted point: one step
//!   ([`Integration::step`]), up to a time ([`Integration::integrate_to`]) or over a grid
//!   of steps ([`Integration::integrate_on_grid`]), with its [`Stats`];
//! - [`Options`]: where importers differ: the rule that makes a change of an indicator a
//!   state event ([`Crossing`]), how the bisection measures its bracket ([`Location`]),
//!   whether a warning ends the run.

mod integration;

pub use integration::{Integration, Stats, Step, Where};

/// The outcome of an FMI call, of either version.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Status {
    Ok,
    /// `fmi2Warning` or `fmi3Warning` (its name).
    Warning(&'static str),
    /// Any other status, named (`fmi3Discard`, ...).
    Fail(String),
}

impl Status {
    /// OK or Warning: the call's outputs are defined.
    pub fn is_ok(&self) -> bool {
        !matches!(self, Status::Fail(_))
    }
}

/// `Ok` for an OK status only; else an error naming the call (`call()`) and the status.
pub fn ok(call: impl FnOnce() -> String, status: impl Into<Status>) -> Result<(), String> {
    match status.into() {
        Status::Ok => Ok(()),
        Status::Warning(name) => Err(format!("{} returned {name}", call())),
        Status::Fail(name) => Err(format!("{} returned {name}", call())),
    }
}

/// The names of a version's functions and flags, for messages.
pub struct CallNames {
    /// `fmi2` or `fmi3`.
    pub prefix: &'static str,
    pub get_derivatives: &'static str,
    pub update_discrete_states: &'static str,
    pub discrete_states_need_update: &'static str,
}

impl CallNames {
    pub const FMI2: CallNames = CallNames {
        prefix: "fmi2",
        get_derivatives: "fmi2GetDerivatives",
        update_discrete_states: "fmi2NewDiscreteStates",
        discrete_states_need_update: "newDiscreteStatesNeeded",
    };
    pub const FMI3: CallNames = CallNames {
        prefix: "fmi3",
        get_derivatives: "fmi3GetContinuousStateDerivatives",
        update_discrete_states: "fmi3UpdateDiscreteStates",
        discrete_states_need_update: "discreteStatesNeedUpdate",
    };
}

/// What one call of the event iteration (`fmi2NewDiscreteStates`,
/// `fmi3UpdateDiscreteStates`) reports.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Event {
    pub discrete_states_need_update: bool,
    pub terminate_simulation: bool,
    pub values_of_continuous_states_changed: bool,
    /// `nextEventTime`, where `nextEventTimeDefined`.
    pub next_event_time: Option<f64>,
}

impl From<&mechfmu::fmi2::ffi::fmi2EventInfo> for Event {
    fn from(info: &mechfmu::fmi2::ffi::fmi2EventInfo) -> Event {
        Event {
            discrete_states_need_update: info.newDiscreteStatesNeeded != 0,
            terminate_simulation: info.terminateSimulation != 0,
            values_of_continuous_states_changed: info.valuesOfContinuousStatesChanged != 0,
            next_event_time: (info.nextEventTimeDefined != 0).then_some(info.nextEventTime),
        }
    }
}

/// What the driver calls on a Model Exchange instance of either version, initialized.
pub trait Instance {
    const NAMES: CallNames;
    fn set_time(&mut self, t: f64) -> Status;
    fn set_continuous_states(&mut self, x: &[f64]) -> Status;
    fn get_derivatives(&mut self, dx: &mut [f64]) -> Status;
    fn get_event_indicators(&mut self, z: &mut [f64]) -> Status;
    /// With `noSetFMUStatePriorToCurrentPoint = true`: the status, `enterEventMode` and
    /// `terminateSimulation` written into `enter` and `terminate`.
    fn completed_integrator_step(&mut self, enter: &mut bool, terminate: &mut bool) -> Status;
    fn enter_event_mode(&mut self) -> Status;
    fn update_discrete_states(&mut self, event: &mut Event) -> Status;
    fn enter_continuous_time_mode(&mut self) -> Status;
    fn get_continuous_states(&mut self, x: &mut [f64]) -> Status;
    fn terminate(&mut self) -> Status;
}

/// Which change of an event indicator between two points is a state event.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Crossing {
    /// A change of domain, `z > 0` or `z <= 0`: the standard's definition of a state event.
    Domain,
    /// From positive to non-positive or from negative to non-negative (FMPy's rule): a zero
    /// at the step's start starts no event, a zero at its end ends one.
    Strict,
}

impl Crossing {
    /// Whether an indicator went from `before` to `after` across zero.
    pub fn crossed(self, before: f64, after: f64) -> bool {
        match self {
            Crossing::Domain => (before > 0.0) != (after > 0.0),
            Crossing::Strict => (before > 0.0 && after <= 0.0) || (before < 0.0 && after >= 0.0),
        }
    }

    /// The indicators that crossed between `before` and `after`.
    pub fn changes(self, before: &[f64], after: &[f64]) -> Vec<usize> {
        (before.iter().zip(after).enumerate())
            .filter(|(_, (a, b))| self.crossed(**a, **b))
            .map(|(i, _)| i)
            .collect()
    }
}

/// How the bisection that locates a state event measures its bracket, which always ends
/// past the crossing (the step is accepted at its end).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Location {
    /// On the trial step's end time, halved (`lo + (hi - lo) / 2`) down to an absolute
    /// width, in seconds.
    Time { tolerance: f64 },
    /// On the trial step's length from the step's start `t`, halved (`(lo + hi) / 2`) down
    /// to a width of `relative · max(|t|, 1)`.
    Length { relative: f64 },
}

/// Where importers differ in driving Model Exchange.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Options {
    pub crossing: Crossing,
    pub location: Location,
    /// Whether `fmi2CompletedIntegratorStep` is called after each step (false where the
    /// FMU declares `completedIntegratorStepNotNeeded`).
    pub completed_integrator_step: bool,
    /// Whether a Warning of `CompletedIntegratorStep` and of the event iteration lets the
    /// run go on (else it ends it, as any status but OK).
    pub warnings_pass: bool,
}

/// The most events handled on the way to one target time before the run is declared stuck
/// (an event indicator that keeps changing sign: chattering), and the most calls of one
/// event iteration.
pub const MAX_EVENTS_PER_STEP: usize = 100;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_state_event_is_a_change_of_domain_z_positive_or_not() {
        let changes = |a: &[f64], b: &[f64]| Crossing::Domain.changes(a, b);
        assert_eq!(changes(&[1.0, -1.0], &[0.5, -2.0]), Vec::<usize>::new());
        assert_eq!(changes(&[1.0, -1.0], &[-0.5, -2.0]), [0]);
        assert_eq!(changes(&[1.0, -1.0], &[-0.5, 2.0]), [0, 1]);
        // z = 0 belongs to z <= 0
        assert_eq!(changes(&[1e-300], &[0.0]), [0]);
        assert_eq!(changes(&[0.0], &[-1.0]), Vec::<usize>::new());
        assert_eq!(changes(&[-0.0], &[1e-300]), [0]);
    }

    #[test]
    fn a_strict_crossing_leaves_zero_by_neither_side() {
        assert!(Crossing::Strict.crossed(1.0, 0.0));
        assert!(Crossing::Strict.crossed(-1.0, 0.0));
        assert!(!Crossing::Strict.crossed(0.0, 1.0));
        assert!(!Crossing::Strict.crossed(0.0, -1.0));
        assert!(!Crossing::Strict.crossed(1.0, 2.0));
    }

    #[test]
    fn statuses_name_the_call() {
        assert!(Status::Warning("fmi3Warning").is_ok());
        assert_eq!(
            ok(|| "fmi3DoStep".into(), Status::Warning("fmi3Warning")),
            Err("fmi3DoStep returned fmi3Warning".into())
        );
        assert!(!Status::Fail("fmi2Discard".into()).is_ok());
        assert_eq!(
            ok(|| "fmi2DoStep".into(), Status::Fail("fmi2Discard".into())),
            Err("fmi2DoStep returned fmi2Discard".into())
        );
    }
}
