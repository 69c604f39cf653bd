//! The architecture `docs/architecture.md` draws is the one the code has: every crate's
//! normal dependencies are those of the page's crate table, every module of the runtime uses
//! only the layers above its own in the page's layer table, and no mechanism crate (nor the
//! `mechfmu new` template) allows `unsafe`.

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::Command;

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

fn architecture() -> String {
    std::fs::read_to_string(root().join("docs/architecture.md")).expect("docs/architecture.md")
}

/// The rows of the Markdown table between `<!-- NAME: begin -->` and `<!-- NAME: end -->`,
/// as cells, without the header and the rule.
fn table(text: &str, name: &str) -> Vec<Vec<String>> {
    let begin = format!("<!-- {name}: begin -->");
    let end = format!("<!-- {name}: end -->");
    let start = text
        .find(&begin)
        .unwrap_or_else(|| panic!("docs/architecture.md has no `{begin}`"));
    let stop = text[start..]
        .find(&end)
        .unwrap_or_else(|| panic!("docs/architecture.md has no `{end}`"));
    text[start + begin.len()..start + stop]
        .lines()
        .map(str::trim)
        .filter(|l| l.starts_with('|'))
        .skip(2)
        .map(|l| {
            l.trim_matches('|')
                .split('|')
                .map(|c| c.trim().to_string())
                .collect()
        })
        .collect()
}

fn names(cell: &str) -> BTreeSet<String> {
    cell.split(',')
        .map(str::trim)
        .filter(|n| !n.is_empty())
        .map(String::from)
        .collect()
}

/// Each workspace crate's normal dependencies, from `cargo metadata`.
fn dependencies() -> BTreeMap<String, BTreeSet<String>> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".into());
    let output = Command::new(cargo)
        .args([
            "metadata",
            "--format-version",
            "1",
            "--no-deps",
            "--manifest-path",
        ])
        .arg(root().join("Cargo.toml"))
        .output()
        .expect("cargo metadata runs");
    assert!(
        output.status.success(),
        "cargo metadata: {}",
        String::from_utf8_lossy(&output.stderr)
    );
    let meta: serde_json::Value = serde_json::from_slice(&output.stdout).unwrap();
    meta["packages"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| {
            let deps = p["dependencies"]
                .as_array()
                .unwrap()
                .iter()
                .filter(|d| d["kind"].is_null())
                .map(|d| d["name"].as_str().unwrap().to_string())
                .collect();
            (p["name"].as_str().unwrap().to_string(), deps)
        })
        .collect()
}

#[test]
fn every_crate_depends_on_what_the_picture_says_and_nothing_else() {
    let drawn: BTreeMap<String, BTreeSet<String>> = table(&architecture(), "crate-dependencies")
        .into_iter()
        .map(|row| (row[0].clone(), names(&row[1])))
        .collect();
    let actual = dependencies();
    let mut problems = Vec::new();
    for (krate, deps) in &actual {
        match drawn.get(krate) {
            None => problems.push(format!("crate `{krate}` is not in the picture")),
            Some(want) if want != deps => problems.push(format!(
                "crate `{krate}` depends on {deps:?}; the picture says {want:?}"
            )),
            Some(_) => {}
        }
    }
    for krate in drawn.keys().filter(|k| !actual.contains_key(*k)) {
        problems.push(format!(
            "the picture has crate `{krate}`, the workspace does not"
        ));
    }
    assert!(
        problems.is_empty(),
        "docs/architecture.md and the crates disagree:\n  {}",
        problems.join("\n  ")
    );
}

#[test]
fn no_mechanism_crate_depends_on_the_tooling() {
    let actual = dependencies();
    let mechanisms: Vec<_> = actual.keys().filter(|k| k.ends_with("-fmu")).collect();
    assert!(mechanisms.len() >= 6, "{mechanisms:?}");
    for tool in [
        "clap",
        "zip",
        "indicatif",
        "libloading",
        "serde_json",
        "mechfmu-cli",
        "mechfmu-host",
        "mechfmu-bench",
        "mechfmu-sweep-worker",
    ] {
        for m in &mechanisms {
            assert!(!actual[*m].contains(tool), "{m} depends on {tool}");
        }
        assert!(
            !actual["mechfmu"].contains(tool),
            "the runtime depends on {tool}"
        );
    }
}

/// The source files of a runtime module (`src/<m>.rs` or `src/<m>/**.rs`), without tests.
fn module_files(src: &Path, module: &str) -> Vec<PathBuf> {
    let file = src.join(format!("{module}.rs"));
    let mut files = Vec::new();
    if file.is_file() {
        files.push(file);
    }
    let mut dirs = vec![src.join(module)];
    while let Some(dir) = dirs.pop() {
        for entry in std::fs::read_dir(&dir).into_iter().flatten().flatten() {
            let path = entry.path();
            if path.is_dir() {
                dirs.push(path);
            } else if path.extension().is_some_and(|e| e == "rs")
                && path.file_stem().is_some_and(|s| s != "tests")
            {
                files.push(path);
            }
        }
    }
    files
}

