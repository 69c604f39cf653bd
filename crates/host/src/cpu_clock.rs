//! The calling thread's CPU time, which `mechfmu bench` and `mechfmu sweep-worker` time
//! calls with.
//!
//! Thread CPU time rather than wall-clock time: on a shared machine another process taking
//! the core stops this clock, so a run is charged for its own work only.

/// Nanoseconds of CPU time the calling thread has used.
#[cfg(target_os = "linux")]
#[inline]
pub fn cpu_ns() -> u64 {
    #[repr(C)]
    struct Timespec {
        tv_sec: i64,
        tv_nsec: i64,
    }
    extern "C" {
        fn clock_gettime(clock: i32, ts: *mut Timespec) -> i32;
    }
    const CLOCK_THREAD_CPUTIME_ID: i32 = 3;
    let mut ts = Timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: clock_gettime writes one timespec (two 64-bit fields on 64-bit Linux).
    let rc = unsafe { clock_gettime(CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    if rc != 0 {
        return wall_ns();
    }
    ts.tv_sec as u64 * 1_000_000_000 + ts.tv_nsec as u64
}

/// Elsewhere: wall-clock time (no portable per-thread CPU clock in std).
#[cfg(not(target_os = "linux"))]
pub fn cpu_ns() -> u64 {
    wall_ns()
}

fn wall_ns() -> u64 {
    use std::sync::OnceLock;
    use std::time::Instant;
    static START: OnceLock<Instant> = OnceLock::new();
    START.get_or_init(Instant::now).elapsed().as_nanos() as u64
}
