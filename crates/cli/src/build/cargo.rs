//! Running `cargo build` for the mechanism crates and finding the shared libraries it
//! wrote: this machine's in cargo's own target folder (sharing the dependencies the
//! `mechfmu` command was built with), then the other platforms' in one invocation with a
//! `--target` each (so cargo spreads their crates over the cores); and the describing
//! build, this machine's library with the runtime's `describe` feature (the extras the
//! command reads an FMU's files from), in a profile of its own.

use super::toolchain;
use super::workspace::{cargo, target_directory, MechanismCrate};
use super::Flavor;
use mechfmu_host::platform::Platform;
use std::io::{BufRead, BufReader, IsTerminal, Read};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// A shared library cargo built.
#[derive(Clone)]
pub(super) struct Library {
    pub package: String,
    pub platform: Platform,
    pub path: PathBuf,
}

/// Builds the crates' cdylibs in release mode for each of `platforms`, with `features`
/// (`package/feature`) on.
pub(super) fn build(
    crates: &[MechanismCrate],
    manifest_path: Option<&Path>,
    flavor: &Flavor,
    platforms: &[Platform],
    features: &[String],
) -> Result<Vec<Library>, String> {
    let host = Platform::host();
    let mut libraries = Vec::new();
    if let Some(host) = host.filter(|h| platforms.contains(h)) {
        libraries.extend(invoke(
            crates,
            manifest_path,
            flavor,
            &[host],
            Targets::Host,
            features,
        )?);
    }
    let cross: Vec<Platform> = platforms
        .iter()
        .copied()
        .filter(|p| Some(*p) != host)
        .collect();
    if !cross.is_empty() {
        let macos_sdk = match cross.iter().any(|p| p.is_darwin()) {
            true => {
                let dir = target_directory(manifest_path)?.join("mechfmu/macos-sdk");
                Some(toolchain::write_macos_sdk(&dir)?)
            }
            false => None,
        };
        let targets = Targets::Cross {
            macos_sdk: macos_sdk.as_deref(),
        };
        libraries.extend(invoke(
            crates,
            manifest_path,
            flavor,
            &cross,
            targets,
            features,
        )?);
    }
    Ok(libraries)
}

/// The profile of the describing build: dev's settings without debug information or
/// incremental caches (it renders a few texts once: optimizing, debugging information and
/// caches would only lengthen the build), in a folder of its own under the target directory, so
/// that a library with the extras never takes the place of a shipped one (cargo writes a
/// crate's shared library to one path whatever its features). Defined on the command line,
/// so that any workspace has it.
const DESCRIBE_PROFILE: &str = "mechfmu-describe";

/// Builds this machine's libraries of `crates` with the runtime's `describe` feature and
/// `features` on (see [`DESCRIBE_PROFILE`]): what the command reads the texts of each FMU
/// from.
pub(super) fn describe(
    crates: &[MechanismCrate],
    manifest_path: Option<&Path>,
    flavor: &Flavor,
    host: Platform,
    features: &[String],
) -> Result<Vec<Library>, String> {
    let mut features = features.to_vec();
    features.push("mechfmu/describe".into());
    invoke(
        crates,
        manifest_path,
        flavor,
        &[host],
        Targets::Describe,
        &features,
    )
}

/// What a `cargo build` is for.
#[derive(Clone, Copy)]
enum Targets<'a> {
    /// This machine, without `--target` (`platforms` is the host alone).
    Host,
    /// A `--target` for each platform; the macOS SDK the Mac ones link with, if any.
    Cross { macos_sdk: Option<&'a Path> },
    /// This machine, the describing build ([`DESCRIBE_PROFILE`]).
    Describe,
}

/// One `cargo build` of `crates` for `platforms`.
fn invoke(
    crates: &[MechanismCrate],
    manifest_path: Option<&Path>,
    flavor: &Flavor,
    platforms: &[Platform],
    targets: Targets,
    features: &[String],
) -> Result<Vec<Library>, String> {
    let with_targets = matches!(targets, Targets::Cross { .. });
    let mut cmd = command(crates, manifest_path, flavor, platforms, targets);
    if !features.is_empty() {
        cmd.args(["--features", &features.join(",")]);
    }
    let tuples: Vec<&str> = platforms.iter().map(|p| p.tuple()).collect();
    eprintln!(
        "building {} crate(s) with cargo ({}) for {} ...",
        crates.len(),
        match targets {
            Targets::Describe => "the texts of their FMUs",
            _ => "release",
        },
        tuples.join(", ")
    );
    // On a terminal, cargo's own progress (its `Compiling` lines and status bar) shows what
    // a first build spends its minutes on; elsewhere its messages are kept for a failure, so
    // what this command prints stays the same from run to run.
    let cargo_stderr = if std::io::stderr().is_terminal() {
        Stdio::inherit()
    } else {
        Stdio::piped()
    };
    let mut child = cmd
        .stdout(Stdio::piped())
        .stderr(cargo_stderr)
        .spawn()
        .map_err(|e| format!("cannot run cargo build: {e}"))?;
    let stderr_thread = child.stderr.take().map(|stderr| {
        std::thread::spawn(move || {
            BufReader::new(stderr)
                .lines()
                .map_while(Result::ok)
                .collect::<Vec<String>>()
        })
    });
    let stdout = child.stdout.take().expect("piped");
    let libraries = libraries_built(stdout, crates, platforms, with_targets);
    let status = child
        .wait()
        .map_err(|e| format!("cargo build did not finish: {e}"))?;
    let stderr = stderr_thread.map(|t| t.join().unwrap_or_default());
    if !status.success() {
        return Err(match stderr {
            Some(lines) => format!("cargo build failed:\n{}", lines.join("\n")),
            None => "cargo build failed (its messages are above)".into(),
        });
    }
    Ok(libraries)
}

