//! Finding the mechanism crates and the system crates of a workspace (through `cargo
//! metadata`).

use std::path::{Path, PathBuf};
use std::process::Command;

/// A crate that builds one FMU (its Cargo.toml has `[package.metadata.mechfmu] model = ...`),
/// or one system (`system = ...`: then `model` is the system's name).
#[derive(Clone, Debug)]
pub struct MechanismCrate {
    pub model: String,
    pub package: String,
    pub manifest: PathBuf,
    /// The package's description (`The <Model> FMU: what it is`).
    pub description: String,
    /// A system crate with the feature `fmu`, under which its binary is the system as one
    /// FMU (`export_fmu!`; its components' crates then export nothing of their own).
    pub one_fmu: bool,
}

/// The feature of a system crate under which its binary is the system's FMU.
pub const SYSTEM_FMU_FEATURE: &str = "fmu";

/// The mechanism crates of the workspace (or crate) at `manifest_path`.
pub fn mechanism_crates(manifest_path: Option<&Path>) -> Result<Vec<MechanismCrate>, String> {
    crates_declaring(manifest_path, "model")
}

/// The crates of the workspace (or crate) at `manifest_path` that each build one FMU with
/// reference cases of its own: the mechanism crates, then the systems that are one FMU, by
/// name.
pub fn fmu_crates(manifest_path: Option<&Path>) -> Result<Vec<MechanismCrate>, String> {
    let mut crates = mechanism_crates(manifest_path)?;
    crates.extend(
        system_crates(manifest_path)?
            .into_iter()
            .filter(|s| s.one_fmu),
    );
    crates.sort_by(|a, b| a.model.cmp(&b.model));
    Ok(crates)
}

/// The system crates of the workspace (or crate) at `manifest_path`.
pub fn system_crates(manifest_path: Option<&Path>) -> Result<Vec<MechanismCrate>, String> {
    crates_declaring(manifest_path, "system")
}

/// The crates whose `[package.metadata.mechfmu]` has `key`, by its value.
fn crates_declaring(
    manifest_path: Option<&Path>,
    key: &str,
) -> Result<Vec<MechanismCrate>, String> {
    let meta = metadata(manifest_path)?;
    let mut crates: Vec<MechanismCrate> = meta["packages"]
        .as_array()
        .into_iter()
        .flatten()
        .filter_map(|p| {
            let model = p["metadata"]["mechfmu"][key].as_str()?;
            Some(MechanismCrate {
                model: model.to_string(),
                package: p["name"].as_str()?.to_string(),
                manifest: PathBuf::from(p["manifest_path"].as_str()?),
                description: p["description"].as_str().unwrap_or_default().to_string(),
                one_fmu: key == "system" && p["features"].get(SYSTEM_FMU_FEATURE).is_some(),
            })
        })
        .collect();
    crates.sort_by(|a, b| a.model.cmp(&b.model));
    Ok(crates)
}

/// The workspace root (the folder of the workspace's Cargo.toml) of `manifest_path`.
pub fn workspace_root(manifest_path: Option<&Path>) -> Result<PathBuf, String> {
    metadata_path(manifest_path, "workspace_root")
}

/// Cargo's target directory for the workspace (or crate) at `manifest_path`.
pub fn target_directory(manifest_path: Option<&Path>) -> Result<PathBuf, String> {
    metadata_path(manifest_path, "target_directory")
}

/// A path `cargo metadata` gives under `key`.
fn metadata_path(manifest_path: Option<&Path>, key: &str) -> Result<PathBuf, String> {
    metadata(manifest_path)?[key]
        .as_str()
        .map(PathBuf::from)
        .ok_or_else(|| format!("cargo metadata gives no {key}"))
}

/// `cargo metadata` of the workspace at `manifest_path`, run in its folder (whose cargo
/// configuration, `build.target-dir` say, is the workspace's), else here.
fn metadata(manifest_path: Option<&Path>) -> Result<serde_json::Value, String> {
    let mut cmd = Command::new(cargo());
    cmd.args(["metadata", "--format-version", "1", "--no-deps"]);
    if let Some(path) = manifest_path {
        cmd.arg("--manifest-path").arg(path);
        if let Some(dir) = path.parent().filter(|d| d.is_dir()) {
            cmd.current_dir(dir);
        }
    }
    let output = cmd
        .output()
        .map_err(|e| format!("cannot run cargo metadata: {e}"))?;
    if !output.status.success() {
        return Err(format!(
            "cargo metadata failed:\n{}",
            String::from_utf8_lossy(&output.stderr).trim()
        ));
    }
    serde_json::from_slice(&output.stdout)
        .map_err(|e| format!("cannot read cargo metadata's output: {e}"))
}

pub(crate) fn cargo() -> String {
    std::env::var("CARGO").unwrap_or_else(|_| "cargo".into())
}

/// The mechfmu source tree this binary was built from (which may be gone since: where the
/// command finds mechfmu's files is `home::root`'s to say).
pub(crate) fn source_tree() -> PathBuf {
    let tree = Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    std::fs::canonicalize(&tree).unwrap_or(tree)
}
