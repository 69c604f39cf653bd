//! Packaging one mechanism's built libraries as an FMU of one FMI version.

use super::Built;
use crate::package::{Packaging, Version};
use crate::platform::Platform;
use std::path::PathBuf;

/// An FMU written.
pub struct Packaged {
    pub path: PathBuf,
    /// Its size in bytes.
    pub size: u64,
}

/// Packages the libraries of `built` for `platforms` as an FMU of `version` (in
/// [`Packaging::folder`] of `out`): asks this machine's binary for its own modelDescription
/// of that version, so the XML and the binaries can never disagree, and for its
/// documentation; checks every binary (see [`crate::binaries::check`]); adds the reference
/// results of the default experiment found in the crate's `reference/` (see
/// [`crate::extras`]).
pub fn package_fmu(
    built: &Built,
    platforms: &[Platform],
    out: &std::path::Path,
    version: Version,
) -> Result<Packaged, String> {
    let model = &built.krate.model;
    let host = built.host_library();
    let xml =
        crate::extras::exported_text(host, version.model_description_symbol(), "modelDescription")?;
    let read = |path: &std::path::Path| {
        std::fs::read(path).map_err(|e| format!("cannot read {}: {e}", path.display()))
    };
    let host_exports = crate::binaries::inspect(&read(host)?)
        .map_err(|e| format!("{}: {e}", host.display()))?
        .exports;
    let mut binaries = Vec::new();
    for &platform in platforms {
        let path = &built.libraries[&platform];
        let bytes = read(path)?;
        crate::binaries::check(&bytes, platform, &host_exports).map_err(|e| {
            format!(
                "the {} binary of {model} ({}) cannot be shipped: {e}",
                platform.tuple(),
                path.display()
            )
        })?;
        let archive_path = format!(
            "binaries/{}/{model}.{}",
            platform.folder(version),
            platform.extension()
        );
        binaries.push((archive_path, bytes));
    }
    let folder = version.folder(out);
    std::fs::create_dir_all(&folder)
        .map_err(|e| format!("cannot create {}: {e}", folder.display()))?;
    let path = folder.join(format!("{model}.fmu"));
    let contents = crate::package::Contents {
        model_description: &xml,
        binaries,
        extra: crate::extras::extra_files(
            model,
            host,
            built.krate.manifest.parent(),
            version,
            &xml,
        )?,
    };
    crate::package::write_fmu(&path, &contents)
        .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    let size = std::fs::metadata(&path).map(|m| m.len()).unwrap_or(0);
    Ok(Packaged { path, size })
}
