//! `mechfmu new`: scaffolds a mechanism crate: its equations written by hand (a damped
//! pendulum), or, with `--energies`, declared from its energies (a cart on a spring carrying a
//! pendulum, `mechfmu::lagrange`). Created where a workspace takes it as a member (this
//! repository's `fmus/<name>/`), it is one of the workspace's mechanisms, its dependencies
//! relative paths; anywhere else it is a workspace of its own.

use std::path::{Path, PathBuf};

#[derive(clap::Args)]
pub struct Args {
    /// The model identifier, in UpperCamelCase (e.g. DoublePendulum).
    name: String,
    /// Where to create the crate (default: ./<snake_case_name>).
    #[arg(long)]
    path: Option<PathBuf>,
    /// The mechfmu checkout to depend on (default: the checkout this command runs from, or
    /// the copy of mechfmu's crates an installed command writes to its data folder).
    #[arg(long, conflicts_with = "git")]
    mechfmu_path: Option<PathBuf>,
    /// Depend on mechfmu from a git repository instead of a path.
    #[arg(long)]
    git: Option<String>,
    /// Declare the example from its energies (kinetic, potential, generalized forces) and
    /// let the runtime form Lagrange's equations, instead of writing them by hand.
    #[arg(long)]
    energies: bool,
}

const CARGO_TOML: &str = include_str!("../templates/Cargo.toml.tmpl");
/// The allocation tests, the same for either kind of mechanism.
const ALLOCATIONS_RS: &str = include_str!("../templates/allocations.rs.tmpl");

/// What a crate that is a workspace of its own adds to its Cargo.toml (a member's profile
/// would be ignored: the workspace's applies).
const STANDALONE: &str = "
# FMI functions catch panics at the C boundary: keep unwinding on.
[profile.release]
panic = \"unwind\"

# A crate of its own, even when created inside another workspace.
[workspace]
";

/// The files of one example that differ between the two kinds of mechanism.
struct Example {
    /// What the FMU is, in a line: the package's description after "The <Name> FMU: ".
    summary: &'static str,
    lib_rs: &'static str,
    test_rs: &'static str,
    cases_py: &'static str,
}

/// Equations written by hand: a damped pendulum.
const BY_HAND: Example = Example {
    summary: "a damped pendulum driven by a torque at its pivot",
    lib_rs: include_str!("../templates/lib.rs.tmpl"),
    test_rs: include_str!("../templates/test.rs.tmpl"),
    cases_py: include_str!("../templates/cases.py.tmpl"),
};

/// Declared from its energies: a cart on a spring carrying a pendulum.
const FROM_ENERGIES: Example = Example {
    summary: "a cart on a spring carrying a pendulum, declared from its energies",
    lib_rs: include_str!("../templates/energies/lib.rs.tmpl"),
    test_rs: include_str!("../templates/energies/test.rs.tmpl"),
    cases_py: include_str!("../templates/energies/cases.py.tmpl"),
};

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
    // name), from the `crates/` of a checkout, or from the installed command's copy of them;
    // a path relative to the crate (`relative_to`) for a workspace's member.
    let dependency = |package: &str, folder: &str, relative_to: Option<&Path>| {
        Ok::<_, String>(match (&args.git, &args.mechfmu_path) {
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
                let path = match relative_to {
                    Some(dir) => slashed(&relative(dir, &canonical(&crate_dir)?)),
                    None => crate_dir.display().to_string(),
                };
                format!("path = {path:?}")
            }
        })
    };
    let dependencies = |relative_to: Option<&Path>| {
        Ok::<_, String>(Dependencies {
            runtime: dependency("mechfmu", "runtime", relative_to)?,
            testkit: dependency("mechfmu-testkit", "testkit", relative_to)?,
        })
    };
    let example = if args.energies {
        &FROM_ENERGIES
    } else {
        &BY_HAND
    };
    // Written as a member first: cargo then says whether a workspace around it takes it.
    std::fs::create_dir_all(&dir).map_err(|e| format!("cannot create {}: {e}", dir.display()))?;
    let here = canonical(&dir)?;
    let member = render(
        &args.name,
        &dir,
        example,
        &dependencies(Some(&here))?,
        false,
    );
    for (path, text) in &member {
        write(path, text)?;
    }
    let standalone = !workspace_takes(&here);
    if standalone {
        for (path, text) in &render(&args.name, &dir, example, &dependencies(None)?, true) {
            write(path, text)?;
        }
    }
    println!("created {} ({})", args.name, dir.display());
    println!("next:");
    let next: Vec<(String, String)> = if standalone {
        println!("  cd {}", dir.display());
        vec![
            (
                "cargo test".into(),
                "physics and conformance, in-process".into(),
            ),
            (
                "mechfmu build --manifest-path Cargo.toml --out fmu".into(),
                format!("fmu/{0}.fmu, fmu/fmi3/{0}.fmu", args.name),
            ),
            (
                "mechfmu validate --manifest-path Cargo.toml --fmu-dir fmu".into(),
                "validation/cases.py under FMPy and others".into(),
            ),
        ]
    } else {
        let package = snake_case(&args.name).replace('_', "-");
        vec![
            (
                format!("cargo test -p {package}"),
                "physics and conformance, in-process".into(),
            ),
            (
                format!("mechfmu build {}", args.name),
                "with the workspace's other mechanisms".into(),
            ),
            (
                format!("mechfmu validate --write-references {}", args.name),
                "its reference results".into(),
            ),
            (
                "mechfmu docs".into(),
                "its interface page, in the index".into(),
            ),
        ]
    };
    for (command, what) in next {
        println!("  {command:<58} # {what}");
    }
    Ok(())
}

