//! `mechfmu docs`: the interface page of every mechanism (variables, units, defaults,
//! equations) as Markdown, `<out>/<Name>.md`. Each page is rendered by the mechanism's own
//! shipped binary (`mechfmu_interface`, exported by `export_fmu!`), as `mechfmu build` asks
//! the binary for its modelDescription and documentation: the tool never renders a
//! mechanism itself. Each crate's `interface_is_current` test checks the same page.

use crate::build::{built_libraries, Flavor};
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
    let built = built_libraries(
        &args.names,
        args.manifest_path.as_deref(),
        &Flavor::Shipped,
        &[],
    )?;
    let mut not_current = Vec::new();
    for b in &built {
        let (c, library) = (&b.krate, b.host_library());
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
    if !args.check {
        return Ok(());
    }
    if not_current.is_empty() {
        println!(
            "{} interface page{} current in {}",
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
}
