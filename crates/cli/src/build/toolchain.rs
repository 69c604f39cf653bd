//! How each platform's binary is cross-compiled from this machine, and what this machine
//! lacks to do it.
//!
//! Every platform's binary is built from the same crate by Rust's own target (the GNU
//! toolchains, so a Linux machine builds them all with Debian's cross linkers).

use mechfmu_host::platform::Platform;
use std::path::Path;
use std::process::Command;

/// Why a platform's binary cannot be built here, and how to make it possible.
#[derive(Debug)]
pub struct MissingToolchain {
    pub platform: Platform,
    /// What is missing, each with the command that installs it.
    pub missing: Vec<(String, String)>,
}

impl MissingToolchain {
    /// What is missing and how to install it, e.g. "the linker x86_64-w64-mingw32-gcc is
    /// missing (install: apt-get install gcc-mingw-w64-x86-64)".
    pub fn what(&self) -> String {
        let what: Vec<String> = self
            .missing
            .iter()
            .map(|(what, install)| format!("{what} is missing (install: {install})"))
            .collect();
        what.join("; ")
    }
}

impl std::fmt::Display for MissingToolchain {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "no {} binary: {}", self.platform.tuple(), self.what())
    }
}

/// The C compiler cargo links with when cross-compiling for `platform`, and the Debian
/// package with it.
fn cross_linker(platform: Platform) -> (&'static str, &'static str) {
    match platform {
        Platform::X86_64Linux => ("x86_64-linux-gnu-gcc", "gcc-x86-64-linux-gnu"),
        Platform::X86_64Windows => ("x86_64-w64-mingw32-gcc", "gcc-mingw-w64-x86-64"),
        Platform::Aarch64Linux => ("aarch64-linux-gnu-gcc", "gcc-aarch64-linux-gnu"),
    }
}

/// A file of the C library the cross linker links every binary of `platform` against, and the
/// Debian package with it: Debian installs the linker without it when recommendations are
/// left out, and the link then fails on a missing `crti.o`.
fn cross_c_library(platform: Platform) -> (&'static str, &'static str) {
    match platform {
        Platform::X86_64Linux => ("crti.o", "libc6-dev-amd64-cross"),
        Platform::X86_64Windows => ("libmsvcrt.a", "mingw-w64-x86-64-dev"),
        Platform::Aarch64Linux => ("crti.o", "libc6-dev-arm64-cross"),
    }
}

/// Whether `linker` finds `file` in its search path (`-print-file-name` answers the bare
/// name when it does not).
fn linker_finds(linker: &str, file: &str) -> bool {
    Command::new(linker)
        .arg(format!("-print-file-name={file}"))
        .output()
        .is_ok_and(|out| Path::new(String::from_utf8_lossy(&out.stdout).trim()).is_absolute())
}

/// `CARGO_TARGET_<TRIPLE>_<key>`, cargo's per-target settings in the environment.
fn cargo_variable(platform: Platform, key: &str) -> String {
    format!(
        "CARGO_TARGET_{}_{key}",
        platform.rust_target().to_uppercase().replace('-', "_")
    )
}

/// What this machine lacks to build `platform`'s binary: the Rust target's standard library
/// and, unless it is this machine's own platform or cargo has been given a linker for it,
/// the cross linker and the target's C library.
pub fn missing(platform: Platform) -> Option<MissingToolchain> {
    let mut missing = Vec::new();
    if !rust_target_installed(platform.rust_target()) {
        missing.push((
            format!("the Rust target {}", platform.rust_target()),
            format!("rustup target add {}", platform.rust_target()),
        ));
    }
    if Platform::host() != Some(platform)
        && std::env::var_os(cargo_variable(platform, "LINKER")).is_none()
    {
        let (linker, package) = cross_linker(platform);
        let (library, library_package) = cross_c_library(platform);
        if !on_path(linker) {
            missing.push((
                format!("the linker {linker}"),
                format!("apt-get install {package} {library_package}"),
            ));
        } else if !linker_finds(linker, library) {
            missing.push((
                format!("the C library for {linker} ({library})"),
                format!("apt-get install {library_package}"),
            ));
        }
    }
    (!missing.is_empty()).then_some(MissingToolchain { platform, missing })
}

/// Sets the environment of a `cargo build --target` for `platform`: the cross linker (the
/// runtime's build script makes the binary carry libgcc's unwinder on Linux).
pub fn configure(platform: Platform, cargo: &mut Command) {
    if Platform::host() != Some(platform)
        && std::env::var_os(cargo_variable(platform, "LINKER")).is_none()
    {
        cargo.env(cargo_variable(platform, "LINKER"), cross_linker(platform).0);
    }
}

fn rust_target_installed(triple: &str) -> bool {
    let Ok(output) = Command::new("rustc").args(["--print", "sysroot"]).output() else {
        return false;
    };
    let sysroot = String::from_utf8_lossy(&output.stdout).trim().to_string();
    Path::new(&sysroot)
        .join("lib/rustlib")
        .join(triple)
        .join("lib")
        .is_dir()
}

fn on_path(program: &str) -> bool {
    std::env::var_os("PATH")
        .is_some_and(|paths| std::env::split_paths(&paths).any(|dir| dir.join(program).is_file()))
}
