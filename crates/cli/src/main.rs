//! The `mechfmu` command: the command line (here) and one module per subcommand
//! (`commands`), over what they share: `build` compiles mechanism crates for each platform
//! (finding them in the workspace, running cargo, the toolchains), `package` writes their
//! `.fmu` archives (checking every binary), `home` finds mechfmu's own files (the
//! checkout's, or the copies an installed command carries) and the Python environment made
//! from them. Loading a built FMU is `mechfmu-host`'s; the benchmark lab and the sweep's
//! native engine are crates of their own, `mechfmu-bench` and `mechfmu-sweep-worker`.

#![deny(unsafe_code)]

mod build;
mod commands;
mod home;
mod package;
mod system;

use clap::{Parser, Subcommand};
use commands::{
    bench, build as build_command, docs, inspect, list, new, sweep, sweep_worker, validate,
};
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "mechfmu",
    version,
    about = "Turns mechanical models into FMI 2.0 and FMI 3.0 FMUs for Linux, Windows and macOS, on x86-64 and ARM"
)]
struct Cli {
    #[command(subcommand)]
    command: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Build (release) and package FMUs: the named mechanisms, or all of them.
    Build(build_command::Args),
    /// Write the interface page of each mechanism (variables, units, defaults, equations),
    /// rendered by its built binary: docs/mechanisms/<Name>.md.
    Docs(docs::Args),
    /// Show the binaries of FMUs: platform, the libraries each loads, the functions it exports.
    Inspect(inspect::Args),
    /// List the mechanisms of the workspace.
    List(list::Args),
    /// Benchmark FMUs: cost per step, plumbing vs physics, work–precision.
    Bench(bench::Args),
    /// Scaffold a mechanism crate of your own (a working pendulum to edit; with `--energies`,
    /// one declared from its energies).
    New(new::Args),
    /// Run a parameter sweep of an FMU on Dask.
    Sweep(sweep::Args),
    /// The native engine of `sweep`: runs chunks of cases fed over stdin (internal).
    #[command(hide = true)]
    SweepWorker,
    /// Validate FMUs: FMPy's and mechfmu's checks, the reference cases under FMPy and libcosim.
    Validate(validate::Args),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Cmd::SweepWorker => return sweep_worker::run(),
        Cmd::Build(args) => build_command::run(args),
        Cmd::Docs(args) => docs::run(args),
        Cmd::Inspect(args) => inspect::run(args),
        Cmd::List(args) => list::run(args),
        Cmd::Bench(args) => bench::run(args),
        Cmd::New(args) => new::run(args),
        Cmd::Sweep(args) => sweep::run(args),
        Cmd::Validate(args) => return validate::main(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}
