//! FMI 2.0's sequences: the importer's next call ([`instantiate`]: instantiation with
//! hostile arguments; [`calls`], [`step`]: the calls of FMI 2.0 only).

mod calls;
mod derivatives;
mod instantiate;
mod step;
mod table;

pub use table::allowed;

use super::core::{standard_c_calls, Sequence, Standard};
use super::machine::{Kind, St};
use super::model::Model;
use crate::ffi::*;
use crate::fmu::Fmu;
use table::f;

/// FMI 2.0 (`fmi2Functions.h`).
pub enum Fmi2 {}

impl Sequence<'_, Fmi2> {
    pub(crate) fn check_platform(&mut self) {
        // SAFETY: no arguments.
        let (p, v) = unsafe {
            (
                (self.fmu.api.get_types_platform)(),
                (self.fmu.api.get_version)(),
            )
        };
        let s = |p: CStr| {
            // SAFETY: the FMU returns a static NUL-terminated string (NULL checked).
            (!p.is_null()).then(|| {
                unsafe { std::ffi::CStr::from_ptr(p) }
                    .to_string_lossy()
                    .into_owned()
            })
        };
        self.stats.calls += 2;
        if s(p).as_deref() != Some("default") || s(v).as_deref() != Some("2.0") {
            self.fail(format!(
                "fmi2GetTypesPlatform/fmi2GetVersion returned {:?}/{:?}",
                s(p),
                s(v)
            ));
        }
    }

    pub(crate) fn random_call(&mut self) {
        if self.insts.is_empty() || self.rng.chance(0.01) {
            self.instantiate();
            return;
        }
        // Half the calls are legal in the instance's state (so sequences reach deep states).
        let i = self.rng.below(self.insts.len());
        // A quarter of the calls are what a normal importer would do next.
        if self.rng.chance(0.25) {
            let next = match self.insts[i].st {
                St::Instantiated if self.rng.chance(0.3) => f::SETUP_EXPERIMENT,
                St::Instantiated => f::ENTER_INIT,
                St::Init if self.rng.chance(0.2) => f::SET_REAL,
                St::Init => f::EXIT_INIT,
                St::StepComplete if self.rng.chance(0.15) => f::SET_REAL,
                St::StepComplete if self.rng.chance(0.05) => f::GET_FMU_STATE,
                St::StepComplete => f::DO_STEP,
                St::EventMode if self.rng.chance(0.35) => f::NEW_DISCRETE_STATES,
                St::EventMode if self.rng.chance(0.1) => f::SET_REAL,
                St::EventMode if self.rng.chance(0.05) => f::GET_FMU_STATE,
                St::EventMode => f::ENTER_CONTINUOUS_TIME_MODE,
                St::ContinuousTimeMode
                    if self.insts[i].event_requested || self.rng.chance(0.03) =>
                {
                    f::ENTER_EVENT_MODE
                }
                St::ContinuousTimeMode if self.rng.chance(0.05) => f::GET_FMU_STATE,
                St::ContinuousTimeMode if self.rng.chance(0.05) => f::SET_REAL,
                St::ContinuousTimeMode => {
                    self.me_step(i);
                    return;
                }
                _ if !self.handles.is_empty() && self.rng.chance(0.3) => f::SET_FMU_STATE,
                _ => f::RESET,
            };
            self.call(next);
            return;
        }
        let function = if self.rng.chance(0.5) {
            let (kind, st) = (self.insts[i].kind, self.insts[i].st);
            let legal: Vec<usize> = (0..f::COUNT)
                .filter(|&g| g != f::INSTANTIATE && allowed(g, kind, st))
                .flat_map(|g| {
                    // Weight the calls that move the simulation on.
                    let w = match g {
                        f::DO_STEP => 8,
                        f::GET_REAL | f::SET_REAL => 3,
                        f::EXIT_INIT | f::ENTER_INIT | f::SETUP_EXPERIMENT => 3,
                        f::SET_TIME | f::SET_CONTINUOUS_STATES | f::GET_DERIVATIVES => 3,
                        f::ENTER_CONTINUOUS_TIME_MODE => 3,
                        f::FREE_INSTANCE => 0,
                        _ => 1,
                    };
                    std::iter::repeat_n(g, w)
                })
                .collect();
            if legal.is_empty() {
                self.rng.below(f::COUNT)
            } else {
                *self.rng.pick(&legal)
            }
        } else {
            self.rng.below(f::COUNT)
        };
        self.call(function);
    }

    /// Makes one call of `function` with generated arguments and checks the result.
    pub(crate) fn call(&mut self, function: usize) {
        if function == f::INSTANTIATE {
            self.instantiate();
            return;
        }
        if matches!(function, f::GET_TYPES_PLATFORM | f::GET_VERSION) {
            self.check_platform();
            return;
        }
        let (target, c) = self.target();
        self.call_on(function, target, c);
    }
}

impl Standard for Fmi2 {
    type Fmu = Fmu;
    fn fmu_name(fmu: &Fmu) -> &str {
        fmu.name()
    }
    fn model(fmu: &Fmu) -> Model {
        Model::fmi2(&fmu.md)
    }
    type Extra = ();
    const NAMES: &'static [&'static str] = &FUNCTION_NAMES;
    const FREE_INSTANCE: usize = f::FREE_INSTANCE;
    const FREE_FMU_STATE: usize = f::FREE_FMU_STATE;
    const ME_STEP: [usize; 6] = [
        f::GET_CONTINUOUS_STATES,
        f::GET_DERIVATIVES,
        f::SET_TIME,
        f::SET_CONTINUOUS_STATES,
        f::COMPLETED_INTEGRATOR_STEP,
        f::GET_EVENT_INDICATORS,
    ];
    const GET_NOMINALS: usize = f::GET_NOMINALS;

    fn status_name(s: Status) -> String {
        status_name(s)
    }
    fn allowed(function: usize, kind: Kind, st: St) -> bool {
        table::allowed(function, kind, st)
    }
    fn interface_of(function: usize) -> Option<Kind> {
        if f::co_simulation_only(function) {
            Some(Kind::CoSimulation)
        } else if f::model_exchange_only(function) {
            Some(Kind::ModelExchange)
        } else {
            None
        }
    }
    fn status_allowed(function: usize, s: Status) -> bool {
        table::status_allowed(function, s)
    }
    fn moves_states(function: usize) -> bool {
        matches!(
            function,
            f::SETUP_EXPERIMENT
                | f::ENTER_INIT
                | f::EXIT_INIT
                | f::RESET
                | f::SET_REAL
                | f::SET_FMU_STATE
                | f::NEW_DISCRETE_STATES
        )
    }

    fn begin(seq: &mut Sequence<Self>) {
        seq.check_platform();
    }
    fn end(_: &mut Sequence<Self>) {}
    fn instantiate(seq: &mut Sequence<Self>) {
        seq.instantiate();
    }
    standard_c_calls!(get_derivatives);

    unsafe fn get_values(fmu: &Fmu, c: Component, vrs: &[u32], out: &mut [f64]) -> Status {
        assert_eq!(vrs.len(), out.len());
        // SAFETY: a live instance (the caller's promise), arrays of vrs.len() elements.
        unsafe { (fmu.api.get_real)(c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr()) }
    }
}
