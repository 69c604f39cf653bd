//! An FMU writes nothing to stdout or stderr, whatever happens; everything goes through the
//! importer's logger (or nowhere, when it gave none). A child process drives each FMU (of
//! FMI 2.0 and of FMI 3.0) through every function, right and wrong, with and without a
//! logger.

mod common;
use common::*;
use mechfmu_robustness::fmu::{required_fmu3_paths, required_fmu_paths};

#[test]
fn fmus_write_nothing_to_stdout_or_stderr() {
    let mut paths = required_fmu_paths();
    paths.extend(required_fmu3_paths());
    let dir = std::env::temp_dir().join(format!("mechfmu-silence-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let results = per_fmu(&paths, jobs(), |i, p| {
        let report = dir.join(format!("{i}-{}.txt", name(p)));
        let out = run_driver(p, &["tour", "--report", report.to_str().unwrap()]);
        (
            p.display().to_string(),
            out,
            std::fs::read_to_string(&report).unwrap_or_default(),
        )
    });
    let _ = std::fs::remove_dir_all(&dir);
    for (name, out, report) in results {
        assert!(
            out.status.success(),
            "{name}: the tour failed ({}): {report}",
            describe_exit(&out)
        );
        assert!(
            out.stdout.is_empty(),
            "{name} wrote to stdout: {:?}",
            String::from_utf8_lossy(&out.stdout)
        );
        assert!(
            out.stderr.is_empty(),
            "{name} wrote to stderr: {:?}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
}
