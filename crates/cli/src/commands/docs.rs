//! `mechfmu docs`: the interface page of every mechanism (variables, units, defaults,
//! equations) as Markdown, `<out>/<Name>.md`. Each page is rendered by the mechanism's own
//! describing binary (`mechfmu_interface`, exported by `export_fmu!` with the `describe`
//! feature), as `mechfmu build` asks it for its modelDescription and documentation: the
//! tool never renders a mechanism itself. Each crate's `interface_is_current` test checks the same page.
//!
//! And the index of the mechanisms, a table of each one's page and what it is (its
//! package's description), in the workspace's `README.md` and in `<out>/README.md`, between
//! the markers `<!-- mechanisms: begin -->` and `<!-- mechanisms: end -->` where a file has
//! them; `the_indexes_of_this_workspace_are_current` checks this repository's.

use crate::build::workspace::{fmu_crates, workspace_root, MechanismCrate};
use crate::build::{built_libraries, built_system_fmus, systems_named, Flavor};
use mechfmu_host::library::{Extra, Library};
use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct Args {
    /// Model identifiers, e.g. Oscillator Crane (default: every mechanism).
    names: Vec<String>,
    /// Where the pages go (one `<Name>.md` per mechanism).
    #[arg(long, default_value = "docs/mechanisms")]
    out: PathBuf,
    /// Write nothing; fail, listing them, when pages are stale or missing.
    #[arg(long)]
    check: bool,
    /// The Cargo.toml of the workspace or crate holding the mechanisms.
    #[arg(long)]
    manifest_path: Option<PathBuf>,
}

/// What a page on disk is, against the page the binary renders.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum State {
    Current,
    Stale,
    Missing,
}

pub fn run(args: Args) -> Result<(), String> {
    let manifest_path = args.manifest_path.as_deref();
    let (systems, mechanisms) = systems_named(&args.names, manifest_path)?;
    // a system that is one FMU has its page as a mechanism has; built first, since its build
    // compiles its components under their feature `component`, and the mechanisms' own build
    // then leaves them as the mechanisms' FMUs want them
    let mut built = built_system_fmus(&systems, manifest_path, &Flavor::Shipped, &[])?;
    if args.names.is_empty() || !mechanisms.is_empty() {
        built.extend(built_libraries(
            &mechanisms,
            manifest_path,
            &Flavor::Shipped,
            &[],
        )?);
    }
    let mut not_current = Vec::new();
    for b in &built {
        let (c, library) = (&b.krate, b.describing.as_path());
        let page = interface_of(library)?;
        let path = args.out.join(format!("{}.md", c.model));
        let state = state_of(&path, &page)?;
        if args.check {
            if state != State::Current {
                not_current.push((path, state));
            }
            continue;
        }
        let what = match state {
            State::Current => "current",
            State::Stale | State::Missing => {
                std::fs::create_dir_all(&args.out)
                    .map_err(|e| format!("cannot create {}: {e}", args.out.display()))?;
                std::fs::write(&path, &page)
                    .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
                "written"
            }
        };
        println!("{:<20} {} ({what})", c.model, path.display());
    }
    for (path, text) in indexes(args.manifest_path.as_deref(), &args.out)? {
        let state = state_of(&path, &text)?;
        if args.check {
            if state != State::Current {
                not_current.push((path, state));
            }
            continue;
        }
        let what = if state == State::Current {
            "current"
        } else {
            std::fs::write(&path, &text)
                .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
            "written"
        };
        println!("{:<20} {} ({what})", "(index)", path.display());
    }
    if !args.check {
        return Ok(());
    }
    if not_current.is_empty() {
        println!(
            "{} interface page{} and the index current in {}",
            built.len(),
            if built.len() == 1 { "" } else { "s" },
            args.out.display()
        );
        return Ok(());
    }
    let list: Vec<String> = not_current
        .iter()
        .map(|(path, state)| {
            let state = if *state == State::Missing {
                "missing"
            } else {
                "stale"
            };
            format!("  {} ({state})", path.display())
        })
        .collect();
    Err(format!(
        "interface pages not current:\n{}\nregenerate them with `mechfmu docs` and commit them",
        list.join("\n")
    ))
}

/// Where the index goes: between these lines of a Markdown file.
const INDEX_BEGIN: &str = "<!-- mechanisms: begin -->";
const INDEX_END: &str = "<!-- mechanisms: end -->";

