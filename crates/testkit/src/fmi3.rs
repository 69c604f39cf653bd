//! An in-process FMI 3.0 importer for tests, the sibling of [`harness`](crate::harness):
//! drives a mechanism through the very `fmi3*` functions its FMU exports
//! (`fmi3::functions`), Co-Simulation or Model Exchange ([`model_exchange`]), with a logger
//! that records every message.
//!
//! Variables are FMI 3.0's: each has its 1-based place in the model description for value
//! reference (`time`, listed last, 0), an array (see `Mechanism::ARRAYS`) is one variable,
//! read and written whole. By name, the
//! harness also reaches one element of an array (`I_C[1,2]`, or the scalar's own name
//! `I_xy`): reading picks it out of the array, writing sets the array with every place
//! of that scalar changed.
//!
//! ```
//! # mechfmu::mechanism! {
//! #     /// Decay.
//! #     pub struct Decay / DecayValues {
//! #         /// Rate
//! #         k: mechfmu::model::Variable::parameter("1/s", 1.0),
//! #         /// Amount
//! #         y: mechfmu::model::Variable::state("1", 1.0, "y_dot"),
//! #         /// Rate of change
//! #         y_dot: mechfmu::model::Variable::output("1/s"),
//! #     }
//! # }
//! # impl mechfmu::model::Mechanism for Decay {
//! #     const EXPERIMENT: mechfmu::model::Experiment =
//! #         mechfmu::model::Experiment::until(1.0).step(0.1).tolerance(1e-8);
//! #     fn evaluate<S: mechfmu::model::Scalar>(v: &mut DecayValues<S>) { v.y_dot = -v.k * v.y; }
//! # }
//! use mechfmu_testkit::fmi3::Fmi3Harness;
//! let mut fmu = Fmi3Harness::<Decay>::new();
//! fmu.initialize(Some(1e-10), 0.0, &[("k", 2.0)]).unwrap();
//! fmu.step_to(1.0, 0.1).unwrap();
//! assert!((fmu.get("y") - (-2.0f64).exp()).abs() < 1e-9);
//! assert_eq!(fmu.get("time"), 1.0);
//! ```

#![allow(non_upper_case_globals)]

pub mod model_exchange;
mod states;
mod variables;

use crate::harness::{self, Message, MessageLog};
use mechfmu::fmi3::ffi::*;
use mechfmu::fmi3::functions;
use mechfmu::model::{Mechanism, Shapes};
use std::ffi::CString;
use std::marker::PhantomData;

/// The FMI 3.0 logger: records the message in the [`MessageLog`] whose environment `env` is.
///
/// # Safety
/// As [`harness::push`]'s.
pub unsafe extern "C" fn record(
    env: fmi3InstanceEnvironment,
    status: fmi3Status,
    category: fmi3String,
    message: fmi3String,
) {
    // SAFETY: the caller's promise.
    unsafe { harness::push(env, status, category, message) }
}

/// What an instance is instantiated as.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    ModelExchange,
    CoSimulation {
        event_mode_used: bool,
        early_return_allowed: bool,
    },
}

/// Plain Co-Simulation: no event mode, no early return.
pub const CO_SIMULATION: Kind = Kind::CoSimulation {
    event_mode_used: false,
    early_return_allowed: false,
};

/// What `fmi3DoStep` returned.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Step {
    pub status: fmi3Status,
    pub event_handling_needed: bool,
    pub terminate_simulation: bool,
    pub early_return: bool,
    pub last_successful_time: f64,
}

/// `Ok(value)` when `status` is fmi3OK.
pub(crate) fn ok<T>(status: fmi3Status, value: T) -> Result<T, fmi3Status> {
    if status == fmi3OK {
        Ok(value)
    } else {
        Err(status)
    }
}

/// One FMI 3.0 instance of mechanism `M`, driven through its FMI functions.
pub struct Fmi3Harness<M: Mechanism> {
    instance: fmi3Instance,
    log: MessageLog,
    shapes: Shapes,
    time: f64,
    _m: PhantomData<M>,
}

// SAFETY: the instance is owned by this harness alone; instances are Send by design.
unsafe impl<M: Mechanism> Send for Fmi3Harness<M> {}

impl<M: Mechanism> Default for Fmi3Harness<M> {
    fn default() -> Self {
        Self::new()
    }
}

impl<M: Mechanism> Fmi3Harness<M> {
    /// Co-Simulation without event mode or early return, the right token, logging on.
    pub fn new() -> Self {
        Self::of_kind(CO_SIMULATION)
    }

    /// Model Exchange, the right token, logging on.
    pub fn model_exchange() -> Self {
        Self::of_kind(Kind::ModelExchange)
    }

    /// `kind`, the right token, logging on (panics if instantiation fails).
    pub fn of_kind(kind: Kind) -> Self {
        let token = mechfmu::contract::instantiation_token::<M>();
        Self::instantiate(M::NAME, &token, kind)
            .unwrap_or_else(|log| panic!("{}: instantiating {kind:?} failed: {log:?}", M::NAME))
    }

