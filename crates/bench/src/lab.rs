//! One run of the lab: the native figures of each mechanism, the instruction counts under
//! valgrind, the Oscillator's work–precision, the FMPy and scipy figures and the clean
//! build, each where the [`Plan`] asks for it, into one [`Report`].

use crate::binary::Binary;
use crate::build_time::clean_build;
use crate::c_step;
use crate::effort::{steps_per_run, Effort};
use crate::energies::{self, TwinProbe};
use crate::figures;
use crate::instructions::{self, ProbeCommand};
use crate::precision::{self, Problem};
use crate::progress;
use crate::python;
use crate::report::{CStep, Report};
use mechfmu_host::archive::{self, Extracted};
use std::path::PathBuf;

/// What `mechfmu bench` asks of the lab.
pub struct Plan<'a> {
    /// The workspace's root: the lab's files go to its `target/bench/`, the FMPy script is
    /// its `scripts/bench_fmpy.py`, a clean build runs there.
    pub root: PathBuf,
    /// The mechanisms: model identifier and `.fmu` (built with the runtime's `bench`
    /// feature), each of which exists.
    pub fmus: Vec<(String, PathBuf)>,
    pub effort: Effort,
    /// Only the Model Exchange figures (and their instruction counts).
    pub me_only: bool,
    /// How to run the probe under valgrind, for the instruction counts (None: not counted).
    pub instructions: Option<ProbeCommand>,
    /// The Python interpreter of the FMPy and scipy figures, provisioned when asked (None:
    /// skipped).
    pub python: Option<&'a dyn Fn() -> Result<PathBuf, String>>,
    /// The cargo program to time a clean build of every FMU with (None: not timed).
    pub clean_build: Option<String>,
    /// The test executables of the mechanisms declared again from their energies, whose
    /// instructions are counted against the hand-written ones' (empty: not counted).
    pub energies: Vec<TwinProbe>,
}

/// A mechanism's FMU as the lab loaded it.
struct Loaded {
    files: Extracted,
    binary: Binary,
}

/// Measures what `plan` asks for.
pub fn run(plan: &Plan) -> Result<Report, String> {
    let mut report = Report {
        runs: plan.effort.runs,
        ..Report::default()
    };
    let loaded = measure(plan, &mut report)?;
    if !plan.me_only {
        progress::show("the C step");
        let (h, tol) = c_step::AGAINST_C;
        report.c_step = Some(CStep {
            ns: c_step::ns_per_step(h, tol, c_step::STEPS, plan.effort.runs)?,
            instructions: None,
        });
    }
    if !plan.me_only {
        progress::show("catch_unwind");
        report.catch_unwind = Some(figures::catch_unwind_cost(plan.effort.runs));
    }
    if let Some(command) = &plan.instructions {
        if instructions::available() {
            count_instructions(plan, command, &loaded, &mut report)?;
        } else {
            (report.notes).push("--instructions: valgrind is not installed".into());
        }
    }
    if !plan.energies.is_empty() {
        if instructions::available() {
            progress::show("declared from energies: instructions under valgrind");
            report.energies = energies::count(&plan.energies)?;
        } else {
            (report.notes).push("--energies: valgrind is not installed".into());
        }
    }
    if plan.me_only {
        progress::clear();
        return Ok(report);
    }
    let problem = work_precision(plan, &loaded, &mut report)?;
    match plan.python {
        None => (report.notes).push("FMPy and scipy skipped (--no-python)".into()),
        Some(interpreter) => {
            progress::clear();
            let interpreter = interpreter()?;
            progress::show("FMPy low-level loops, simulate_fmu, scipy work–precision (Python)");
            let binaries: Vec<&Binary> = loaded.iter().map(|l| &l.binary).collect();
            let config = python::config(&report, &binaries, problem.as_ref(), plan.effort);
            let script = plan.root.join("scripts/bench_fmpy.py");
            let result = python::run(&interpreter, &script, &config, &work_dir(plan))?;
            python::record(&result, &mut report);
        }
    }
    if let Some(cargo) = &plan.clean_build {
        progress::clear();
        let names: Vec<String> = plan.fmus.iter().map(|(name, _)| name.clone()).collect();
        report.build = Some(clean_build(cargo, &plan.root, &names)?);
    }
    progress::clear();
    Ok(report)
}

