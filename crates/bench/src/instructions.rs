//! Repeatable figures: instructions executed, counted by valgrind (`cachegrind
//! --cache-sim=no`), which no neighbour on the machine can disturb.
//!
//! The benchmark runs itself under valgrind in a probe mode (`mechfmu bench --probe ...`:
//! the command's program, given as a [`ProbeCommand`], with the hidden options of
//! [`ProbeArgs`]) that loads the FMU and repeats one kind of work `k` times; the difference
//! between `k = 3` and `k = 1` divided by the work done removes start-up and loading.

use crate::binary::Binary;
use crate::c_step;
use crate::effort::{steps_per_run, Effort};
use crate::instance::Instance;
use crate::model_exchange;
use crate::native::{self, Split};
use clap::ValueEnum;
use mechfmu::simulation::Part;
use mechfmu_host::archive::Extracted;
use std::path::{Path, PathBuf};
use std::process::Command;

/// What a probe repeats.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Probe {
    /// A run of `fmi2DoStep` over the default experiment.
    Step,
    /// The same run with one `fmi2GetReal` (the first output) after every step: what an
    /// importer's loop does, held against the C step.
    StepGet,
    /// The same run of the C step (the Oscillator's, [`crate::c_step`]; no FMU).
    CStep,
    /// The same run of `fmi3DoStep` (an FMI 3.0 instance of the same binary).
    Fmi3Step,
    /// As many model evaluations alone as a run of steps does.
    Eval,
    /// As many right-hand-side callbacks (load, evaluate, read derivatives).
    Rhs,
    /// The solver alone over the same steps.
    Integrate,
    /// `Simulation::step` over the same steps (no FMI layer).
    SimStep,
    /// 10 000 `fmi2GetReal` of all outputs.
    Get,
    /// A Model Exchange walk through the API (`fmi2SetTime` + `fmi2SetContinuousStates` +
    /// `fmi2GetDerivatives` per point; see [`crate::model_exchange`]).
    MeApi,
    /// The same walk by the simulation's Model Exchange code (`Part::ModelExchange`).
    MeSimulation,
    /// The same points by the equations alone (`Part::Evaluate`).
    MeEquations,
}

/// Calls of `fmi2GetReal` per `Get` repetition.
pub const GET_CALLS: usize = 10_000;

/// Instruction counts per unit of work at one communication step and tolerance.
#[derive(Clone, Copy, Debug, Default)]
pub struct Counts {
    pub h: f64,
    pub tol: f64,
    /// Per `fmi2DoStep`, everything.
    pub per_step: f64,
    /// Per `fmi2DoStep` and one `fmi2GetReal` of the first output: an importer's loop.
    pub step_get_per_step: f64,
    /// Per `fmi2DoStep`, the parts alone (as in [`crate::native::StepFigures`]).
    pub rhs_per_step: f64,
    pub callback_per_step: f64,
    pub integrate_per_step: f64,
    pub sim_step_per_step: f64,
    /// Per `fmi2GetReal` of all outputs.
    pub per_get_real: f64,
    /// Per `fmi3DoStep` over the same run (None: the binary has no FMI 3.0 functions).
    pub fmi3_per_step: Option<f64>,
}

impl Counts {
    /// Instructions per `fmi3DoStep` over those per `fmi2DoStep`.
    pub fn fmi3_ratio(&self) -> Option<f64> {
        self.fmi3_per_step.map(|n| n / self.per_step)
    }

    /// The same split as [`Split`], in instructions.
    pub fn split(&self) -> Split {
        Split {
            rhs: self.rhs_per_step,
            copying: self.callback_per_step - self.rhs_per_step,
            solver: self.integrate_per_step - self.callback_per_step,
            step: self.sim_step_per_step - self.integrate_per_step,
            fmi: self.per_step - self.sim_step_per_step,
        }
    }

    pub fn to_json(self) -> serde_json::Value {
        serde_json::json!({
            "h": self.h, "tol": self.tol,
            "instructions_per_step": self.per_step,
            "instructions_per_step_and_get_real": self.step_get_per_step,
            "split_per_step": {
                "rhs": self.split().rhs, "copying": self.split().copying,
                "solver": self.split().solver, "step": self.split().step, "fmi": self.split().fmi,
            },
            "beyond_rhs_per_step": self.split().beyond_rhs(),
            "runtime_plumbing_per_step": self.split().runtime(),
            "instructions_per_get_real_outputs": self.per_get_real,
            "fmi3_instructions_per_step": self.fmi3_per_step,
            "fmi3_over_fmi2": self.fmi3_ratio(),
        })
    }
}

