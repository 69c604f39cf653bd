//! `mechfmu sweep-worker` as the Python side drives it: the built command, the Oscillator
//! FMU `mechfmu build` wrote to `fmus/`, frames over stdin and stdout.

use mechfmu_host::platform::{Platform, Version};
use serde_json::{json, Value};
use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, ChildStdout, Command, Stdio};

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The FMI 2.0 folder of this machine's binaries.
fn platform_folder() -> &'static str {
    let host = Platform::host().expect("a platform FMUs are built for");
    host.folder(Version::Fmi2)
}

/// `fmus/Oscillator.fmu` unzipped into a folder of its own; the setup's paths and GUID.
fn oscillator(tag: &str) -> (PathBuf, Value) {
    let fmu = root().join("fmus/Oscillator.fmu");
    assert!(
        fmu.is_file(),
        "{} is missing: build the FMUs first (`cargo run --release -- build`)",
        fmu.display()
    );
    let dir =
        std::env::temp_dir().join(format!("mechfmu-sweep-worker-{tag}-{}", std::process::id()));
    let file = std::fs::File::open(&fmu).unwrap();
    zip::ZipArchive::new(file).unwrap().extract(&dir).unwrap();
    let xml = std::fs::read_to_string(dir.join("modelDescription.xml")).unwrap();
    let guid = xml
        .split("guid=\"")
        .nth(1)
        .unwrap()
        .split('"')
        .next()
        .unwrap();
    let setup = json!({
        "library": dir.join(format!("binaries/{}/Oscillator.so", platform_folder())),
        "model_identifier": "Oscillator",
        "guid": guid,
        "resource_location": format!("file://{}/resources", dir.display()),
        "instance_name": "sweep-test",
        "start_time": 0.0, "stop_time": 20.0, "output_interval": 0.01,
        "tolerance": null, "set_stop_time": true, "can_vary_step": true,
        // m (fixed parameter), c and k (tunable), all set before initialization mode.
        "starts": [{"vr": 0, "type": "Real", "initialization": false},
                   {"vr": 1, "type": "Real", "initialization": false},
                   {"vr": 2, "type": "Real", "initialization": false}],
        "inputs": [5],
        "trajectory": [6, 7],
        "finals": [8],
        "summaries": [
            {"func": "max_abs", "source": "trajectory", "index": 0},
            {"func": "mean", "source": "trajectory", "index": 0},
            {"func": "rms", "source": "trajectory", "index": 1},
            {"func": "final", "source": "trajectory", "index": 0},
            {"func": "final", "source": "final", "index": 0}
        ]
    });
    (dir, setup)
}

struct Worker {
    child: Child,
    stdin: Option<ChildStdin>,
    stdout: ChildStdout,
}

impl Worker {
    fn start() -> Worker {
        let mut child = Command::new(env!("CARGO_BIN_EXE_mechfmu"))
            .arg("sweep-worker")
            .stdin(Stdio::piped())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .expect("mechfmu sweep-worker starts");
        let stdin = child.stdin.take();
        let stdout = child.stdout.take().unwrap();
        Worker {
            child,
            stdin,
            stdout,
        }
    }

    fn send(&mut self, payload: &[u8]) {
        let stdin = self.stdin.as_mut().unwrap();
        stdin
            .write_all(&(payload.len() as u32).to_le_bytes())
            .unwrap();
        stdin.write_all(payload).unwrap();
        stdin.flush().unwrap();
    }

    fn receive(&mut self) -> Vec<u8> {
        let mut length = [0u8; 4];
        self.stdout.read_exact(&mut length).expect("a reply");
        let mut payload = vec![0; u32::from_le_bytes(length) as usize];
        self.stdout.read_exact(&mut payload).unwrap();
        payload
    }

    /// Closes stdin and waits: the exit status and stderr.
    fn finish(mut self) -> (Option<i32>, String) {
        drop(self.stdin.take());
        let output = self.child.wait_with_output().unwrap();
        (
            output.status.code(),
            String::from_utf8_lossy(&output.stderr).into_owned(),
        )
    }
}

/// A case of a request: its index, start values (m, c, k) and input rows (time, F).
type Request<'a> = (u64, [f64; 3], &'a [[f64; 2]]);

fn chunk(cases: &[Request]) -> Vec<u8> {
    mechfmu_sweep_worker::encode_chunk(cases)
}

#[derive(Debug)]
struct Answer {
    index: u64,
    status: u8,
    function: String,
    discard_time: f64,
    log: Vec<(u8, String, String)>,
    summaries: Vec<f64>,
    elapsed_s: f64,
    cpu_s: f64,
}

/// Reads a chunk reply of cases with `summaries` summaries each.
fn answers(reply: &[u8], summaries: usize) -> Vec<Answer> {
    let mut at = 0;
    let mut take = |n: usize| {
        at += n;
        &reply[at - n..at]
    };
    let u32_ = |b: &[u8]| u32::from_le_bytes(b.try_into().unwrap());
    let f64_ = |b: &[u8]| f64::from_le_bytes(b.try_into().unwrap());
    let n = u32_(take(4));
    let mut cases = Vec::new();
    for _ in 0..n {
        let index = u64::from_le_bytes(take(8).try_into().unwrap());
        let status = take(1)[0];
        let len = u32_(take(4)) as usize;
        let function = String::from_utf8(take(len).to_vec()).unwrap();
        let discard_time = f64_(take(8));
        let _last_successful_time = f64_(take(8));
        let mut log = Vec::new();
        for _ in 0..u32_(take(4)) {
            let status = take(1)[0];
            let len = u32_(take(4)) as usize;
            let category = String::from_utf8(take(len).to_vec()).unwrap();
            let len = u32_(take(4)) as usize;
            let message = String::from_utf8(take(len).to_vec()).unwrap();
            log.push((status, category, message));
        }
        let summaries = (0..summaries).map(|_| f64_(take(8))).collect();
        let (elapsed_s, cpu_s) = (f64_(take(8)), f64_(take(8)));
        cases.push(Answer {
            index,
            status,
            function,
            discard_time,
            log,
            summaries,
            elapsed_s,
            cpu_s,
        });
    }
    assert_eq!(at, reply.len(), "the whole reply is read");
    cases
}

