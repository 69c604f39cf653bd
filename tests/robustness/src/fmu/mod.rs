//! Finding, unpacking and loading the built FMUs (`fmus/<Name>.fmu` of FMI 2.0,
//! `fmus/fmi3/<Name>.fmu` of FMI 3.0), and what this importer needs of their
//! modelDescription.xml ([`md2`], [`md3`]: read by `mechfmu_host::description`'s parser,
//! its [`Variable`]s as it gives them, asked through [`VariableExt`]).

mod md2;
mod md3;
mod variable;

pub use md2::{Experiment, ModelDescription};
pub use md3::ModelDescription3;
pub use mechfmu_host::description::Variable;
pub use variable::VariableExt;

use crate::ffi::Api;
use crate::ffi3::Api3;
use mechfmu_host::archive;
use mechfmu_host::description;
use mechfmu_host::library::Library;
use mechfmu_host::platform::Version;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// The directory holding the built FMUs: `$MECHFMU_FMUS_DIR`, else the workspace's `fmus/`.
pub fn fmus_dir() -> PathBuf {
    std::env::var_os("MECHFMU_FMUS_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fmus"))
}

/// Every `*.fmu` in `dir`, sorted, restricted to the comma-separated model names in
/// `$MECHFMU_ROBUSTNESS_ONLY` if set.
fn fmus_in(dir: &Path) -> Vec<PathBuf> {
    let only: Option<Vec<String>> = std::env::var("MECHFMU_ROBUSTNESS_ONLY")
        .ok()
        .map(|s| s.split(',').map(|x| x.trim().to_string()).collect());
    let mut paths: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|d| {
            d.filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|e| e == "fmu"))
                .filter(|p| {
                    only.as_ref().is_none_or(|o| {
                        p.file_stem()
                            .is_some_and(|s| o.iter().any(|n| n.as_str() == s.to_string_lossy()))
                    })
                })
                .collect()
        })
        .unwrap_or_default();
    paths.sort();
    paths
}

/// The FMI 2.0 FMUs: every `*.fmu` in [`fmus_dir`] (see [`fmus_in`]).
pub fn fmu_paths() -> Vec<PathBuf> {
    fmus_in(&fmus_dir())
}

/// The FMI 3.0 FMUs: every `*.fmu` in [`fmus_dir`]`/fmi3`.
pub fn fmu3_paths() -> Vec<PathBuf> {
    fmus_in(&fmus_dir().join("fmi3"))
}

/// `paths`, or a panic telling how to build them (a robustness suite that finds nothing
/// to test must not pass).
fn required(paths: Vec<PathBuf>, dir: PathBuf) -> Vec<PathBuf> {
    assert!(
        !paths.is_empty(),
        "no FMUs in {}: build them first with `cargo run --release -- build` \
         (or point MECHFMU_FMUS_DIR at a directory of .fmu files)",
        dir.display()
    );
    paths
}

/// The FMI 2.0 FMUs to test.
pub fn required_fmu_paths() -> Vec<PathBuf> {
    required(fmu_paths(), fmus_dir())
}

/// The FMI 3.0 FMUs to test.
pub fn required_fmu3_paths() -> Vec<PathBuf> {
    required(fmu3_paths(), fmus_dir().join("fmi3"))
}

/// A modelDescription.xml of `version`, read by `mechfmu_host::description`'s parser.
fn parse_of_version(xml: &str, version: Version) -> Result<description::ModelDescription, String> {
    let d = description::ModelDescription::parse(xml)?;
    if d.version != version {
        return Err(format!("not an {} modelDescription", version.name()));
    }
    Ok(d)
}

/// What an importer of either standard relies on: Model Exchange, if declared, in the
/// Co-Simulation binary (it loads one).
fn one_binary(model_exchange: Option<&String>, model_identifier: &str) -> Result<(), String> {
    if model_exchange.is_some_and(|id| id != model_identifier) {
        return Err(
            "ModelExchange and CoSimulation name different binaries: this importer loads one"
                .into(),
        );
    }
    Ok(())
}

/// One past the largest value reference of `variables`.
fn vr_end(variables: &[Variable]) -> u32 {
    variables.iter().map(|v| v.vr + 1).max().unwrap_or(0)
}

/// The FMI version a `.fmu`'s modelDescription.xml declares (`fmiVersion`).
pub fn fmi_version(fmu: &Path) -> Result<String, String> {
    let xml = archive::model_description(fmu)?;
    let at = xml
        .find("fmiVersion=\"")
        .ok_or_else(|| format!("{}: no fmiVersion", fmu.display()))?;
    let rest = &xml[at + 12..];
    Ok(rest[..rest.find('"').unwrap_or(0)].to_string())
}