/// The `cargo build` of [`invoke`].
fn command(
    crates: &[MechanismCrate],
    manifest_path: Option<&Path>,
    flavor: &Flavor,
    platforms: &[Platform],
    targets: Targets,
) -> Command {
    let mut cmd = Command::new(cargo());
    cmd.args(["build", "--lib", "--message-format=json-render-diagnostics"]);
    match targets {
        Targets::Describe => {
            cmd.args(["--profile", DESCRIBE_PROFILE]);
            for setting in ["inherits=\"dev\"", "debug=false", "incremental=false"] {
                cmd.arg("--config")
                    .arg(format!("profile.{DESCRIBE_PROFILE}.{setting}"));
            }
        }
        _ => {
            cmd.arg("--release");
        }
    }
    if let Flavor::Bench { target_dir } = flavor {
        cmd.args([
            "--features",
            "mechfmu/bench,mechfmu/describe",
            "--target-dir",
        ])
        .arg(target_dir);
    }
    if let Some(path) = manifest_path {
        cmd.arg("--manifest-path").arg(path);
    }
    for c in crates {
        cmd.args(["-p", &c.package]);
    }
    if let Targets::Cross { macos_sdk } = targets {
        for p in platforms {
            cmd.args(["--target", p.rust_target()]);
            toolchain::configure(*p, &mut cmd, macos_sdk);
        }
    }
    cmd
}

/// The shared libraries of `crates` for `platforms` among the artifacts cargo reports on
/// `stdout` (its JSON messages).
fn libraries_built(
    stdout: impl Read,
    crates: &[MechanismCrate],
    platforms: &[Platform],
    with_targets: bool,
) -> Vec<Library> {
    let mut libraries = Vec::new();
    for line in BufReader::new(stdout).lines().map_while(Result::ok) {
        let Ok(msg) = serde_json::from_str::<serde_json::Value>(&line) else {
            continue;
        };
        if msg["reason"] != "compiler-artifact" {
            continue;
        }
        let Some(package) = package_name(msg["package_id"].as_str().unwrap_or(""), crates) else {
            continue;
        };
        for path in msg["filenames"].as_array().into_iter().flatten() {
            let path = Path::new(path.as_str().unwrap_or(""));
            let platform = if with_targets {
                platform_of(path, platforms)
            } else {
                platforms.first().copied().filter(|p| {
                    path.extension()
                        .is_some_and(|e| e.to_str() == Some(p.extension()))
                })
            };
            if let Some(platform) = platform {
                libraries.push(Library {
                    package: package.clone(),
                    platform,
                    path: path.to_path_buf(),
                });
            }
        }
    }
    libraries
}

/// The platform a file cargo wrote is the shared library of: cargo puts each target's
/// output under `<target dir>/<triple>/`; the extension tells the library from the import
/// library and the like beside it.
fn platform_of(path: &Path, platforms: &[Platform]) -> Option<Platform> {
    let extension = path.extension()?.to_str()?;
    platforms.iter().copied().find(|p| {
        extension == p.extension() && path.components().any(|c| c.as_os_str() == p.rust_target())
    })
}

/// Which of our crates a cargo package id belongs to (ids look like
/// `path+file:///…/fmus/oscillator#oscillator-fmu@0.1.0`).
fn package_name(package_id: &str, crates: &[MechanismCrate]) -> Option<String> {
    crates
        .iter()
        .find(|c| {
            let dir = c
                .manifest
                .parent()
                .map(|d| d.display().to_string())
                .unwrap_or_default();
            package_id.contains(&format!("#{}@", c.package))
                || (package_id.contains(&format!("{dir}#")) && !dir.is_empty())
                || package_id.starts_with(&format!("{} ", c.package))
        })
        .map(|c| c.package.clone())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn libraries_are_told_by_target_folder_and_extension() {
        let all = Platform::ALL;
        let at = |p: &str| platform_of(Path::new(p), &all);
        assert_eq!(
            at("/t/x86_64-pc-windows-gnu/release/crane.dll"),
            Some(Platform::X86_64Windows)
        );
        assert_eq!(at("/t/x86_64-pc-windows-gnu/release/libcrane.dll.a"), None);
        assert_eq!(
            at("/t/aarch64-unknown-linux-gnu/release/libcrane.so"),
            Some(Platform::Aarch64Linux)
        );
        assert_eq!(at("/t/release/libcrane.so"), None);
    }
}
