//! FMI 3.0's sequences: the importer's next call ([`instantiate`]: instantiation with
//! hostile arguments and the other standard's instance; [`calls`], [`values`],
//! [`no_variables`], [`derivatives`], [`step`]: the calls of FMI 3.0 only).

mod calls;
mod derivatives;
mod instantiate;
mod no_variables;
mod step;
mod table;
mod values;

pub use instantiate::OtherStandard;

use super::core::{standard_c_calls, Sequence, Standard};
use super::machine::{Kind, St, Target};
use super::model::Model;
use crate::ffi::{Component, FmuState, Status};
use crate::ffi3::{status_name, FUNCTION_NAMES_FMI3};
use crate::fmu::Fmu3;
use table::f;

/// FMI 3.0 (`fmi3Functions.h`).
pub enum Fmi3 {}

impl Sequence<'_, Fmi3> {
    /// fmi3GetVersion, the one function without an instance.
    fn check_version(&mut self) {
        // SAFETY: no arguments.
        let v = unsafe { (self.fmu.api.get_version)() };
        // SAFETY: the FMU returns a static NUL-terminated string (NULL checked).
        let v = (!v.is_null()).then(|| {
            unsafe { std::ffi::CStr::from_ptr(v) }
                .to_string_lossy()
                .into_owned()
        });
        self.stats.calls += 1;
        if v.as_deref() != Some("3.0") {
            self.fail(format!("fmi3GetVersion returned {v:?}"));
        }
    }

    /// The instance of a call: mostly a live one; NULL, foreign memory, a live instance's
    /// pointer misaligned, or the FMI 2.0 instance of the same binary sometimes.
    fn target3(&mut self) -> (Target, Component) {
        let r = self.rng.unit();
        if self.insts.is_empty() || r < 0.03 {
            return (Target::Null, std::ptr::null_mut());
        }
        if r < 0.05 {
            return (Target::Foreign, self.foreign_memory());
        }
        let i = self.rng.below(self.insts.len());
        if r < 0.065 {
            return (
                Target::Misaligned,
                self.insts[i].c.cast::<u8>().wrapping_add(1).cast(),
            );
        }
        if let (true, Some(other)) = (r < 0.08, &self.extra.other) {
            return (Target::OtherStandard, other.c);
        }
        (Target::Live(i), self.insts[i].c)
    }

    fn random_call(&mut self) {
        if self.insts.is_empty() || self.rng.chance(0.01) {
            self.instantiate(None);
            return;
        }
        let i = self.rng.below(self.insts.len());
        // A quarter of the calls are what a normal importer would do next.
        if self.rng.chance(0.25) {
            let inst = &self.insts[i];
            let (kind, event_mode, requested) =
                (inst.kind, inst.event_mode_used, inst.event_requested);
            let next = match inst.st {
                St::Instantiated if self.rng.chance(0.3) => f::SET_FLOAT64,
                St::Instantiated => f::ENTER_INIT,
                St::Init if self.rng.chance(0.2) => f::SET_FLOAT64,
                St::Init => f::EXIT_INIT,
                St::StepComplete if self.rng.chance(0.15) => f::SET_FLOAT64,
                St::StepComplete if self.rng.chance(0.05) => f::GET_FMU_STATE,
                St::StepComplete if event_mode && self.rng.chance(0.05) => f::ENTER_EVENT_MODE,
                St::StepComplete => f::DO_STEP,
                St::EventMode if self.rng.chance(0.35) => f::UPDATE_DISCRETE_STATES,
                St::EventMode if self.rng.chance(0.1) => f::SET_FLOAT64,
                St::EventMode if self.rng.chance(0.05) => f::GET_FMU_STATE,
                St::EventMode if kind == Kind::CoSimulation => f::ENTER_STEP_MODE,
                St::EventMode => f::ENTER_CONTINUOUS_TIME_MODE,
                St::ContinuousTimeMode if requested || self.rng.chance(0.03) => f::ENTER_EVENT_MODE,
                St::ContinuousTimeMode if self.rng.chance(0.05) => f::GET_FMU_STATE,
                St::ContinuousTimeMode if self.rng.chance(0.05) => f::SET_FLOAT64,
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
        // Half the calls are legal in the instance's state (so sequences reach deep states).
        let function = if self.rng.chance(0.5) {
            let (kind, st) = (self.insts[i].kind, self.insts[i].st);
            let legal: Vec<usize> = (0..f::COUNT)
                .filter(|&g| table::allowed(g, kind, st))
                .flat_map(|g| {
                    // Weight the calls that move the simulation on.
                    let w = match g {
                        f::DO_STEP => 8,
                        f::GET_FLOAT64 | f::SET_FLOAT64 => 3,
                        f::EXIT_INIT | f::ENTER_INIT | f::UPDATE_DISCRETE_STATES => 3,
                        f::SET_TIME | f::SET_CONTINUOUS_STATES | f::GET_DERIVATIVES => 3,
                        f::ENTER_CONTINUOUS_TIME_MODE | f::ENTER_STEP_MODE => 3,
                        f::FREE_INSTANCE => 0,
                        _ if f::unsupported(g) => 0,
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
    fn call(&mut self, function: usize) {
        match function {
            f::INSTANTIATE_ME | f::INSTANTIATE_CS | f::INSTANTIATE_SE => {
                self.instantiate(Some(function))
            }
            f::GET_VERSION => self.check_version(),
            _ => {
                let (target, c) = self.target3();
                self.call_on(function, target, c);
            }
        }
    }
}

impl Standard for Fmi3 {
    type Fmu = Fmu3;
    fn fmu_name(fmu: &Fmu3) -> &str {
        fmu.name()
    }
    fn model(fmu: &Fmu3) -> Model {
        Model::fmi3(&fmu.md)
    }
    type Extra = Extra;
    const NAMES: &'static [&'static str] = &FUNCTION_NAMES_FMI3;
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
        table::interface_of(function)
    }
    fn status_allowed(function: usize, s: Status) -> bool {
        table::status_allowed(function, s)
    }
    fn moves_states(function: usize) -> bool {
        table::moves_states(function)
    }

    fn begin(seq: &mut Sequence<Self>) {
        seq.check_version();
        seq.other_standard();
    }
    fn end(seq: &mut Sequence<Self>) {
        seq.free_other_standard();
    }
    fn instantiate(seq: &mut Sequence<Self>) {
        seq.instantiate(None);
    }
    standard_c_calls!(get_continuous_state_derivatives);

    unsafe fn get_values(fmu: &Fmu3, c: Component, vrs: &[u32], out: &mut [f64]) -> Status {
        // SAFETY: a live instance (the caller's promise), arrays of their lengths.
        unsafe { (fmu.api.get_float64)(c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr(), out.len()) }
    }
}

/// What an FMI 3.0 sequence keeps besides the shared state.
#[derive(Default)]
pub struct Extra {
    /// An FMI 2.0 instance of the same binary, its FMU state and that state's bytes.
    pub other: Option<OtherStandard>,
}