fn work_dir(plan: &Plan) -> PathBuf {
    plan.root.join("target/bench")
}

/// Loads each mechanism's FMU and measures it natively (its Model Exchange figures alone
/// with `me_only`), with a note for what its binary lacks.
fn measure(plan: &Plan, report: &mut Report) -> Result<Vec<Loaded>, String> {
    let mut loaded = Vec::new();
    for (name, fmu) in &plan.fmus {
        let files = archive::extract(fmu, &work_dir(plan).join(name))?;
        let binary = Binary::load(&files.binary, &files.model_description)?;
        if !binary.has_counters() {
            report.notes.push(format!(
                "{name}: the binary exports no mechfmu_counters/mechfmu_bench (built without the runtime's `bench` feature: drop --no-build): no split"
            ));
        }
        let figures = figures::measure(
            name,
            fmu.clone(),
            &binary,
            plan.effort,
            plan.me_only,
            &progress::show,
        )?;
        if binary.fmi3.is_none() {
            report.notes.push(format!(
                "{name}: the binary exports no FMI 3.0 functions: no fmi3DoStep figures"
            ));
        }
        if figures.model_exchange.is_none() {
            report.notes.push(format!(
                "{name}: no Model Exchange figures (the FMU declares no ModelExchange or its binary lacks the functions)"
            ));
        }
        report.mechanisms.push(figures);
        loaded.push(Loaded { files, binary });
    }
    Ok(loaded)
}

/// The instruction counts of each mechanism under valgrind, by the probe `command` runs.
fn count_instructions(
    plan: &Plan,
    command: &ProbeCommand,
    loaded: &[Loaded],
    report: &mut Report,
) -> Result<(), String> {
    let effort = plan.effort;
    if let Some(c) = &mut report.c_step {
        progress::show("the C step: instructions under valgrind");
        c.instructions = Some(instructions::count_c_step(
            command,
            c_step::AGAINST_C,
            c_step::STEPS,
        )?);
    }
    for (m, l) in report.mechanisms.iter_mut().zip(loaded) {
        if !plan.me_only {
            progress::show(&format!("{}: instructions under valgrind", m.name));
            let n = steps_per_run(&l.binary, 1e-2, effort);
            let fmi3 = l.binary.fmi3.is_some();
            let counts = instructions::count(command, &l.files, (1e-2, 1e-6), effort, n, fmi3)?;
            m.instructions = Some(counts);
        }
        if m.model_exchange.is_some() {
            progress::show(&format!(
                "{}: Model Exchange instructions under valgrind",
                m.name
            ));
            let counts = instructions::count_model_exchange(command, &l.files, effort)?;
            m.me_instructions = Some(counts);
        }
    }
    Ok(())
}

/// The Oscillator's work–precision from a native loop, with a note where it cannot be run;
/// its problem, for scipy's side.
fn work_precision(
    plan: &Plan,
    loaded: &[Loaded],
    report: &mut Report,
) -> Result<Option<Problem>, String> {
    let oscillator = (loaded.iter())
        .map(|l| &l.binary)
        .find(|bin| bin.description.model_identifier == "Oscillator");
    let Some(bin) = oscillator else {
        (report.notes).push("work–precision: needs the Oscillator among the mechanisms".into());
        return Ok(None);
    };
    let problem = match Problem::of(&bin.description) {
        Ok(p) => p,
        Err(e) => {
            report.notes.push(format!("work–precision skipped: {e}"));
            return Ok(None);
        }
    };
    progress::show("Oscillator: work–precision, native loop");
    report.precision = precision::native(bin, &problem, plan.effort.runs)?;
    Ok(Some(problem))
}
