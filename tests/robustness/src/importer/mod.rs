//! The importer's side of an instance: callbacks (a logger of either standard that records
//! and checks every message; memory, step-finished and intermediate-update callbacks that
//! must never be called) and thin wrappers for well-behaved use ([`Instance`] of FMI 2.0,
//! [`Instance3`] of FMI 3.0, both [`ModelExchangeInstance`]s).

mod instance;
mod instance3;
mod model_exchange;

pub use instance::Instance;
pub use instance3::Instance3;
pub use model_exchange::ModelExchangeInstance;

use crate::ffi::*;
use std::ffi::{c_char, c_void};
use std::sync::Mutex;

/// A message the FMU logged.
#[derive(Clone, Debug, PartialEq)]
pub struct Message {
    pub status: Status,
    pub category: String,
    pub text: String,
    pub instance_name: Vec<u8>,
}

/// Where one instance's logger writes: the messages, and any breach of the logger contract
/// (a format other than "%s", an unknown category, a NULL string).
#[derive(Default)]
pub struct Sink {
    pub messages: Mutex<Vec<Message>>,
    pub violations: Mutex<Vec<String>>,
}

pub const CATEGORIES: [&str; 6] = [
    "logEvents",
    "logStatusWarning",
    "logStatusDiscard",
    "logStatusError",
    "logStatusFatal",
    "logAll",
];

impl Sink {
    pub fn len(&self) -> usize {
        self.messages.lock().map(|m| m.len()).unwrap_or(0)
    }
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
    pub fn since(&self, n: usize) -> Vec<Message> {
        self.messages
            .lock()
            .map(|m| m.get(n..).map(|s| s.to_vec()).unwrap_or_default())
            .unwrap_or_default()
    }
    pub fn all(&self) -> Vec<Message> {
        self.since(0)
    }
    pub fn take_violations(&self) -> Vec<String> {
        self.violations
            .lock()
            .map(|mut v| std::mem::take(&mut *v))
            .unwrap_or_default()
    }
    fn violation(&self, what: String) {
        if let Ok(mut v) = self.violations.lock() {
            v.push(what);
        }
    }
}

/// Receives the FMU's log calls. The header declares the logger C-variadic; Rust cannot
/// define one on stable, so this takes the fixed arguments plus exactly one string, which
/// is all the FMU ever passes ("%s", message): on x86-64 and AArch64 Linux a variadic
/// callee with these arguments receives them in the same registers.
unsafe extern "C" fn record(
    env: Env,
    instance_name: CStr,
    status: Status,
    category: CStr,
    format: CStr,
    message: *const c_char,
) {
    if env.is_null() {
        return; // nowhere to record: the test that passed a NULL environment expects none
    }
    // SAFETY: env is the Sink this importer registered, alive as long as the instance.
    let sink = unsafe { &*(env as *const Sink) };
    // SAFETY: the FMU passes a NUL-terminated string (NULL is checked).
    let format = unsafe { text(format) };
    if format.as_deref() != Some(b"%s") {
        sink.violation(format!(
            "logger called with format {:?} instead of \"%s\"",
            format.map(|f| String::from_utf8_lossy(&f).into_owned())
        ));
    }
    // SAFETY: as for `format`.
    unsafe {
        sink.receive(
            status,
            PENDING,
            category,
            message,
            text_or_empty(instance_name),
        )
    };
}

/// Receives the FMU's log calls through FMI 3.0's `fmi3LogMessageCallback`.
///
/// # Safety
/// `env` is NULL or the [`Sink`] the importer registered, alive; the strings are NULL or
/// NUL-terminated (what the FMU promises).
pub unsafe extern "C" fn record3(env: Env, status: Status, category: CStr, message: CStr) {
    if env.is_null() {
        return;
    }
    // SAFETY: env is the Sink this importer registered, alive as long as the instance.
    let sink = unsafe { &*(env as *const Sink) };
    // SAFETY: the FMU passes NUL-terminated strings (NULL is checked).
    unsafe { sink.receive(status, crate::ffi3::FATAL, category, message, vec![]) };
}

/// The bytes of a NUL-terminated string, `None` for NULL.
///
/// # Safety
/// `p` is NULL or NUL-terminated.
unsafe fn text(p: *const c_char) -> Option<Vec<u8>> {
    // SAFETY: the caller's promise (NULL is checked).
    (!p.is_null()).then(|| unsafe { std::ffi::CStr::from_ptr(p) }.to_bytes().to_vec())
}