/// Whether a workspace around the crate at `dir` (written as a member) takes it: cargo reads
/// the crate as one of its members, or, when none does, refuses it (inside a workspace that
/// does not list it) or reads it as its own root (inside none).
fn workspace_takes(dir: &Path) -> bool {
    crate::build::workspace::workspace_root(Some(&dir.join("Cargo.toml")))
        .and_then(|root| canonical(&root))
        .is_ok_and(|root| root != dir)
}

/// The path from the folder `from` to `to`, both canonical: `..` up to what they share.
fn relative(from: &Path, to: &Path) -> PathBuf {
    let (from, to): (Vec<_>, Vec<_>) = (from.components().collect(), to.components().collect());
    let shared = from.iter().zip(&to).take_while(|(a, b)| a == b).count();
    let up = std::iter::repeat_n(std::path::Component::ParentDir, from.len() - shared);
    up.chain(to[shared..].iter().copied()).collect()
}

/// A relative path with `/` between its parts on every platform, as Cargo.toml files write it.
fn slashed(path: &Path) -> String {
    let parts: Vec<String> = path
        .iter()
        .map(|p| p.to_string_lossy().into_owned())
        .collect();
    parts.join("/")
}

fn canonical(path: &Path) -> Result<PathBuf, String> {
    std::fs::canonicalize(path).map_err(|e| format!("{}: {e}", path.display()))
}

/// Where the crate finds the runtime and the test kit: the inside of a `[dependencies]`
/// entry's braces (`path = "..."` or `git = "..."`).
struct Dependencies {
    runtime: String,
    testkit: String,
}

