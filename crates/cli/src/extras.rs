//! What the `mechfmu` command reads besides a built FMU binary's functions: the texts the
//! binary renders of itself (its modelDescription, documentation and interface page, through
//! the documented extras of `export_fmu!`), and the reference results of its default
//! experiment committed beside its crate.

use crate::package::{Packaging, Version};
use std::path::Path;

/// Where reference results go inside the archive (the FMI layered standard's folder).
pub const REFERENCE_DIR: &str = "extra/org.fmi-standard.fmi-ls-ref";

/// The files `mechfmu build` adds to the archive of version `version` of `model` built
/// into `library` from the crate in `crate_dir`: `documentation/index.html` (rendered by
/// the binary for that version) and, when the crate has them, `reference/<model>_ref.csv`,
/// `_in.csv` and `_ref.opt` under [`REFERENCE_DIR`] (in an FMI 3.0 FMU, the columns of
/// scalars that are array elements there named as the elements, from its model
/// description `xml`). Sorted by archive path.
pub fn extra_files(
    model: &str,
    library: &Path,
    crate_dir: Option<&Path>,
    version: Version,
    xml: &str,
) -> Result<Vec<(String, Vec<u8>)>, String> {
    let mut files = vec![(
        "documentation/index.html".to_string(),
        exported_text(library, version.documentation_symbol(), "documentation")?.into_bytes(),
    )];
    if let Some(dir) = crate_dir {
        let mut references = reference_files(model, &dir.join("reference"))?;
        if version == Version::Fmi3 {
            let names = crate::fmi3_names::element_names(xml)?;
            for (path, bytes) in &mut references {
                if path.ends_with(".csv") {
                    *bytes = crate::fmi3_names::rename_columns(bytes, &names);
                }
            }
        }
        files.extend(references);
    }
    files.sort_by(|a, b| a.0.cmp(&b.0));
    Ok(files)
}

/// The reference files of `model` in `dir` (`<model>_ref.csv`, `<model>_in.csv`,
/// `<model>_ref.opt`, those that exist), as archive entries under [`REFERENCE_DIR`].
/// A missing directory gives none; an `_in.csv` or `_ref.opt` without `_ref.csv` is an error.
pub fn reference_files(model: &str, dir: &Path) -> Result<Vec<(String, Vec<u8>)>, String> {
    let mut files = Vec::new();
    for suffix in ["_in.csv", "_ref.csv", "_ref.opt"] {
        let name = format!("{model}{suffix}");
        let path = dir.join(&name);
        if path.is_file() {
            let bytes =
                std::fs::read(&path).map_err(|e| format!("cannot read {}: {e}", path.display()))?;
            files.push((format!("{REFERENCE_DIR}/{name}"), bytes));
        }
    }
    if !files.is_empty() && !files.iter().any(|(p, _)| p.ends_with("_ref.csv")) {
        return Err(format!(
            "{} has reference inputs or options for {model} but no {model}_ref.csv \
             (regenerate them with `mechfmu validate --write-references {model}`)",
            dir.display()
        ));
    }
    Ok(files)
}

/// The text a built FMU binary renders of itself through one of the documented extras of
/// `export_fmu!` (`symbol`: `mechfmu_model_description`, `mechfmu_documentation`, their
/// `_fmi3` siblings, `mechfmu_interface`; `what` names the text in messages), with the
/// buffer protocol of
/// `mechfmu::export::write_text`.
pub(crate) fn exported_text(library: &Path, symbol: &str, what: &str) -> Result<String, String> {
    type Render = unsafe extern "C" fn(*mut u8, usize) -> usize;
    // SAFETY: loading our own freshly built FMU binary; its initializers are Rust's.
    let lib = unsafe { libloading::Library::new(library) }
        .map_err(|e| format!("cannot load {}: {e}", library.display()))?;
    // SAFETY: the extras are exported by `export_fmu!` with this signature.
    let render: libloading::Symbol<Render> =
        unsafe { lib.get(symbol.as_bytes()) }.map_err(|e| {
            format!(
                "{} does not export {symbol} (not a mechfmu FMU binary, or built by an older \
                 mechfmu?): {e}",
                library.display()
            )
        })?;
    // SAFETY: a NULL buffer asks for the length; then a buffer of that length plus the NUL.
    let len = unsafe { render(std::ptr::null_mut(), 0) };
    let mut buf = vec![0u8; len + 1];
    let written = unsafe { render(buf.as_mut_ptr(), buf.len()) };
    if written != len || len == 0 {
        return Err(format!("{} rendered no {what}", library.display()));
    }
    buf.truncate(len);
    let text = String::from_utf8(buf).map_err(|e| format!("{what} is not UTF-8: {e}"))?;
    match text.strip_prefix("error: ") {
        Some(message) => Err(format!(
            "{}: cannot render its {what}: {message}",
            library.display()
        )),
        None => Ok(text),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reference_files_are_found_by_model_name() {
        let dir = std::env::temp_dir().join(format!("mechfmu-docs-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        assert!(reference_files("Spring", &dir).unwrap().is_empty());
        std::fs::write(dir.join("Spring_ref.opt"), "StartTime, 0\n").unwrap();
        assert!(reference_files("Spring", &dir)
            .unwrap_err()
            .contains("no Spring_ref.csv"));
        std::fs::write(dir.join("Spring_ref.csv"), "\"time\",\"x\"\n0,1\n").unwrap();
        std::fs::write(dir.join("Other_ref.csv"), "\"time\"\n0\n").unwrap();
        let files = reference_files("Spring", &dir).unwrap();
        let names: Vec<&str> = files.iter().map(|(p, _)| p.as_str()).collect();
        assert_eq!(
            names,
            [
                "extra/org.fmi-standard.fmi-ls-ref/Spring_ref.csv",
                "extra/org.fmi-standard.fmi-ls-ref/Spring_ref.opt"
            ]
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
