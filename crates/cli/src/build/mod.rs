//! `mechfmu build` and `mechfmu list`: compile mechanism crates for each platform and
//! package their FMUs.

mod cargo;
mod fmu;

pub use fmu::package_fmu;

use crate::package::Version;
use crate::platform::{MissingToolchain, Platform};
use crate::workspace::{mechanism_crates, MechanismCrate};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::time::Instant;

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
    /// of a step with), in a target directory of its own so the shipped build is untouched;
    /// for this machine only.
    Bench { target_dir: &'a Path },
}

/// The platforms an FMU is to carry binaries for.
pub(crate) enum Platforms {
    /// This machine's only.
    Host,
    /// Every platform this machine has the toolchain for; those it lacks are named, with how
    /// to install them, and left out.
    Available,
    /// These: a missing toolchain is an error.
    Chosen(Vec<Platform>),
}

/// One mechanism crate's shared library for each platform built.
pub(crate) struct Built {
    pub krate: MechanismCrate,
    pub libraries: BTreeMap<Platform, PathBuf>,
}

impl Built {
    /// This machine's library: the one the `mechfmu` command loads to read what the binary
    /// says of itself (model description, documentation, interface page).
    pub fn host_library(&self) -> &Path {
        let host = Platform::host().expect("checked by built_libraries");
        &self.libraries[&host]
    }
}

pub(crate) fn build(
    names: &[String],
    out: &Path,
    manifest_path: Option<&Path>,
    flavor: Flavor,
    platforms: Platforms,
) -> Result<(), String> {
    let started = Instant::now();
    let (platforms, missing) = resolve(platforms)?;
    for m in &missing {
        eprintln!("warning: {m}");
    }
    let built = built_libraries(names, manifest_path, &flavor, &platforms)?;
    std::fs::create_dir_all(out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    for b in &built {
        for version in [Version::Fmi2, Version::Fmi3] {
            let packaged = package_fmu(b, &platforms, out, version)?;
            let folders: Vec<&str> = platforms.iter().map(|p| p.folder(version)).collect();
            println!(
                "{:<20} {:<8} {} ({} KiB): {}",
                b.krate.model,
                version.name(),
                packaged.path.display(),
                packaged.size.div_ceil(1024),
                folders.join(", ")
            );
        }
    }
    let tuples: Vec<&str> = platforms.iter().map(|p| p.tuple()).collect();
    println!(
        "built {} mechanism{} as FMI 2.0 and FMI 3.0 FMUs for {} in {:.1} s",
        built.len(),
        if built.len() == 1 { "" } else { "s" },
        tuples.join(", "),
        started.elapsed().as_secs_f64()
    );
    for m in &missing {
        println!("not built for {}: {}", m.platform.tuple(), m.what());
    }
    Ok(())
}

/// This machine's platform: the one whose binary the command loads.
fn host() -> Result<Platform, String> {
    Platform::host().ok_or_else(|| {
        format!(
            "mechfmu builds FMUs on {} only (this machine is {}-{})",
            Platform::ALL.map(Platform::tuple).join(", "),
            std::env::consts::ARCH,
            std::env::consts::OS
        )
    })
}

/// The platforms to build for, and the toolchains missing for those left out.
fn resolve(platforms: Platforms) -> Result<(Vec<Platform>, Vec<MissingToolchain>), String> {
    let host = host()?;
    let (wanted, chosen) = match platforms {
        Platforms::Host => (vec![host], true),
        Platforms::Available => (Platform::ALL.to_vec(), false),
        Platforms::Chosen(p) => (p, true),
    };
    let mut usable = Vec::new();
    let mut missing = Vec::new();
    for p in wanted {
        match p.missing_toolchain() {
            None => usable.push(p),
            Some(m) if p == host || chosen => return Err(m.to_string()),
            Some(m) => missing.push(m),
        }
    }
    Ok((usable, missing))
}

/// The mechanism crates named (every one when `names` is empty), built in release mode
/// for this machine and for `platforms`.
pub(crate) fn built_libraries(
    names: &[String],
    manifest_path: Option<&Path>,
    flavor: &Flavor,
    platforms: &[Platform],
) -> Result<Vec<Built>, String> {
    let host = host()?;
    let mut targets = platforms.to_vec();
    if !targets.contains(&host) {
        targets.push(host);
    }
    targets.sort();
    let selected = select(mechanism_crates(manifest_path)?, names)?;
    let libraries = cargo::build(&selected, manifest_path, flavor, &targets)?;
    selected
        .into_iter()
        .map(|krate| {
            let mine: BTreeMap<Platform, PathBuf> = libraries
                .iter()
                .filter(|l| l.package == krate.package)
                .map(|l| (l.platform, l.path.clone()))
                .collect();
            if let Some(p) = targets.iter().find(|p| !mine.contains_key(p)) {
                return Err(format!(
                    "cargo built no {} shared library for `{}`",
                    p.tuple(),
                    krate.package
                ));
            }
            Ok(Built {
                krate,
                libraries: mine,
            })
        })
        .collect()
}
