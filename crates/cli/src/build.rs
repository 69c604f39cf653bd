//! `mechfmu build` and `mechfmu list`: compile mechanism crates and package their FMUs.

use super::workspace::{cargo, mechanism_crates, MechanismCrate};
use crate::package::{Packaging, Version};
use indicatif::{ProgressBar, ProgressStyle};
use std::io::{BufRead, BufReader, IsTerminal};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

pub(crate) fn list(manifest_path: Option<&Path>) -> Result<(), String> {
    for c in mechanism_crates(manifest_path)? {
        println!("{:<20} {:<24} {}", c.model, c.package, c.manifest.display());
    }
    Ok(())
}

pub(crate) fn select(
    all: Vec<MechanismCrate>,
    names: &[String],
) -> Result<Vec<MechanismCrate>, String> {
    if all.is_empty() {
        return Err("no mechanism crates found (a crate declares one with `[package.metadata.mechfmu] model = \"Name\"`)".into());
    }
    if names.is_empty() {
        return Ok(all);
    }
    let known: Vec<&str> = all.iter().map(|c| c.model.as_str()).collect();
    names
        .iter()
        .map(|n| {
            all.iter()
                .find(|c| &c.model == n)
                .cloned()
                .ok_or_else(|| format!("unknown mechanism `{n}` (known: {})", known.join(", ")))
        })
        .collect()
}

/// Which binaries to build.
pub(crate) enum Flavor<'a> {
    /// What an FMU ships: the FMI functions and the documented extras.
    Shipped,
    /// With the runtime's `bench` feature (the entry points `mechfmu bench` times the parts
    /// of a step with), in a target directory of its own so the shipped build is untouched.
    Bench { target_dir: &'a Path },
}

pub(crate) fn build(
    names: &[String],
    out: &Path,
    manifest_path: Option<&Path>,
    flavor: Flavor,
) -> Result<(), String> {
    let started = Instant::now();
    let built = built_libraries(names, manifest_path, &flavor)?;
    std::fs::create_dir_all(out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    for (c, library) in &built {
        for version in [Version::Fmi2, Version::Fmi3] {
            let path = package_fmu(&c.model, library, out, c.manifest.parent(), version)?;
            let size = std::fs::metadata(&path).map(|m| m.len()).unwrap_or(0);
            println!(
                "{:<20} {:<8} {} ({} KiB)",
                c.model,
                version.name(),
                path.display(),
                size.div_ceil(1024)
            );
        }
    }
    println!(
        "built {} mechanism{} as FMI 2.0 and FMI 3.0 FMUs in {:.1} s",
        built.len(),
        if built.len() == 1 { "" } else { "s" },
        started.elapsed().as_secs_f64()
    );
    Ok(())
}

/// The mechanism crates named (every one when `names` is empty), built in release mode,
/// each with the path of its shared library.
pub(crate) fn built_libraries(
    names: &[String],
    manifest_path: Option<&Path>,
    flavor: &Flavor,
) -> Result<Vec<(MechanismCrate, PathBuf)>, String> {
    let selected = select(mechanism_crates(manifest_path)?, names)?;
    let libraries = cargo_build(&selected, manifest_path, flavor)?;
    selected
        .into_iter()
        .map(|c| {
            let library = libraries
                .iter()
                .find(|(package, _)| package == &c.package)
                .map(|(_, path)| path.clone())
                .ok_or_else(|| format!("cargo built no shared library for `{}`", c.package))?;
            Ok((c, library))
        })
        .collect()
}

/// Builds the crates' cdylibs in release mode; returns (package name, path of the .so).
fn cargo_build(
    crates: &[MechanismCrate],
    manifest_path: Option<&Path>,
    flavor: &Flavor,
) -> Result<Vec<(String, PathBuf)>, String> {
    let mut cmd = Command::new(cargo());
    cmd.args([
        "build",
        "--release",
        "--lib",
        "--message-format=json-render-diagnostics",
    ]);
    if let Flavor::Bench { target_dir } = flavor {
        cmd.args(["--features", "mechfmu/bench", "--target-dir"])
            .arg(target_dir);
    }
    if let Some(path) = manifest_path {
        cmd.arg("--manifest-path").arg(path);
    }
    for c in crates {
        cmd.args(["-p", &c.package]);
    }
    let progress = spinner(&format!(
        "building {} crate(s) with cargo (release)",
        crates.len()
    ));
    let mut child = cmd
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("cannot run cargo build: {e}"))?;
    let stderr = child.stderr.take().expect("piped");
    let stderr_thread = std::thread::spawn(move || {
        let mut lines = Vec::new();
        for line in BufReader::new(stderr).lines().map_while(Result::ok) {
            lines.push(line);
        }
        lines
    });
    let mut libraries = Vec::new();
    for line in BufReader::new(child.stdout.take().expect("piped"))
        .lines()
        .map_while(Result::ok)
    {
        let Ok(msg) = serde_json::from_str::<serde_json::Value>(&line) else {
            continue;
        };
        if msg["reason"] == "compiler-artifact" {
            let name = msg["target"]["name"].as_str().unwrap_or("");
            if let Some(p) = &progress {
                p.set_message(format!("compiled {name}"));
            }
            let package = package_name(msg["package_id"].as_str().unwrap_or(""), crates);
            if let Some(package) = package {
                for f in msg["filenames"].as_array().into_iter().flatten() {
                    if let Some(f) = f.as_str().filter(|f| f.ends_with(".so")) {
                        libraries.push((package.clone(), PathBuf::from(f)));
                    }
                }
            }
        }
    }
    let status = child
        .wait()
        .map_err(|e| format!("cargo build did not finish: {e}"))?;
    let stderr = stderr_thread.join().unwrap_or_default();
    if let Some(p) = progress {
        p.finish_and_clear();
    }
    if !status.success() {
        return Err(format!("cargo build failed:\n{}", stderr.join("\n")));
    }
    Ok(libraries)
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

fn spinner(message: &str) -> Option<ProgressBar> {
    if !std::io::stderr().is_terminal() {
        eprintln!("{message} ...");
        return None;
    }
    let p = ProgressBar::new_spinner();
    p.set_style(
        ProgressStyle::with_template("{spinner} {msg} [{elapsed}]").expect("valid template"),
    );
    p.set_message(message.to_string());
    p.enable_steady_tick(Duration::from_millis(120));
    Some(p)
}

/// Packages one built library as an FMU of `version` (in [`Packaging::folder`] of `out`):
/// asks the binary for its own modelDescription of that version, so the XML and the binary
/// can never disagree, and for its documentation; adds the reference results of the
/// default experiment found in `<crate_dir>/reference/` (see [`crate::extras`]).
pub fn package_fmu(
    model: &str,
    library: &Path,
    out: &Path,
    crate_dir: Option<&Path>,
    version: Version,
) -> Result<PathBuf, String> {
    let xml = crate::extras::exported_text(
        library,
        version.model_description_symbol(),
        "modelDescription",
    )?;
    let binary =
        std::fs::read(library).map_err(|e| format!("cannot read {}: {e}", library.display()))?;
    let folder = version.folder(out);
    std::fs::create_dir_all(&folder)
        .map_err(|e| format!("cannot create {}: {e}", folder.display()))?;
    let path = folder.join(format!("{model}.fmu"));
    let contents = crate::package::Contents {
        model_identifier: model,
        model_description: &xml,
        platform: version.platform(),
        binary: &binary,
        extra: crate::extras::extra_files(model, library, crate_dir, version, &xml)?,
    };
    crate::package::write_fmu(&path, &contents)
        .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    Ok(path)
}
