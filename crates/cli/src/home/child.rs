//! Running a child (the venv's interpreter on one of mechfmu's packages) to its end as if it
//! were this command. The signals that end a command, SIGTERM, SIGHUP and SIGINT, are passed
//! on to it once, and the command waits while the child ends what it started and removes its
//! files; killed outright, the command takes the child with it (Linux's parent-death signal,
//! SIGTERM, which the child handles the same way).
//!
//! The child runs in a process group of its own: a terminal's Ctrl-C, or a signal to this
//! command's group, reaches this command alone, which passes it on. Sent to both, the child
//! would get it twice, and the second would cut its clean-up short.

// Signal handlers and `prctl` are the C library's: the one place the command needs `unsafe`.
#![allow(unsafe_code)]

use std::io;
use std::process::{Command, ExitStatus};

#[cfg(unix)]
pub fn run(command: &mut Command) -> io::Result<ExitStatus> {
    use std::os::unix::process::CommandExt;
    use std::sync::atomic::{AtomicI32, Ordering};

    /// The child signals are passed on to (0: none). A handler can read nothing else.
    static CHILD: AtomicI32 = AtomicI32::new(0);

    extern "C" fn pass_on(signal: libc::c_int) {
        let pid = CHILD.load(Ordering::SeqCst);
        if pid > 0 {
            // SAFETY: kill(2) is async-signal-safe; `pid` is the child this command waits
            // for, so it is not reused before the wait below returns.
            unsafe { libc::kill(pid, signal) };
        }
    }

    command.process_group(0);
    #[cfg(target_os = "linux")]
    // SAFETY: the closure runs in the forked child before exec and calls prctl(2) alone,
    // which is async-signal-safe.
    unsafe {
        command.pre_exec(|| {
            if libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGTERM) == -1 {
                return Err(io::Error::last_os_error());
            }
            Ok(())
        });
    }
    let mut child = command.spawn()?;
    CHILD.store(child.id() as i32, Ordering::SeqCst);
    let signals = [libc::SIGTERM, libc::SIGHUP, libc::SIGINT];
    let handler = pass_on as extern "C" fn(libc::c_int) as libc::sighandler_t;
    // SAFETY: `pass_on` is async-signal-safe (an atomic load and kill(2)).
    let previous = signals.map(|s| unsafe { libc::signal(s, handler) });
    let status = child.wait();
    for (s, p) in signals.into_iter().zip(previous) {
        // SAFETY: restores the disposition signal(2) returned for the same signal.
        unsafe { libc::signal(s, p) };
    }
    CHILD.store(0, Ordering::SeqCst);
    status
}

#[cfg(not(unix))]
pub fn run(command: &mut Command) -> io::Result<ExitStatus> {
    command.status()
}
