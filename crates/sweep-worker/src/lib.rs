//! The native engine of `mechfmu sweep`, which the hidden `mechfmu sweep-worker` runs
//! ([`run`]). The Python side starts one per Dask worker and feeds it chunks of cases over
//! stdin; the worker runs each case on one FMI 2.0 Co-Simulation instance (through
//! `mechfmu-host`) exactly as `python/mechfmu_sweep/runner.py` runs it through FMPy, and
//! answers each chunk with the cases' statuses, logs and summaries on stdout, at the cost of
//! the FMU's own steps.
//!
//! Protocol (little-endian; every message a frame: u32 byte length + payload):
//! 1. setup, JSON (`setup::Setup`); answered `{"ok": true}`, or `{"ok": false, "error"}`
//!    and exit status 1 when the binary or one of its functions cannot be loaded;
//! 2. chunks of cases (`protocol::parse_chunk`), each answered by one frame
//!    (`protocol::Reply`);
//! 3. the end of stdin at a frame boundary: exit 0. Anything malformed: a message on
//!    stderr, exit status 2.
//!
//! `driver` runs a case (FMPy's calls, through `instance`), `input` interpolates the input
//! table as FMPy does (over CPython's `isclose` and `bisect` in `pymath`), `summary`
//! computes the summaries as numpy does.

#![forbid(unsafe_code)]

mod driver;
mod input;
mod instance;
mod protocol;
mod pymath;
mod setup;
mod summary;

use driver::{Driver, Timing};
use instance::Failure;
use mechfmu_host::log::Message;
/// The chunk requests the tests of the worker send, written as the Python side writes them.
pub use protocol::encode_chunk;
use protocol::{frame, parse_chunk, read_frame, CaseReport, Reply};
use serde_json::json;
use setup::Setup;
use std::fs::File;
use std::io::Write;
use std::process::ExitCode;

/// Why the worker stops before the end of its input.
enum Stop {
    /// The setup's binary could not be loaded (answered with `"ok": false`): status 1.
    Unloadable(String),
    /// A malformed request, or stdout gone: status 2.
    Malformed(String),
}

impl From<String> for Stop {
    fn from(message: String) -> Stop {
        Stop::Malformed(message)
    }
}

/// Serves until the end of stdin; the process's exit status.
pub fn run() -> ExitCode {
    let outcome = std::panic::catch_unwind(serve).unwrap_or_else(|_| {
        // The panic hook has printed what and where already.
        Err(Stop::Malformed("internal error".into()))
    });
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(Stop::Unloadable(message)) => {
            eprintln!("mechfmu sweep-worker: {message}");
            ExitCode::from(1)
        }
        Err(Stop::Malformed(message)) => {
            eprintln!("mechfmu sweep-worker: {message}");
            ExitCode::from(2)
        }
    }
}

fn serve() -> Result<(), Stop> {
    let mut input = std::io::stdin().lock();
    let mut output = raw_stdout()?;
    let mut payload = Vec::new();
    if !read_frame(&mut input, &mut payload)? {
        return Ok(()); // closed before any setup: nothing to do
    }
    let setup = Setup::parse(&payload)?;
    let mut driver = match Driver::new(setup) {
        Ok(driver) => driver,
        Err(error) => {
            send(
                &mut output,
                &frame(json!({"ok": false, "error": error}).to_string().as_bytes()),
            )?;
            return Err(Stop::Unloadable(error));
        }
    };
    send(
        &mut output,
        &frame(json!({"ok": true}).to_string().as_bytes()),
    )?;
    let mut reply = Reply::default();
    while read_frame(&mut input, &mut payload)? {
        let setup = driver.setup();
        let cases = parse_chunk(&payload, setup.starts.len(), setup.inputs.len())
            .map_err(|e| format!("malformed chunk: {e}"))?;
        reply.start(cases.len() as u32);
        for case in &cases {
            let (failure, timing) = driver.run_case(case);
            let log = driver.log().messages();
            reply.case(&report(
                case.index,
                failure,
                timing,
                &log,
                driver.summaries(),
            ));
        }
        send(&mut output, reply.finish()?)?;
    }
    Ok(())
}

/// What a case reports: its failure (if any), its timing, the FMU's messages, summaries.
fn report<'a>(
    index: u64,
    failure: Option<Failure>,
    timing: Timing,
    log: &'a [Message],
    summaries: &'a [f64],
) -> CaseReport<'a> {
    let (discard_time, last_successful_time) = failure
        .and_then(|f| f.discarded)
        .unwrap_or((f64::NAN, f64::NAN));
    CaseReport {
        index,
        status: failure.map_or(0, |f| f.status.min(u8::MAX as u32) as u8),
        function: failure.map_or("", |f| f.function),
        discard_time,
        last_successful_time,
        log,
        summaries,
        elapsed_s: timing.elapsed_s,
        cpu_s: timing.cpu_s,
    }
}

/// One write of a whole message.
fn send(output: &mut File, bytes: &[u8]) -> Result<(), Stop> {
    output
        .write_all(bytes)
        .map_err(|e| Stop::Malformed(format!("cannot write the reply to stdout: {e}")))
}

/// Stdout unbuffered: `std::io::Stdout` is line-buffered and would cut a binary reply at
/// every newline byte; a reply is written whole, once.
fn raw_stdout() -> Result<File, String> {
    #[cfg(unix)]
    let handle = std::os::fd::AsFd::as_fd(&std::io::stdout()).try_clone_to_owned();
    #[cfg(windows)]
    let handle = std::os::windows::io::AsHandle::as_handle(&std::io::stdout()).try_clone_to_owned();
    handle
        .map(File::from)
        .map_err(|e| format!("cannot use stdout: {e}"))
}