/// Instructions per derivative evaluation of Model Exchange (see
/// [`crate::model_exchange::MeFigures`]).
#[derive(Clone, Copy, Debug, Default)]
pub struct MeCounts {
    pub api: f64,
    pub simulation: f64,
    pub equations: f64,
}

impl MeCounts {
    pub fn overhead(&self) -> f64 {
        self.api - self.equations
    }

    pub fn to_json(self) -> serde_json::Value {
        serde_json::json!({
            "api_per_evaluation": self.api,
            "simulation_per_evaluation": self.simulation,
            "equations_per_evaluation": self.equations,
            "overhead_per_evaluation": self.overhead(),
            "fmi_layer_per_evaluation": self.api - self.simulation,
            "simulation_code_per_evaluation": self.simulation - self.equations,
        })
    }
}

/// Whether valgrind can be run.
pub fn available() -> bool {
    Command::new("valgrind")
        .arg("--version")
        .output()
        .is_ok_and(|o| o.status.success())
}

/// Instructions of `exe args` under cachegrind.
fn instructions(program: &Path, args: &[String]) -> Result<u64, String> {
    instructions_with(program, args, &[])
}

/// Instructions of `exe args` under cachegrind, with `environment` set.
pub(crate) fn instructions_with(
    program: &Path,
    args: &[String],
    environment: &[(&str, String)],
) -> Result<u64, String> {
    let output = Command::new("valgrind")
        .args([
            "--tool=cachegrind",
            "--cache-sim=no",
            "--cachegrind-out-file=/dev/null",
        ])
        .arg(program)
        .args(args)
        .envs(environment.iter().map(|(k, v)| (k, v)))
        .output()
        .map_err(|e| format!("cannot run valgrind: {e}"))?;
    let stderr = String::from_utf8_lossy(&output.stderr);
    if !output.status.success() {
        return Err(format!(
            "the probe failed under valgrind ({}): {stderr}",
            output.status
        ));
    }
    stderr
        .lines()
        .find_map(|l| {
            let (_, rest) = l
                .split_once("I   refs:")
                .or_else(|| l.split_once("I refs:"))?;
            rest.trim().replace(',', "").parse::<u64>().ok()
        })
        .ok_or_else(|| format!("no instruction count in valgrind's output: {stderr}"))
}

/// Counts for one FMU binary at `(h, tol)` by running `command --probe ...` under
/// valgrind; `steps` is the steps per run of an ordinary run; with `fmi3`, also
/// `fmi3DoStep` over the same run.
pub fn count(
    command: &ProbeCommand,
    fmu: &Extracted,
    (h, tol): (f64, f64),
    effort: Effort,
    steps: usize,
    fmi3: bool,
) -> Result<Counts, String> {
    let diff = |probe| difference(command, fmu, h, tol, effort, probe);
    Ok(Counts {
        h,
        tol,
        per_step: diff(Probe::Step)? / steps as f64,
        step_get_per_step: diff(Probe::StepGet)? / steps as f64,
        rhs_per_step: diff(Probe::Eval)? / steps as f64,
        callback_per_step: diff(Probe::Rhs)? / steps as f64,
        integrate_per_step: diff(Probe::Integrate)? / steps as f64,
        sim_step_per_step: diff(Probe::SimStep)? / steps as f64,
        per_get_real: diff(Probe::Get)? / GET_CALLS as f64,
        fmi3_per_step: match fmi3 {
            true => Some(diff(Probe::Fmi3Step)? / steps as f64),
            false => None,
        },
    })
}

/// Instructions per communication step of the C step ([`crate::c_step`]) at `(h, tol)`,
/// over `steps` steps (the Oscillator's run), under valgrind.
pub fn count_c_step(
    command: &ProbeCommand,
    (h, tol): (f64, f64),
    steps: usize,
) -> Result<f64, String> {
    let per = |repeat: usize| -> Result<u64, String> {
        let args = ProbeArgs {
            probe: Some(Probe::CStep),
            probe_so: None,
            probe_xml: None,
            probe_h: h,
            probe_tol: tol,
            probe_repeat: repeat,
            probe_max_steps: steps,
        };
        let mut args_of_command = command.args.clone();
        args_of_command.extend(args.command_line());
        instructions(&command.program, &args_of_command)
    };
    let one = per(1)?;
    let three = per(3)?;
    Ok(three.saturating_sub(one) as f64 / 2.0 / steps as f64)
}