static UNPACKED: AtomicUsize = AtomicUsize::new(0);

/// An FMU's model description and this machine's binary, written into a private temporary
/// directory (removed again on drop), and the binary loaded.
struct Unpacked {
    library: Library,
    dir: PathBuf,
    binary: PathBuf,
}

impl Unpacked {
    /// Writes out the model description and the binary of `fmu` (`mechfmu_host::archive`:
    /// from this machine's platform folder of the FMU's version) and loads the binary.
    fn new(fmu: &Path) -> Result<Unpacked, String> {
        let dir = std::env::temp_dir().join(format!(
            "mechfmu-robustness-{}-{}",
            std::process::id(),
            UNPACKED.fetch_add(1, Ordering::Relaxed)
        ));
        let extracted = archive::extract(fmu, &dir)?;
        Ok(Unpacked {
            library: Library::open(&extracted.binary)?,
            dir,
            binary: extracted.binary,
        })
    }
}

impl Drop for Unpacked {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// `fmu`'s modelDescription.xml parsed, its binary unpacked and the functions loaded from
/// it (the errors naming the FMU).
fn unpack_and_load<M, A>(
    fmu: &Path,
    parse: fn(&str) -> Result<M, String>,
    load: fn(&Library) -> Result<A, String>,
) -> Result<(M, Unpacked, A), String> {
    let xml = archive::model_description(fmu)?;
    let md = parse(&xml).map_err(|e| format!("{}: {e}", fmu.display()))?;
    let unpacked = Unpacked::new(fmu)?;
    let api = load(&unpacked.library).map_err(|e| format!("{}: {e}", fmu.display()))?;
    Ok((md, unpacked, api))
}

/// An FMI 2.0 FMU unpacked into a private temporary directory and loaded.
pub struct Fmu {
    pub md: ModelDescription,
    pub api: Api,
    pub path: PathBuf,
    unpacked: Unpacked,
}

impl Fmu {
    /// Unpacks `fmu` (modelDescription.xml and this machine's binary) and loads the
    /// binary, resolving all 44 functions.
    pub fn load(fmu: &Path) -> Result<Fmu, String> {
        let (md, unpacked, api) = unpack_and_load(fmu, ModelDescription::parse, Api::load)?;
        Ok(Fmu {
            md,
            api,
            path: fmu.to_path_buf(),
            unpacked,
        })
    }

    pub fn name(&self) -> &str {
        &self.md.model_identifier
    }

    /// The unpacked binary.
    pub fn binary(&self) -> PathBuf {
        self.unpacked.binary.clone()
    }
}

/// An FMI 3.0 FMU unpacked into a private temporary directory and loaded.
pub struct Fmu3 {
    pub md: ModelDescription3,
    pub api: Api3,
    /// The FMI 2.0 functions of the same binary (it serves the FMU of either version) and
    /// the GUID of the FMI 2.0 FMU built with it (`fmus/<Name>.fmu`, when there): a
    /// hostile importer's way to the other standard's instances and FMU states.
    pub fmi2: Option<(Api, String)>,
    pub path: PathBuf,
    /// Held for its lifetime: the binary stays loaded, the directory is removed on drop.
    _unpacked: Unpacked,
}

impl Fmu3 {
    /// Unpacks `fmu` (modelDescription.xml and this machine's binary) and loads the
    /// binary, resolving all 75 functions.
    pub fn load(fmu: &Path) -> Result<Fmu3, String> {
        let (md, unpacked, api) = unpack_and_load(fmu, ModelDescription3::parse, Api3::load)?;
        let sibling = fmu
            .parent()
            .and_then(Path::parent)
            .map(|d| d.join(fmu.file_name().unwrap_or_default()));
        let guid = sibling
            .and_then(|p| archive::model_description(&p).ok())
            .and_then(|xml| ModelDescription::parse(&xml).ok())
            .filter(|md2| md2.model_identifier == md.model_identifier)
            .map(|md2| md2.guid);
        // the binary exports the FMI 2.0 functions too (tests/exports.rs)
        let fmi2 = guid.and_then(|g| Api::load(&unpacked.library).ok().map(|a| (a, g)));
        Ok(Fmu3 {
            md,
            api,
            fmi2,
            path: fmu.to_path_buf(),
            _unpacked: unpacked,
        })
    }

    pub fn name(&self) -> &str {
        &self.md.model_identifier
    }
}
