//! Embeds the parts of mechfmu's source tree the `mechfmu` command needs besides its own
//! code, so that an installed command works without the checkout it was built from (see
//! `src/home.rs`, which writes them out on first use):
//!
//! - `python/` (the packages `mechfmu validate` and `mechfmu sweep` run) with
//!   `tests/python/requirements.txt` (their pinned dependencies) and `tests/python/refs/`
//!   (the reference solutions `validation/cases.py` files may import);
//! - the crates a new mechanism depends on, `crates/runtime` and `crates/testkit`, and the
//!   fmi-crate importer `tools/fmi-run` with the workspace's `Cargo.lock` (its pinned
//!   dependencies), and every crate these depend on by path, each under the same path as in
//!   the tree (so their `path = "../x"` dependencies hold).
//!
//! A crate is copied as cargo needs it to build it as a dependency: its `Cargo.toml`, its
//! `build.rs` and its `src/`. The copies of the manifests stand alone: the fields they inherit
//! from the workspace (`version.workspace = true`, ...) are written out with the workspace's
//! values. The `Cargo.toml` of a workspace whose one member is the importer is generated
//! beside them, so that the copy is laid out, and the importer built, as in the checkout.
//!
//! Output: `$OUT_DIR/embedded.rs`, a table of (path, `include_bytes!`), a hash of all the
//! contents, which names the folder they are written to, and a hash of the importer's
//! sources, which names the importer built from them.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

/// Folders embedded whole (but for Python's caches and build metadata), from the tree's root.
const FOLDERS: &[&str] = &["python", "tests/python/refs"];

/// Single files, from the tree's root.
const FILES: &[&str] = &["tests/python/requirements.txt", "Cargo.lock"];

/// The crates embedded with every crate they depend on by path, from the tree's root.
const CRATES: &[&str] = &["crates/runtime", "crates/testkit", IMPORTER];

/// The fmi-crate importer `mechfmu validate` builds.
const IMPORTER: &str = "tools/fmi-run";

