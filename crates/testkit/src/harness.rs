//! An in-process importer for tests: drives a mechanism through the very functions its FMU
//! exports (`fmi2::functions`), with a logger that records every message. Mechanism crates use
//! it to test their physics through the FMI boundary without building a `.so`.
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
//! use mechfmu_testkit::harness::Harness;
//! let mut fmu = Harness::<Decay>::new();
//! fmu.initialize(Some(1e-10), 0.0, &[("k", 2.0)]).unwrap();
//! fmu.step_to(1.0, 0.1).unwrap();
//! assert!((fmu.get("y") - (-2.0f64).exp()).abs() < 1e-9);
//! ```

#![allow(non_upper_case_globals)]

use mechfmu::fmi2::ffi::*;
use mechfmu::fmi2::functions;
use mechfmu::model::{Experiment, Mechanism};
use std::ffi::{c_char, c_uint, c_void, CStr, CString};
use std::marker::PhantomData;
use std::sync::Mutex;

/// A logged message: status, category, text.
pub type Message = (fmi2Status, String, String);

/// One instance of mechanism `M`, driven through its FMI functions.
pub struct Harness<M: Mechanism> {
    component: fmi2Component,
    log: MessageLog,
    time: f64,
    _m: PhantomData<M>,
}

// SAFETY: the component is owned by this harness alone; instances are Send by design.
unsafe impl<M: Mechanism> Send for Harness<M> {}

/// Receives `"%s", message` from the FMU. Declared with exactly the arguments the FMU
/// passes (Rust cannot define a C-variadic function on stable), which the x86-64 and
/// AArch64 C calling conventions make compatible for this call.
unsafe extern "C" fn record(
    env: fmi2ComponentEnvironment,
    _instance: fmi2String,
    status: fmi2Status,
    category: fmi2String,
    _format: fmi2String,
    message: *const c_char,
) {
    // SAFETY: the FMU passes back the environment this harness registered, and C strings.
    unsafe { push(env, status, category, message) }
}

/// Records one message in the [`MessageLog`] whose [`environment`](MessageLog::environment)
/// `env` is (NULL strings as empty ones).
///
/// # Safety
/// `env` is the environment of a live `MessageLog`; `category` and `message` are NULL or
/// NUL-terminated.
pub(crate) unsafe fn push(
    env: *mut c_void,
    status: c_uint,
    category: *const c_char,
    message: *const c_char,
) {
    // SAFETY: the caller's promise.
    unsafe {
        let log = &*(env as *const Mutex<Vec<Message>>);
        let text = |p: *const c_char| {
            if p.is_null() {
                String::new()
            } else {
                CStr::from_ptr(p).to_string_lossy().into_owned()
            }
        };
        if let Ok(mut log) = log.lock() {
            log.push((status, text(category), text(message)));
        }
    }
}

/// The importer's side of logging: callbacks whose logger records every message. Keep it
/// alive as long as any instance given its callbacks.
pub struct MessageLog {
    log: Box<Mutex<Vec<Message>>>,
    callbacks: Box<fmi2CallbackFunctions>,
}

impl Default for MessageLog {
    fn default() -> Self {
        Self::new()
    }
}

impl MessageLog {
    pub fn new() -> Self {
        let log: Box<Mutex<Vec<Message>>> = Box::default();
        // SAFETY: see `record`.
        let logger: unsafe extern "C" fn(
            fmi2ComponentEnvironment,
            fmi2String,
            fmi2Status,
            fmi2String,
            fmi2String,
            ...
        ) = unsafe { std::mem::transmute(record as *const c_void) };
        let callbacks = Box::new(fmi2CallbackFunctions {
            logger: Some(logger),
            allocateMemory: None,
            freeMemory: None,
            stepFinished: None,
            componentEnvironment: std::ptr::null_mut(),
        });
        let mut log = MessageLog { log, callbacks };
        log.callbacks.componentEnvironment = log.environment();
        log
    }

    /// The environment pointer under which the log's callbacks (FMI 2.0's here, FMI 3.0's
    /// in [`fmi3`](crate::fmi3)) record a message.
    pub fn environment(&self) -> *mut c_void {
        &*self.log as *const Mutex<Vec<Message>> as *mut c_void
    }

    /// The callbacks to pass to `fmi2Instantiate`.
    pub fn callbacks(&self) -> *const fmi2CallbackFunctions {
        &*self.callbacks
    }

