//! Where the `mechfmu` command finds mechfmu's own files besides its code: the Python
//! packages `validate` and `sweep` run (`python/`, with `tests/python/requirements.txt`,
//! in the environment `python` makes), the crates a new mechanism depends on
//! (`crates/runtime`, `crates/testkit`) and the fmi-crate importer `validate` builds
//! (`tools/fmi-run`).
//!
//! Run from a checkout (the binary is inside the source tree it was built from, as
//! `cargo run` and `target/release/mechfmu` are), they are the checkout's own, so edits take
//! effect at once. Installed (`cargo install`), the command carries copies of them (embedded
//! by `build.rs`) and writes them on first use to a per-user data folder named by its
//! version and a hash of their contents, laid out as in the source tree: everything that
//! works on the checkout's files works on the copy's, and a copy never changes under a
//! command that wrote it.

mod child;
pub mod python;

use std::ffi::OsString;
use std::path::{Path, PathBuf};

mod embedded {
    include!(concat!(env!("OUT_DIR"), "/embedded.rs"));
}

/// Names a mechfmu checkout to use instead of anything else (a developer's override).
const ROOT_ENV: &str = "MECHFMU_ROOT";
/// The folder under which the installed command writes its copies (default: the platform's
/// per-user data folder, see [`data_folder`]).
const HOME_ENV: &str = "MECHFMU_HOME";

/// The root of mechfmu's files: a checkout, or the copy written for this build of the
/// command. Either has `python/`, `tests/python/requirements.txt`, `crates/runtime`,
/// `crates/testkit`, `tools/fmi-run` and a workspace `Cargo.toml` holding the last.
pub(crate) fn root() -> Result<PathBuf, String> {
    if let Some(root) = std::env::var_os(ROOT_ENV).filter(|r| !r.is_empty()) {
        return std::path::absolute(&root)
            .map_err(|e| format!("{ROOT_ENV}={}: {e}", PathBuf::from(root).display()));
    }
    if let Some(tree) = running_checkout() {
        return Ok(tree);
    }
    let base = data_folder(|name| std::env::var_os(name))?;
    unpack(&base)
}

/// The source tree this binary was built from, when the binary runs from inside it and the
/// tree still has mechfmu's Python package: a developer's build. An installed binary (in
/// `~/.cargo/bin`) is never inside it, so it does not depend on the checkout staying put.
fn running_checkout() -> Option<PathBuf> {
    let tree = crate::build::workspace::source_tree();
    let exe = std::env::current_exe().ok()?;
    let exe = std::fs::canonicalize(&exe).unwrap_or(exe);
    (exe.starts_with(&tree) && tree.join("python/mechfmu_validate/__init__.py").is_file())
        .then_some(tree)
}

/// The folder the installed command writes under: `$MECHFMU_HOME`, else
/// `$XDG_DATA_HOME/mechfmu` or `~/.local/share/mechfmu` (Windows: `%LOCALAPPDATA%\mechfmu`).
/// `var` reads the environment.
fn data_folder(var: impl Fn(&str) -> Option<OsString>) -> Result<PathBuf, String> {
    let set = |name: &str| var(name).filter(|v| !v.is_empty()).map(PathBuf::from);
    if let Some(home) = set(HOME_ENV) {
        return std::path::absolute(&home)
            .map_err(|e| format!("{HOME_ENV}={}: {e}", home.display()));
    }
    let data = if cfg!(windows) {
        set("LOCALAPPDATA")
    } else {
        // the XDG base directory specification ignores a relative XDG_DATA_HOME
        set("XDG_DATA_HOME")
            .filter(|d| d.is_absolute())
            .or_else(|| set("HOME").map(|h| h.join(".local/share")))
    };
    data.map(|d| d.join("mechfmu")).ok_or_else(|| {
        format!("cannot tell where to keep mechfmu's files (no home folder): set {HOME_ENV}")
    })
}

/// Whether `root` is this build's copy (rather than a checkout): its folder is named by the
/// version and the contents' hash, and so never changes once written.
fn is_copy(root: &Path) -> bool {
    root.file_name()
        .is_some_and(|name| name.to_str() == Some(copy_name().as_str()))
}

/// Where the fmi-crate importer built from the copy at `root` is kept, once built: beside
/// the copies, named by a hash of its sources (`tools/fmi-run`, `Cargo.lock`), so that builds
/// of the command that differ elsewhere (in `python/`, in the runtime) share it. `None` for
/// a checkout, where cargo tells whether the importer is up to date.
pub(crate) fn kept_importer(root: &Path) -> Option<PathBuf> {
    let base = root.parent().filter(|_| is_copy(root))?;
    let name = format!(
        "mechfmu-fmi-run-{}{}",
        embedded::IMPORTER_HASH,
        std::env::consts::EXE_SUFFIX
    );
    Some(base.join(IMPORTERS).join(name))
}

/// The folder beside the copies that holds the importers built from them.
const IMPORTERS: &str = "bin";

/// The name of this build's copy's folder: the command's version and the contents' hash.
fn copy_name() -> String {
    format!("{}-{}", env!("CARGO_PKG_VERSION"), embedded::CONTENT_HASH)
}

