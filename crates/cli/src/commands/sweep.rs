//! `mechfmu sweep`: a parameter sweep of an FMU on Dask distributed.
//!
//! The grammar is Python's: this side makes sure the Python environment is there and passes
//! its arguments through, unparsed, to `python -m mechfmu_sweep` (the package in `python/`,
//! installed in the venv), which parses them (`python/mechfmu_sweep/cli.py`: its help is
//! `mechfmu sweep --help`), checks every value and the names against the FMU's model
//! description, and runs the sweep. A request it refuses ends with its message naming the
//! problem (exit status 2) and a non-zero exit of this command. Otherwise the exit status is
//! that of the sweep machinery: cases that fail are rows of the results (status and the
//! FMU's message), not a failure of the command.

use crate::home::python::{ensure_venv, exit_status};
use std::ffi::OsString;
use std::path::PathBuf;
use std::process::Command;

#[derive(clap::Args, Debug)]
#[command(disable_help_flag = true)]
pub struct Args {
    /// The arguments of `python -m mechfmu_sweep` (`mechfmu sweep --help` lists them).
    #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
    arguments: Vec<OsString>,
}

pub fn run(args: Args) -> Result<(), String> {
    let root = project_root()?;
    let python = ensure_venv(&root)?;
    let mut cmd = Command::new(&python);
    cmd.arg("-m").arg("mechfmu_sweep").args(&args.arguments);
    // the native engine's workers run `<this executable> sweep-worker`
    if let Ok(exe) = std::env::current_exe() {
        cmd.env(EXE_ENV, exe);
    }
    let status = exit_status(&mut cmd)?;
    match status.code() {
        Some(0) => Ok(()),
        // a request python -m mechfmu_sweep refused: its message (above) names the problem
        Some(2) => Err("the sweep was not started (the message above names the problem)".into()),
        _ => Err(format!("the sweep failed ({status})")),
    }
}

/// The environment variable naming this executable to the Python side (`native.py`).
const EXE_ENV: &str = "MECHFMU_EXE";

/// mechfmu's files holding `python/mechfmu_sweep` and `tests/python/requirements.txt` (whose
/// venv gets the package installed): the checkout, the installed command's copy, or
/// `MECHFMU_ROOT` if set.
fn project_root() -> Result<PathBuf, String> {
    let root = crate::home::root()?;
    let package = root.join("python/mechfmu_sweep/__main__.py");
    if package.is_file() {
        Ok(root)
    } else {
        Err(format!(
            "cannot find the sweep's Python package at {} (set MECHFMU_ROOT to the mechfmu repository)",
            package.display()
        ))
    }
}
