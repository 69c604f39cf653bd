//! The FMPy and scipy figures, from `scripts/bench_fmpy.py` run by the project venv.

use std::path::Path;
use std::process::Command;

/// Runs the script with `config` (written to `work_dir/bench_fmpy.json`); returns its JSON.
pub fn run(
    python: &Path,
    script: &Path,
    config: &serde_json::Value,
    work_dir: &Path,
) -> Result<serde_json::Value, String> {
    std::fs::create_dir_all(work_dir)
        .map_err(|e| format!("cannot create {}: {e}", work_dir.display()))?;
    let path = work_dir.join("bench_fmpy.json");
    std::fs::write(&path, config.to_string())
        .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    let output = Command::new(python)
        .arg(script)
        .arg(&path)
        .output()
        .map_err(|e| format!("cannot run {} {}: {e}", python.display(), script.display()))?;
    if !output.status.success() {
        return Err(format!(
            "{} failed ({}):\n{}",
            script.display(),
            output.status,
            String::from_utf8_lossy(&output.stderr).trim()
        ));
    }
    let text = String::from_utf8_lossy(&output.stdout);
    let last = text
        .lines()
        .rev()
        .find(|l| l.trim_start().starts_with('{'))
        .unwrap_or("");
    serde_json::from_str(last)
        .map_err(|e| format!("{} printed no JSON result ({e}): {text}", script.display()))
}
