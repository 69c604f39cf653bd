//! A well-behaved FMI 3.0 importer's instance: Co-Simulation (with or without event mode
//! and early return) or Model Exchange, variables by FMI 3.0 value reference (an array's
//! values are its elements, in order).

use super::{forbidden_intermediate_update, record3, Message, Sink};
use crate::ffi3::*;
use crate::fmu::Fmu3;
use std::ffi::CString;

/// An instance made with the right instantiation token and the recording logger; freed
/// on drop.
pub struct Instance3<'a> {
    pub fmu: &'a Fmu3,
    pub c: Instance,
    pub sink: Box<Sink>,
    _name: CString,
}

// SAFETY: an instance is used by one thread at a time (FMI allows that; the FMU has no
// global state), and the sink is Sync.
unsafe impl Send for Instance3<'_> {}

impl<'a> Instance3<'a> {
    /// A Co-Simulation instance.
    pub fn new_cs(
        fmu: &'a Fmu3,
        name: &str,
        event_mode_used: bool,
        early_return_allowed: bool,
    ) -> Result<Instance3<'a>, Vec<Message>> {
        Self::new(fmu, name, Some((event_mode_used, early_return_allowed)))
    }

    /// A Model Exchange instance.
    pub fn new_me(fmu: &'a Fmu3, name: &str) -> Result<Instance3<'a>, Vec<Message>> {
        Self::new(fmu, name, None)
    }

    fn new(
        fmu: &'a Fmu3,
        name: &str,
        co_simulation: Option<(bool, bool)>,
    ) -> Result<Instance3<'a>, Vec<Message>> {
        let sink = Box::<Sink>::default();
        let env = &*sink as *const Sink as Env;
        let name = CString::new(name).expect("instance name");
        let token = CString::new(fmu.md.instantiation_token.as_str()).expect("token");
        let resources = c"file:///nonexistent/resources/";
        // SAFETY: valid strings; the sink outlives the instance.
        let c = unsafe {
            match co_simulation {
                None => (fmu.api.instantiate_model_exchange)(
                    name.as_ptr(),
                    token.as_ptr(),
                    resources.as_ptr(),
                    false,
                    false,
                    env,
                    Some(record3),
                ),
                Some((event_mode_used, early_return_allowed)) => {
                    (fmu.api.instantiate_co_simulation)(
                        name.as_ptr(),
                        token.as_ptr(),
                        resources.as_ptr(),
                        false,
                        false,
                        event_mode_used,
                        early_return_allowed,
                        std::ptr::null(),
                        0,
                        env,
                        Some(record3),
                        Some(forbidden_intermediate_update),
                    )
                }
            }
        };
        if c.is_null() {
            return Err(sink.all());
        }
        Ok(Instance3 {
            fmu,
            c,
            sink,
            _name: name,
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

    pub fn enter_init(&mut self, tolerance: Option<f64>, start: f64, stop: Option<f64>) -> Status {
        // SAFETY: live instance.
        unsafe {
            (self.fmu.api.enter_initialization_mode)(
                self.c,
                tolerance.is_some(),
                tolerance.unwrap_or(0.0),
                start,
                stop.is_some(),
                stop.unwrap_or(0.0),
            )
        }
    }

    pub fn exit_init(&mut self) -> Status {
        // SAFETY: live instance.
        unsafe { (self.fmu.api.exit_initialization_mode)(self.c) }
    }

    /// Initialization at the default experiment's start and tolerance, with `values`
    /// (value reference, its values) set in initialization mode.
    pub fn initialize(&mut self, values: &[(u32, Vec<f64>)]) -> Result<(), String> {
        let e = self.fmu.md.experiment;
        let s = self.enter_init(Some(e.tolerance), e.start, None);
        if s != OK {
            return Err(self.failed("fmi3EnterInitializationMode", s));
        }
        for (vr, x) in values {
            let s = self.set_float64(&[*vr], x);
            if s != OK {
                return Err(self.failed(&format!("fmi3SetFloat64 of {vr}"), s));
            }
        }
        match self.exit_init() {
            OK => Ok(()),
            s => Err(self.failed("fmi3ExitInitializationMode", s)),
        }
    }

    fn failed(&self, what: &str, s: Status) -> String {
        format!("{what}: {}\n{}", status_name(s), self.log_tail())
    }

    pub fn set_float64(&mut self, vrs: &[u32], values: &[f64]) -> Status {
        // SAFETY: arrays of their lengths.
        unsafe {
            (self.fmu.api.set_float64)(
                self.c,
                vrs.as_ptr(),
                vrs.len(),
                values.as_ptr(),
                values.len(),
            )
        }
    }

    /// The values of `vrs` (as many as their elements; NaN where the call wrote nothing).
    pub fn get_float64(&mut self, vrs: &[u32]) -> (Status, Vec<f64>) {
        let n = self.fmu.md.len_of(vrs).unwrap_or(vrs.len());
        let mut out = vec![f64::NAN; n];
        // SAFETY: arrays of their lengths.
        let s = unsafe {
            (self.fmu.api.get_float64)(self.c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr(), n)
        };
        (s, out)
    }

    /// Every variable's values but time's, by increasing value reference (panics unless
    /// fmi3OK).
    pub fn all_values(&mut self) -> Vec<f64> {
        let vrs = self.fmu.md.all_vrs();
        let (s, v) = self.get_float64(&vrs);
        assert_eq!(
            s,
            OK,
            "fmi3GetFloat64 of all variables: {}",
            self.log_tail()
        );
        v
    }

    pub fn do_step(&mut self, t: f64, h: f64) -> Step {
        let (mut event, mut terminate, mut early) = (0xa5u8, 0xa5u8, 0xa5u8);
        let mut last = f64::NAN;
        // SAFETY: live instance, valid out pointers.
        let status = unsafe {
            (self.fmu.api.do_step)(
                self.c,
                t,
                h,
                true,
                boolean_out(&mut event),
                boolean_out(&mut terminate),
                boolean_out(&mut early),
                &mut last,
            )
        };
        Step {
            status,
            event_handling_needed: event,
            terminate_simulation: terminate,
            early_return: early,
            last_successful_time: last,
        }
    }

    pub fn terminate(&mut self) -> Status {
        // SAFETY: live instance.
        unsafe { (self.fmu.api.terminate)(self.c) }
    }

    pub fn reset(&mut self) -> Status {
        // SAFETY: live instance.
        unsafe { (self.fmu.api.reset)(self.c) }
    }

    pub fn enter_event_mode(&mut self) -> Status {
        // SAFETY: live instance.
        unsafe { (self.fmu.api.enter_event_mode)(self.c) }
    }

    pub fn enter_step_mode(&mut self) -> Status {
        // SAFETY: live instance.
        unsafe { (self.fmu.api.enter_step_mode)(self.c) }
    }

    pub fn enter_continuous_time_mode(&mut self) -> Status {
        // SAFETY: live instance.
        unsafe { (self.fmu.api.enter_continuous_time_mode)(self.c) }
    }

    pub fn update_discrete_states(&mut self) -> (Status, DiscreteStates) {
        let mut d = DiscreteStates {
            discrete_states_need_update: 0xa5,
            terminate_simulation: 0xa5,
            nominals_changed: 0xa5,
            values_changed: 0xa5,
            next_event_time_defined: 0xa5,
            next_event_time: f64::NAN,
        };
        // SAFETY: live instance, valid out pointers.
        let s = unsafe {
            (self.fmu.api.update_discrete_states)(
                self.c,
                boolean_out(&mut d.discrete_states_need_update),
                boolean_out(&mut d.terminate_simulation),
                boolean_out(&mut d.nominals_changed),
                boolean_out(&mut d.values_changed),
                boolean_out(&mut d.next_event_time_defined),
                &mut d.next_event_time,
            )
        };
        (s, d)
    }

    /// fmi3CompletedIntegratorStep: the status, enterEventMode, terminateSimulation.
    pub fn completed_integrator_step(&mut self, no_set_prior: bool) -> (Status, bool, bool) {
        let (mut event, mut terminate) = (0xa5u8, 0xa5u8);
        // SAFETY: live instance, valid out pointers.
        let s = unsafe {
            (self.fmu.api.completed_integrator_step)(
                self.c,
                no_set_prior,
                boolean_out(&mut event),
                boolean_out(&mut terminate),
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

    pub fn get_continuous_states(&mut self, x: &mut [f64]) -> Status {
        // SAFETY: an array of x.len() elements.
        unsafe { (self.fmu.api.get_continuous_states)(self.c, x.as_mut_ptr(), x.len()) }
    }

    pub fn get_derivatives(&mut self, dx: &mut [f64]) -> Status {
        // SAFETY: an array of dx.len() elements.
        unsafe {
            (self.fmu.api.get_continuous_state_derivatives)(self.c, dx.as_mut_ptr(), dx.len())
        }
    }

    pub fn get_event_indicators(&mut self, z: &mut [f64]) -> Status {
        // SAFETY: an array of z.len() elements.
        unsafe { (self.fmu.api.get_event_indicators)(self.c, z.as_mut_ptr(), z.len()) }
    }

    pub fn get_nominals(&mut self, n: &mut [f64]) -> Status {
        // SAFETY: an array of n.len() elements.
        unsafe { (self.fmu.api.get_nominals_of_continuous_states)(self.c, n.as_mut_ptr(), n.len()) }
    }

    /// fmi3GetFMUState into a new state.
    pub fn get_state(&mut self) -> Result<FmuState, Status> {
        let mut state: FmuState = std::ptr::null_mut();
        // SAFETY: live instance, a NULL slot.
        match unsafe { (self.fmu.api.get_fmu_state)(self.c, &mut state) } {
            OK => Ok(state),
            s => Err(s),
        }
    }

    /// # Safety
    /// `state` is NULL or a handle of this binary's FMU states (freed or not).
    pub unsafe fn set_state(&mut self, state: FmuState) -> Status {
        // SAFETY: live instance; the caller's promise.
        unsafe { (self.fmu.api.set_fmu_state)(self.c, state) }
    }

    /// Frees `state` (a handle [`get_state`](Self::get_state) or
    /// [`deserialize`](Self::deserialize) gave, or NULL) and sets it to NULL.
    pub fn free_state(&mut self, state: &mut FmuState) -> Status {
        // SAFETY: live instance, a valid slot.
        unsafe { (self.fmu.api.free_fmu_state)(self.c, state) }
    }

    /// The bytes of `state` (fmi3SerializedFMUStateSize, fmi3SerializeFMUState).
    ///
    /// # Safety
    /// As for [`set_state`](Self::set_state).
    pub unsafe fn serialize(&mut self, state: FmuState) -> Result<Vec<u8>, Status> {
        let mut size = 0usize;
        // SAFETY: live instance, valid out pointer and a buffer of `size` bytes.
        unsafe {
            match (self.fmu.api.serialized_fmu_state_size)(self.c, state, &mut size) {
                OK => {}
                s => return Err(s),
            }
            let mut bytes = vec![0u8; size];
            match (self.fmu.api.serialize_fmu_state)(self.c, state, bytes.as_mut_ptr(), size) {
                OK => Ok(bytes),
                s => Err(s),
            }
        }
    }

    /// fmi3DeserializeFMUState into a new state.
    pub fn deserialize(&mut self, bytes: &[u8]) -> Result<FmuState, Status> {
        let mut state: FmuState = std::ptr::null_mut();
        // SAFETY: live instance, `bytes.len()` readable bytes, a NULL slot.
        match unsafe {
            (self.fmu.api.deserialize_fmu_state)(self.c, bytes.as_ptr(), bytes.len(), &mut state)
        } {
            OK => Ok(state),
            s => Err(s),
        }
    }
}

impl Drop for Instance3<'_> {
    fn drop(&mut self) {
        // SAFETY: live instance, freed once.
        unsafe { (self.fmu.api.free_instance)(self.c) }
    }
}
