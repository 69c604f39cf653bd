//! `mechfmu build --cross-check DIR`: the FMUs as an exporter submits them to the FMI
//! cross-check (github.com/modelica/fmi-cross-check): for each FMI version, interface and
//! platform an FMU carries, `DIR/fmus/<2.0|3.0>/<cs|me>/<platform>/mechfmu/<version>/<Model>/`
//! holding `<Model>.fmu`, the reference files the archive carries (`<Model>_ref.csv`,
//! `_in.csv`, `_ref.opt`, the same bytes) and a `README.md`. The platform folder is the
//! binary's folder in the FMU (FMI 2.0's `linux64`, `win64`, else FMI 3.0's tuple).

use super::references::REFERENCE_DIR;
use mechfmu::contract::Version;
use mechfmu_host::platform::Platform;
use std::path::{Path, PathBuf};

/// The exporting tool's name in the tree.
pub const TOOL: &str = "mechfmu";

/// The interfaces every mechfmu FMU offers: the tree's folder and the standard's name.
const INTERFACES: [(&str, &str); 2] = [("cs", "Co-Simulation"), ("me", "Model Exchange")];

/// The tree's name of an FMI version.
fn version_folder(version: Version) -> &'static str {
    match version {
        Version::Fmi2 => "2.0",
        Version::Fmi3 => "3.0",
    }
}

/// The folder of `model` for `version`, `interface` (`cs`, `me`) and `platform` in the tree
/// under `root`.
pub fn model_folder(
    root: &Path,
    version: Version,
    interface: &str,
    platform: Platform,
    model: &str,
) -> PathBuf {
    root.join("fmus")
        .join(version_folder(version))
        .join(interface)
        .join(platform.folder(version))
        .join(TOOL)
        .join(env!("CARGO_PKG_VERSION"))
        .join(model)
}

/// Writes the folders of the FMU `fmu` of `model` and `version`, built for `platforms`, whose
/// archive carries `references` (archive path, bytes); returns the folders written.
pub fn write_model(
    root: &Path,
    model: &str,
    version: Version,
    platforms: &[Platform],
    fmu: &Path,
    references: &[(String, Vec<u8>)],
) -> Result<Vec<PathBuf>, String> {
    let files: Vec<(&str, &[u8])> = references
        .iter()
        .filter_map(|(path, bytes)| {
            let name = path.strip_prefix(REFERENCE_DIR)?.trim_start_matches('/');
            Some((name, bytes.as_slice()))
        })
        .collect();
    let folders: Vec<&str> = platforms.iter().map(|p| p.folder(version)).collect();
    let mut written = Vec::new();
    for &platform in platforms {
        for (interface, interface_name) in INTERFACES {
            let dir = model_folder(root, version, interface, platform, model);
            let fail = |e: std::io::Error| format!("cannot write {}: {e}", dir.display());
            // the folder is this build's alone: a file no longer carried must not stay
            if dir.exists() {
                std::fs::remove_dir_all(&dir).map_err(fail)?;
            }
            std::fs::create_dir_all(&dir).map_err(fail)?;
            std::fs::copy(fmu, dir.join(format!("{model}.fmu"))).map_err(fail)?;
            for (name, bytes) in &files {
                std::fs::write(dir.join(name), bytes).map_err(fail)?;
            }
            let readme = readme(
                model,
                version,
                interface_name,
                platform.folder(version),
                &folders,
                &files,
            );
            std::fs::write(dir.join("README.md"), readme).map_err(fail)?;
            written.push(dir);
        }
    }
    Ok(written)
}