/// The manifest of the copy's own workspace (`cargo build -p mechfmu-fmi-run` runs in it;
/// the other crates are only ever dependencies of a user's crate).
const WORKSPACE_MANIFEST: &str = "\
# Written by the `mechfmu` command: the crates it carries, laid out as in its source tree.
[workspace]
members = [\"tools/fmi-run\"]
resolver = \"2\"

# The importer only drives the FMU, whose binary does the numbers: built for a short build,
# not for speed (the checkout's own profile `importer`).
[profile.importer]
inherits = \"release\"
opt-level = 1
codegen-units = 16
strip = \"symbols\"

[profile.importer.package.\"*\"]
opt-level = 0
";

fn main() {
    let manifest_dir = PathBuf::from(std::env::var("CARGO_MANIFEST_DIR").expect("set by cargo"));
    let out_dir = PathBuf::from(std::env::var("OUT_DIR").expect("set by cargo"));
    let tree = manifest_dir.join("../..");
    println!("cargo::rerun-if-changed=build.rs");
    let files = files(&tree, &out_dir.join("embedded"));
    let importer = with_path_dependencies(&tree, IMPORTER);
    std::fs::write(out_dir.join("embedded.rs"), table(&files, &importer))
        .expect("cannot write embedded.rs");
}

/// What the command carries: path in the copy -> the file whose bytes it gets (the crates'
/// manifests as rewritten into `generated`, the other files where they are).
fn files(tree: &Path, generated: &Path) -> BTreeMap<String, PathBuf> {
    let mut files = BTreeMap::new();
    for folder in FOLDERS {
        for file in walk(&tree.join(folder)) {
            let relative = file.strip_prefix(tree).expect("under the tree");
            files.insert(slashed(relative), file);
        }
    }
    for file in FILES {
        files.insert(file.to_string(), tree.join(file));
    }
    let workspace = tree.join("Cargo.toml");
    println!("cargo::rerun-if-changed={}", workspace.display());
    let inherited = workspace_package(
        &std::fs::read_to_string(&workspace).expect("the workspace's Cargo.toml"),
    );
    let mut crates = Vec::new();
    for root in CRATES {
        for krate in with_path_dependencies(tree, root) {
            if !crates.contains(&krate) {
                crates.push(krate);
            }
        }
    }
    for krate in &crates {
        let dir = tree.join(krate);
        let manifest = dir.join("Cargo.toml");
        let text = std::fs::read_to_string(&manifest)
            .unwrap_or_else(|e| panic!("cannot read {}: {e}", manifest.display()));
        let standalone = standalone_manifest(&text, &inherited)
            .unwrap_or_else(|e| panic!("{krate}/Cargo.toml: {e}"));
        println!("cargo::rerun-if-changed={}", manifest.display());
        let copy = format!("{krate}/Cargo.toml");
        files.insert(copy.clone(), write(&generated.join(&copy), &standalone));
        if dir.join("build.rs").is_file() {
            files.insert(format!("{krate}/build.rs"), dir.join("build.rs"));
        }
        for file in walk(&dir.join("src")) {
            let relative = file.strip_prefix(tree).expect("under the tree");
            files.insert(slashed(relative), file);
        }
    }
    files.insert(
        "Cargo.toml".into(),
        write(&generated.join("Cargo.toml"), WORKSPACE_MANIFEST),
    );
    files
}

/// The Rust source of `embedded.rs`: the table of the files and the two hashes, of them all
/// and of what the importer (`importer_crates`) is built from.
fn table(files: &BTreeMap<String, PathBuf>, importer_crates: &[String]) -> String {
    let of_importer = |path: &str| {
        ["Cargo.toml", "Cargo.lock"].contains(&path)
            || importer_crates
                .iter()
                .any(|c| path.starts_with(&format!("{c}/")))
    };
    let mut table = String::from(
        "/// mechfmu's own files the command carries: (path in the copy, contents).\n\
         pub(crate) static FILES: &[(&str, &[u8])] = &[\n",
    );
    let mut hash = Fnv1a::new();
    let mut importer_hash = Fnv1a::new();
    for (path, file) in files {
        // a file that is only read (not generated) is watched where it is; a new file in a
        // watched folder is picked up with the next change to any watched file (watching
        // the folders themselves would rebuild on every Python run, which writes caches there)
        println!("cargo::rerun-if-changed={}", file.display());
        let bytes =
            std::fs::read(file).unwrap_or_else(|e| panic!("cannot read {}: {e}", file.display()));
        hash.write_file(path, &bytes);
        if of_importer(path) {
            importer_hash.write_file(path, &bytes);
        }
        let absolute = std::fs::canonicalize(file).unwrap_or_else(|_| file.clone());
        writeln!(
            table,
            "    ({path:?}, include_bytes!({:?})),",
            absolute.display().to_string()
        )
        .expect("writing to a String");
    }
    table.push_str("];\n\n");
    writeln!(
        table,
        "/// A hash of [`FILES`] (paths and contents): the folder they are written to is named by it.\n\
         pub(crate) const CONTENT_HASH: &str = \"{:016x}\";\n\n\
         /// A hash of the files the fmi-crate importer is built from: its build is shared by\n\
         /// the commands whose copies differ elsewhere.\n\
         pub(crate) const IMPORTER_HASH: &str = \"{:016x}\";",
        hash.finish(),
        importer_hash.finish()
    )
    .expect("writing to a String");
    table
}

/// Every file under `dir`, but hidden ones, Python's byte-code caches and setuptools'
/// build metadata (`*.egg-info`), which a Python run or an editable install leave there.
fn walk(dir: &Path) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let entries =
        std::fs::read_dir(dir).unwrap_or_else(|e| panic!("cannot read {}: {e}", dir.display()));
    for entry in entries {
        let path = entry.expect("a directory entry").path();
        let name = path
            .file_name()
            .and_then(|n| n.to_str())
            .unwrap_or_default();
        let skipped = name.starts_with('.')
            || name == "__pycache__"
            || name.ends_with(".egg-info")
            || name.ends_with(".pyc");
        if skipped {
            continue;
        }
        if path.is_dir() {
            found.extend(walk(&path));
        } else {
            found.push(path);
        }
    }
    found
}

fn slashed(path: &Path) -> String {
    path.components()
        .map(|c| c.as_os_str().to_string_lossy())
        .collect::<Vec<_>>()
        .join("/")
}

fn write(path: &Path, text: &str) -> PathBuf {
    std::fs::create_dir_all(path.parent().expect("a parent"))
        .expect("cannot create OUT_DIR's folders");
    // only when changed, so the file's time does not make cargo rebuild
    if std::fs::read_to_string(path).ok().as_deref() != Some(text) {
        std::fs::write(path, text)
            .unwrap_or_else(|e| panic!("cannot write {}: {e}", path.display()));
    }
    path.to_path_buf()
}

/// `krate` (a folder under `tree`) and every crate it depends on by path, directly or not.
fn with_path_dependencies(tree: &Path, krate: &str) -> Vec<String> {
    let mut found: Vec<String> = Vec::new();
    let mut pending = vec![krate.to_string()];
    while let Some(krate) = pending.pop() {
        if found.contains(&krate) {
            continue;
        }
        let manifest = tree.join(&krate).join("Cargo.toml");
        let text = std::fs::read_to_string(&manifest)
            .unwrap_or_else(|e| panic!("cannot read {}: {e}", manifest.display()));
        for path in path_dependencies(&text) {
            let dependency = normalized(&format!("{krate}/{path}"))
                .unwrap_or_else(|| panic!("{krate} depends on {path}, outside the source tree"));
            pending.push(dependency);
        }
        found.push(krate);
    }
    found
}

/// The `path = "..."` of a manifest's dependencies and build dependencies (its
/// dev-dependencies are not needed to build it for another crate).
fn path_dependencies(manifest: &str) -> Vec<String> {
    let mut paths = Vec::new();
    let mut table = String::new();
    for line in manifest.lines().map(str::trim) {
        if line.starts_with('[') {
            table = line.trim_matches(['[', ']']).to_string();
            continue;
        }
        let dependencies = table
            .split('.')
            .any(|part| part == "dependencies" || part == "build-dependencies");
        if !dependencies || line.starts_with('#') {
            continue;
        }
        // `path = "..."` as a key of its own, not the end of another name (`xpath = ...`)
        let path = line.match_indices("path").find_map(|(at, _)| {
            let own_key = line[..at]
                .chars()
                .next_back()
                .is_none_or(|c| !(c.is_alphanumeric() || c == '_' || c == '-'));
            let value = line[at + 4..].trim_start().strip_prefix('=')?.trim_start();
            let rest = value.strip_prefix('"').filter(|_| own_key)?;
            Some(rest[..rest.find('"')?].to_string())
        });
        paths.extend(path);
    }
    paths
}

/// `a/b/../c` as `a/c`; `None` when it leaves the root.
fn normalized(path: &str) -> Option<String> {
    let mut parts: Vec<&str> = Vec::new();
    for part in path.split('/') {
        match part {
            "" | "." => {}
            ".." => {
                parts.pop()?;
            }
            _ => parts.push(part),
        }
    }
    Some(parts.join("/"))
}

/// The `key = value` lines of the workspace's `[workspace.package]` table.
fn workspace_package(workspace: &str) -> BTreeMap<String, String> {
    let mut fields = BTreeMap::new();
    let mut inside = false;
    for line in workspace.lines().map(str::trim) {
        if line.starts_with('[') {
            inside = line == "[workspace.package]";
        } else if let (true, Some((key, value))) = (inside, line.split_once('=')) {
            fields.insert(key.trim().to_string(), value.trim().to_string());
        }
    }
    fields
}

/// A crate's manifest with its inherited `[package]` fields written out. `[lints]` taken
/// from the workspace is left out (lints concern the crate's own development, and the
/// workspace declares none); any other inheritance (a dependency's) is refused, so a copy
/// that would not build is a build error here rather than a user's.
fn standalone_manifest(text: &str, inherited: &BTreeMap<String, String>) -> Result<String, String> {
    let mut out = String::new();
    let mut table = String::new();
    for line in text.lines() {
        let trimmed = line.trim();
        if trimmed.starts_with('[') {
            table = trimmed.to_string();
            if table == "[lints]" {
                continue;
            }
        }
        if table == "[lints]" {
            if !(trimmed.is_empty() || trimmed.replace(' ', "") == "workspace=true") {
                return Err(format!("cannot write out the lint `{trimmed}`"));
            }
            continue;
        }
        if let Some(key) = trimmed
            .strip_suffix("true")
            .and_then(|l| l.trim_end().strip_suffix('='))
            .and_then(|l| l.trim_end().strip_suffix(".workspace"))
        {
            if table != "[package]" {
                return Err(format!("cannot write out `{trimmed}` (in {table})"));
            }
            let value = inherited
                .get(key)
                .ok_or_else(|| format!("`{key}` is not in the workspace's [workspace.package]"))?;
            writeln!(out, "{key} = {value}").expect("writing to a String");
        } else if trimmed.contains("workspace = true") || trimmed.contains("workspace=true") {
            return Err(format!("cannot write out `{trimmed}` (in {table})"));
        } else {
            out.push_str(line);
            out.push('\n');
        }
    }
    Ok(out)
}

/// 64-bit FNV-1a: a hash whose value is fixed by its definition, so a copy written by one
/// build is recognised by any build of the same files.
struct Fnv1a(u64);

impl Fnv1a {
    fn new() -> Self {
        Fnv1a(0xcbf2_9ce4_8422_2325)
    }

    fn write(&mut self, bytes: &[u8]) {
        for b in bytes {
            self.0 = (self.0 ^ u64::from(*b)).wrapping_mul(0x0100_0000_01b3);
        }
    }

    /// A file of the copy: its path, length and contents.
    fn write_file(&mut self, path: &str, contents: &[u8]) {
        self.write(path.as_bytes());
        self.write(&(contents.len() as u64).to_le_bytes());
        self.write(contents);
    }

    fn finish(&self) -> u64 {
        self.0
    }
}