#[test]
fn runs_a_chunk_of_oscillator_cases() {
    let (dir, setup) = oscillator("chunk");
    let mut worker = Worker::start();
    worker.send(setup.to_string().as_bytes());
    let answer: Value = serde_json::from_slice(&worker.receive()).unwrap();
    assert_eq!(answer, json!({"ok": true}));

    // The default case; a stiffer, well damped spring pushed by a force stepping up at
    // t = 5; a negative mass, which the Oscillator refuses (m is declared positive).
    let step: &[[f64; 2]] = &[[0.0, 0.0], [5.0, 0.0], [5.0, 1.0], [20.0, 1.0]];
    worker.send(&chunk(&[
        (10, [1.0, 0.4, 4.0], &[]),
        (11, [1.0, 4.0, 9.0], step),
        (12, [-1.0, 0.4, 4.0], &[]),
    ]));
    let cases = answers(&worker.receive(), 5);
    let (code, stderr) = worker.finish();
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(code, Some(0), "exit status; stderr: {stderr}");

    let indices: Vec<u64> = cases.iter().map(|c| c.index).collect();
    assert_eq!(indices, [10, 11, 12]);
    for case in &cases[..2] {
        assert_eq!((case.status, case.function.as_str()), (0, ""), "{case:?}");
        assert!(case.summaries.iter().all(|s| s.is_finite()), "{case:?}");
        assert!(case.discard_time.is_nan());
        assert!(case.elapsed_s > 0.0 && case.cpu_s >= 0.0, "{case:?}");
    }
    // x starts at 1 and decays: its largest magnitude is the start value.
    assert_eq!(cases[0].summaries[0], 1.0);
    // The step of F moves the spring's rest position to F / k = 1/9, where it has settled
    // (decay rate c / 2m = 2 per second) with no acceleration left.
    assert!(
        (cases[1].summaries[3] - 1.0 / 9.0).abs() < 1e-4,
        "{:?}",
        cases[1]
    );
    assert!(cases[1].summaries[4].abs() < 1e-3, "{:?}", cases[1]);

    let refused = &cases[2];
    assert_eq!(refused.status, 3, "{refused:?}");
    assert!(refused.function.starts_with("fmi2"), "{refused:?}");
    assert!(refused.summaries.iter().all(|s| s.is_nan()), "{refused:?}");
    assert!(
        refused
            .log
            .iter()
            .any(|(status, _, message)| *status >= 3 && message.contains("m = -1")),
        "the log names the variable: {refused:?}"
    );
}

#[test]
fn a_malformed_chunk_stops_the_worker_with_a_message() {
    let (dir, setup) = oscillator("malformed");
    let mut worker = Worker::start();
    worker.send(setup.to_string().as_bytes());
    worker.receive();
    // Five cases announced, one index's worth of bytes behind.
    let mut bytes = 5u32.to_le_bytes().to_vec();
    bytes.extend_from_slice(&7u64.to_le_bytes());
    worker.send(&bytes);
    let (code, stderr) = worker.finish();
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(code, Some(2), "stderr: {stderr}");
    assert!(stderr.contains("malformed chunk"), "{stderr}");
}

#[test]
fn a_frame_cut_short_stops_the_worker_with_a_message() {
    let mut worker = Worker::start();
    let stdin = worker.stdin.as_mut().unwrap();
    stdin.write_all(&100u32.to_le_bytes()).unwrap();
    stdin.write_all(b"{\"li").unwrap();
    let (code, stderr) = worker.finish();
    assert_eq!(code, Some(2), "stderr: {stderr}");
    assert!(stderr.contains("4 of its 100 bytes"), "{stderr}");
}

#[test]
fn a_missing_binary_is_answered_then_status_1() {
    let (dir, mut setup) = oscillator("missing");
    std::fs::remove_dir_all(&dir).ok();
    setup["library"] = json!(dir.join("nowhere/Oscillator.so"));
    let mut worker = Worker::start();
    worker.send(setup.to_string().as_bytes());
    let answer: Value = serde_json::from_slice(&worker.receive()).unwrap();
    let (code, _) = worker.finish();
    assert_eq!(answer["ok"], json!(false));
    let error = answer["error"].as_str().unwrap();
    assert!(error.contains("nowhere/Oscillator.so"), "{error}");
    assert_eq!(code, Some(1));
}

#[test]
fn a_bare_setup_only_steps() {
    let (dir, mut setup) = oscillator("bare");
    setup["bare"] = json!(true);
    let mut worker = Worker::start();
    worker.send(setup.to_string().as_bytes());
    worker.receive();
    let step: &[[f64; 2]] = &[[0.0, 0.0], [5.0, 1.0]];
    worker.send(&chunk(&[
        (1, [1.0, 0.4, 4.0], step),
        (2, [1.0, 0.4, 4.0], &[]),
    ]));
    let cases = answers(&worker.receive(), 5);
    let (code, stderr) = worker.finish();
    std::fs::remove_dir_all(&dir).ok();
    assert_eq!(code, Some(0), "stderr: {stderr}");
    for case in &cases {
        assert_eq!(case.status, 0, "{case:?}");
        assert!(case.summaries.iter().all(|s| s.is_nan()), "{case:?}");
        assert!(case.cpu_s > 0.0, "{case:?}");
    }
}
