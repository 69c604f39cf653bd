//! The Python environment validation and sweeps run in: a venv under `target/venv` of
//! mechfmu's files ([`crate::home::root`]: the checkout, or the installed command's copy)
//! with the pinned packages of `tests/python/requirements.txt` and mechfmu's own Python
//! packages (`python/`: `mechfmu_validate`, `mechfmu_sweep`) installed editable, created on
//! first use.

use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus};

/// The venv's interpreter, under the workspace's `target/`.
pub fn venv_python(workspace: &Path) -> PathBuf {
    let venv = workspace.join("target/venv");
    if cfg!(windows) {
        venv.join("Scripts/python.exe")
    } else {
        venv.join("bin/python")
    }
}

/// Creates or updates the venv when its requirements or `python/pyproject.toml` changed (the
/// same stamps as `scripts/test`: copies of both files in the venv), telling the user what
/// takes time. Returns the interpreter.
pub fn ensure_venv(workspace: &Path) -> Result<PathBuf, String> {
    let venv = workspace.join("target/venv");
    let python = venv_python(workspace);
    let requirements = workspace.join("tests/python/requirements.txt");
    let package = workspace.join("python");
    // each file, and its copy in the venv that says what was installed
    let stamps = [
        (requirements.clone(), venv.join(".requirements")),
        (package.join("pyproject.toml"), venv.join(".pyproject.toml")),
    ];
    let mut wanted = Vec::new();
    for (file, _) in &stamps {
        wanted
            .push(std::fs::read(file).map_err(|e| format!("cannot read {}: {e}", file.display()))?);
    }
    let current = stamps
        .iter()
        .zip(&wanted)
        .all(|((_, stamp), want)| std::fs::read(stamp).is_ok_and(|s| &s == want));
    if python.exists() && current {
        return Ok(python);
    }
    eprintln!(
        "setting up mechfmu's Python environment in {} (first use, about a minute) ...",
        venv.display()
    );
    if !python.exists() {
        run(
            Command::new("python3").arg("-m").arg("venv").arg(&venv),
            "create the venv with python3 (Python 3.11 or newer, with its venv module)",
        )?;
    }
    run(
        Command::new(&python)
            .args(["-m", "pip", "install", "-q", "-r"])
            .arg(&requirements),
        "install the pinned Python packages",
    )?;
    // editable: the venv imports the packages from `python/` (no PYTHONPATH); their
    // dependencies are the pins above
    run(
        Command::new(&python)
            .args(["-m", "pip", "install", "-q", "--no-deps", "-e"])
            .arg(&package),
        "install mechfmu's Python packages (python/)",
    )?;
    for ((_, stamp), want) in stamps.iter().zip(wanted) {
        std::fs::write(stamp, want)
            .map_err(|e| format!("cannot write {}: {e}", stamp.display()))?;
    }
    Ok(python)
}

fn run(cmd: &mut Command, what: &str) -> Result<(), String> {
    let status = cmd.status().map_err(|e| format!("cannot {what}: {e}"))?;
    if status.success() {
        Ok(())
    } else {
        Err(format!("could not {what} ({status})"))
    }
}

/// Runs `command` (the venv's interpreter on one of mechfmu's packages) to its end, passing
/// on the signals that end this command ([`child`](super::child)): its exit status, or why
/// it could not start.
pub fn exit_status(command: &mut Command) -> Result<ExitStatus, String> {
    super::child::run(command).map_err(|e| {
        let program = Path::new(command.get_program());
        format!("cannot run {}: {e}", program.display())
    })
}