    /// Instantiates with the given arguments; `Err` carries the logged messages.
    pub fn instantiate(name: &str, token: &str, kind: Kind) -> Result<Self, Vec<Message>> {
        // The runtime refuses to instantiate a declaration whose arrays these are not.
        let shapes = Shapes::new(M::VARIABLES, M::ARRAYS)
            .map_err(|e| vec![(fmi3Error, String::new(), e)])?;
        let log = MessageLog::new();
        let name = CString::new(name).unwrap_or_default();
        let token = CString::new(token).unwrap_or_default();
        let (env, logger): (_, fmi3LogMessageCallback) = (log.environment(), Some(record));
        // SAFETY: valid strings, and a logger environment that outlives the instance.
        let instance = unsafe {
            match kind {
                Kind::ModelExchange => functions::fmi3InstantiateModelExchange::<M>(
                    name.as_ptr(),
                    token.as_ptr(),
                    std::ptr::null(),
                    false,
                    true,
                    env,
                    logger,
                ),
                Kind::CoSimulation {
                    event_mode_used,
                    early_return_allowed,
                } => functions::fmi3InstantiateCoSimulation::<M>(
                    name.as_ptr(),
                    token.as_ptr(),
                    std::ptr::null(),
                    false,
                    true,
                    event_mode_used,
                    early_return_allowed,
                    std::ptr::null(),
                    0,
                    env,
                    logger,
                    None,
                ),
            }
        };
        if instance.is_null() {
            return Err(log.messages());
        }
        Ok(Fmi3Harness {
            instance,
            log,
            shapes,
            time: 0.0,
            _m: PhantomData,
        })
    }

    /// The raw instance, for tests of the C boundary.
    pub fn instance(&self) -> fmi3Instance {
        self.instance
    }

    /// The variables as FMI 3.0 sees them.
    pub fn shapes(&self) -> &Shapes {
        &self.shapes
    }

    /// Every message logged so far.
    pub fn messages(&self) -> Vec<Message> {
        self.log.messages()
    }

    /// Whether a message containing `text` was logged.
    pub fn logged(&self, text: &str) -> bool {
        self.messages().iter().any(|(_, _, m)| m.contains(text))
    }

    pub fn enter_initialization_mode(
        &mut self,
        tolerance: Option<f64>,
        start: f64,
        stop: Option<f64>,
    ) -> fmi3Status {
        self.time = start;
        // SAFETY: live instance.
        unsafe {
            functions::fmi3EnterInitializationMode::<M>(
                self.instance,
                tolerance.is_some(),
                tolerance.unwrap_or(0.0),
                start,
                stop.is_some(),
                stop.unwrap_or(0.0),
            )
        }
    }

    pub fn exit_initialization_mode(&mut self) -> fmi3Status {
        // SAFETY: live instance.
        unsafe { functions::fmi3ExitInitializationMode::<M>(self.instance) }
    }

    /// Initialization mode (tolerance, start, no stop time), start values by name (see
    /// [`set`](Self::set)), exit: the usual importer sequence.
    pub fn initialize(
        &mut self,
        tolerance: Option<f64>,
        start: f64,
        values: &[(&str, f64)],
    ) -> Result<(), String> {
        let status = self.enter_initialization_mode(tolerance, start, None);
        self.check(status, "fmi3EnterInitializationMode")?;
        for &(name, value) in values {
            let status = self.set(name, value);
            self.check(status, &format!("setting {name}"))?;
        }
        let status = self.exit_initialization_mode();
        self.check(status, "fmi3ExitInitializationMode")
    }

    fn check(&self, status: fmi3Status, what: &str) -> Result<(), String> {
        ok(status, ()).map_err(|s| format!("{what} returned {s}: {:?}", self.messages()))
    }

    pub fn do_step(&mut self, t: f64, h: f64) -> Step {
        let (mut event, mut terminate, mut early) = (false, false, false);
        let mut last = f64::NAN;
        // SAFETY: live instance, valid out-pointers.
        let status = unsafe {
            functions::fmi3DoStep::<M>(
                self.instance,
                t,
                h,
                true,
                &mut event,
                &mut terminate,
                &mut early,
                &mut last,
            )
        };
        if status <= fmi3Warning {
            self.time = if early { last } else { t + h };
        }
        Step {
            status,
            event_handling_needed: event,
            terminate_simulation: terminate,
            early_return: early,
            last_successful_time: last,
        }
    }

    /// Moves the harness's clock back to `t` (after restoring an FMU state taken there).
    pub fn rewind(&mut self, t: f64) {
        self.time = t;
    }

    /// The communication point the harness has reached.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Steps of size `h` from the current time until `t_end`, as
    /// [`Harness::step_to`](crate::harness::Harness::step_to); an early return is an `Err`.
    pub fn step_to(&mut self, t_end: f64, h: f64) -> Result<(), String> {
        harness::step_to(self.time, t_end, h, |t, size| match self.do_step(t, size) {
            step if step.status <= fmi3Warning && !step.early_return => Ok(()),
            step => Err(format!(
                "fmi3DoStep({t}, {size}) gave {step:?}: {:?}",
                self.messages()
            )),
        })
    }

    pub fn terminate(&mut self) -> fmi3Status {
        // SAFETY: live instance.
        unsafe { functions::fmi3Terminate::<M>(self.instance) }
    }

    pub fn reset(&mut self) -> fmi3Status {
        self.time = 0.0;
        // SAFETY: live instance.
        unsafe { functions::fmi3Reset::<M>(self.instance) }
    }
}

impl<M: Mechanism> Drop for Fmi3Harness<M> {
    fn drop(&mut self) {
        // SAFETY: the instance is live and freed once.
        unsafe { functions::fmi3FreeInstance::<M>(self.instance) }
    }
}