impl Sink {
    /// Records a message of `status` (at most `last_status`, the standard's largest),
    /// after checking the logger's contract: a declared category other than `logAll`,
    /// non-empty UTF-8 text.
    ///
    /// # Safety
    /// `category` and `message` are NULL or NUL-terminated.
    unsafe fn receive(
        &self,
        status: Status,
        last_status: Status,
        category: CStr,
        message: CStr,
        instance_name: Vec<u8>,
    ) {
        // SAFETY: the caller's promise.
        let category = unsafe { text(category) }
            .map(|c| String::from_utf8_lossy(&c).into_owned())
            .unwrap_or_default();
        if !CATEGORIES.contains(&category.as_str()) || category == "logAll" {
            self.violation(format!("logger called with category {category:?}"));
        }
        // SAFETY: the caller's promise.
        let Some(message) = (unsafe { text(message) }) else {
            self.violation("logger called with a NULL message".into());
            return;
        };
        let text = match String::from_utf8(message) {
            Ok(t) => t,
            Err(e) => {
                self.violation("logger called with a message that is not UTF-8".into());
                String::from_utf8_lossy(e.as_bytes()).into_owned()
            }
        };
        if text.trim().is_empty() {
            self.violation(format!("empty log message (status {status})"));
        }
        if status > last_status {
            self.violation(format!("logger called with status {status}"));
        }
        if let Ok(mut m) = self.messages.lock() {
            m.push(Message {
                status,
                category,
                text,
                instance_name,
            });
        }
    }
}

fn text_or_empty(p: CStr) -> Vec<u8> {
    if p.is_null() {
        return vec![];
    }
    // SAFETY: NUL-terminated (from the FMU).
    unsafe { std::ffi::CStr::from_ptr(p) }.to_bytes().to_vec()
}

/// The recording logger, as the header's variadic type.
pub fn logger() -> Logger {
    // SAFETY: see `record`.
    unsafe {
        std::mem::transmute::<
            Option<unsafe extern "C" fn(Env, CStr, Status, CStr, CStr, *const c_char)>,
            Logger,
        >(Some(record))
    }
}

/// `allocateMemory`: the modelDescription says `canNotUseMemoryManagementFunctions`, so a
/// call is a bug: abort loudly (the test running this in a child process reports it).
pub extern "C" fn forbidden_allocate(nobj: usize, size: usize) -> *mut c_void {
    eprintln!("robustness: the FMU called allocateMemory({nobj}, {size}) although it declares canNotUseMemoryManagementFunctions");
    std::process::abort()
}

pub extern "C" fn forbidden_free(obj: *mut c_void) {
    eprintln!("robustness: the FMU called freeMemory({obj:?}) although it declares canNotUseMemoryManagementFunctions");
    std::process::abort()
}

/// `stepFinished`: the FMU never runs asynchronously (`canRunAsynchronuously="false"`).
pub extern "C" fn forbidden_step_finished(_env: Env, status: Status) {
    eprintln!(
        "robustness: the FMU called stepFinished({status}) although it cannot run asynchronously"
    );
    std::process::abort()
}

/// `intermediateUpdate` (FMI 3.0): the FMU provides no intermediate update
/// (`providesIntermediateUpdate="false"`), so a call is a bug.
///
/// # Safety
/// None needed: it reads no argument; `unsafe` for the callback's type.
pub unsafe extern "C" fn forbidden_intermediate_update(
    _env: Env,
    time: f64,
    _: bool,
    _: bool,
    _: bool,
    _: bool,
    _: *mut bool,
    _: *mut f64,
) {
    eprintln!("robustness: the FMU called intermediateUpdate({time}) although it provides none");
    std::process::abort()
}

/// Callbacks with the recording logger and the forbidden memory functions.
pub fn callbacks(sink: &Sink) -> CallbackFunctions {
    CallbackFunctions {
        logger: logger(),
        allocateMemory: Some(forbidden_allocate),
        freeMemory: Some(forbidden_free),
        stepFinished: Some(forbidden_step_finished),
        componentEnvironment: sink as *const Sink as Env,
    }
}

/// Resident set size of this process in bytes, from /proc/self/statm.
pub fn rss_bytes() -> Option<u64> {
    let statm = std::fs::read_to_string("/proc/self/statm").ok()?;
    let pages: u64 = statm.split_whitespace().nth(1)?.parse().ok()?;
    // SAFETY: sysconf has no preconditions.
    Some(pages * page_size())
}

fn page_size() -> u64 {
    extern "C" {
        fn sysconf(name: i32) -> i64;
    }
    const SC_PAGESIZE: i32 = 30; // Linux
                                 // SAFETY: sysconf has no preconditions.
    let p = unsafe { sysconf(SC_PAGESIZE) };
    if p > 0 {
        p as u64
    } else {
        4096
    }
}
