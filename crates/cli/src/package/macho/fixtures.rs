//! The tiny dylibs of `tests/data/macho` (its README says how they were built) and what
//! doctors them, for the tests of this module and of the packaging checks.

use super::bytes::le32;
use super::load::HEADER;

pub const ARM64: &[u8] = include_bytes!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/tests/data/macho/libtiny-arm64.dylib"
));
pub const X86_64: &[u8] = include_bytes!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/tests/data/macho/libtiny-x86_64.dylib"
));
/// The libSystem stub the Mac binaries link against (the tiny dylibs were linked against it too).
pub const STUB: &str = crate::build::toolchain::LIBSYSTEM_TBD;

/// Where the first load command `cmd` of the thin file `m` starts.
pub fn command_at(m: &[u8], cmd: u32) -> usize {
    let mut at = HEADER;
    for _ in 0..le32(m, 16).unwrap() {
        if le32(m, at).unwrap() == cmd {
            return at;
        }
        at += le32(m, at + 4).unwrap() as usize;
    }
    panic!("no load command {cmd:#x}");
}

/// The bytes of `m` with `value` at `at`.
pub fn with(m: &[u8], at: usize, value: &[u8]) -> Vec<u8> {
    let mut m = m.to_vec();
    m[at..at + value.len()].copy_from_slice(value);
    m
}
