//! The reference results of a mechanism (over its default experiment's time and step, from
//! the FMU's start values), committed beside its crate
//! (`reference/<model>_ref.csv`, `_in.csv`, `_ref.opt`), as `mechfmu build` packages them
//! (the FMI layered standard's folder); in an FMI 3.0 FMU with the columns of the scalars
//! that are array elements there named as the elements.

use std::path::Path;

/// Where reference results go inside the archive (the FMI layered standard's folder).
pub const REFERENCE_DIR: &str = "extra/org.fmi-standard.fmi-ls-ref";

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

/// `csv` with the quoted column names of its first line renamed by `names` (FMI 2.0 scalar,
/// FMI 3.0 element).
pub fn rename_columns(csv: &[u8], names: &[(String, String)]) -> Vec<u8> {
    let text = String::from_utf8_lossy(csv);
    let (header, rest) = text.split_once('\n').unwrap_or((&text, ""));
    let renamed: Vec<String> = header
        .trim_end_matches('\r')
        .split(',')
        .map(|column| {
            let bare = column.trim().trim_matches('"');
            match names.iter().find(|(scalar, _)| scalar == bare) {
                Some((_, element)) => format!("\"{element}\""),
                None => column.to_string(),
            }
        })
        .collect();
    let mut out = renamed.join(",");
    out.push('\n');
    out.push_str(rest);
    out.into_bytes()
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

    #[test]
    fn only_the_header_is_renamed() {
        let names = [("a", "I[1,1]"), ("c", "I[2,2]")].map(|(s, e)| (s.into(), e.into()));
        let csv = b"\"time\",\"a\",\"g\",\"c\"\n0,1,2,3\n";
        assert_eq!(
            String::from_utf8(rename_columns(csv, &names)).unwrap(),
            "\"time\",\"I[1,1]\",\"g\",\"I[2,2]\"\n0,1,2,3\n"
        );
    }
}
