//! `mechfmu validate`: FMPy's validation and mechfmu's stricter checks of each FMU, its
//! reference cases (`<crate>/validation/cases.py`) under FMPy, and the same cases under two
//! more importers, libcosim and the Rust `fmi` crate (rust-fmi), each of which must agree with
//! FMPy; with a table, an exit status, and optionally a report.
//!
//! A mechanism named (or all of them) is validated through `<fmu dir>/<Name>.fmu` (FMI 2.0);
//! the Python side finds its FMI 3.0 FMU beside it, `<fmu dir>/fmi3/<Name>.fmu` (as `mechfmu
//! build` writes them), and runs the same cases on it under FMI 3.0 (`--no-fmi3`: not). An
//! FMI 3.0 `.fmu` given on the command line is validated as such (its checks and the cases).
//! A directory is handed over as it is: the Python side walks it for FMUs (an FMI cross-check
//! tree's as its rules lay them out) and `--cross-check-results DIR` writes the importer's
//! results the rules ask for. A system's SSP (`fmus/<System>.ssp`) is run for each of its
//! parameter sets by every SSP importer installed, each against the system's solution
//! (`mechfmu_validate.systems`).
//!
//! The work is done by the Python package `mechfmu_validate` (in `python/` of mechfmu's
//! files, [`crate::home::root`]: the checkout, or the installed command's copy), installed in
//! the venv that [`ensure_venv`]
//! provisions (editable, so the venv's interpreter imports it as is). The
//! fmi-crate importer is a separate executable, `mechfmu-fmi-run` (`tools/fmi-run`), which
//! this command builds first (`cargo build --profile importer -p mechfmu-fmi-run` in mechfmu's files,
//! a few minutes the first time; it needs libclang) and names to the Python side in `MECHFMU_FMI_RUN`. If it cannot
//! be built, the command says why and goes on: the fmi-crate rows then fail.

use crate::build::workspace::{cargo, fmu_crates, target_directory, MechanismCrate};
use crate::home::python::{ensure_venv, exit_status};
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode, ExitStatus};

#[derive(clap::Args)]
pub struct Args {
    /// FMU files, SSP files (a system: each parameter set in every SSP importer), directories
    /// to find FMUs in (an FMI cross-check tree: its FMUs for this platform, each against the
    /// reference files beside it), or model identifiers (found in --fmu-dir); default: every
    /// mechanism of the workspace.
    targets: Vec<String>,
    /// The Cargo.toml of the workspace or crate whose mechanisms (and their
    /// `validation/cases.py`) to use.
    #[arg(long)]
    manifest_path: Option<PathBuf>,
    /// Where FMUs named by model identifier are (as written by `mechfmu build --out`).
    #[arg(long, default_value = "fmus")]
    fmu_dir: PathBuf,
    /// Write DIR/index.md and DIR/index.html with one PNG plot per case.
    #[arg(long, value_name = "DIR")]
    report: Option<PathBuf>,
    /// Write the results as JSON.
    #[arg(long, value_name = "FILE")]
    json: Option<PathBuf>,
    /// Write the results as JUnit XML (one testcase per row of the table).
    #[arg(long, value_name = "FILE")]
    junit: Option<PathBuf>,
    /// Only the cases whose name contains this text (repeatable).
    #[arg(long = "case", value_name = "TEXT")]
    cases: Vec<String>,
    /// Write the README material: DIR/validation.md (the table) and the PNGs of the cases
    /// marked as highlights; for an SSP, DIR/validation/<system>-coupling.png (its plain
    /// Jacobi co-simulation at three steps against the system's solution).
    #[arg(long, value_name = "DIR")]
    readme: Option<PathBuf>,
    /// For each FMU of an FMI cross-check tree, write what an importer submits (its result,
    /// `passed`, `failed` or `rejected`, a README.md) to DIR/results/<version>/<cs|me>/
    /// <platform>/mechfmu/<version>/<tool>/<tool version>/<model>/.
    #[arg(long, value_name = "DIR")]
    cross_check_results: Option<PathBuf>,
    /// Instead of validating: (re)compute the reference results of each mechanism's reference
    /// case (the one naming `reference_files`, else the default experiment's) with the
    /// independent reference and write them to `<crate>/reference/`.
    #[arg(long)]
    write_references: bool,
    /// Stop an FMU's validation as hung after SECONDS without progress (no result, no FMI
    /// call); each FMU runs in a process of its own, and one that crashes or hangs is one
    /// FAIL row (default: the Python side's, 300).
    #[arg(long, value_name = "SECONDS", value_parser = positive_seconds)]
    time_limit: Option<f64>,
    /// Do not run the cases under the Rust `fmi` crate (and do not build `mechfmu-fmi-run`).
    #[arg(long)]
    no_fmi_crate: bool,
    /// Do not validate the FMI 3.0 FMUs (`<fmu dir>/fmi3/<Name>.fmu`) beside the FMI 2.0 ones.
    #[arg(long)]
    no_fmi3: bool,
}

