//! Committed files generated from a mechanism's declaration (its `modelDescription.xml`, its
//! interface page), checked by a test to be current.

use mechfmu::model::Mechanism;
use std::path::Path;

/// `golden_tests!(Model)`: the two tests of a mechanism crate's committed generated files,
/// `model_description_is_current` ([`model_description`]) and `interface_is_current`
/// ([`interface`]), for the crate the macro is called in.
#[macro_export]
macro_rules! golden_tests {
    ($model:ty) => {
        #[test]
        fn model_description_is_current() {
            $crate::golden::model_description::<$model>(
                env!("CARGO_MANIFEST_DIR"),
                env!("CARGO_PKG_NAME"),
            );
        }

        #[test]
        fn interface_is_current() {
            $crate::golden::interface::<$model>(env!("CARGO_MANIFEST_DIR"), env!("CARGO_PKG_NAME"));
        }
    };
}

/// Asserts the model descriptions `M`'s declaration generates are those committed in the
/// repository holding the mechanism crate at `crate_dir` (two folders up, as
/// `fmus/<name>/`): FMI 2.0's at `modelDescription/<Name>.xml`, FMI 3.0's at
/// `modelDescription/fmi3/<Name>.xml`. `package` names the crate in the regeneration
/// command, which writes both.
///
///
/// A mechanism crate's tests check it with [`golden_tests!`](crate::golden_tests).
pub fn model_description<M: Mechanism>(crate_dir: &str, package: &str) {
    let hint = format!("MECHFMU_BLESS=1 cargo test -p {package} model_description");
    let folder = Path::new(crate_dir).join("../../modelDescription");
    let file = format!("{}.xml", M::NAME);
    let fmi2 = mechfmu::xml::model_description::<M>().unwrap_or_else(|e| panic!("{e}"));
    let fmi3 = mechfmu::xml::fmi3::model_description::<M>().unwrap_or_else(|e| panic!("{e}"));
    assert_current(&folder.join(&file), &fmi2, &hint);
    assert_current(&folder.join("fmi3").join(&file), &fmi3, &hint);
}

/// Asserts `docs/mechanisms/<Name>.md` of the repository holding the mechanism crate at
/// `crate_dir` is the interface page `M`'s declaration generates (what `mechfmu docs`
/// writes).
pub fn interface<M: Mechanism>(crate_dir: &str, package: &str) {
    let page = mechfmu::docs::interface::<M>().unwrap_or_else(|e| panic!("{e}"));
    let path = Path::new(crate_dir).join(format!("../../docs/mechanisms/{}.md", M::NAME));
    let hint = format!("MECHFMU_BLESS=1 cargo test -p {package} interface");
    assert_current(&path, &page, &hint);
}

/// Asserts the file committed at `path` is `generated`; with `MECHFMU_BLESS=1` in the
/// environment, (re)writes it instead (creating its folder). A missing or stale file panics
/// with its path, the first line that differs and `regenerate_hint`, the command that
/// regenerates it.
///
/// ```no_run
/// # let xml = String::new();
/// mechfmu_testkit::golden::assert_current(
///     std::path::Path::new("../../modelDescription/Oscillator.xml"),
///     &xml,
///     "MECHFMU_BLESS=1 cargo test -p oscillator-fmu model_description",
/// );
/// ```
pub fn assert_current(path: &Path, generated: &str, regenerate_hint: &str) {
    let bless = std::env::var_os("MECHFMU_BLESS").is_some_and(|v| v == "1");
    check_or_write(path, generated, regenerate_hint, bless);
}

/// [`assert_current`], told whether to bless.
fn check_or_write(path: &Path, generated: &str, regenerate_hint: &str, bless: bool) {
    if bless {
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir)
                .unwrap_or_else(|e| panic!("cannot create {}: {e}", dir.display()));
        }
        std::fs::write(path, generated)
            .unwrap_or_else(|e| panic!("cannot write {}: {e}", path.display()));
        return;
    }
    let committed = match std::fs::read_to_string(path) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => panic!(
            "{} is missing: generate it with `{regenerate_hint}` and commit it",
            path.display()
        ),
        Err(e) => panic!("cannot read {}: {e}", path.display()),
    };
    if let Some(line) = first_difference(&committed, generated) {
        panic!(
            "{} is stale (first difference at line {line}): regenerate it with \
             `{regenerate_hint}` and commit it",
            path.display()
        );
    }
}

/// The first line (from 1) where `a` and `b` differ, `None` when they are equal.
fn first_difference(a: &str, b: &str) -> Option<usize> {
    if a == b {
        return None;
    }
    Some(
        a.lines()
            .zip(b.lines())
            .position(|(x, y)| x != y)
            .map_or(a.lines().count().min(b.lines().count()) + 1, |i| i + 1),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_differing_line_is_named() {
        assert_eq!(first_difference("a\nb\n", "a\nb\n"), None);
        assert_eq!(first_difference("a\nb\n", "a\nc\n"), Some(2));
        assert_eq!(first_difference("a\n", "a\nb\n"), Some(2));
        assert_eq!(first_difference("a\nb", "a\nb\n"), Some(3));
        assert_eq!(first_difference("", "a\n"), Some(1));
    }

    #[test]
    fn a_current_file_passes_and_a_stale_one_names_itself_and_the_fix() {
        let dir = std::env::temp_dir().join(format!("mechfmu-golden-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("Spring.md");
        std::fs::write(&path, "# Spring\nold\n").unwrap();
        check_or_write(&path, "# Spring\nold\n", "regen", false);
        let stale =
            std::panic::catch_unwind(|| check_or_write(&path, "# Spring\nnew\n", "regen", false))
                .unwrap_err();
        let message = stale.downcast_ref::<String>().unwrap();
        assert!(message.contains("Spring.md is stale (first difference at line 2)"));
        assert!(message.contains("`regen`"), "{message}");
        let missing = std::panic::catch_unwind(|| {
            check_or_write(&dir.join("Other.md"), "x", "regen other", false)
        })
        .unwrap_err();
        let message = missing.downcast_ref::<String>().unwrap();
        assert!(message.contains("Other.md is missing"), "{message}");
        assert!(message.contains("`regen other`"), "{message}");
        // blessing writes the file, its folder too
        let blessed = dir.join("new").join("Spring.md");
        check_or_write(&blessed, "# Spring\nnew\n", "regen", true);
        assert_eq!(
            std::fs::read_to_string(&blessed).unwrap(),
            "# Spring\nnew\n"
        );
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
