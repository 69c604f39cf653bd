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

const CARGO_TOML: &str = include_str!("../templates/Cargo.toml.tmpl");
const LIB_RS: &str = include_str!("../templates/lib.rs.tmpl");
const TEST_RS: &str = include_str!("../templates/test.rs.tmpl");
const CASES: &str = include_str!("../templates/cases.py.tmpl");

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
    // name), from the `crates/` of a checkout, or from the installed command's copy of them.
    let dependency = |package: &str, folder: &str| -> Result<String, String> {
        Ok(match (&args.git, &args.mechfmu_path) {
            (Some(url), _) => format!("git = \"{url}\""),
            (None, _) => {
                let tree = match &args.mechfmu_path {
                    Some(path) => absolute(path)?,
                    None => crate::home::root()?,
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
    let files: [(PathBuf, String); 5] = [
        (dir.join("Cargo.toml"), fill(CARGO_TOML)),
        (dir.join("src/lib.rs"), fill(LIB_RS)),
        (dir.join(format!("tests/{snake}.rs")), fill(TEST_RS)),
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
    for (command, what) in [
        ("cargo test", "physics and conformance, in-process"),
        (
            "mechfmu build --manifest-path Cargo.toml --out fmu",
            &format!("fmu/{0}.fmu, fmu/fmi3/{0}.fmu", args.name),
        ),
        (
            "mechfmu validate --manifest-path Cargo.toml --fmu-dir fmu",
            "validation/cases.py under FMPy and others",
        ),
    ] {
        println!("  {command:<58} # {what}");
    }
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
    if TAKEN_TYPE_NAMES.contains(&name) {
        return Err(format!(
            "`{name}` cannot name a mechanism: the crate's code already uses it (a Rust keyword, a \
             name of Rust's prelude or one the scaffold imports); choose another, e.g. My{name}"
        ));
    }
    let snake = snake_case(name);
    if TAKEN_CRATE_NAMES.contains(&snake.as_str())
        || (snake.len() == 4
            && ["com", "lpt"].contains(&&snake[..3])
            && snake.as_bytes()[3].is_ascii_digit())
    {
        return Err(format!(
            "`{name}` cannot name a mechanism: its crate would be `{snake}`, which cargo or \
             Windows reserves (a Rust keyword, a built-in crate, a build directory or a device \
             name); choose another, e.g. My{name}"
        ));
    }
    Ok(())
}

/// Type names a mechanism's struct cannot take: `Self`, the names Rust's prelude brings into
/// every module (the struct would shadow them in the code `mechanism!` generates) and the
/// ones the scaffold's `lib.rs` and tests import.
const TAKEN_TYPE_NAMES: &[&str] = &[
    "Self",
    "Box",
    "Vec",
    "String",
    "Option",
    "Some",
    "None",
    "Result",
    "Ok",
    "Err",
    "Send",
    "Sync",
    "Sized",
    "Unpin",
    "Copy",
    "Clone",
    "Default",
    "Drop",
    "Eq",
    "PartialEq",
    "Ord",
    "PartialOrd",
    "Fn",
    "FnMut",
    "FnOnce",
    "Iterator",
    "IntoIterator",
    "DoubleEndedIterator",
    "ExactSizeIterator",
    "Extend",
    "ToOwned",
    "ToString",
    "From",
    "Into",
    "TryFrom",
    "TryInto",
    "AsRef",
    "AsMut",
    "FromIterator",
    "Experiment",
    "Mechanism",
    "Scalar",
    "Variable",
    "Harness",
];

/// Crate names cargo refuses or that cannot be a folder on Windows: Rust's keywords (a
/// lower-case mechanism name becomes one), its built-in crates, cargo's build folders and
/// Windows' device names (and `com1`–`com9`, `lpt1`–`lpt9`, checked apart).
const TAKEN_CRATE_NAMES: &[&str] = &[
    "as",
    "async",
    "await",
    "box",
    "break",
    "const",
    "continue",
    "crate",
    "do",
    "dyn",
    "else",
    "enum",
    "extern",
    "false",
    "final",
    "fn",
    "for",
    "gen",
    "if",
    "impl",
    "in",
    "let",
    "loop",
    "macro",
    "match",
    "mod",
    "move",
    "mut",
    "override",
    "priv",
    "pub",
    "ref",
    "return",
    "self",
    "static",
    "struct",
    "super",
    "trait",
    "true",
    "try",
    "type",
    "typeof",
    "unsafe",
    "unsized",
    "use",
    "virtual",
    "where",
    "while",
    "yield",
    "abstract",
    "become",
    "core",
    "std",
    "alloc",
    "proc_macro",
    "test",
    "build",
    "deps",
    "examples",
    "incremental",
    "con",
    "prn",
    "aux",
    "nul",
];

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
    #[test]
    fn names_rust_cargo_or_windows_take_are_refused() {
        for taken in [
            "Self",
            "Fn",
            "Test",
            "Std",
            "Mechanism",
            "Option",
            "Con",
            "Com1",
            "Build",
        ] {
            let err = super::check_name(taken).unwrap_err();
            assert!(
                err.contains(&format!("`{taken}` cannot name a mechanism")),
                "{err}"
            );
        }
        for fine in ["DoublePendulum", "Tester", "Com", "Com10", "Pendulum2"] {
            assert_eq!(super::check_name(fine), Ok(()), "{fine}");
        }
    }

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