/// The crate's files, by path under `dir`, with the templates filled in: a workspace's
/// member, or (`standalone`) a workspace of its own, which ignores what it builds.
fn render(
    name: &str,
    dir: &Path,
    example: &Example,
    dependencies: &Dependencies,
    standalone: bool,
) -> Vec<(PathBuf, String)> {
    let snake = snake_case(name);
    let fill = |template: &str| {
        template
            .replace("{{Name}}", name)
            .replace("{{snake}}", &snake)
            .replace("{{crate}}", &snake.replace('_', "-"))
            .replace("{{summary}}", example.summary)
            .replace("{{standalone}}", if standalone { STANDALONE } else { "" })
            .replace("{{mechfmu_dependency}}", &dependencies.runtime)
            .replace("{{testkit_dependency}}", &dependencies.testkit)
    };
    let mut files = vec![
        (dir.join("Cargo.toml"), fill(CARGO_TOML)),
        (dir.join("src/lib.rs"), fill(example.lib_rs)),
        (dir.join(format!("tests/{snake}.rs")), fill(example.test_rs)),
        (dir.join("tests/allocations.rs"), fill(ALLOCATIONS_RS)),
        (dir.join("validation/cases.py"), fill(example.cases_py)),
    ];
    if standalone {
        files.push((
            dir.join(".gitignore"),
            "/target\n/fmu\nCargo.lock\n__pycache__\n".to_string(),
        ));
    }
    files
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
/// ones the scaffolds' `lib.rs` and tests import (either example's: one list for both).
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
    "Coordinate",
    "Lagrangian",
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
    use super::*;
    use clap::Parser;
    use std::collections::BTreeMap;

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

    /// `mechfmu new`'s arguments, parsed as the command line gives them.
    #[derive(clap::Parser)]
    struct New {
        #[command(flatten)]
        args: Args,
    }

    fn parse(line: &[&str]) -> Result<Args, clap::Error> {
        New::try_parse_from(std::iter::once("new").chain(line.iter().copied())).map(|n| n.args)
    }

    #[test]
    fn energies_is_a_flag_off_by_default() {
        let by_hand = parse(&["DoublePendulum"]).unwrap();
        assert!(!by_hand.energies);
        assert_eq!(by_hand.name, "DoublePendulum");
        let args = parse(&["CartPendulum", "--energies", "--path", "cart"]).unwrap();
        assert!(args.energies);
        assert_eq!(args.path, Some(PathBuf::from("cart")));
        let args = parse(&["CartPendulum", "--git", "https://x/mechfmu", "--energies"]).unwrap();
        assert!(args.energies && args.git.is_some());
        assert!(parse(&["CartPendulum", "--energies=yes"]).is_err());
        assert!(parse(&["CartPendulum", "--mechfmu-path", "a", "--git", "b"]).is_err());
    }

    fn rendered(example: &Example) -> BTreeMap<String, String> {
        rendered_as(example, true)
    }

    fn rendered_as(example: &Example, standalone: bool) -> BTreeMap<String, String> {
        let dependencies = Dependencies {
            runtime: "path = \"/m/crates/runtime\"".into(),
            testkit: "path = \"/m/crates/testkit\"".into(),
        };
        let files = render(
            "CartPendulum",
            Path::new("cart"),
            example,
            &dependencies,
            standalone,
        );
        files
            .into_iter()
            .map(|(path, text)| (path.display().to_string().replace('\\', "/"), text))
            .collect()
    }

    #[test]
    fn a_member_leaves_the_workspace_and_the_profile_to_its_workspace() {
        for example in [&BY_HAND, &FROM_ENERGIES] {
            let member = rendered_as(example, false);
            let paths: Vec<&str> = member.keys().map(String::as_str).collect();
            assert_eq!(
                paths,
                [
                    "cart/Cargo.toml",
                    "cart/src/lib.rs",
                    "cart/tests/allocations.rs",
                    "cart/tests/cart_pendulum.rs",
                    "cart/validation/cases.py"
                ]
            );
            let manifest = &member["cart/Cargo.toml"];
            assert!(!manifest.contains("[workspace]") && !manifest.contains("[profile"));
            assert!(!manifest.contains("{{"), "{manifest}");
            let own = &rendered_as(example, true)["cart/Cargo.toml"];
            assert!(own.contains("\n[workspace]\n") && own.contains("panic = \"unwind\""));
            let summary = format!(
                "description = \"The CartPendulum FMU: {}\"",
                example.summary
            );
            assert!(
                manifest.contains(&summary) && own.contains(&summary),
                "{manifest}"
            );
        }
    }

    #[test]
    fn a_members_dependencies_are_relative_to_it() {
        let path = |p: &str| PathBuf::from(p);
        let up = relative(&path("/repo/fmus/probe"), &path("/repo/crates/runtime"));
        assert_eq!(slashed(&up), "../../crates/runtime");
        assert_eq!(slashed(&relative(&path("/a/b"), &path("/a/b/c"))), "c");
        assert_eq!(slashed(&relative(&path("/a/b"), &path("/x"))), "../../x");
    }

    #[test]
    fn both_examples_fill_every_placeholder_in_the_same_layout() {
        for example in [&BY_HAND, &FROM_ENERGIES] {
            let files = rendered(example);
            let paths: Vec<&str> = files.keys().map(String::as_str).collect();
            assert_eq!(
                paths,
                [
                    "cart/.gitignore",
                    "cart/Cargo.toml",
                    "cart/src/lib.rs",
                    "cart/tests/allocations.rs",
                    "cart/tests/cart_pendulum.rs",
                    "cart/validation/cases.py"
                ]
            );
            for (path, text) in &files {
                assert!(!text.contains("{{"), "{path} keeps a placeholder");
            }
            let manifest = &files["cart/Cargo.toml"];
            assert!(manifest.contains("name = \"cart-pendulum\""), "{manifest}");
            assert!(manifest.contains("mechfmu = { path = \"/m/crates/runtime\" }"));
            assert!(manifest.contains("model = \"CartPendulum\""));
            let lib = &files["cart/src/lib.rs"];
            assert!(lib.lines().any(|l| l == "#![forbid(unsafe_code)]"));
            assert!(lib.contains("pub struct CartPendulum / CartPendulumValues {"));
            assert!(lib.contains("mechfmu::export_fmu!(CartPendulum);"));
            let tests = &files["cart/tests/cart_pendulum.rs"];
            assert!(tests.contains("use cart_pendulum::{CartPendulum, CartPendulumValues};"));
            assert!(tests.contains("conformance::check::<CartPendulum>()"));
        }
    }

    #[test]
    fn the_energies_example_is_declared_from_its_energies() {
        let files = rendered(&FROM_ENERGIES);
        let lib = &files["cart/src/lib.rs"];
        for line in [
            "impl Lagrangian<2> for CartPendulum {",
            "const COORDINATES: [Coordinate; 2] = [Coordinate::free(\"x\"), Coordinate::free(\"theta\")];",
            "fn kinetic_energy<S: Scalar>(v: &CartPendulumValues<S>) -> S {",
            "fn potential_energy<S: Scalar>(v: &CartPendulumValues<S>) -> S {",
            "fn generalized_forces<S: Scalar>(v: &CartPendulumValues<S>) -> [S; 2] {",
            "Self::lagrange(v);",
            "Self::mass_matrix_problem(v)",
        ] {
            assert!(lib.contains(line), "no `{line}` in\n{lib}");
        }
        let inlined = lib.lines().filter(|l| l.trim() == "#[inline(always)]");
        assert_eq!(inlined.count(), 2, "on T and V");
        // The notes show T, V and Q (lines indented by four spaces are equations).
        for equation in [
            "T = ½ M ẋ²",
            "V = ½ k x²",
            "Q_x = F - c ẋ",
            "Q_θ = F l cos θ",
        ] {
            assert!(lib.contains(equation), "the notes lack `{equation}`");
        }
        assert!(files["cart/tests/cart_pendulum.rs"].contains("fn newton("));
        assert!(files["cart/validation/cases.py"].contains("def linear_modes("));
        assert!(!rendered(&BY_HAND)["cart/src/lib.rs"].contains("Lagrangian"));
    }

    /// Every type name a scaffold's `lib.rs` or tests import is refused as a mechanism's name:
    /// the struct would clash with the import.
    #[test]
    fn the_names_the_scaffolds_import_are_taken() {
        for example in [&BY_HAND, &FROM_ENERGIES] {
            let files = rendered(example);
            for code in [
                &files["cart/src/lib.rs"],
                &files["cart/tests/cart_pendulum.rs"],
            ] {
                for line in code.lines().filter(|l| l.starts_with("use ")) {
                    let imported = line
                        .split(|c: char| !c.is_ascii_alphanumeric() && c != '_')
                        .filter(|word| word.starts_with(|c: char| c.is_ascii_uppercase()))
                        .filter(|word| !word.starts_with("CartPendulum"));
                    for name in imported {
                        assert!(TAKEN_TYPE_NAMES.contains(&name), "`{name}` ({line})");
                    }
                }
            }
        }
    }

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
