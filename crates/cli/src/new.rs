//! `mechfmu new`: scaffolds a mechanism crate of the user's own, outside this repository.

use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct Args {
    /// The model identifier, in UpperCamelCase (e.g. DoublePendulum).
    name: String,
    /// Where to create the crate (default: ./<snake_case_name>).
    #[arg(long)]
    path: Option<PathBuf>,
    /// The mechfmu checkout to depend on (default: the one this command was built from).
    #[arg(long, conflicts_with = "git")]
    mechfmu_path: Option<PathBuf>,
    /// Depend on mechfmu from a git repository instead of a path.
    #[arg(long)]
    git: Option<String>,
}

const CARGO_TOML: &str = include_str!("templates/Cargo.toml.tmpl");
const LIB_RS: &str = include_str!("templates/lib.rs.tmpl");
const TEST_RS: &str = include_str!("templates/test.rs.tmpl");
const TEST_FMPY: &str = include_str!("templates/test_fmpy.py.tmpl");
const CASES: &str = include_str!("templates/cases.py.tmpl");

pub fn run(args: Args) -> Result<(), String> {
    check_name(&args.name)?;
    let snake = snake_case(&args.name);
    let dir = args.path.clone().unwrap_or_else(|| PathBuf::from(&snake));
    if dir.exists() && std::fs::read_dir(&dir).map_or(true, |mut d| d.next().is_some()) {
        return Err(format!(
            "{} already exists and is not empty: choose another --path",
            dir.display()
        ));
    }
    // The runtime and the test kit, from a git repository (cargo finds each package by
    // name) or from the `crates/` of a checkout.
    let dependency = |package: &str, folder: &str| -> Result<String, String> {
        Ok(match (&args.git, &args.mechfmu_path) {
            (Some(url), _) => format!("git = \"{url}\""),
            (None, _) => {
                let tree = match &args.mechfmu_path {
                    Some(path) => absolute(path)?,
                    None => crate::workspace::source_tree(),
                };
                let crate_dir = tree.join("crates").join(folder);
                if !crate_dir.join("Cargo.toml").is_file() {
                    return Err(format!(
                        "{} is not a mechfmu checkout: it has no crates/{folder}/Cargo.toml ({package})",
                        tree.display()
                    ));
                }
                format!("path = {:?}", crate_dir.display().to_string())
            }
        })
    };
    let runtime = dependency("mechfmu", "runtime")?;
    let testkit = dependency("mechfmu-testkit", "testkit")?;
    let fill = |template: &str| {
        template
            .replace("{{Name}}", &args.name)
            .replace("{{snake}}", &snake)
            .replace("{{crate}}", &snake.replace('_', "-"))
            .replace("{{mechfmu_dependency}}", &runtime)
            .replace("{{testkit_dependency}}", &testkit)
    };
    let files: [(PathBuf, String); 6] = [
        (dir.join("Cargo.toml"), fill(CARGO_TOML)),
        (dir.join("src/lib.rs"), fill(LIB_RS)),
        (dir.join(format!("tests/{snake}.rs")), fill(TEST_RS)),
        (dir.join("tests/test_fmpy.py"), fill(TEST_FMPY)),
        (dir.join("validation/cases.py"), fill(CASES)),
        (
            dir.join(".gitignore"),
            "/target\n/fmu\nCargo.lock\n__pycache__\n".to_string(),
        ),
    ];
    for (path, text) in &files {
        write(path, text)?;
    }
    println!("created {} ({})", args.name, dir.display());
    println!("next:");
    println!("  cd {}", dir.display());
    println!(
        "  cargo test                                       # physics and conformance, in-process"
    );
    println!(
        "  mechfmu build --manifest-path Cargo.toml --out fmu  # -> fmu/{}.fmu",
        args.name
    );
    Ok(())
}

fn write(path: &Path, text: &str) -> Result<(), String> {
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent)
            .map_err(|e| format!("cannot create {}: {e}", parent.display()))?;
    }
    std::fs::write(path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))
}

fn absolute(path: &Path) -> Result<PathBuf, String> {
    std::path::absolute(path).map_err(|e| format!("{}: {e}", path.display()))
}

/// A model identifier must be a Rust type name and a C-friendly file name.
fn check_name(name: &str) -> Result<(), String> {
    let mut chars = name.chars();
    let ok = chars.next().is_some_and(|c| c.is_ascii_uppercase())
        && chars.all(|c| c.is_ascii_alphanumeric());
    if !ok {
        return Err(format!(
            "`{name}` is not a valid mechanism name: use UpperCamelCase letters and digits, e.g. DoublePendulum"
        ));
    }
    Ok(())
}

/// `DoublePendulum` → `double_pendulum`.
fn snake_case(name: &str) -> String {
    let mut out = String::new();
    for (i, c) in name.chars().enumerate() {
        if c.is_ascii_uppercase() && i > 0 {
            out.push('_');
        }
        out.push(c.to_ascii_lowercase());
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names() {
        assert_eq!(snake_case("DoublePendulum"), "double_pendulum");
        assert_eq!(snake_case("Crane"), "crane");
        assert!(check_name("DoublePendulum").is_ok());
        for bad in [
            "",
            "doublePendulum",
            "Double-Pendulum",
            "Double Pendulum",
            "Dé",
        ] {
            assert!(check_name(bad).is_err(), "{bad}");
        }
    }
}