/// The folder's `README.md`: what the FMU is and what each file holds.
fn readme(
    model: &str,
    version: Version,
    interface: &str,
    platform: &str,
    folders: &[&str],
    files: &[(&str, &[u8])],
) -> String {
    let mut text = format!(
        "# {model}\n\n\
         An {} FMU exported by mechfmu {}, here for {interface} on {platform}. The one archive \
         offers both Co-Simulation and Model Exchange, with binaries for {}; its \
         `documentation/index.html` describes the model: its equations, variables and units.\n\n\
         | file | content |\n|---|---|\n| `{model}.fmu` | the FMU |\n",
        version.name(),
        env!("CARGO_PKG_VERSION"),
        folders.join(", "),
    );
    for (name, bytes) in files {
        let content = if name.ends_with("_ref.csv") {
            "the reference results, computed by mechfmu's independent reference of the mechanism \
             (closed forms, or an accurate solution of its equations), never by the FMU"
                .to_string()
        } else if name.ends_with("_in.csv") {
            "the inputs over the experiment".to_string()
        } else if name.ends_with("_ref.opt") {
            let settings: Vec<&str> = std::str::from_utf8(bytes)
                .unwrap_or("")
                .lines()
                .map(str::trim)
                .filter(|l| !l.is_empty())
                .collect();
            format!("the experiment: {}", settings.join("; "))
        } else {
            continue;
        };
        text.push_str(&format!("| `{name}` | {content} |\n"));
    }
    text.push_str(&format!(
        "\nThe archive carries the same reference files in `{REFERENCE_DIR}/`. Written by \
         `mechfmu build --cross-check`.\n"
    ));
    text
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_version_interface_and_platform_has_its_folder() {
        let root =
            std::env::temp_dir().join(format!("mechfmu-cross-check-test-{}", std::process::id()));
        let fmu = root.join("Spring.fmu");
        std::fs::create_dir_all(&root).unwrap();
        std::fs::write(&fmu, b"PK archive").unwrap();
        let references = vec![
            (
                format!("{REFERENCE_DIR}/Spring_ref.csv"),
                b"\"time\",\"x\"\n0,1\n".to_vec(),
            ),
            (
                format!("{REFERENCE_DIR}/Spring_ref.opt"),
                b"StartTime, 0.0\nStopTime, 1.0\n".to_vec(),
            ),
        ];
        let platforms = [Platform::X86_64Linux, Platform::X86_64Windows];
        for version in [Version::Fmi2, Version::Fmi3] {
            let written =
                write_model(&root, "Spring", version, &platforms, &fmu, &references).unwrap();
            assert_eq!(written.len(), 4);
        }
        let version = env!("CARGO_PKG_VERSION");
        for (v, platform) in [
            ("2.0", "linux64"),
            ("2.0", "win64"),
            ("3.0", "x86_64-linux"),
            ("3.0", "x86_64-windows"),
        ] {
            for interface in ["cs", "me"] {
                let dir = root.join(format!(
                    "fmus/{v}/{interface}/{platform}/mechfmu/{version}/Spring"
                ));
                let mut names: Vec<String> = std::fs::read_dir(&dir)
                    .unwrap()
                    .map(|e| e.unwrap().file_name().into_string().unwrap())
                    .collect();
                names.sort();
                assert_eq!(
                    names,
                    [
                        "README.md",
                        "Spring.fmu",
                        "Spring_ref.csv",
                        "Spring_ref.opt"
                    ],
                    "{}",
                    dir.display()
                );
                assert_eq!(
                    std::fs::read(dir.join("Spring_ref.csv")).unwrap(),
                    references[0].1
                );
                let readme = std::fs::read_to_string(dir.join("README.md")).unwrap();
                assert!(readme.contains("StartTime, 0.0; StopTime, 1.0"), "{readme}");
            }
        }
        // a file the archive no longer carries leaves the folder
        write_model(
            &root,
            "Spring",
            Version::Fmi2,
            &platforms[..1],
            &fmu,
            &references[..1],
        )
        .unwrap();
        let dir = model_folder(&root, Version::Fmi2, "cs", platforms[0], "Spring");
        assert!(!dir.join("Spring_ref.opt").exists());
        std::fs::remove_dir_all(&root).unwrap();
    }
}
