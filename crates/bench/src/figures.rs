//! Everything measured for one mechanism ([`Figures`]), and the native runs that measure it.

use crate::binary::Binary;
use crate::c_step;
use crate::clock::{self, Stat};
use crate::effort::Effort;
use crate::instructions;
use crate::model_exchange;
use crate::native::{self, StepFigures};
use std::path::PathBuf;

/// Communication steps of the `fmi2DoStep` figures.
pub const STEPS: [f64; 2] = [1e-3, 1e-2];
/// Tolerances of the `fmi2DoStep` figures.
pub const TOLERANCES: [f64; 2] = [1e-6, 1e-10];
/// `fmi2GetReal` of this many variables has a target of its own.
pub const GET_MANY: usize = 10;

/// `n` value references and the ns per call of one array call with them.
#[derive(Clone, Debug)]
pub struct CallFigures {
    pub n: usize,
    pub ns: Stat,
}

/// Everything measured for one mechanism.
#[derive(Clone, Debug)]
pub struct Figures {
    pub name: String,
    pub fmu: PathBuf,
    pub fmu_bytes: u64,
    pub steps: Vec<StepFigures>,
    /// `fmi2GetReal` of all outputs.
    pub get_outputs: CallFigures,
    /// `fmi2GetReal` of the first [`GET_MANY`] value references (all, if fewer).
    pub get_many: CallFigures,
    /// `fmi2SetReal` of all inputs (None without inputs).
    pub set_inputs: Option<CallFigures>,
    /// The DefaultExperiment's step and tolerance.
    pub default_h: f64,
    pub default_tol: f64,
    /// ns per cycle set inputs + `fmi2DoStep` + get outputs at the default step/tolerance.
    pub cycle: Stat,
    /// ns per `fmi2DoStep` + one `fmi2GetReal` at [`c_step::AGAINST_C`]: what is held
    /// against the C step.
    pub step_get: Stat,
    /// One derivative evaluation through Model Exchange (None: the FMU has none).
    pub model_exchange: Option<model_exchange::MeFigures>,
    pub instructions: Option<instructions::Counts>,
    /// Instructions per derivative evaluation of Model Exchange (valgrind).
    pub me_instructions: Option<instructions::MeCounts>,
    /// µs per step of FMPy's low-level loop (same cycle), and of `simulate_fmu`.
    pub fmpy: Option<Stat>,
    pub simulate_fmu: Option<Stat>,
}

impl Figures {
    /// The native cost of the FMPy cycle as a fraction of FMPy's µs per step.
    pub fn fmu_share(&self) -> Option<f64> {
        self.fmpy.map(|f| self.cycle.median * 1e-3 / f.median)
    }

    pub fn step(&self, h: f64, tol: f64) -> Option<&StepFigures> {
        self.steps.iter().find(|s| s.h == h && s.tol == tol)
    }
}

/// Runs the native measurements of one loaded FMU; with `me_only` (`mechfmu bench
/// --me-only`) its Model Exchange figures alone, the others left unmeasured (no runs).
pub fn measure(
    name: &str,
    fmu: PathBuf,
    binary: &Binary,
    effort: Effort,
    me_only: bool,
    progress: &dyn Fn(&str),
) -> Result<Figures, String> {
    let d = &binary.description;
    let steps = if me_only {
        Vec::new()
    } else {
        let configurations: Vec<(f64, f64)> = STEPS
            .iter()
            .flat_map(|&h| TOLERANCES.iter().map(move |&tol| (h, tol)))
            .collect();
        native::step_figures(binary, &configurations, effort, &|what| {
            progress(&format!("{name}: {what}"))
        })?
    };
    let me = model_exchange::figures(binary, effort, &|what| progress(&format!("{name}: {what}")))?;
    let unmeasured = |n: usize| CallFigures {
        n,
        ns: Stat::of(&[]),
    };
    let figures = Figures {
        name: name.to_string(),
        fmu_bytes: std::fs::metadata(&fmu).map(|m| m.len()).unwrap_or(0),
        fmu,
        steps,
        get_outputs: unmeasured(0),
        get_many: unmeasured(0),
        set_inputs: None,
        default_h: d.step,
        default_tol: d.tolerance,
        cycle: Stat::of(&[]),
        step_get: Stat::of(&[]),
        model_exchange: me,
        instructions: None,
        me_instructions: None,
        fmpy: None,
        simulate_fmu: None,
    };
    if me_only {
        Ok(figures)
    } else {
        with_calls(figures, binary, effort, progress)
    }
}

/// `figures` with the array calls and the co-simulation cycle measured.
fn with_calls(
    figures: Figures,
    binary: &Binary,
    effort: Effort,
    progress: &dyn Fn(&str),
) -> Result<Figures, String> {
    let d = &binary.description;
    progress(&format!(
        "{}: fmi2GetReal, fmi2SetReal, co-simulation cycle",
        figures.name
    ));
    let outputs: Vec<u32> = d.with_causality("output").iter().map(|v| v.vr).collect();
    let many: Vec<u32> = d.variables.iter().take(GET_MANY).map(|v| v.vr).collect();
    let inputs = d.with_causality("input");
    let set_inputs = if inputs.is_empty() {
        None
    } else {
        let vrs: Vec<u32> = inputs.iter().map(|v| v.vr).collect();
        let values: Vec<f64> = inputs.iter().map(|v| v.start.unwrap_or(0.0)).collect();
        Some(CallFigures {
            n: vrs.len(),
            ns: native::set_real(binary, &vrs, &values, effort)?,
        })
    };
    Ok(Figures {
        get_outputs: CallFigures {
            n: outputs.len(),
            ns: native::get_real(binary, &outputs, effort)?,
        },
        get_many: CallFigures {
            n: many.len(),
            ns: native::get_real(binary, &many, effort)?,
        },
        set_inputs,
        cycle: native::cycle(binary, d.step, d.tolerance, effort)?,
        step_get: native::step_get(binary, c_step::AGAINST_C, effort)?,
        ..figures
    })
}

/// ns that `catch_unwind` adds around a call that does not panic (the guard every FMI
/// function runs under), measured here in the benchmark's own binary, built with the same
/// profile as the FMUs: (direct, guarded) ns per call, medians of `runs`.
pub fn catch_unwind_cost(runs: usize) -> (Stat, Stat) {
    #[inline(never)]
    fn work(x: u64) -> u64 {
        x.wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407)
    }
    const N: u64 = 1_000_000;
    let mut direct = Vec::new();
    let mut guarded = Vec::new();
    for _ in 0..runs {
        let (ns, _) = clock::time(|| {
            let mut x = 1u64;
            for _ in 0..N {
                x = std::hint::black_box(work)(x);
            }
            x
        });
        direct.push(ns / N as f64);
        let (ns, _) = clock::time(|| {
            let mut x = 1u64;
            for _ in 0..N {
                x = std::panic::catch_unwind(|| std::hint::black_box(work)(x)).unwrap_or(0);
            }
            x
        });
        guarded.push(ns / N as f64);
    }
    (Stat::of(&direct), Stat::of(&guarded))
}
