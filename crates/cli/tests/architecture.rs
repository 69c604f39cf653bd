//! The architecture `docs/architecture.md` draws is the one the code has: every crate's
//! normal dependencies are those of the page's crate table, every module of the runtime uses
//! only the layers above its own in the page's layer table, no two modules of a crate of
//! `crates/` and no two files of any workspace crate use each other in a circle, and no
//! mechanism crate (nor the `mechfmu new` template) allows `unsafe`.

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
fn mechanism_crates_and_the_templates_forbid_unsafe_code() {
    let mut checked = Vec::new();
    for entry in std::fs::read_dir(root().join("fmus")).unwrap().flatten() {
        let lib = entry.path().join("src/lib.rs");
        if lib.is_file() {
            checked.push(lib);
        }
    }
    checked.push(root().join("crates/cli/src/templates/lib.rs.tmpl"));
    checked.push(root().join("crates/cli/src/templates/energies/lib.rs.tmpl"));
    assert!(checked.len() >= 8, "{checked:?}");
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

/// The folders of the workspace's crates: the members of the root `Cargo.toml` (`dir/*`
/// standing for every folder of `dir` with a `Cargo.toml`), less its `exclude`.
fn workspace_crate_folders() -> Vec<PathBuf> {
    let manifest = std::fs::read_to_string(root().join("Cargo.toml")).unwrap();
    // The quoted strings of the array `key = [...]` of the root manifest.
    let array = |key: &str| -> Vec<String> {
        let Some(start) = manifest
            .lines()
            .position(|l| l.trim_start().starts_with(key) && l.contains('='))
        else {
            return Vec::new();
        };
        let text: String = manifest.lines().skip(start).collect::<Vec<_>>().join("\n");
        let inside = &text[text.find('[').unwrap() + 1..text.find(']').unwrap()];
        inside
            .split('"')
            .skip(1)
            .step_by(2)
            .map(String::from)
            .collect()
    };
    let excluded: BTreeSet<PathBuf> = array("exclude").iter().map(|e| root().join(e)).collect();
    let mut folders = Vec::new();
    for member in array("members") {
        match member.strip_suffix("/*") {
            Some(parent) => {
                let mut found: Vec<PathBuf> = std::fs::read_dir(root().join(parent))
                    .unwrap()
                    .flatten()
                    .map(|e| e.path())
                    .filter(|p| p.join("Cargo.toml").is_file())
                    .collect();
                found.sort();
                folders.extend(found);
            }
            None => folders.push(root().join(member)),
        }
    }
    folders.retain(|f| !excluded.contains(f));
    assert!(folders.len() >= 10, "workspace members: {folders:?}");
    folders
}

/// A module of a crate as the names from its root (`["model", "layout"]`; the root: none).
type ModulePath = Vec<String>;

/// The file of each module of the crate whose sources are in `src`: `a.rs` and `a/mod.rs`
/// are module `a`, `lib.rs` and `main.rs` the root. Tests (`tests.rs`, `tests/`) are left out.
fn files_by_module(src: &Path) -> BTreeMap<ModulePath, PathBuf> {
    let mut files = BTreeMap::new();
    let mut dirs = vec![src.to_path_buf()];
    while let Some(dir) = dirs.pop() {
        for path in std::fs::read_dir(&dir).unwrap().flatten().map(|e| e.path()) {
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            if path.is_dir() {
                if name != "tests" {
                    dirs.push(path);
                }
                continue;
            }
            let Some(stem) = name.strip_suffix(".rs") else {
                continue;
            };
            if stem == "tests" {
                continue;
            }
            let mut module: ModulePath = path
                .parent()
                .unwrap()
                .strip_prefix(src)
                .unwrap()
                .iter()
                .map(|s| s.to_string_lossy().into_owned())
                .collect();
            let root_file = module.is_empty() && (stem == "lib" || stem == "main");
            if stem != "mod" && !root_file {
                module.push(stem.to_string());
            }
            files.insert(module, path);
        }
    }
    files
}

/// A file's code before its `#[cfg(test)] mod name {`, with `//` comments blanked (lines
/// kept, so positions give line numbers).
fn code_outside_tests(path: &Path) -> String {
    let text = std::fs::read_to_string(path).unwrap();
    let mut end = text.len();
    for (at, attribute) in text.match_indices("#[cfg(test)]") {
        let rest = text[at + attribute.len()..].trim_start();
        let rest = rest.strip_prefix("pub").map_or(rest, str::trim_start);
        let Some(rest) = rest.strip_prefix("mod") else {
            continue;
        };
        if !rest.starts_with(char::is_whitespace) {
            continue;
        }
        let rest = rest.trim_start();
        let name_len = rest
            .find(|c: char| !(c.is_ascii_alphanumeric() || c == '_'))
            .unwrap_or(rest.len());
        if name_len > 0 && rest[name_len..].trim_start().starts_with('{') {
            end = at;
            break;
        }
    }
    text[..end]
        .lines()
        .map(|l| l.find("//").map_or(l, |i| &l[..i]))
        .collect::<Vec<_>>()
        .join("\n")
}

fn is_word_char(c: char) -> bool {
    c.is_ascii_alphanumeric() || c == '_'
}

/// The places in `code` where the word `word` starts.
fn word_starts<'a>(code: &'a str, word: &'a str) -> impl Iterator<Item = usize> + 'a {
    code.match_indices(word).map(|(i, _)| i).filter(move |&i| {
        !code[..i].ends_with(is_word_char) && !code[i + word.len()..].starts_with(is_word_char)
    })
}

fn line_at(code: &str, at: usize) -> usize {
    code[..at].matches('\n').count() + 1
}

/// The paths of a use tree: `crate::a::{b, c::d as e}` gives `crate::a::b` and `crate::a::c::d`.
fn use_tree_paths(prefix: &str, tree: &str, out: &mut Vec<String>) {
    let mut depth = 0;
    let mut parts = Vec::new();
    let mut start = 0;
    for (i, c) in tree.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                parts.push(&tree[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    parts.push(&tree[start..]);
    for part in parts.iter().map(|p| p.trim()).filter(|p| !p.is_empty()) {
        let unspaced = |s: &str| s.split_whitespace().collect::<String>();
        match part.split_once('{') {
            Some((head, rest)) => {
                let inner = &rest[..rest.rfind('}').unwrap_or(rest.len())];
                use_tree_paths(&format!("{prefix}{}", unspaced(head)), inner, out);
            }
            None => {
                let path = part.split_whitespace().collect::<Vec<_>>();
                let path = match path.iter().position(|w| *w == "as") {
                    Some(n) => path[..n].concat(),
                    None => path.concat(),
                };
                out.push(format!("{prefix}{path}"));
            }
        }
    }
}

/// Every path that starts with `crate`, `super` or `self` in `code`, with its line: those
/// of `use` declarations first, then every one written out.
fn relative_paths(code: &str) -> Vec<(String, usize)> {
    let mut paths = Vec::new();
    for at in word_starts(code, "use") {
        let rest = &code[at + 3..];
        let tree = rest.trim_start();
        let starts_relative = ["crate", "super", "self"]
            .iter()
            .any(|k| tree.starts_with(k) && !tree[k.len()..].starts_with(is_word_char));
        if rest.starts_with(char::is_whitespace) && starts_relative {
            if let Some(end) = tree.find(';') {
                let mut expanded = Vec::new();
                use_tree_paths("", &tree[..end], &mut expanded);
                let line = line_at(code, at);
                paths.extend(expanded.into_iter().map(|p| (p, line)));
            }
        }
    }
    let mut written = Vec::new();
    for keyword in ["crate", "super", "self"] {
        for at in word_starts(code, keyword) {
            let mut path = keyword.to_string();
            let mut rest = &code[at + keyword.len()..];
            while let Some(after) = rest.strip_prefix("::") {
                let len = after
                    .find(|c: char| !is_word_char(c))
                    .unwrap_or(after.len());
                if len == 0 || after.starts_with(|c: char| c.is_ascii_digit()) {
                    break;
                }
                path = format!("{path}::{}", &after[..len]);
                rest = &after[len..];
            }
            if path != keyword {
                written.push((at, path));
            }
        }
    }
    written.sort();
    paths.extend(written.into_iter().map(|(at, p)| (p, line_at(code, at))));
    paths
}

/// The module a path names from module `here`: the longest start of it that is a module of
/// `modules`.
fn module_named<'a>(
    path: &str,
    here: &ModulePath,
    modules: &'a BTreeMap<ModulePath, PathBuf>,
) -> Option<&'a ModulePath> {
    let mut segments: Vec<&str> = path.split("::").collect();
    let mut base: ModulePath = Vec::new();
    if segments[0] == "crate" {
        segments.remove(0);
    } else {
        base.clone_from(here);
        while let Some(&first) = segments.first() {
            match first {
                "super" => {
                    base.pop();
                }
                "self" => {}
                _ => break,
            }
            segments.remove(0);
        }
    }
    let mut named = None;
    for n in 0..=segments.len() {
        let candidate: ModulePath = base
            .iter()
            .cloned()
            .chain(segments[..n].iter().map(|s| s.to_string()))
            .collect();
        if let Some((module, _)) = modules.get_key_value(&candidate) {
            named = Some(module);
        }
    }
    named
}

/// Which file of the crate in `folder` uses which, `"a/b"` -> `"c"` (the root: `crate`),
/// with the first place of each arrow. A module naming itself or one of its own
/// descendants (a parent presenting its children) draws none.
fn file_arrows(folder: &Path) -> BTreeMap<(String, String), String> {
    let modules = files_by_module(&folder.join("src"));
    let name = |m: &ModulePath| {
        if m.is_empty() {
            "crate".to_string()
        } else {
            m.join("/")
        }
    };
    let mut arrows = BTreeMap::new();
    for (here, file) in &modules {
        let code = code_outside_tests(file);
        for (path, line) in relative_paths(&code) {
            let Some(target) = module_named(&path, here, &modules) else {
                continue;
            };
            if target.starts_with(here) {
                continue;
            }
            let place = format!(
                "{}:{line}",
                file.strip_prefix(root()).unwrap_or(file).display()
            );
            arrows.entry((name(here), name(target))).or_insert(place);
        }
    }
    arrows
}

/// The circles of a graph: its sets of two or more nodes each of which reaches every other.
fn circles_among(arrows: &BTreeMap<(String, String), String>) -> Vec<Vec<String>> {
    let nodes: BTreeSet<&String> = arrows.keys().map(|(a, _)| a).collect();
    let reach = |from: &String| {
        let mut seen = BTreeSet::new();
        let mut stack = vec![from];
        while let Some(node) = stack.pop() {
            for (_, next) in arrows.keys().filter(|(a, _)| a == node) {
                if seen.insert(next) {
                    stack.push(next);
                }
            }
        }
        seen
    };
    let reached: BTreeMap<&String, BTreeSet<&String>> =
        nodes.iter().map(|&n| (n, reach(n))).collect();
    let mut circles = BTreeSet::new();
    for &node in &nodes {
        let circle: Vec<String> = nodes
            .iter()
            .filter(|&&other| reached[node].contains(other) && reached[other].contains(node))
            .map(|&other| other.clone())
            .collect();
        if circle.len() > 1 {
            circles.insert(circle);
        }
    }
    circles.into_iter().collect()
}

#[test]
fn no_crate_has_files_that_use_each_other_in_a_circle() {
    let mut found = Vec::new();
    for folder in workspace_crate_folders() {
        if !folder.join("src").is_dir() {
            continue;
        }
        let arrows = file_arrows(&folder);
        for circle in circles_among(&arrows) {
            let krate = folder.strip_prefix(root()).unwrap_or(&folder).display();
            found.push(format!("{krate}: {}", circle.join(" <-> ")));
            for ((a, b), place) in &arrows {
                if circle.contains(a) && circle.contains(b) {
                    found.push(format!("    {a} -> {b}   {place}"));
                }
            }
        }
    }
    assert!(
        found.is_empty(),
        "files that use each other in a circle (through `crate::`, `super::` or `self::` \
         paths; a parent naming its own children does not count):\n{}",
        found.join("\n")
    );
}