    /// Every message logged so far.
    pub fn messages(&self) -> Vec<Message> {
        self.log.lock().map(|l| l.clone()).unwrap_or_default()
    }
}

/// The experiment of the test kit's own small mechanisms: one second in steps of 0.1, at
/// a tolerance tight enough for their exact solutions.
pub const ONE_SECOND: Experiment = Experiment::until(1.0).step(0.1).tolerance(1e-8);

impl<M: Mechanism> Default for Harness<M> {
    fn default() -> Self {
        Self::new()
    }
}

impl<M: Mechanism> Harness<M> {
    /// Instantiates with the right GUID, logging on.
    pub fn new() -> Self {
        Self::instantiate(M::NAME, fmi2CoSimulation, &mechfmu::contract::guid::<M>())
            .unwrap_or_else(|log| panic!("fmi2Instantiate failed: {log:?}"))
    }

    /// Instantiates with the given arguments; `Err` carries the logged messages.
    pub fn instantiate(name: &str, fmu_type: fmi2Type, guid: &str) -> Result<Self, Vec<Message>> {
        let log = MessageLog::new();
        let name = CString::new(name).unwrap_or_default();
        let guid = CString::new(guid).unwrap_or_default();
        // SAFETY: valid strings and callbacks that outlive the instance.
        let component = unsafe {
            functions::fmi2Instantiate::<M>(
                name.as_ptr(),
                fmu_type,
                guid.as_ptr(),
                std::ptr::null(),
                log.callbacks(),
                fmi2False,
                fmi2True,
            )
        };
        if component.is_null() {
            return Err(log.messages());
        }
        Ok(Harness {
            component,
            log,
            time: 0.0,
            _m: PhantomData,
        })
    }

    /// The raw component, for tests of the C boundary.
    pub fn component(&self) -> fmi2Component {
        self.component
    }

    /// Every message logged so far.
    pub fn messages(&self) -> Vec<Message> {
        self.log.messages()
    }

    /// Whether a message containing `text` was logged.
    pub fn logged(&self, text: &str) -> bool {
        self.messages().iter().any(|(_, _, m)| m.contains(text))
    }

    /// The value reference of a variable, by name (panics on an unknown name: a test bug).
    pub fn vr(name: &str) -> fmi2ValueReference {
        M::VARIABLES
            .iter()
            .position(|v| v.name == name)
            .unwrap_or_else(|| panic!("{} has no variable `{name}`", M::NAME))
            as fmi2ValueReference
    }

    pub fn setup_experiment(
        &mut self,
        tolerance: Option<f64>,
        start: f64,
        stop: Option<f64>,
    ) -> fmi2Status {
        self.time = start;
        // SAFETY: live component.
        unsafe {
            functions::fmi2SetupExperiment::<M>(
                self.component,
                tolerance.is_some() as fmi2Boolean,
                tolerance.unwrap_or(0.0),
                start,
                stop.is_some() as fmi2Boolean,
                stop.unwrap_or(0.0),
            )
        }
    }

    pub fn enter_initialization_mode(&mut self) -> fmi2Status {
        // SAFETY: live component.
        unsafe { functions::fmi2EnterInitializationMode::<M>(self.component) }
    }

    pub fn exit_initialization_mode(&mut self) -> fmi2Status {
        // SAFETY: live component.
        unsafe { functions::fmi2ExitInitializationMode::<M>(self.component) }
    }

    /// Setup, start values, initialization: the usual importer sequence.
    pub fn initialize(
        &mut self,
        tolerance: Option<f64>,
        start: f64,
        values: &[(&str, f64)],
    ) -> Result<(), String> {
        let check = |s: fmi2Status, what: &str, h: &Self| {
            if s == fmi2OK {
                Ok(())
            } else {
                Err(format!("{what} returned {s}: {:?}", h.messages()))
            }
        };
        check(
            self.setup_experiment(tolerance, start, None),
            "fmi2SetupExperiment",
            self,
        )?;
        check(
            self.enter_initialization_mode(),
            "fmi2EnterInitializationMode",
            self,
        )?;
        for &(name, value) in values {
            check(
                self.set_real(&[Self::vr(name)], &[value]),
                "fmi2SetReal",
                self,
            )?;
        }
        check(
            self.exit_initialization_mode(),
            "fmi2ExitInitializationMode",
            self,
        )
    }