/// Instructions per derivative evaluation of Model Exchange (through the API, by the
/// simulation's code, the equations alone), for one FMU binary: the walks of
/// [`crate::model_exchange`] of `effort.max_steps` evaluations, under valgrind.
pub fn count_model_exchange(
    command: &ProbeCommand,
    fmu: &Extracted,
    effort: Effort,
) -> Result<MeCounts, String> {
    let tol = Binary::load(&fmu.binary, &fmu.model_description)?
        .description
        .tolerance;
    let n = model_exchange::points(effort.max_steps) as f64;
    let diff = |probe| difference(command, fmu, 1e-2, tol, effort, probe);
    Ok(MeCounts {
        api: diff(Probe::MeApi)? / n,
        simulation: diff(Probe::MeSimulation)? / n,
        equations: diff(Probe::MeEquations)? / n,
    })
}

/// Instructions of `probe` repeated 3 times minus once, over 2: one repetition's, without
/// start-up and loading.
fn difference(
    command: &ProbeCommand,
    fmu: &Extracted,
    h: f64,
    tol: f64,
    effort: Effort,
    probe: Probe,
) -> Result<f64, String> {
    let per = |repeat: usize| -> Result<u64, String> {
        let args = ProbeArgs {
            probe: Some(probe),
            probe_so: Some(fmu.binary.clone()),
            probe_xml: Some(fmu.model_description.clone()),
            probe_h: h,
            probe_tol: tol,
            probe_repeat: repeat,
            probe_max_steps: effort.max_steps,
        };
        let mut args_of_command = command.args.clone();
        args_of_command.extend(args.command_line());
        instructions(&command.program, &args_of_command)
    };
    let one = per(1)?;
    let three = per(3)?;
    Ok(three.saturating_sub(one) as f64 / 2.0)
}

/// How the lab runs a probe: `program` with `args` before the probe's own options (the
/// `mechfmu` command and `bench`).
#[derive(Clone, Debug)]
pub struct ProbeCommand {
    pub program: PathBuf,
    pub args: Vec<String>,
}

/// The probe's options, hidden options of `mechfmu bench`: written by [`count`] for the
/// command it runs under valgrind, read back by the command's parser there.
#[derive(clap::Args, Clone, Debug)]
pub struct ProbeArgs {
    /// The instruction-count probe, run by the benchmark under valgrind.
    #[arg(long, hide = true, value_enum)]
    pub probe: Option<Probe>,
    #[arg(long, hide = true)]
    pub probe_so: Option<PathBuf>,
    #[arg(long, hide = true)]
    pub probe_xml: Option<PathBuf>,
    #[arg(long, hide = true, default_value_t = 1e-2)]
    pub probe_h: f64,
    #[arg(long, hide = true, default_value_t = 1e-6)]
    pub probe_tol: f64,
    #[arg(long, hide = true, default_value_t = 1)]
    pub probe_repeat: usize,
    #[arg(long, hide = true, default_value_t = 100_000)]
    pub probe_max_steps: usize,
}

impl ProbeArgs {
    /// The options as a command line.
    fn command_line(&self) -> Vec<String> {
        let path = |p: &Option<PathBuf>| p.as_deref().map(Path::display).map(|d| d.to_string());
        let probe = (self.probe)
            .and_then(|p| p.to_possible_value())
            .map(|v| v.get_name().to_string());
        [
            ("--probe", probe),
            ("--probe-so", path(&self.probe_so)),
            ("--probe-xml", path(&self.probe_xml)),
            ("--probe-h", Some(self.probe_h.to_string())),
            ("--probe-tol", Some(self.probe_tol.to_string())),
            ("--probe-repeat", Some(self.probe_repeat.to_string())),
            ("--probe-max-steps", Some(self.probe_max_steps.to_string())),
        ]
        .into_iter()
        .filter_map(|(option, value)| Some([option.to_string(), value?]))
        .flatten()
        .collect()
    }