/// The folder of this build's copy under `base`, written if it is not there yet.
fn unpack(base: &Path) -> Result<PathBuf, String> {
    let name = copy_name();
    let folder = base.join(&name);
    if folder.is_dir() {
        return Ok(folder);
    }
    eprintln!(
        "writing mechfmu's Python packages and crates to {} (first use of this mechfmu)",
        folder.display()
    );
    // written aside and renamed into place, so the folder is complete whenever it exists,
    // even with another mechfmu writing it at the same time
    let partial = base.join(format!(".{name}.{}.partial", std::process::id()));
    let written = write_files(&partial).and_then(|()| {
        std::fs::rename(&partial, &folder)
            .or_else(|e| if folder.is_dir() { Ok(()) } else { Err(e) })
            .map_err(|e| {
                format!(
                    "cannot move {} to {}: {e}",
                    partial.display(),
                    folder.display()
                )
            })
    });
    let _ = std::fs::remove_dir_all(&partial);
    written?;
    let others = older_copies(base, &name);
    if !others.is_empty() {
        eprintln!(
            "note: {} also holds the files of other builds of mechfmu ({}); remove those no \
             longer installed to free their disk space",
            base.display(),
            others.join(", ")
        );
    }
    Ok(folder)
}

fn write_files(folder: &Path) -> Result<(), String> {
    for (path, contents) in embedded::FILES {
        let file = folder.join(path);
        if let Some(parent) = file.parent() {
            std::fs::create_dir_all(parent)
                .map_err(|e| format!("cannot create {}: {e}", parent.display()))?;
        }
        std::fs::write(&file, contents)
            .map_err(|e| format!("cannot write {}: {e}", file.display()))?;
    }
    Ok(())
}

/// The other copies under `base` (other versions or builds), by folder name.
fn older_copies(base: &Path, current: &str) -> Vec<String> {
    let Ok(entries) = std::fs::read_dir(base) else {
        return Vec::new();
    };
    let mut names: Vec<String> = entries
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| !n.starts_with('.') && n != current && n != IMPORTERS)
        .collect();
    names.sort();
    names
}

#[cfg(test)]
mod tests {
    use super::*;

    fn folder(vars: &[(&str, &str)]) -> Result<PathBuf, String> {
        data_folder(|name| {
            vars.iter()
                .find(|(n, _)| *n == name)
                .map(|(_, v)| OsString::from(v))
        })
    }

    #[test]
    #[cfg(not(windows))]
    fn the_data_folder_follows_mechfmu_home_then_xdg_then_home() {
        let home = [("HOME", "/home/u")];
        assert_eq!(
            folder(&home),
            Ok(PathBuf::from("/home/u/.local/share/mechfmu"))
        );
        let xdg = [("HOME", "/home/u"), ("XDG_DATA_HOME", "/data")];
        assert_eq!(folder(&xdg), Ok(PathBuf::from("/data/mechfmu")));
        let relative_xdg = [("HOME", "/home/u"), ("XDG_DATA_HOME", "data")];
        assert_eq!(
            folder(&relative_xdg),
            Ok(PathBuf::from("/home/u/.local/share/mechfmu"))
        );
        let own = [
            ("HOME", "/home/u"),
            ("XDG_DATA_HOME", "/data"),
            ("MECHFMU_HOME", "/opt/m"),
        ];
        assert_eq!(folder(&own), Ok(PathBuf::from("/opt/m")));
        assert!(folder(&[]).is_err_and(|e| e.contains("MECHFMU_HOME")));
    }

    #[test]
    fn the_copy_holds_what_the_commands_use() {
        let paths: Vec<&str> = embedded::FILES.iter().map(|(p, _)| *p).collect();
        for wanted in [
            "Cargo.toml",
            "Cargo.lock",
            "python/pyproject.toml",
            "python/mechfmu_validate/__main__.py",
            "python/mechfmu_sweep/__main__.py",
            "tests/python/requirements.txt",
            "crates/runtime/Cargo.toml",
            "crates/runtime/src/lib.rs",
            "crates/testkit/src/lib.rs",
            "tools/fmi-run/src/main.rs",
        ] {
            assert!(paths.contains(&wanted), "{wanted} is not embedded");
        }
        assert!(!paths
            .iter()
            .any(|p| p.contains("__pycache__") || p.contains(".egg-info")));
    }

    #[test]
    fn the_copied_manifests_inherit_nothing() {
        for (path, contents) in embedded::FILES {
            if path.ends_with("Cargo.toml") {
                let text = std::str::from_utf8(contents).expect("UTF-8");
                assert!(
                    !text.contains("workspace = true"),
                    "{path} inherits:\n{text}"
                );
            }
        }
        let runtime = embedded::FILES
            .iter()
            .find(|(p, _)| *p == "crates/runtime/Cargo.toml")
            .map(|(_, c)| std::str::from_utf8(c).expect("UTF-8"))
            .expect("the runtime's manifest");
        let version = format!("version = \"{}\"", env!("CARGO_PKG_VERSION"));
        assert!(runtime.contains(&version), "{runtime}");
    }
}