/// `--time-limit`'s value: a finite number of seconds above 0.
fn positive_seconds(text: &str) -> Result<f64, String> {
    match text.parse::<f64>() {
        Ok(seconds) if seconds.is_finite() && seconds > 0.0 => Ok(seconds),
        _ => Err(format!("{text:?} is not a number of seconds above 0")),
    }
}

/// mechfmu's own files: where `python/mechfmu_validate`, the pinned requirements and
/// `tools/fmi-run` are (the checkout, or the installed command's copy).
fn home() -> Result<PathBuf, String> {
    crate::home::root()
}

/// `mechfmu validate`, ending with the exit status docs/validate.md gives: the Python
/// side's (0 all rows pass, 1 a row fails, 3 the validator failed, 128 + a signal's number
/// when one ended it), 2 for arguments that name nothing to validate, 1 when the validation
/// cannot be set up.
pub fn main(args: Args) -> ExitCode {
    match run(args) {
        Ok(()) => ExitCode::SUCCESS,
        Err((message, status)) => {
            eprintln!("error: {message}");
            ExitCode::from(status)
        }
    }
}

/// A usage error: the arguments name nothing to validate.
const USAGE: u8 = 2;

fn run(args: Args) -> Result<(), (String, u8)> {
    let failed = |message: String| (message, 1);
    let home = home().map_err(failed)?;
    if !home.join("python/mechfmu_validate/__init__.py").is_file() {
        return Err(failed(format!(
            "mechfmu's Python package is not at {}/python/mechfmu_validate (run a mechfmu built from its source tree)",
            home.display()
        )));
    }
    let usage = |message: String| (message, USAGE);
    let crates = workspace_crates(&args).map_err(usage)?;
    let py = if args.write_references {
        references_arguments(&crates, &args).map_err(usage)?
    } else {
        validation_arguments(&crates, &args).map_err(usage)?
    };
    let python = ensure_venv(&home).map_err(failed)?;
    // without a path, the Python side fails the fmi-crate rows, saying why
    let fmi_run = if args.write_references || args.no_fmi_crate {
        None
    } else {
        match build_fmi_run(&home) {
            Ok(path) => Some(path),
            Err(e) => {
                eprintln!(
                    "mechfmu validate: {e}\n  => the fmi-crate rows will fail (--no-fmi-crate leaves them out)"
                );
                None
            }
        }
    };
    let mut command = Command::new(&python);
    command
        .args(["-m", "mechfmu_validate"])
        .args(&py)
        .env_remove(FMI_RUN_ENV);
    if let Some(path) = &fmi_run {
        command.env(FMI_RUN_ENV, path);
    }
    let status = exit_status(&mut command).map_err(failed)?;
    // the Python side's exit status: 1 after printing a table with FAIL rows (an FMU that
    // cannot be opened is one of them), 3 when the validator itself failed
    let message = match status.code() {
        Some(0) => return Ok(()),
        Some(1) if !args.write_references => {
            "validation failed (see the FAIL rows in the table above)".to_string()
        }
        Some(1) => "writing the references failed (see the messages above)".to_string(),
        Some(3) => {
            "the validator failed (the traceback above): a bug of mechfmu's, not of the FMUs"
                .to_string()
        }
        _ => format!("python -m mechfmu_validate ended with {status}"),
    };
    Err((message, ended_with(status)))
}

/// This command's exit status for the child's: the same code, or 128 + the number of the
/// signal that ended it (as a shell reports it).
fn ended_with(status: ExitStatus) -> u8 {
    #[cfg(unix)]
    if let Some(signal) = std::os::unix::process::ExitStatusExt::signal(&status) {
        return (128 + signal).clamp(0, 255) as u8;
    }
    status.code().map_or(1, |code| code.clamp(1, 255) as u8)
}

/// The workspace's crates that build one FMU each, mechanisms and systems (none, with a note,
/// when only FMU files are given and there is no workspace).
fn workspace_crates(args: &Args) -> Result<Vec<MechanismCrate>, String> {
    match fmu_crates(args.manifest_path.as_deref()) {
        Ok(c) => Ok(c),
        Err(e)
            if args.manifest_path.is_none()
                && args
                    .targets
                    .iter()
                    .all(|t| is_fmu_file(t) || is_directory(t))
                && !args.targets.is_empty() =>
        {
            eprintln!(
                "note: no Cargo workspace here ({}); validating without reference cases",
                first_line(&e)
            );
            Ok(Vec::new())
        }
        Err(e) => Err(e),
    }
}

