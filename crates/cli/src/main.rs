//! The `mechfmu` command. One module per subcommand (`build` with `list`, `inspect`, `new`,
//! `validate`, `sweep`, `bench`, `interface` for `docs`); `workspace` finds mechanism crates,
//! `package` writes the `.fmu` archive, `python` provisions the Python environment the
//! validation and sweeps run in, `home` finds mechfmu's own files (the checkout's, or the
//! copies an installed command carries).

mod bench;
mod binaries;
mod build;
mod cpu_clock;
mod extras;
mod fmi2_library;
mod fmi3_names;
mod home;
mod inspect;
mod interface;
mod new;
mod package;
mod platform;
mod python;
mod sweep;
mod sweep_worker;
mod validate;
mod workspace;

use clap::{Parser, Subcommand};
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "mechfmu",
    version,
    about = "Turns mechanical models into FMI 2.0 and FMI 3.0 FMUs for Linux, Windows and ARM Linux"
)]
struct Cli {
    #[command(subcommand)]
    command: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Build (release) and package FMUs: the named mechanisms, or all of them.
    Build {
        /// Model identifiers, e.g. Oscillator Crane (default: every mechanism).
        names: Vec<String>,
        /// Where to write the .fmu files.
        #[arg(long, default_value = "fmus")]
        out: PathBuf,
        /// The Cargo.toml of the workspace or crate holding the mechanisms.
        #[arg(long)]
        manifest_path: Option<PathBuf>,
        /// The platforms to carry binaries for, comma-separated: x86_64-linux (linux64),
        /// x86_64-windows (win64), aarch64-linux, or all; a platform whose toolchain is
        /// missing is then an error. Default: every platform this machine can build for
        /// (those it cannot are named, with how to install their toolchains).
        #[arg(long, value_name = "PLATFORMS")]
        platform: Option<String>,
    },
    /// Write the interface page of each mechanism (variables, units, defaults, equations),
    /// rendered by its built binary: docs/mechanisms/<Name>.md.
    Docs(interface::Args),
    /// Show the binaries of FMUs: platform, the libraries each loads, the functions it exports.
    Inspect(inspect::Args),
    /// List the mechanisms of the workspace.
    List {
        #[arg(long)]
        manifest_path: Option<PathBuf>,
    },
    /// Benchmark FMUs: cost per step, plumbing vs physics, work–precision.
    Bench(bench::command::Args),
    /// Scaffold a mechanism crate of your own (a working pendulum to edit).
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
        Cmd::Build {
            names,
            out,
            manifest_path,
            platform,
        } => platform
            .as_deref()
            .map(platform::parse_list)
            .transpose()
            .and_then(|chosen| {
                build::build(
                    &names,
                    &out,
                    manifest_path.as_deref(),
                    build::Flavor::Shipped,
                    chosen.map_or(build::Platforms::Available, build::Platforms::Chosen),
                )
            }),
        Cmd::Docs(args) => interface::run(args),
        Cmd::Inspect(args) => inspect::run(args),
        Cmd::List { manifest_path } => build::list(manifest_path.as_deref()),
        Cmd::Bench(args) => bench::command::run(args),
        Cmd::New(args) => new::run(args),
        Cmd::Sweep(args) => sweep::run(args),
        Cmd::Validate(args) => validate::run(args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(message) => {
            eprintln!("error: {message}");
            ExitCode::FAILURE
        }
    }
}