    pub fn set_real(&mut self, vr: &[fmi2ValueReference], values: &[f64]) -> fmi2Status {
        assert_eq!(vr.len(), values.len());
        // SAFETY: live component, arrays of the given length.
        unsafe {
            functions::fmi2SetReal::<M>(self.component, vr.as_ptr(), vr.len(), values.as_ptr())
        }
    }

    pub fn get_real(&mut self, vr: &[fmi2ValueReference], values: &mut [f64]) -> fmi2Status {
        assert_eq!(vr.len(), values.len());
        // SAFETY: live component, arrays of the given length.
        unsafe {
            functions::fmi2GetReal::<M>(self.component, vr.as_ptr(), vr.len(), values.as_mut_ptr())
        }
    }

    /// Sets one variable by name.
    pub fn set(&mut self, name: &str, value: f64) -> fmi2Status {
        self.set_real(&[Self::vr(name)], &[value])
    }

    /// One variable by name (NaN if the call fails).
    pub fn get(&mut self, name: &str) -> f64 {
        let mut v = [f64::NAN];
        self.get_real(&[Self::vr(name)], &mut v);
        v[0]
    }

    pub fn do_step(&mut self, t: f64, h: f64) -> fmi2Status {
        // SAFETY: live component.
        let status = unsafe { functions::fmi2DoStep::<M>(self.component, t, h, fmi2True) };
        if status <= fmi2Warning {
            self.time = t + h;
        }
        status
    }

    /// Moves the harness's clock back to `t` (after restoring an FMU state taken there).
    pub fn rewind(&mut self, t: f64) {
        self.time = t;
    }

    /// The communication point the harness has reached.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Steps of size `h` from the current time until `t_end` (the last step shortened to
    /// land on it), with times `t0 + n·h` as an importer computes them.
    pub fn step_to(&mut self, t_end: f64, h: f64) -> Result<(), String> {
        step_to(self.time, t_end, h, |t, step| match self.do_step(t, step) {
            status if status <= fmi2Warning => Ok(()),
            status => Err(format!(
                "fmi2DoStep({t}, {step}) returned {status}: {:?}",
                self.messages()
            )),
        })
    }

    pub fn terminate(&mut self) -> fmi2Status {
        // SAFETY: live component.
        unsafe { functions::fmi2Terminate::<M>(self.component) }
    }

    pub fn reset(&mut self) -> fmi2Status {
        self.time = 0.0;
        // SAFETY: live component.
        unsafe { functions::fmi2Reset::<M>(self.component) }
    }
}

// These take FMU-state handles as the C API does, unchecked, because tests must be able to
// pass stale or foreign ones: the FMU itself validates every handle it is given.
#[allow(clippy::not_unsafe_ptr_arg_deref)]
impl<M: Mechanism> Harness<M> {
    /// `fmi2GetFMUstate` into a fresh handle.
    pub fn get_fmu_state(&mut self) -> Result<fmi2FMUstate, fmi2Status> {
        let mut state: fmi2FMUstate = std::ptr::null_mut();
        // SAFETY: live component; `state` is a valid out-pointer.
        match unsafe { functions::fmi2GetFMUstate::<M>(self.component, &mut state) } {
            fmi2OK => Ok(state),
            s => Err(s),
        }
    }

    pub fn set_fmu_state(&mut self, state: fmi2FMUstate) -> fmi2Status {
        // SAFETY: live component; the FMU checks the handle.
        unsafe { functions::fmi2SetFMUstate::<M>(self.component, state) }
    }

    pub fn free_fmu_state(&mut self, mut state: fmi2FMUstate) -> fmi2Status {
        // SAFETY: live component; the FMU checks the handle.
        unsafe { functions::fmi2FreeFMUstate::<M>(self.component, &mut state) }
    }

    /// Serialized bytes of a state handle.
    pub fn serialize(&mut self, state: fmi2FMUstate) -> Result<Vec<u8>, fmi2Status> {
        let mut size = 0usize;
        // SAFETY: live component, valid out-pointers and a buffer of `size` bytes.
        unsafe {
            match functions::fmi2SerializedFMUstateSize::<M>(self.component, state, &mut size) {
                fmi2OK => {}
                s => return Err(s),
            }
            let mut bytes = vec![0u8; size];
            match functions::fmi2SerializeFMUstate::<M>(
                self.component,
                state,
                bytes.as_mut_ptr() as *mut fmi2Byte,
                size,
            ) {
                fmi2OK => Ok(bytes),
                s => Err(s),
            }
        }
    }

