//! Helpers shared by the robustness tests: the driver binary and running it per FMU.
#![allow(dead_code)]

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

pub fn driver() -> &'static str {
    env!("CARGO_BIN_EXE_robustness-driver")
}

/// Runs the driver with `args` on `fmu`, capturing its output.
pub fn run_driver(fmu: &Path, args: &[&str]) -> Output {
    Command::new(driver())
        .arg(args[0])
        .arg("--fmu")
        .arg(fmu)
        .args(&args[1..])
        .output()
        .expect("cannot run robustness-driver")
}

/// How long a child may run before it counts as hung: `$MECHFMU_ROBUSTNESS_TIMEOUT`
/// seconds, else 600 (a run of the random sequences of one FMU takes seconds).
pub fn time_limit() -> Duration {
    Duration::from_secs(env_u64("MECHFMU_ROBUSTNESS_TIMEOUT", 600))
}

/// [`run_driver`], killing the driver if it has not ended after `limit`: its output, and
/// whether it was killed.
pub fn run_driver_within(fmu: &Path, args: &[&str], limit: Duration) -> (Output, bool) {
    let mut child = Command::new(driver())
        .arg(args[0])
        .arg("--fmu")
        .arg(fmu)
        .args(&args[1..])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("cannot run robustness-driver");
    // Read both pipes while waiting, so a child writing much never blocks on them.
    let drain = |pipe: Option<Box<dyn Read + Send>>| {
        std::thread::spawn(move || {
            let mut bytes = vec![];
            if let Some(mut p) = pipe {
                let _ = p.read_to_end(&mut bytes);
            }
            bytes
        })
    };
    let out = drain(child.stdout.take().map(|p| Box::new(p) as _));
    let err = drain(child.stderr.take().map(|p| Box::new(p) as _));
    let deadline = Instant::now() + limit;
    let mut killed = false;
    let status = loop {
        if let Some(status) = child.try_wait().expect("waiting for robustness-driver") {
            break status;
        }
        if Instant::now() > deadline {
            let _ = child.kill();
            killed = true;
            break child.wait().expect("waiting for robustness-driver");
        }
        std::thread::sleep(Duration::from_millis(20));
    };
    let output = Output {
        status,
        stdout: out.join().unwrap_or_default(),
        stderr: err.join().unwrap_or_default(),
    };
    (output, killed)
}

/// How a child process ended, in words (the signal if it crashed).
pub fn describe_exit(out: &Output) -> String {
    use std::os::unix::process::ExitStatusExt;
    match (out.status.code(), out.status.signal()) {
        (Some(c), _) => format!("exit status {c}"),
        (None, Some(s)) => format!(
            "killed by signal {s}{}",
            if s == 6 {
                " (SIGABRT)"
            } else if s == 11 {
                " (SIGSEGV)"
            } else {
                ""
            }
        ),
        _ => "unknown end".into(),
    }
}

/// `f` on every FMU, at most `jobs` at a time (each usually runs a child process).
pub fn per_fmu<T: Send>(
    paths: &[PathBuf],
    jobs: usize,
    f: impl Fn(usize, &Path) -> T + Sync,
) -> Vec<T> {
    let next = std::sync::atomic::AtomicUsize::new(0);
    let results = std::sync::Mutex::new(Vec::new());
    std::thread::scope(|s| {
        for _ in 0..jobs.max(1) {
            s.spawn(|| loop {
                let i = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let Some(p) = paths.get(i) else { break };
                let r = f(i, p);
                results.lock().unwrap().push((i, r));
            });
        }
    });
    let mut r = results.into_inner().unwrap();
    r.sort_by_key(|(i, _)| *i);
    r.into_iter().map(|(_, x)| x).collect()
}

pub fn env_u64(name: &str, default: u64) -> u64 {
    std::env::var(name)
        .ok()
        .map(|v| {
            v.replace('_', "")
                .parse()
                .unwrap_or_else(|_| panic!("{name}={v}: not a number"))
        })
        .unwrap_or(default)
}

/// Parallel jobs: `$MECHFMU_ROBUSTNESS_JOBS`, else 2 (the machines here have 2 cores).
pub fn jobs() -> usize {
    env_u64("MECHFMU_ROBUSTNESS_JOBS", 2) as usize
}

pub fn name(p: &Path) -> String {
    p.file_stem().unwrap().to_string_lossy().into_owned()
}
