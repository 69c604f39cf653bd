//! FMI 3.0's three instantiation functions with sane and hostile arguments (NULL, empty or
//! non-UTF-8 names, a wrong or NULL instantiation token, FMI 2.0's GUID, required
//! intermediate variables, no logger, hostile resource paths; Scheduled Execution, which
//! the FMU does not offer), and the FMI 2.0 instance of the same binary whose pointer and
//! FMU state a hostile importer hands to FMI 3.0's functions.

use super::table::f;
use super::Fmi3;
use crate::ffi::{self, CallbackFunctions};
use crate::ffi3::*;
use crate::importer::{callbacks, forbidden_intermediate_update, record3, Sink};
use crate::sequences::args::SANE_NAMES;
use crate::sequences::core::Sequence;
use crate::sequences::machine::{Inst, Kind, Snap, St};
use std::ffi::CString;

/// An FMI 2.0 Co-Simulation instance of the binary under test, stepped once, with an FMU
/// state of it and that state's serialized bytes.
pub struct OtherStandard {
    pub c: Instance,
    pub state: FmuState,
    pub bytes: Vec<u8>,
    _sink: Box<Sink>,
    _callbacks: Box<CallbackFunctions>,
}

impl Sequence<'_, Fmi3> {
    /// Instantiates through `function` (one of the three; `None`: Model Exchange or
    /// Co-Simulation at random), with hostile arguments sometimes.
    pub(crate) fn instantiate(&mut self, function: Option<usize>) {
        if self.insts.len() >= 2 {
            return;
        }
        let function = function.unwrap_or(if self.model.me && self.rng.chance(0.4) {
            f::INSTANTIATE_ME
        } else if self.rng.chance(0.03) {
            f::INSTANTIATE_SE
        } else {
            f::INSTANTIATE_CS
        });
        let name = FUNCTION_NAMES_FMI3[function];
        let sink = Box::<Sink>::default();
        let mut env = &*sink as *const Sink as Env;
        let mut logger: LogMessage = Some(record3);
        let mut logs = true;
        if self.rng.chance(0.05) {
            logger = None;
            logs = false;
        } else if self.rng.chance(0.03) {
            env = std::ptr::null_mut();
            logs = false;
        }
        let mut name_bytes: Vec<u8> = self.rng.pick(&SANE_NAMES).as_bytes().to_vec();
        if self.rng.chance(0.02) {
            name_bytes = "n".repeat(10_000).into_bytes();
        }
        let mut name_null = false;
        let mut token = self.fmu.md.instantiation_token.clone();
        let mut token_null = false;
        // requiredIntermediateVariables: none (there is no intermediate update to give).
        let required: Vec<u32> = vec![0, 1, u32::MAX];
        let (mut n_required, mut required_null) = (0usize, self.rng.chance(0.5));
        let hostile = self.rng.chance(0.15);
        if hostile {
            match self.rng.below(8) {
                0 => name_null = true,
                1 => name_bytes = vec![],
                2 => name_bytes = vec![b'a', 0xff, 0xfe],
                3 => token_null = true,
                4 => {
                    token = self
                        .rng
                        .pick(&["", "{00000000-0000-0000-0000-000000000000}", "garbage"])
                        .to_string()
                }
                5 => token = token.trim_matches(|c| c == '{' || c == '}').to_string(),
                // The FMI 2.0 FMU's GUID: the binary is the same, the standard not.
                6 => {
                    if let Some((_, guid)) = &self.fmu.fmi2 {
                        token = guid.clone();
                    } else {
                        token_null = true;
                    }
                }
                _ if function == f::INSTANTIATE_CS => {
                    n_required = 1 + self.rng.below(3);
                    required_null = self.rng.chance(0.3);
                }
                _ => name_null = true,
            }
        }
        let expect_null = hostile || function == f::INSTANTIATE_SE;
        let name_c = CString::new(name_bytes.clone()).expect("no NUL");
        let token_c = CString::new(token).expect("no NUL");
        let resources = match self.rng.below(3) {
            0 => None,
            1 => Some(CString::new("file:///tmp/mechfmu-robustness/resources/").unwrap()),
            _ => Some(CString::new("\u{1}garbage: not a URI %s").unwrap()),
        };
        let (visible, logging_on) = (self.rng.chance(0.5), self.rng.chance(0.6));
        let (event_mode_used, early_return_allowed) = (self.rng.chance(0.4), self.rng.chance(0.5));
        let update = if self.rng.chance(0.5) {
            None
        } else {
            Some(forbidden_intermediate_update as _)
        };
        self.note(|| {
            format!(
                "{name}(name {:?}, token {:?}{}, loggingOn {logging_on}, logger {logs}, eventModeUsed {event_mode_used}, earlyReturnAllowed {early_return_allowed}, {n_required} required intermediate variables)",
                (!name_null).then(|| String::from_utf8_lossy(&name_bytes).into_owned()),
                token_c,
                if token_null { " NULL" } else { "" },
            )
        });
        let name_p = if name_null {
            std::ptr::null()
        } else {
            name_c.as_ptr()
        };
        let token_p = if token_null {
            std::ptr::null()
        } else {
            token_c.as_ptr()
        };
        let res_p = resources.as_ref().map_or(std::ptr::null(), |r| r.as_ptr());
        let api = *self.fmu.api;
        // SAFETY: every pointer is NULL or valid for the call (the required variables'
        // array holds 3); the sink outlives the instance (it moves into `Inst`).
        let c = unsafe {
            match function {
                f::INSTANTIATE_ME => (api.instantiate_model_exchange)(
                    name_p, token_p, res_p, visible, logging_on, env, logger,
                ),
                f::INSTANTIATE_CS => (api.instantiate_co_simulation)(
                    name_p,
                    token_p,
                    res_p,
                    visible,
                    logging_on,
                    event_mode_used,
                    early_return_allowed,
                    if required_null {
                        std::ptr::null()
                    } else {
                        required.as_ptr()
                    },
                    n_required,
                    env,
                    logger,
                    update,
                ),
                _ => (api.instantiate_scheduled_execution)(
                    name_p, token_p, res_p, visible, logging_on, env, logger, None, None, None,
                ),
            }
        };
        self.stats.calls += 1;
        for v in sink.take_violations() {
            self.fail(format!("{name}: {v}"));
        }
        if expect_null {
            if !c.is_null() {
                self.fail(format!(
                    "{name} accepted hostile arguments (returned an instance)"
                ));
                // SAFETY: the instance it returned.
                unsafe { (api.free_instance)(c) };
            } else if logs && sink.is_empty() {
                self.fail(format!(
                    "{name} refused its arguments without a logged message"
                ));
            }
            return;
        }
        if c.is_null() {
            let why: Vec<String> = sink.all().into_iter().map(|m| m.text).collect();
            self.fail(format!(
                "{name} failed with valid arguments: {}",
                why.join("; ")
            ));
            return;
        }
        let kind = if function == f::INSTANTIATE_ME {
            self.stats.me_instances += 1;
            Kind::ModelExchange
        } else {
            self.stats.cs_event_mode_instances += event_mode_used as u64;
            Kind::CoSimulation
        };
        let mut inst = Inst::new(c, sink, name_c, logs, kind);
        inst.categories[0] = logging_on;
        inst.event_mode_used = kind == Kind::CoSimulation && event_mode_used;
        inst.early_return_allowed = kind == Kind::CoSimulation && early_return_allowed;
        self.insts.push(inst);
    }

    /// A well-formed Co-Simulation instance with a logger (for cleaning up).
    pub(crate) fn clean_instance(&mut self) {
        let sink = Box::<Sink>::default();
        let name = CString::new("cleanup").unwrap();
        let token = CString::new(self.fmu.md.instantiation_token.as_str()).unwrap();
        // SAFETY: valid strings; the sink outlives the instance.
        let c = unsafe {
            (self.fmu.api.instantiate_co_simulation)(
                name.as_ptr(),
                token.as_ptr(),
                std::ptr::null(),
                false,
                false,
                false,
                false,
                std::ptr::null(),
                0,
                &*sink as *const Sink as Env,
                Some(record3),
                None,
            )
        };
        self.stats.calls += 1;
        if c.is_null() {
            self.fail("fmi3InstantiateCoSimulation with valid arguments failed".into());
            return;
        }
        let mut inst = Inst::new(c, sink, name, true, Kind::CoSimulation);
        inst.categories[0] = false;
        self.insts.push(inst);
    }

    /// One sequence in three has an FMI 2.0 instance of the same binary (when the FMI 2.0
    /// FMU's GUID is known), initialized and stepped once, with an FMU state and its bytes:
    /// FMI 3.0's functions must refuse all three.
    pub(crate) fn other_standard(&mut self) {
        let Some((api, guid)) = self.fmu.fmi2.clone() else {
            return;
        };
        if !self.rng.chance(1.0 / 3.0) {
            return;
        }
        let sink = Box::<Sink>::default();
        let cb = Box::new(callbacks(&sink));
        let name = CString::new("fmi2").unwrap();
        let guid = CString::new(guid).unwrap();
        let e = self.model.experiment;
        // SAFETY: valid arguments; the callbacks and the sink outlive the instance (they
        // move into `OtherStandard`), which `free_other_standard` frees with its state.
        unsafe {
            let c = (api.instantiate)(
                name.as_ptr(),
                ffi::CO_SIMULATION,
                guid.as_ptr(),
                std::ptr::null(),
                &*cb,
                0,
                0,
            );
            if c.is_null() {
                self.fail("fmi2Instantiate of the same binary failed".into());
                return;
            }
            let mut state: FmuState = std::ptr::null_mut();
            let mut size = 0;
            let ok = (api.setup_experiment)(c, 1, e.tolerance, e.start, 0, 0.0) == OK
                && (api.enter_initialization_mode)(c) == OK
                && (api.exit_initialization_mode)(c) == OK
                && (api.do_step)(c, e.start, e.step, 1) == OK
                && (api.get_fmu_state)(c, &mut state) == OK
                && (api.serialized_fmu_state_size)(c, state, &mut size) == OK;
            let mut bytes = vec![0u8; size];
            if !ok || (api.serialize_fmu_state)(c, state, bytes.as_mut_ptr().cast(), size) != OK {
                self.fail("the FMI 2.0 instance of the same binary does not step".into());
                (api.free_fmu_state)(c, &mut state);
                (api.free_instance)(c);
                return;
            }
            self.stats.calls += 9;
            self.extra.other = Some(OtherStandard {
                c,
                state,
                bytes,
                _sink: sink,
                _callbacks: cb,
            });
        }
    }

    /// Frees the FMI 2.0 instance and its FMU state.
    pub(crate) fn free_other_standard(&mut self) {
        let (Some(mut other), Some((api, _))) = (self.extra.other.take(), self.fmu.fmi2.clone())
        else {
            return;
        };
        // SAFETY: the live instance and state `other_standard` made, freed once.
        unsafe {
            (api.free_fmu_state)(other.c, &mut other.state);
            (api.free_instance)(other.c);
        }
        self.stats.calls += 2;
    }

    /// What an FMU state of the FMI 2.0 instance captures (Co-Simulation, one step done).
    pub(crate) fn other_standard_snap(&self) -> Snap {
        let e = &self.model.experiment;
        Snap {
            st: St::StepComplete,
            time: e.start + e.step,
            stop: None,
            kind: Kind::CoSimulation,
            other_standard: true,
            forged: false,
        }
    }
}
