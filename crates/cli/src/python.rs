//! The Python environment validation and sweeps run in: a venv under `target/venv` with
//! the pinned packages of `tests/python/requirements.txt`, created on first use.

use std::path::{Path, PathBuf};
use std::process::Command;

/// The venv's interpreter, under the workspace's `target/`.
pub fn venv_python(workspace: &Path) -> PathBuf {
    workspace.join("target/venv/bin/python")
}

/// Creates or updates the venv when its requirements changed (the same stamp as
/// `scripts/test`), telling the user what takes time. Returns the interpreter.
pub fn ensure_venv(workspace: &Path) -> Result<PathBuf, String> {
    let requirements = workspace.join("tests/python/requirements.txt");
    let venv = workspace.join("target/venv");
    let python = venv_python(workspace);
    let wanted = std::fs::read(&requirements)
        .map_err(|e| format!("cannot read {}: {e}", requirements.display()))?;
    let stamp = venv.join(".requirements");
    if python.exists() && std::fs::read(&stamp).is_ok_and(|s| s == wanted) {
        return Ok(python);
    }
    eprintln!(
        "setting up the Python environment in {} (first use; takes a minute) ...",
        venv.display()
    );
    if !python.exists() {
        run(
            Command::new("python3").arg("-m").arg("venv").arg(&venv),
            "create the venv",
        )?;
    }
    run(
        Command::new(&python)
            .args(["-m", "pip", "install", "-q", "-r"])
            .arg(&requirements),
        "install the pinned Python packages",
    )?;
    std::fs::write(&stamp, wanted).map_err(|e| format!("cannot write {}: {e}", stamp.display()))?;
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
