//! How each platform's binary is cross-compiled from this machine, and what this machine
//! lacks to do it.
//!
//! Every platform's binary is built from the same crate by Rust's own target: Linux and
//! Windows with the GNU toolchains (Debian's cross linkers), macOS with Rust's own linker,
//! `rust-lld` (which ships with rustc), against the text stub of Apple's `libSystem` in
//! `macos/libSystem.tbd` (no Apple SDK: the stub lists the symbols of libSystem the binaries
//! take; the comment at its top says how it is written).

use mechfmu_host::platform::Platform;
use std::path::{Path, PathBuf};
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

/// The text stub of macOS's `/usr/lib/libSystem.B.dylib` the macOS binaries link against,
/// and the list of what they may import: the same symbols.
pub const LIBSYSTEM_TBD: &str = include_str!("macos/libSystem.tbd");

/// The linker of the macOS targets: Rust's own, in the sysroot beside rustc.
const MACOS_LINKER: &str = "rust-lld";

/// The linker cargo links with when cross-compiling for `platform`, and the package with
/// it (a GNU platform's C compiler, from Debian; the Mac's, Rust's own).
fn cross_linker(platform: Platform) -> (&'static str, &'static str) {
    match platform {
        Platform::X86_64Windows => ("x86_64-w64-mingw32-gcc", "gcc-mingw-w64-x86-64"),
        Platform::Aarch64Linux => ("aarch64-linux-gnu-gcc", "gcc-aarch64-linux-gnu"),
        Platform::X86_64Linux => ("x86_64-linux-gnu-gcc", "gcc-x86-64-linux-gnu"),
        Platform::X86_64Darwin | Platform::Aarch64Darwin => (MACOS_LINKER, "rustc"),
    }
}

/// A file of the C library the cross linker links every binary of `platform` against, and the
/// package with it (for the Macs, the stub mechfmu writes): Debian installs the linker without it
/// when recommendations are left out, and the link then fails on a missing `crti.o`.
fn cross_c_library(platform: Platform) -> (&'static str, &'static str) {
    match platform {
        Platform::X86_64Windows => ("libmsvcrt.a", "mingw-w64-x86-64-dev"),
        Platform::Aarch64Linux => ("crti.o", "libc6-dev-arm64-cross"),
        Platform::X86_64Linux => ("crti.o", "libc6-dev-amd64-cross"),
        Platform::X86_64Darwin | Platform::Aarch64Darwin => ("libSystem.tbd", "rustc"),
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
    let linker_given = std::env::var_os(cargo_variable(platform, "LINKER")).is_some();
    if platform.is_darwin() && Platform::host() != Some(platform) && !linker_given {
        if !sysroot_tool(MACOS_LINKER).is_some_and(|p| p.is_file()) {
            missing.push((
                format!("Rust's linker {MACOS_LINKER} (part of rustc's toolchain)"),
                "rustup component add rustc".to_string(),
            ));
        }
    } else if Platform::host() != Some(platform) && !linker_given {
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
/// runtime's build script makes the binary carry libgcc's unwinder on Linux); for macOS,
/// `rust-lld`, and `SDKROOT` at `macos_sdk` (see [`write_macos_sdk`]), which rustc passes
/// the linker as its `-syslibroot`.
pub fn configure(platform: Platform, cargo: &mut Command, macos_sdk: Option<&Path>) {
    if Platform::host() == Some(platform)
        || std::env::var_os(cargo_variable(platform, "LINKER")).is_some()
    {
        return;
    }
    if platform.is_darwin() {
        cargo.env(cargo_variable(platform, "LINKER"), MACOS_LINKER);
        if let Some(sdk) = macos_sdk {
            cargo.env("SDKROOT", sdk);
        }
    } else {
        cargo.env(cargo_variable(platform, "LINKER"), cross_linker(platform).0);
    }
}

/// Writes the smallest macOS SDK `rust-lld` links against under `dir`: `MacOSX.sdk/usr/lib/`
/// with [`LIBSYSTEM_TBD`] as `libSystem.tbd`, `libc.tbd` and `libm.tbd` (rustc asks for all
/// three, as Apple's SDK has them), each rewritten only when it differs (so cargo's
/// fingerprints hold). Returns the SDK's root, for `SDKROOT`; the folder's name must say
/// `MacOSX`, or rustc ignores it.
pub fn write_macos_sdk(dir: &Path) -> Result<PathBuf, String> {
    let sdk = dir.join("MacOSX.sdk");
    let lib = sdk.join("usr/lib");
    std::fs::create_dir_all(&lib).map_err(|e| format!("cannot create {}: {e}", lib.display()))?;
    for name in ["libSystem.tbd", "libc.tbd", "libm.tbd"] {
        let path = lib.join(name);
        if std::fs::read(&path).is_ok_and(|b| b == LIBSYSTEM_TBD.as_bytes()) {
            continue;
        }
        std::fs::write(&path, LIBSYSTEM_TBD)
            .map_err(|e| format!("cannot write {}: {e}", path.display()))?;
    }
    Ok(sdk)
}

/// rustc's sysroot.
fn sysroot() -> Option<PathBuf> {
    let output = Command::new("rustc")
        .args(["--print", "sysroot"])
        .output()
        .ok()?;
    Some(PathBuf::from(
        String::from_utf8_lossy(&output.stdout).trim(),
    ))
}

/// A tool of rustc's toolchain for this machine (`lib/rustlib/<host>/bin/<name>`).
fn sysroot_tool(name: &str) -> Option<PathBuf> {
    let rustlib = sysroot()?.join("lib/rustlib");
    let host = Command::new("rustc").arg("-vV").output().ok()?;
    let host = String::from_utf8_lossy(&host.stdout)
        .lines()
        .find_map(|l| l.strip_prefix("host: ").map(str::to_string))?;
    Some(rustlib.join(host).join("bin").join(name))
}

fn rust_target_installed(triple: &str) -> bool {
    sysroot().is_some_and(|sysroot| {
        sysroot
            .join("lib/rustlib")
            .join(triple)
            .join("lib")
            .is_dir()
    })
}

fn on_path(program: &str) -> bool {
    std::env::var_os("PATH")
        .is_some_and(|paths| std::env::split_paths(&paths).any(|dir| dir.join(program).is_file()))
}