/// `python -m mechfmu_validate references`' arguments: each selected mechanism's FMU and
/// its cases.
fn references_arguments(crates: &[MechanismCrate], args: &Args) -> Result<Vec<String>, String> {
    // the FMU gives the DefaultExperiment and the inputs; the values come from the cases
    let mut py: Vec<String> = vec!["references".into()];
    let selected = select(crates, &args.targets)?;
    let mut cases = Vec::new();
    for c in &selected {
        let file = cases_file(c).ok_or_else(|| {
            format!(
                "{} has no validation/cases.py: nothing to compute references from",
                c.model
            )
        })?;
        let fmu = args.fmu_dir.join(format!("{}.fmu", c.model));
        if !fmu.is_file() {
            return Err(format!(
                "{} does not exist: build it first (`mechfmu build {}`)",
                fmu.display(),
                c.model
            ));
        }
        py.push(fmu.display().to_string());
        cases.extend([
            "--cases".to_string(),
            format!("{}={}", c.model, file.display()),
        ]);
    }
    py.extend(cases);
    Ok(py)
}

/// `python -m mechfmu_validate`'s arguments: the FMUs, every crate's cases, the outputs and
/// filters asked for.
fn validation_arguments(crates: &[MechanismCrate], args: &Args) -> Result<Vec<String>, String> {
    let mut py: Vec<String> = Vec::new();
    let fmus = fmu_paths(crates, args)?;
    py.extend(fmus.iter().map(|p| p.display().to_string()));
    for c in crates {
        if let Some(cases) = cases_file(c) {
            py.push("--cases".into());
            py.push(format!("{}={}", c.model, cases.display()));
        }
    }
    for (flag, value) in [
        ("--report", &args.report),
        ("--json", &args.json),
        ("--junit", &args.junit),
        ("--readme", &args.readme),
        ("--cross-check-results", &args.cross_check_results),
    ] {
        if let Some(v) = value {
            py.push(flag.into());
            py.push(v.display().to_string());
        }
    }
    for c in &args.cases {
        py.push("--case".into());
        py.push(c.clone());
    }
    if let Some(seconds) = args.time_limit {
        py.push("--time-limit".into());
        py.push(seconds.to_string());
    }
    if args.no_fmi_crate {
        py.push("--no-fmi-crate".into());
    }
    if args.no_fmi3 {
        py.push("--no-fmi3".into());
    }
    Ok(py)
}

/// The environment variable that names `mechfmu-fmi-run` to the Python side.
const FMI_RUN_ENV: &str = "MECHFMU_FMI_RUN";

/// The cargo profile the fmi-crate importer is built with (the workspace's, and the copy's
/// that the installed command carries): built for a short build, since the FMU does the numbers.
const IMPORTER_PROFILE: &str = "importer";

/// Builds `mechfmu-fmi-run` (the fmi-crate importer, `tools/fmi-run`) in mechfmu's files,
/// with the profile [`IMPORTER_PROFILE`]; returns the executable's path. In a checkout, a no-op when it is up to
/// date. The installed command's copy of the files never changes, so the importer built
/// from it is kept where [`crate::home::kept_importer`] says and the build's own files
/// (some 350 MB) are removed.
fn build_fmi_run(home: &Path) -> Result<PathBuf, String> {
    let manifest = home.join("Cargo.toml");
    let kept = crate::home::kept_importer(home);
    if let Some(kept) = kept.as_ref().filter(|k| k.is_file()) {
        return Ok(kept.clone());
    }
    let target = if kept.is_some() {
        home.join("target/fmi-run")
    } else {
        target_dir(home)?
    };
    let exe = target
        .join(IMPORTER_PROFILE)
        .join(format!("mechfmu-fmi-run{}", std::env::consts::EXE_SUFFIX));
    if !exe.is_file() {
        eprintln!(
            "building the fmi-crate importer (tools/fmi-run, first use; takes a few minutes) ..."
        );
    }
    let out = Command::new(cargo())
        .args([
            "build",
            "--profile",
            IMPORTER_PROFILE,
            "--quiet",
            "-p",
            "mechfmu-fmi-run",
            "--manifest-path",
        ])
        .arg(&manifest)
        .arg("--target-dir")
        .arg(&target)
        .current_dir(home)
        .output()
        .map_err(|e| format!("cannot run cargo to build the fmi-crate importer: {e}"))?;
    if !out.status.success() {
        let stderr = String::from_utf8_lossy(&out.stderr);
        let tail: Vec<&str> = stderr.lines().rev().take(12).collect();
        let tail: Vec<&str> = tail.into_iter().rev().collect();
        let cause = if stderr.contains("libclang") || stderr.contains("clang-sys") {
            "libclang is missing (the fmi crate's bindings are generated by bindgen, which needs it): \
             install it with `apt-get install libclang-dev` (or set LIBCLANG_PATH)"
                .to_string()
        } else {
            format!("cargo build failed ({})", out.status)
        };
        return Err(format!(
            "cannot build the fmi-crate importer (`cargo build --profile {IMPORTER_PROFILE} -p mechfmu-fmi-run` in {}): \
             {cause}\n  cargo said:\n    {}",
            home.display(),
            tail.join("\n    ")
        ));
    }
    if !exe.is_file() {
        return Err(format!(
            "cargo built mechfmu-fmi-run but {} does not exist",
            exe.display()
        ));
    }
    let Some(kept) = kept else {
        return Ok(exe);
    };
    std::fs::create_dir_all(kept.parent().expect("in a folder"))
        .and_then(|()| std::fs::rename(&exe, &kept))
        .map_err(|e| format!("cannot move {} to {}: {e}", exe.display(), kept.display()))?;
    // what is left is cargo's intermediate files, of no use for a copy that never changes
    let _ = std::fs::remove_dir_all(&target);
    Ok(kept)
}

