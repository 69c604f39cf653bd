//! A well-behaved FMI 2.0 importer's instance.

use super::{callbacks, Message, Sink};
use crate::ffi::*;
use crate::fmu::Fmu;
use std::ffi::CString;

/// A well-behaved importer's instance: instantiate with the right GUID, free on drop.
/// [`Instance::new`] makes a Co-Simulation instance, [`Instance::new_me`] a Model Exchange
/// one.
pub struct Instance<'a> {
    pub fmu: &'a Fmu,
    pub c: Component,
    pub sink: Box<Sink>,
    _callbacks: Box<CallbackFunctions>,
    _name: CString,
    _guid: CString,
}

// SAFETY: an instance is used by one thread at a time (FMI allows that; the FMU has no
// global state), and the sink is Sync.
unsafe impl Send for Instance<'_> {}

impl<'a> Instance<'a> {
    pub fn new(fmu: &'a Fmu, name: &str) -> Result<Instance<'a>, Vec<Message>> {
        Self::new_as(fmu, name, CO_SIMULATION)
    }

    /// A Model Exchange instance.
    pub fn new_me(fmu: &'a Fmu, name: &str) -> Result<Instance<'a>, Vec<Message>> {
        Self::new_as(fmu, name, MODEL_EXCHANGE)
    }

    pub fn new_as(
        fmu: &'a Fmu,
        name: &str,
        fmu_type: FmuType,
    ) -> Result<Instance<'a>, Vec<Message>> {
        let sink = Box::<Sink>::default();
        let callbacks = Box::new(callbacks(&sink));
        let name = CString::new(name).expect("instance name");
        let guid = CString::new(fmu.md.guid.as_str()).expect("GUID");
        let resources = CString::new("file:///nonexistent/resources").unwrap();
        // SAFETY: valid strings and callbacks that outlive the instance.
        let c = unsafe {
            (fmu.api.instantiate)(
                name.as_ptr(),
                fmu_type,
                guid.as_ptr(),
                resources.as_ptr(),
                &*callbacks,
                0,
                0,
            )
        };
        if c.is_null() {
            return Err(sink.all());
        }
        Ok(Instance {
            fmu,
            c,
            sink,
            _callbacks: callbacks,
            _name: name,
            _guid: guid,
        })
    }

    pub fn messages(&self) -> Vec<Message> {
        self.sink.all()
    }

    /// The last messages, for assertion texts.
    pub fn log_tail(&self) -> String {
        let m = self.sink.all();
        m[m.len().saturating_sub(5)..]
            .iter()
            .map(|m| format!("[{}] {}", status_name(m.status), m.text))
            .collect::<Vec<_>>()
            .join("\n")
    }

    pub fn setup(&mut self, tolerance: Option<f64>, start: f64, stop: Option<f64>) -> Status {
        // SAFETY: live instance.
        unsafe {
            (self.fmu.api.setup_experiment)(
                self.c,
                tolerance.is_some() as Boolean,
                tolerance.unwrap_or(0.0),
                start,
                stop.is_some() as Boolean,
                stop.unwrap_or(0.0),
            )
        }
    }

    pub fn enter_init(&mut self) -> Status {
        // SAFETY: live instance.
        unsafe { (self.fmu.api.enter_initialization_mode)(self.c) }
    }

    pub fn exit_init(&mut self) -> Status {
        // SAFETY: live instance.
        unsafe { (self.fmu.api.exit_initialization_mode)(self.c) }
    }

    /// Setup at the default experiment's start and tolerance, start values, initialization.
    pub fn initialize(&mut self, values: &[(u32, f64)]) -> Result<(), String> {
        let e = self.fmu.md.experiment;
        for (what, s) in [
            (
                "fmi2SetupExperiment",
                self.setup(Some(e.tolerance), e.start, None),
            ),
            ("fmi2EnterInitializationMode", self.enter_init()),
        ] {
            if s != OK {
                return Err(format!("{what}: {}\n{}", status_name(s), self.log_tail()));
            }
        }
        if !values.is_empty() {
            let (vrs, xs): (Vec<u32>, Vec<f64>) = values.iter().copied().unzip();
            let s = self.set_real(&vrs, &xs);
            if s != OK {
                return Err(format!(
                    "fmi2SetReal: {}\n{}",
                    status_name(s),
                    self.log_tail()
                ));
            }
        }
        match self.exit_init() {
            OK => Ok(()),
            s => Err(format!(
                "fmi2ExitInitializationMode: {}\n{}",
                status_name(s),
                self.log_tail()
            )),
        }
    }

    pub fn set_real(&mut self, vrs: &[u32], values: &[f64]) -> Status {
        assert_eq!(vrs.len(), values.len());
        // SAFETY: arrays of nvr elements.
        unsafe { (self.fmu.api.set_real)(self.c, vrs.as_ptr(), vrs.len(), values.as_ptr()) }
    }

    pub fn get_real(&mut self, vrs: &[u32]) -> (Status, Vec<f64>) {
        let mut out = vec![f64::NAN; vrs.len()];
        // SAFETY: arrays of nvr elements.
        let s =
            unsafe { (self.fmu.api.get_real)(self.c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr()) };
        (s, out)
    }

    /// Every variable's value (panics unless fmi2OK).
    pub fn all_values(&mut self) -> Vec<f64> {
        let vrs = self.fmu.md.all_vrs();
        let (s, v) = self.get_real(&vrs);
        assert_eq!(s, OK, "fmi2GetReal of all variables: {}", self.log_tail());
        v
    }

    pub fn do_step(&mut self, t: f64, h: f64) -> Status {
        // SAFETY: live instance.
        unsafe { (self.fmu.api.do_step)(self.c, t, h, 1) }
    }

    pub fn last_successful_time(&mut self) -> (Status, f64) {
        let mut t = f64::NAN;
        // SAFETY: live instance, valid out pointer.
        let s = unsafe { (self.fmu.api.get_real_status)(self.c, LAST_SUCCESSFUL_TIME, &mut t) };
        (s, t)
    }

    pub fn terminated(&mut self) -> (Status, bool) {
        let mut b: Boolean = -1;
        // SAFETY: live instance, valid out pointer.
        let s = unsafe { (self.fmu.api.get_boolean_status)(self.c, TERMINATED, &mut b) };
        (s, b != 0)
    }

    pub fn terminate(&mut self) -> Status {
        // SAFETY: live instance.
        unsafe { (self.fmu.api.terminate)(self.c) }
    }

    pub fn reset(&mut self) -> Status {
        // SAFETY: live instance.
        unsafe { (self.fmu.api.reset)(self.c) }
    }

    // Model Exchange.

    pub fn enter_event_mode(&mut self) -> Status {
        // SAFETY: live instance.
        unsafe { (self.fmu.api.enter_event_mode)(self.c) }
    }

    pub fn enter_continuous_time_mode(&mut self) -> Status {
        // SAFETY: live instance.
        unsafe { (self.fmu.api.enter_continuous_time_mode)(self.c) }
    }

    pub fn new_discrete_states(&mut self) -> (Status, EventInfo) {
        let mut info = unwritten_event_info();
        // SAFETY: live instance, valid out pointer.
        let s = unsafe { (self.fmu.api.new_discrete_states)(self.c, &mut info) };
        (s, info)
    }

    /// The event iteration of an importer: fmi2NewDiscreteStates until no new discrete
    /// states are needed (at most `limit` times). The last status and event info.
    pub fn event_iteration(&mut self, limit: usize) -> (Status, EventInfo) {
        let mut last = self.new_discrete_states();
        for _ in 1..limit {
            if last.0 > WARNING || last.1.newDiscreteStatesNeeded == 0 {
                break;
            }
            last = self.new_discrete_states();
        }
        last
    }

    /// fmi2CompletedIntegratorStep: the status, enterEventMode, terminateSimulation.
    pub fn completed_integrator_step(&mut self, no_set_prior: bool) -> (Status, bool, bool) {
        let (mut event, mut terminate) = (-1, -1);
        // SAFETY: live instance, valid out pointers.
        let s = unsafe {
            (self.fmu.api.completed_integrator_step)(
                self.c,
                no_set_prior as Boolean,
                &mut event,
                &mut terminate,
            )
        };
        (s, event != 0, terminate != 0)
    }

    pub fn set_time(&mut self, t: f64) -> Status {
        // SAFETY: live instance.
        unsafe { (self.fmu.api.set_time)(self.c, t) }
    }

    pub fn set_continuous_states(&mut self, x: &[f64]) -> Status {
        // SAFETY: an array of x.len() elements.
        unsafe { (self.fmu.api.set_continuous_states)(self.c, x.as_ptr(), x.len()) }
    }

    /// `get` (one of the four array getters of Model Exchange) into `out`.
    fn get_array(&mut self, get: GetRealArrayFn, out: &mut [f64]) -> Status {
        // SAFETY: an array of out.len() elements.
        unsafe { get(self.c, out.as_mut_ptr(), out.len()) }
    }

    pub fn get_continuous_states(&mut self, x: &mut [f64]) -> Status {
        self.get_array(self.fmu.api.get_continuous_states, x)
    }

    pub fn get_derivatives(&mut self, dx: &mut [f64]) -> Status {
        self.get_array(self.fmu.api.get_derivatives, dx)
    }

    pub fn get_event_indicators(&mut self, z: &mut [f64]) -> Status {
        self.get_array(self.fmu.api.get_event_indicators, z)
    }

    pub fn get_nominals_of_continuous_states(&mut self, n: &mut [f64]) -> Status {
        self.get_array(self.fmu.api.get_nominals_of_continuous_states, n)
    }
}

impl Drop for Instance<'_> {
    fn drop(&mut self) {
        // SAFETY: live instance, freed once.
        unsafe { (self.fmu.api.free_instance)(self.c) }
    }
}
