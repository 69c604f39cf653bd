//! Compiling mechanism crates: finding them in the workspace (`workspace`), running cargo
//! for each platform (`cargo`) with the toolchains it needs (`toolchain`), and the shared
//! libraries it wrote.

mod cargo;
pub mod toolchain;
pub mod workspace;

use mechfmu_host::platform::Platform;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use toolchain::MissingToolchain;
use workspace::{mechanism_crates, system_crates, MechanismCrate};

/// The crates of `all` named by `names` (all of them when empty).
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
    /// What an FMU ships: the FMI functions alone.
    Shipped,
    /// With the runtime's `bench` feature (the entry points `mechfmu bench` times the parts
    /// of a step with) and its `describe` feature (the benchmark reads the FMI 3.0 model
    /// description from the binary; no describing build of its own), in a target directory
    /// of its own so the shipped build is untouched; for this machine only.
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

/// One mechanism crate's shared library for each platform built, and the library the FMU's
/// texts are read from.
pub(crate) struct Built {
    pub krate: MechanismCrate,
    pub libraries: BTreeMap<Platform, PathBuf>,
    /// This machine's library with the runtime's `describe` feature, never shipped: the one
    /// the `mechfmu` command loads to read what the binary says of itself (model
    /// descriptions, documentation, interface page), or, for a system's declaration, its
    /// own library.
    pub describing: PathBuf,
}

impl Built {
    /// This machine's shipped library.
    pub fn host_library(&self) -> &Path {
        let host = Platform::host().expect("checked by built_libraries");
        &self.libraries[&host]
    }
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
pub(crate) fn resolve(
    platforms: Platforms,
) -> Result<(Vec<Platform>, Vec<MissingToolchain>), String> {
    let host = host()?;
    let (wanted, chosen) = match platforms {
        Platforms::Host => (vec![host], true),
        Platforms::Available => (Platform::ALL.to_vec(), false),
        Platforms::Chosen(p) => (p, true),
    };
    let mut usable = Vec::new();
    let mut missing = Vec::new();
    for p in wanted {
        match toolchain::missing(p) {
            None => usable.push(p),
            Some(m) if p == host || chosen => return Err(m.to_string()),
            Some(m) => missing.push(m),
        }
    }
    Ok((usable, missing))
}

/// The system crates among `names` (every one when `names` is empty), and the names that
/// are not systems'.
pub(crate) fn systems_named(
    names: &[String],
    manifest_path: Option<&Path>,
) -> Result<(Vec<MechanismCrate>, Vec<String>), String> {
    let all = system_crates(manifest_path)?;
    if names.is_empty() {
        return Ok((all, Vec::new()));
    }
    let (systems, others): (Vec<&String>, Vec<&String>) = names
        .iter()
        .partition(|n| all.iter().any(|c| &&c.model == n));
    let chosen = all
        .into_iter()
        .filter(|c| systems.contains(&&c.model))
        .collect();
    Ok((chosen, others.into_iter().cloned().collect()))
}

/// The system crates `systems`, built in release mode for this machine, without features:
/// each binary says what its system is (`mechfmu_system_declaration`; the SSP carries the
/// components' FMUs, not it).
pub(crate) fn built_systems(
    systems: &[MechanismCrate],
    manifest_path: Option<&Path>,
    flavor: &Flavor,
) -> Result<Vec<Built>, String> {
    if systems.is_empty() {
        return Ok(Vec::new());
    }
    let host = [host()?];
    let libraries = cargo::build(systems, manifest_path, flavor, &host, &[])?;
    libraries_of(systems.to_vec(), &libraries, &libraries, &host)
}

/// The systems among `systems` that are one FMU (their feature `fmu`), built in release mode
/// for `platforms` and this machine with that feature on, in a cargo invocation of their own
/// (there their components export nothing, which would not do for the mechanisms' own FMUs),
/// and for this machine with the runtime's `describe` feature too: each binary is the
/// system's FMU's.
pub(crate) fn built_system_fmus(
    systems: &[MechanismCrate],
    manifest_path: Option<&Path>,
    flavor: &Flavor,
    platforms: &[Platform],
) -> Result<Vec<Built>, String> {
    let one_fmu: Vec<MechanismCrate> = systems.iter().filter(|s| s.one_fmu).cloned().collect();
    if one_fmu.is_empty() {
        return Ok(Vec::new());
    }
    let targets = with_host(platforms, host()?);
    let features: Vec<String> = one_fmu
        .iter()
        .map(|s| format!("{}/{}", s.package, workspace::SYSTEM_FMU_FEATURE))
        .collect();
    let libraries = cargo::build(&one_fmu, manifest_path, flavor, &targets, &features)?;
    let describing = describing(&one_fmu, manifest_path, flavor, &libraries, &features)?;
    libraries_of(one_fmu, &libraries, &describing, &targets)
}

/// `platforms` and this machine's, in order: the binaries built (the command reads what this
/// machine's says of itself).
fn with_host(platforms: &[Platform], host: Platform) -> Vec<Platform> {
    let mut targets = platforms.to_vec();
    if !targets.contains(&host) {
        targets.push(host);
    }
    targets.sort();
    targets
}

/// The libraries of `crates` to read their FMUs' texts from: the describing build's, or, for
/// the benchmark, whose binaries carry the extras, this machine's among `built`.
fn describing(
    crates: &[MechanismCrate],
    manifest_path: Option<&Path>,
    flavor: &Flavor,
    built: &[cargo::Library],
    features: &[String],
) -> Result<Vec<cargo::Library>, String> {
    match flavor {
        Flavor::Shipped => cargo::describe(crates, manifest_path, flavor, host()?, features),
        Flavor::Bench { .. } => Ok(built.to_vec()),
    }
}

/// Each crate of `crates` with its library for each of `targets` among the `libraries`
/// cargo built, and its describing library among `describing` (this machine's).
fn libraries_of(
    crates: Vec<MechanismCrate>,
    libraries: &[cargo::Library],
    describing: &[cargo::Library],
    targets: &[Platform],
) -> Result<Vec<Built>, String> {
    let missing = |p: Platform, krate: &MechanismCrate| {
        format!(
            "cargo built no {} shared library for `{}`",
            p.tuple(),
            krate.package
        )
    };
    let host = host()?;
    crates
        .into_iter()
        .map(|krate| {
            let mine: BTreeMap<Platform, PathBuf> = libraries
                .iter()
                .filter(|l| l.package == krate.package)
                .map(|l| (l.platform, l.path.clone()))
                .collect();
            if let Some(p) = targets.iter().find(|p| !mine.contains_key(p)) {
                return Err(missing(*p, &krate));
            }
            let describing = (describing.iter())
                .find(|l| l.package == krate.package && l.platform == host)
                .map(|l| l.path.clone())
                .ok_or_else(|| missing(host, &krate))?;
            Ok(Built {
                krate,
                libraries: mine,
                describing,
            })
        })
        .collect()
}

/// The mechanism crates named (every one when `names` is empty), built in release mode
/// for this machine and for `platforms`, and for this machine with the runtime's
/// `describe` feature.
pub(crate) fn built_libraries(
    names: &[String],
    manifest_path: Option<&Path>,
    flavor: &Flavor,
    platforms: &[Platform],
) -> Result<Vec<Built>, String> {
    let targets = with_host(platforms, host()?);
    let selected = select(mechanism_crates(manifest_path)?, names)?;
    let libraries = cargo::build(&selected, manifest_path, flavor, &targets, &[])?;
    let describing = describing(&selected, manifest_path, flavor, &libraries, &[])?;
    libraries_of(selected, &libraries, &describing, &targets)
}