/// The code of a file before its `#[cfg(test)]` module, without comments.
fn code(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap();
    let text = text.split("#[cfg(test)]").next().unwrap();
    text.lines()
        .map(|l| l.split("//").next().unwrap())
        .collect::<Vec<_>>()
        .join("\n")
}

/// The first path segments after every `crate::` in `code`.
fn crate_paths(code: &str) -> BTreeSet<String> {
    code.match_indices("crate::")
        .map(|(i, m)| {
            code[i + m.len()..]
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                .collect()
        })
        .collect()
}

#[test]
fn every_runtime_module_uses_only_the_layers_above_it() {
    let src = root().join("crates/runtime/src");
    let rows = table(&architecture(), "runtime-layers");
    let mut layer_of = BTreeMap::new();
    for row in &rows {
        let layer: u32 = row[0].parse().expect("a layer number");
        for module in names(&row[1]) {
            layer_of.insert(module, layer);
        }
    }
    // Every module of the crate is in the table.
    let lib = std::fs::read_to_string(src.join("lib.rs")).unwrap();
    let declared: BTreeSet<String> = lib
        .lines()
        .filter_map(|l| l.trim().strip_prefix("pub mod "))
        .map(|l| l.trim_end_matches(';').to_string())
        .collect();
    assert_eq!(
        declared,
        layer_of.keys().cloned().collect::<BTreeSet<_>>(),
        "the modules of crates/runtime/src/lib.rs and the layer table"
    );
    // Exported macros live at the crate root: each belongs to the module defining it.
    let mut owner = BTreeMap::new();
    for module in &declared {
        for file in module_files(&src, module) {
            let text = code(&file);
            for (i, m) in text.match_indices("macro_rules! ") {
                let name: String = text[i + m.len()..]
                    .chars()
                    .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
                    .collect();
                owner.insert(name, module.clone());
            }
        }
    }
    let mut problems = Vec::new();
    for module in &declared {
        for file in module_files(&src, module) {
            for used in crate_paths(&code(&file)) {
                let used = owner.get(&used).cloned().unwrap_or(used);
                let Some(&target) = layer_of.get(&used) else {
                    continue; // a re-export such as `crate::nalgebra`
                };
                if used != *module && target >= layer_of[module] {
                    problems.push(format!(
                        "{} (layer {}) uses `{used}` (layer {target})",
                        file.strip_prefix(&src).unwrap().display(),
                        layer_of[module]
                    ));
                }
            }
        }
    }
    assert!(
        problems.is_empty(),
        "arrows the layer table of docs/architecture.md does not allow:\n  {}",
        problems.join("\n  ")
    );
}

#[test]
fn mechanism_crates_and_the_template_forbid_unsafe_code() {
    let mut checked = Vec::new();
    for entry in std::fs::read_dir(root().join("fmus")).unwrap().flatten() {
        let lib = entry.path().join("src/lib.rs");
        if lib.is_file() {
            checked.push(lib);
        }
    }
    checked.push(root().join("crates/cli/src/templates/lib.rs.tmpl"));
    assert!(checked.len() >= 7, "{checked:?}");
    for file in checked {
        let text = std::fs::read_to_string(&file).unwrap();
        assert!(
            text.lines().any(|l| l.trim() == "#![forbid(unsafe_code)]"),
            "{} does not say #![forbid(unsafe_code)]",
            file.display()
        );
    }
}

/// The top-level modules of the crate whose sources are in `src`.
fn top_modules(src: &Path) -> BTreeSet<String> {
    std::fs::read_dir(src)
        .unwrap()
        .flatten()
        .filter_map(|e| {
            let path = e.path();
            let name = path.file_stem()?.to_str()?.to_string();
            let module = path.is_dir() || path.extension().is_some_and(|x| x == "rs");
            (module && name != "lib" && name != "main").then_some(name)
        })
        .collect()
}

#[test]
fn no_crate_has_modules_that_use_each_other_in_a_circle() {
    for krate in ["runtime", "testkit", "cli", "host", "bench", "sweep-worker"] {
        let src = root().join("crates").join(krate).join("src");
        let modules = top_modules(&src);
        let uses: BTreeMap<String, BTreeSet<String>> = modules
            .iter()
            .map(|m| {
                let used = module_files(&src, m)
                    .iter()
                    .flat_map(|f| crate_paths(&code(f)))
                    .filter(|u| modules.contains(u) && u != m)
                    .collect();
                (m.clone(), used)
            })
            .collect();
        // A module reaches itself through others: a circle.
        for start in &modules {
            let mut seen = BTreeSet::new();
            let mut stack: Vec<&String> = uses[start].iter().collect();
            while let Some(m) = stack.pop() {
                assert!(
                    m != start,
                    "crates/{krate}: `{start}` reaches itself through {seen:?}"
                );
                if seen.insert(m.clone()) {
                    stack.extend(uses[m].iter());
                }
            }
        }
    }
}