/// Each file that has the index's markers (the workspace's `README.md`, `<out>/README.md`),
/// with the index of the workspace's mechanisms between them.
fn indexes(manifest_path: Option<&Path>, out: &Path) -> Result<Vec<(PathBuf, String)>, String> {
    let crates = fmu_crates(manifest_path)?;
    let root = workspace_root(manifest_path)?;
    let out = std::path::absolute(out).map_err(|e| format!("{}: {e}", out.display()))?;
    // the pages' folder as the workspace's README links it (none outside the workspace)
    let from_root = out.strip_prefix(&root).ok().map(|folder| {
        let parts: Vec<String> = folder
            .iter()
            .map(|p| p.to_string_lossy().into_owned())
            .collect();
        parts.iter().map(|p| format!("{p}/")).collect::<String>()
    });
    let readmes = [
        (root.join("README.md"), from_root),
        (out.join("README.md"), Some(String::new())),
    ];
    let mut found = Vec::new();
    for (path, folder) in readmes {
        let (Some(folder), Ok(text)) = (folder, std::fs::read_to_string(&path)) else {
            continue;
        };
        if let Some(text) = with_index(&text, &index(&crates, &folder)) {
            found.push((path, text));
        }
    }
    Ok(found)
}

/// The table of the mechanisms: each one's page (under `folder`) and what it is.
fn index(crates: &[MechanismCrate], folder: &str) -> String {
    let mut table = String::from("| FMU | what it is |\n|---|---|\n");
    for c in crates {
        let (fmu, system) = (
            format!("The {} FMU: ", c.model),
            format!("The {} system: ", c.model),
        );
        let what = (c.description.strip_prefix(&fmu))
            .or_else(|| c.description.strip_prefix(&system))
            .unwrap_or(&c.description);
        table += &format!("| [`{0}`]({folder}{0}.md) | {what} |\n", c.model);
    }
    table
}

/// `text` with `index` between the index's markers; None when it has no markers.
fn with_index(text: &str, index: &str) -> Option<String> {
    let begin = text.find(INDEX_BEGIN)? + INDEX_BEGIN.len();
    let end = begin + text[begin..].find(INDEX_END)?;
    Some(format!("{}\n{index}{}", &text[..begin], &text[end..]))
}

/// The interface page a built FMU binary renders of itself (`mechfmu_interface`).
fn interface_of(library: &Path) -> Result<String, String> {
    Library::open(library)?.text(Extra::Interface)
}

fn state_of(path: &Path, page: &str) -> Result<State, String> {
    match std::fs::read(path) {
        Ok(bytes) if bytes == page.as_bytes() => Ok(State::Current),
        Ok(_) => Ok(State::Stale),
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(State::Missing),
        Err(e) => Err(format!("cannot read {}: {e}", path.display())),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pages_are_current_stale_or_missing() {
        let dir = std::env::temp_dir().join(format!("mechfmu-interface-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("Spring.md");
        assert_eq!(state_of(&path, "# Spring\n").unwrap(), State::Missing);
        std::fs::write(&path, "# Spring\n").unwrap();
        assert_eq!(state_of(&path, "# Spring\n").unwrap(), State::Current);
        assert_eq!(state_of(&path, "# Spring\n\n").unwrap(), State::Stale);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn the_index_goes_between_its_markers() {
        let spring = MechanismCrate {
            model: "Spring".into(),
            package: "spring-fmu".into(),
            manifest: PathBuf::from("fmus/spring/Cargo.toml"),
            description: "The Spring FMU: a linear spring".into(),
            one_fmu: false,
        };
        let table = index(&[spring], "docs/");
        assert_eq!(
            table,
            "| FMU | what it is |\n|---|---|\n| [`Spring`](docs/Spring.md) | a linear spring |\n"
        );
        let text = format!("# A\n\n{INDEX_BEGIN}\nold\n{INDEX_END}\n\nmore\n");
        let want = format!("# A\n\n{INDEX_BEGIN}\n{table}{INDEX_END}\n\nmore\n");
        assert_eq!(with_index(&text, &table).as_deref(), Some(want.as_str()));
        assert_eq!(with_index(&want, &table).as_deref(), Some(want.as_str()));
        assert_eq!(with_index("# A\n", &table), None);
    }

    /// This repository's README.md and docs/mechanisms/README.md list every mechanism crate of
    /// the workspace: `mechfmu docs` (or `mechfmu docs --check`, which builds them) keeps them so.
    #[test]
    fn the_indexes_of_this_workspace_are_current() {
        let root = crate::build::workspace::source_tree();
        let found = indexes(
            Some(&root.join("Cargo.toml")),
            &root.join("docs/mechanisms"),
        )
        .unwrap();
        let paths: Vec<PathBuf> = found.iter().map(|(p, _)| p.clone()).collect();
        assert_eq!(
            paths,
            [
                root.join("README.md"),
                root.join("docs/mechanisms/README.md")
            ]
        );
        for (path, text) in found {
            let committed = std::fs::read_to_string(&path).unwrap();
            assert!(
                committed == text,
                "{} is not current: run `mechfmu docs`",
                path.display()
            );
        }
    }
}
