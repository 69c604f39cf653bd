//! The packager's side: the documentation a built FMU binary renders of itself, and the
//! reference results of its default experiment committed beside its crate.

use std::path::Path;

/// Where reference results go inside the archive (the FMI layered standard's folder).
pub const REFERENCE_DIR: &str = "extra/org.fmi-standard.fmi-ls-ref";

/// The files `mechfmu build` adds to the archive of `model` built into `library` from the
/// crate in `crate_dir`: `documentation/index.html` (rendered by the binary) and, when the
/// crate has them, `reference/<model>_ref.csv`, `_in.csv` and `_ref.opt` under
/// [`REFERENCE_DIR`]. Sorted by archive path.
pub fn extra_files(
    model: &str,
    library: &Path,
    crate_dir: Option<&Path>,
) -> Result<Vec<(String, Vec<u8>)>, String> {
    let mut files = vec![(
        "documentation/index.html".to_string(),
        documentation_of(library)?.into_bytes(),
    )];
    if let Some(dir) = crate_dir {
        files.extend(reference_files(model, &dir.join("reference"))?);
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

/// The `documentation/index.html` a built FMU binary renders of itself
/// (`mechfmu_documentation`, exported by `export_fmu!`).
pub fn documentation_of(library: &Path) -> Result<String, String> {
    crate::build::exported_text(library, "mechfmu_documentation", "documentation")
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