    /// The probe itself (run under valgrind): `probe_repeat` repetitions of `probe`.
    pub fn run(&self) -> Result<(), String> {
        let (h, tol, repeat) = (self.probe_h, self.probe_tol, self.probe_repeat);
        let max_steps = self.probe_max_steps;
        if self.probe == Some(Probe::CStep) {
            // the same warm-up run as the FMUs' probes, so that it cancels in the difference
            for _ in 0..=repeat {
                std::hint::black_box(c_step::run(h, tol, max_steps)?);
            }
            return Ok(());
        }
        let (Some(probe), Some(so), Some(xml)) = (self.probe, &self.probe_so, &self.probe_xml)
        else {
            return Err("--probe needs --probe-so and --probe-xml".into());
        };
        let binary = Binary::load(so, xml)?;
        match probe {
            Probe::MeApi | Probe::MeSimulation | Probe::MeEquations => {
                probe_model_exchange(&binary, probe, tol, repeat, max_steps)
            }
            Probe::Fmi3Step => crate::fmi3::probe(&binary, h, tol, repeat, max_steps),
            _ => probe_co_simulation(&binary, probe, h, tol, repeat, max_steps),
        }
    }
}

/// The Co-Simulation probes: `repeat` repetitions of `probe` after the same warm-up.
fn probe_co_simulation(
    binary: &Binary,
    probe: Probe,
    h: f64,
    tol: f64,
    repeat: usize,
    max_steps: usize,
) -> Result<(), String> {
    let n = steps_per_run(binary, h, Effort::probe(max_steps));
    let mut inst = Instance::new(binary)?;
    // The same warm-up in every probe, so it cancels in the difference.
    let (_, work) = native::step_run(&mut inst, tol, h, n, true)?;
    match probe {
        Probe::Step => {
            for _ in 0..repeat {
                native::step_run(&mut inst, tol, h, n, false)?;
            }
        }
        Probe::StepGet => {
            let output = binary.first_output()?;
            for _ in 0..repeat {
                native::step_get_run(&mut inst, tol, h, n, output)?;
            }
        }
        Probe::Eval | Probe::Rhs | Probe::Integrate | Probe::SimStep => {
            let span = n as f64 * h;
            let (part, count, h) = match probe {
                Probe::Eval => (Part::Evaluate, work[3], span),
                Probe::Rhs => (Part::Rhs, work[3], span),
                Probe::Integrate => (Part::Integrate, n as u64, h),
                _ => (Part::Step, n as u64, h),
            };
            inst.start(tol, binary.description.start, &[], true)?;
            for _ in 0..repeat {
                inst.bench(part, count, h)?;
            }
        }
        Probe::Get => {
            let outputs: Vec<u32> = binary
                .description
                .with_causality("output")
                .iter()
                .map(|v| v.vr)
                .collect();
            let mut out = vec![0.0; outputs.len()];
            for _ in 0..repeat * GET_CALLS {
                inst.get_real(&outputs, &mut out);
            }
        }
        Probe::MeApi | Probe::MeSimulation | Probe::MeEquations | Probe::Fmi3Step => {}
        Probe::CStep => {}
    }
    Ok(())
}

/// The Model Exchange probes: `repeat` walks from the initial point (after the same
/// warm-up in every probe: one walk of the equations, which leaves the instance where it
/// was).
fn probe_model_exchange(
    binary: &Binary,
    probe: Probe,
    tol: f64,
    repeat: usize,
    max_steps: usize,
) -> Result<(), String> {
    let d = &binary.description;
    let n = model_exchange::points(max_steps);
    let span = d.stop - d.start;
    let mut inst = Instance::model_exchange(binary)?;
    inst.start(tol, d.start, &[], false)?;
    inst.enter_continuous_time_mode()?;
    let mut x0 = vec![0.0; d.states];
    inst.continuous_states(&mut x0)?;
    let (mut x, mut dx) = (x0.clone(), vec![0.0; d.states]);
    let me = inst.me()?;
    let mut walk = || -> Result<(), String> {
        x.copy_from_slice(&x0);
        let status = model_exchange::api_walk(&me, d.start, span / n as f64, n, &mut x, &mut dx);
        if status != mechfmu::fmi2::ffi::fmi2OK {
            return Err(format!("the Model Exchange walk returned {status}"));
        }
        Ok(())
    };
    inst.bench(Part::Evaluate, n, span)?;
    for _ in 0..repeat {
        match probe {
            Probe::MeApi => walk()?,
            Probe::MeSimulation => inst.bench(Part::ModelExchange, n, span)?,
            _ => inst.bench(Part::Evaluate, n, span)?,
        }
    }
    Ok(())
}