    /// A new state handle from serialized bytes.
    pub fn deserialize(&mut self, bytes: &[u8]) -> Result<fmi2FMUstate, fmi2Status> {
        let mut state: fmi2FMUstate = std::ptr::null_mut();
        // SAFETY: live component; `bytes` is a valid buffer.
        match unsafe {
            functions::fmi2DeSerializeFMUstate::<M>(
                self.component,
                bytes.as_ptr() as *const fmi2Byte,
                bytes.len(),
                &mut state,
            )
        } {
            fmi2OK => Ok(state),
            s => Err(s),
        }
    }

    pub fn directional_derivative(
        &mut self,
        unknowns: &[fmi2ValueReference],
        knowns: &[fmi2ValueReference],
        dv_known: &[f64],
        dv_unknown: &mut [f64],
    ) -> fmi2Status {
        assert_eq!(knowns.len(), dv_known.len());
        assert_eq!(unknowns.len(), dv_unknown.len());
        // SAFETY: live component, arrays of the given lengths.
        unsafe {
            functions::fmi2GetDirectionalDerivative::<M>(
                self.component,
                unknowns.as_ptr(),
                unknowns.len(),
                knowns.as_ptr(),
                knowns.len(),
                dv_known.as_ptr(),
                dv_unknown.as_mut_ptr(),
            )
        }
    }

    pub fn set_input_derivatives(
        &mut self,
        vr: &[fmi2ValueReference],
        order: &[i32],
        values: &[f64],
    ) -> fmi2Status {
        // SAFETY: live component, arrays of the given lengths.
        unsafe {
            functions::fmi2SetRealInputDerivatives::<M>(
                self.component,
                vr.as_ptr(),
                vr.len(),
                order.as_ptr(),
                values.as_ptr(),
            )
        }
    }

    pub fn output_derivatives(
        &mut self,
        vr: &[fmi2ValueReference],
        order: &[i32],
        values: &mut [f64],
    ) -> fmi2Status {
        // SAFETY: live component, arrays of the given lengths.
        unsafe {
            functions::fmi2GetRealOutputDerivatives::<M>(
                self.component,
                vr.as_ptr(),
                vr.len(),
                order.as_ptr(),
                values.as_mut_ptr(),
            )
        }
    }

    /// Every variable's value, by value reference.
    pub fn all_values(&mut self) -> Vec<f64> {
        let vrs: Vec<fmi2ValueReference> = (0..M::VARIABLES.len() as u32).collect();
        let mut values = vec![f64::NAN; vrs.len()];
        self.get_real(&vrs, &mut values);
        values
    }
}

/// Calls `step(t, h)` for steps of size `h` from `t0` until `t_end` (the last one shortened
/// to land on it), with times `t0 + n·h` as an importer computes them; stops at the first
/// `Err`.
pub(crate) fn step_to(
    t0: f64,
    t_end: f64,
    h: f64,
    mut step: impl FnMut(f64, f64) -> Result<(), String>,
) -> Result<(), String> {
    let (mut time, mut n) = (t0, 0u64);
    while time < t_end - 1e-12 * t_end.abs().max(1.0) {
        let t = t0 + n as f64 * h;
        let size = (t0 + (n + 1) as f64 * h).min(t_end) - t;
        step(t, size)?;
        time = t + size;
        n += 1;
    }
    Ok(())
}

impl<M: Mechanism> Drop for Harness<M> {
    fn drop(&mut self) {
        // SAFETY: the component is live and freed once.
        unsafe { functions::fmi2FreeInstance::<M>(self.component) }
    }
}

/// Asserts that setting `name` to `value` makes `fmi2ExitInitializationMode` fail with
/// fmi2Error and a logged message naming `name = value`.
pub fn assert_rejected_at_initialization<M: Mechanism>(name: &str, value: f64) {
    let mut fmu = Harness::<M>::new();
    assert_eq!(fmu.setup_experiment(None, 0.0, None), fmi2OK);
    assert_eq!(fmu.enter_initialization_mode(), fmi2OK);
    assert_eq!(fmu.set(name, value), fmi2OK);
    assert_eq!(
        fmu.exit_initialization_mode(),
        fmi2Error,
        "{name} = {value} was accepted"
    );
    assert!(
        fmu.logged(&format!("{name} = {value}")),
        "no message names {name} = {value}: {:?}",
        fmu.messages()
    );
}
