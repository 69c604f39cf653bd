//! `mechfmu bench`: per mechanism, ns per `fmi2DoStep` from a native loop and where they go,
//! ns per `fmi2GetReal`, µs per step under FMPy, the Oscillator's work–precision against
//! scipy; a table on stdout and JSON for comparing runs. The lab that measures is the crate
//! `mechfmu-bench`; this command selects the mechanisms, builds their FMUs with the
//! runtime's `bench` feature, provisions the Python environment when asked, and runs the
//! lab's valgrind probe when the lab re-invokes it (`--probe`).

use crate::build::workspace::{cargo, fmu_crates, workspace_root};
use crate::build::{select, Flavor, Platforms};
use crate::home::python::ensure_venv;
use crate::package::write_fmus;
use mechfmu_bench::effort::Effort;
use mechfmu_bench::energies::TwinProbe;
use mechfmu_bench::instructions::{ProbeArgs, ProbeCommand};
use mechfmu_bench::lab::{self, Plan};
use std::path::{Path, PathBuf};
use std::process::Command;

#[derive(clap::Args)]
pub struct Args {
    /// Model identifiers (default: every mechanism).
    names: Vec<String>,
    /// Where to write the results as JSON (relative to the workspace root); the same figures
    /// go to a Markdown file beside it (`.md`).
    #[arg(long, default_value = "target/bench.json")]
    json: PathBuf,
    /// Folder for the .fmu files built with the runtime's `bench` feature (relative to the
    /// workspace root).
    #[arg(long, default_value = "target/bench/fmus")]
    fmus: PathBuf,
    /// Measure the .fmu files of --fmus as they are, without building them first.
    #[arg(long)]
    no_build: bool,
    /// Timed runs per figure (medians are reported).
    #[arg(long, default_value_t = 15)]
    runs: usize,
    /// A smoke test: few runs and short loops.
    #[arg(long)]
    quick: bool,
    /// Skip the FMPy and scipy figures.
    #[arg(long)]
    no_python: bool,
    /// Only the Model Exchange figures: ns per derivative evaluation through the API
    /// (fmi2SetTime + fmi2SetContinuousStates + fmi2GetDerivatives) next to the equations
    /// alone (with --instructions, their instruction counts).
    #[arg(long)]
    me_only: bool,
    /// Also count instructions with valgrind (repeatable on a busy machine; slower), and
    /// those of the mechanisms declared again from their energies (`tests/energies`, where
    /// the workspace has them) against the hand-written ones'.
    #[arg(long)]
    instructions: bool,
    /// Also time a clean release build of every FMU for every platform (`cargo run
    /// --release -- build --platform all` in a fresh target directory; takes minutes).
    #[arg(long)]
    build_time: bool,
    /// The Cargo.toml of the workspace holding the mechanisms.
    #[arg(long)]
    manifest_path: Option<PathBuf>,

    #[command(flatten)]
    probe: ProbeArgs,
}

pub fn run(args: Args) -> Result<(), String> {
    if args.probe.probe.is_some() {
        return args.probe.run();
    }
    let root = workspace_root(args.manifest_path.as_deref())?;
    let fmus_dir = root.join(&args.fmus);
    let crates = select(fmu_crates(args.manifest_path.as_deref())?, &args.names)?;
    let names: Vec<String> = crates.iter().map(|c| c.model.clone()).collect();
    if !args.no_build {
        let target_dir = root.join("target/bench/build");
        write_fmus(
            &names,
            &fmus_dir,
            args.manifest_path.as_deref(),
            Flavor::Bench {
                target_dir: &target_dir,
            },
            Platforms::Host,
            None,
        )?;
    }
    let mut fmus = Vec::new();
    for name in names.iter().cloned() {
        let fmu = fmus_dir.join(format!("{name}.fmu"));
        if !fmu.exists() {
            return Err(format!(
                "{} does not exist: drop --no-build to build it with the runtime's `bench` feature",
                fmu.display()
            ));
        }
        fmus.push((name, fmu));
    }
    let energies = match args.instructions && !args.me_only {
        true => twin_probes(&root, &names)?,
        false => Vec::new(),
    };
    let python = || ensure_venv(&root);
    let plan = Plan {
        root: root.clone(),
        fmus,
        effort: match args.quick {
            true => Effort::quick(),
            false => Effort::full(args.runs),
        },
        me_only: args.me_only,
        instructions: args.instructions.then(probe_command).transpose()?,
        python: (!args.no_python).then_some(&python as &dyn Fn() -> Result<PathBuf, String>),
        clean_build: args.build_time.then(cargo),
        energies,
    };
    lab::run(&plan)?.write(&root.join(&args.json))
}

/// The package that declares the workspace's mechanisms again from their energies.
const TWINS_PACKAGE: &str = "mechfmu-energies";

/// The test executables of the twins of `names` (`tests/energies`), built in release mode;
/// none when the workspace has no such package (a workspace of one's own mechanisms).
fn twin_probes(root: &Path, names: &[String]) -> Result<Vec<TwinProbe>, String> {
    if !root.join("tests/energies/Cargo.toml").exists() {
        return Ok(Vec::new());
    }
    let output = Command::new(cargo())
        .current_dir(root)
        .args(["test", "--release", "--no-run", "--message-format=json"])
        .args(["-p", TWINS_PACKAGE])
        .output()
        .map_err(|e| format!("cannot run cargo: {e}"))?;
    if !output.status.success() {
        return Err(format!(
            "cargo test --no-run -p {TWINS_PACKAGE} failed:\n{}",
            String::from_utf8_lossy(&output.stderr)
        ));
    }
    let mut probes = Vec::new();
    for line in String::from_utf8_lossy(&output.stdout).lines() {
        let Ok(message) = serde_json::from_str::<serde_json::Value>(line) else {
            continue;
        };
        let is_test_file = message["target"]["kind"] == serde_json::json!(["test"]);
        let (Some(file), Some(executable)) = (
            message["target"]["name"].as_str(),
            message["executable"].as_str(),
        ) else {
            continue;
        };
        let mechanism = model_identifier(file);
        if is_test_file && names.contains(&mechanism) {
            probes.push(TwinProbe {
                mechanism,
                executable: PathBuf::from(executable),
            });
        }
    }
    probes.sort_by(|a, b| a.mechanism.cmp(&b.mechanism));
    Ok(probes)
}

/// The model identifier a twin's test file is named after: `two_mass_oscillator` →
/// `TwoMassOscillator`.
fn model_identifier(file: &str) -> String {
    file.split('_')
        .map(|word| {
            let mut chars = word.chars();
            chars.next().map_or(String::new(), |first| {
                first.to_uppercase().chain(chars).collect()
            })
        })
        .collect()
}

/// This program as the lab runs its probe: `mechfmu bench --probe ...`.
fn probe_command() -> Result<ProbeCommand, String> {
    let program = std::env::current_exe().map_err(|e| format!("cannot find this program: {e}"))?;
    Ok(ProbeCommand {
        program,
        args: vec!["bench".into()],
    })
}

#[cfg(test)]
mod tests {
    use super::model_identifier;

    #[test]
    fn a_twins_test_file_names_its_mechanism() {
        assert_eq!(model_identifier("two_mass_oscillator"), "TwoMassOscillator");
        assert_eq!(model_identifier("crane"), "Crane");
    }
}