/// The target directory of mechfmu's workspace: `$CARGO_TARGET_DIR` (relative to `home`
/// when relative), else what `cargo metadata` says (which honours `build.target-dir`).
fn target_dir(home: &Path) -> Result<PathBuf, String> {
    if let Some(dir) = std::env::var_os("CARGO_TARGET_DIR").filter(|d| !d.is_empty()) {
        return Ok(home.join(dir));
    }
    target_directory(Some(&home.join("Cargo.toml")))
}

fn is_fmu_file(target: &str) -> bool {
    target.ends_with(".fmu") || Path::new(target).is_file()
}

/// A system's SSP (`mechfmu build` writes `fmus/<System>.ssp`).
fn is_ssp_file(target: &str) -> bool {
    target.ends_with(".ssp")
}

/// A directory the Python side walks for FMUs (an FMI cross-check tree).
fn is_directory(target: &str) -> bool {
    Path::new(target).is_dir()
}

fn first_line(s: &str) -> &str {
    s.lines().find(|l| !l.trim().is_empty()).unwrap_or(s).trim()
}

/// `<crate dir>/validation/cases.py`, if the crate has one.
fn cases_file(c: &MechanismCrate) -> Option<PathBuf> {
    let path = c.manifest.parent()?.join("validation/cases.py");
    path.is_file().then_some(path)
}

/// The crates named by `names` (all of them when empty).
fn select(crates: &[MechanismCrate], names: &[String]) -> Result<Vec<MechanismCrate>, String> {
    if names.is_empty() {
        return Ok(crates.to_vec());
    }
    names
        .iter()
        .map(|n| {
            crates
                .iter()
                .find(|c| &c.model == n)
                .cloned()
                .ok_or_else(|| {
                    let known: Vec<&str> = crates.iter().map(|c| c.model.as_str()).collect();
                    format!("unknown mechanism `{n}` (known: {})", known.join(", "))
                })
        })
        .collect()
}

/// The FMU files to validate: the targets that are files or directories, `<fmu dir>/<NAME>.fmu`
/// for the others, or every mechanism's when there are no targets.
fn fmu_paths(crates: &[MechanismCrate], args: &Args) -> Result<Vec<PathBuf>, String> {
    let hint = "build it with `mechfmu build` (or pass --fmu-dir)";
    let named = |model: &str| -> Result<PathBuf, String> {
        let path = args.fmu_dir.join(format!("{model}.fmu"));
        if path.is_file() {
            Ok(path)
        } else {
            Err(format!("{} does not exist: {hint}", path.display()))
        }
    };
    if args.targets.is_empty() {
        if crates.is_empty() {
            return Err("no mechanism crates found and no FMU given".into());
        }
        return crates.iter().map(|c| named(&c.model)).collect();
    }
    args.targets
        .iter()
        .map(|t| {
            if is_directory(t) {
                Ok(PathBuf::from(t))
            } else if is_fmu_file(t) || is_ssp_file(t) {
                let p = PathBuf::from(t);
                if p.is_file() {
                    Ok(p)
                } else {
                    Err(format!("{t} does not exist"))
                }
            } else if crates.iter().any(|c| &c.model == t)
                || args.fmu_dir.join(format!("{t}.fmu")).is_file()
            {
                named(t)
            } else {
                let known: Vec<&str> = crates.iter().map(|c| c.model.as_str()).collect();
                Err(format!(
                    "`{t}` is neither an FMU file, an SSP file, a directory nor a mechanism (known: {})",
                    known.join(", ")
                ))
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::positive_seconds;

    #[test]
    fn the_time_limit_is_a_number_of_seconds_above_0() {
        assert_eq!(positive_seconds("2.5"), Ok(2.5));
        for refused in ["0", "-1", "NaN", "inf", "soon"] {
            let why = positive_seconds(refused).unwrap_err();
            assert!(
                why.contains("not a number of seconds above 0"),
                "{refused}: {why}"
            );
        }
    }
}
