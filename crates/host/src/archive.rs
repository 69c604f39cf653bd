//! The `.fmu` file: a zip archive of `modelDescription.xml`, `binaries/<platform>/` and
//! the rest. Read here as an importer reads it: the model description, and this machine's
//! binary taken out to be loaded.

use crate::description::ModelDescription;
use crate::platform::Platform;
use std::fs::File;
use std::io::Read;
use std::path::{Path, PathBuf};
use zip::ZipArchive;

/// An FMU's model description and this machine's binary, written out of the archive.
pub struct Extracted {
    /// `<dir>/<model identifier>.<extension>`.
    pub binary: PathBuf,
    /// `<dir>/modelDescription.xml`.
    pub model_description: PathBuf,
}

/// A file under `binaries/` of an FMU.
pub struct Binary {
    /// Its path in the archive.
    pub path: String,
    /// The folder under `binaries/` it is in (the platform, as the FMU names it).
    pub folder: String,
    pub bytes: Vec<u8>,
}

fn open(fmu: &Path) -> Result<ZipArchive<File>, String> {
    let file = File::open(fmu).map_err(|e| format!("cannot open {}: {e}", fmu.display()))?;
    ZipArchive::new(file)
        .map_err(|e| format!("{} is not an FMU (not a zip archive): {e}", fmu.display()))
}

/// The entry `name` of the archive at `fmu` (read from `zip`).
fn read(zip: &mut ZipArchive<File>, fmu: &Path, name: &str) -> Result<Vec<u8>, String> {
    let mut entry = zip
        .by_name(name)
        .map_err(|e| format!("{} has no {name}: {e}", fmu.display()))?;
    let mut bytes = Vec::new();
    entry
        .read_to_end(&mut bytes)
        .map_err(|e| format!("cannot read {name} from {}: {e}", fmu.display()))?;
    Ok(bytes)
}

/// The bytes of the entry `name` (a path in the archive) of the FMU at `fmu`.
pub fn entry(fmu: &Path, name: &str) -> Result<Vec<u8>, String> {
    read(&mut open(fmu)?, fmu, name)
}

/// The model description of the FMU at `fmu`, as its archive holds it.
pub fn model_description(fmu: &Path) -> Result<String, String> {
    String::from_utf8(entry(fmu, "modelDescription.xml")?)
        .map_err(|e| format!("{}: modelDescription.xml is not UTF-8: {e}", fmu.display()))
}

/// Writes the model description and this machine's binary of the FMU at `fmu` into `dir`
/// (the binary from the folder of this machine's platform in the FMU's version).
pub fn extract(fmu: &Path, dir: &Path) -> Result<Extracted, String> {
    let mut zip = open(fmu)?;
    let xml = read(&mut zip, fmu, "modelDescription.xml")?;
    let description = ModelDescription::parse(&String::from_utf8_lossy(&xml))?;
    let host = Platform::host().ok_or("no FMU binary for this machine")?;
    let (id, extension) = (&description.model_identifier, host.extension());
    let folder = host.folder(description.version);
    let binary = read(
        &mut zip,
        fmu,
        &format!("binaries/{folder}/{id}.{extension}"),
    )?;
    std::fs::create_dir_all(dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let extracted = Extracted {
        binary: dir.join(format!("{id}.{extension}")),
        model_description: dir.join("modelDescription.xml"),
    };
    for (path, bytes) in [
        (&extracted.model_description, &xml),
        (&extracted.binary, &binary),
    ] {
        std::fs::write(path, bytes).map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    }
    Ok(extracted)
}

/// Every file under `binaries/<folder>/` of the FMU at `fmu`, in the archive's order.
pub fn binaries(fmu: &Path) -> Result<Vec<Binary>, String> {
    let mut zip = open(fmu)?;
    let mut binaries = Vec::new();
    for i in 0..zip.len() {
        let mut entry = zip
            .by_index(i)
            .map_err(|e| format!("cannot read {}: {e}", fmu.display()))?;
        let path = entry.name().unwrap_or_default().to_string();
        let Some(folder) = path
            .strip_prefix("binaries/")
            .and_then(|rest| rest.split_once('/'))
            .filter(|(_, file)| !file.is_empty())
            .map(|(folder, _)| folder.to_string())
        else {
            continue;
        };
        let mut bytes = Vec::new();
        entry
            .read_to_end(&mut bytes)
            .map_err(|e| format!("cannot read {path} from {}: {e}", fmu.display()))?;
        binaries.push(Binary {
            path,
            folder,
            bytes,
        });
    }
    Ok(binaries)
}
