//! The clean release build of every FMU for every platform, timed (`mechfmu bench
//! --build-time`).

use crate::report::Build;
use std::path::Path;
use std::process::Command;
use std::time::Instant;

/// `cargo run --release -- build` (`cargo` the program) in the workspace at `root`, in a
/// fresh target directory (a clean build, without touching the workspace's `target/`),
/// timed by the wall clock; every one of `names` must have come out as a `.fmu`.
pub fn clean_build(cargo: &str, root: &Path, names: &[String]) -> Result<Build, String> {
    let target = std::env::temp_dir().join(format!("mechfmu-bench-build-{}", std::process::id()));
    let out = target.join("fmus");
    let _ = std::fs::remove_dir_all(&target);
    eprintln!(
        "timing a clean release build in {} (cargo run --release -- build --platform all) ...",
        target.display()
    );
    let started = Instant::now();
    let output = Command::new(cargo)
        .current_dir(root)
        .env("CARGO_TARGET_DIR", &target)
        .args([
            "run",
            "--release",
            "--",
            "build",
            "--platform",
            "all",
            "--out",
        ])
        .arg(&out)
        .output()
        .map_err(|e| format!("cannot run cargo: {e}"))?;
    let seconds = started.elapsed().as_secs_f64();
    if !output.status.success() {
        let _ = std::fs::remove_dir_all(&target);
        return Err(format!(
            "the clean build failed:\n{}",
            String::from_utf8_lossy(&output.stderr)
        ));
    }
    let fmus = std::fs::read_dir(&out)
        .map_err(|e| format!("cannot read {}: {e}", out.display()))?
        .flatten()
        .filter_map(|e| {
            let name = e
                .file_name()
                .to_string_lossy()
                .strip_suffix(".fmu")?
                .to_string();
            Some((name, e.metadata().ok()?.len()))
        })
        .collect::<Vec<_>>();
    let _ = std::fs::remove_dir_all(&target);
    let mut fmus = fmus;
    fmus.sort();
    let built: Vec<&str> = fmus.iter().map(|(n, _)| n.as_str()).collect();
    let missing: Vec<&String> = names
        .iter()
        .filter(|n| !built.contains(&n.as_str()))
        .collect();
    if !missing.is_empty() {
        return Err(format!("the clean build made no .fmu for {missing:?}"));
    }
    Ok(Build {
        command: "cargo run --release -- build --platform all (fresh CARGO_TARGET_DIR)".into(),
        seconds,
        fmus,
    })
}
