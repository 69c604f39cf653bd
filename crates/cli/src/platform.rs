//! The platforms an FMU carries binaries for, how each is cross-compiled from this machine,
//! and what each binary may depend on.
//!
//! Every platform's binary is built from the same crate by Rust's own target (the GNU
//! toolchains, so a Linux machine builds them all with Debian's cross linkers). FMI 2.0
//! names the x86-64 platforms `linux64` and `win64`; for any other, FMI 2.0.5 (section 2.3)
//! says to use FMI 3.0's platform tuple, so ARM Linux is `aarch64-linux` in both versions.

use crate::package::Version;
use std::path::Path;
use std::process::Command;

#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Platform {
    X86_64Linux,
    X86_64Windows,
    Aarch64Linux,
}

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

impl Platform {
    pub const ALL: [Platform; 3] = [
        Platform::X86_64Linux,
        Platform::X86_64Windows,
        Platform::Aarch64Linux,
    ];

    /// The platform this `mechfmu` runs on, when it is one FMUs are built for.
    pub fn host() -> Option<Platform> {
        Platform::ALL.into_iter().find(|p| {
            p.rust_target().starts_with(std::env::consts::ARCH)
                && p.rust_target().contains(std::env::consts::OS)
        })
    }

    /// FMI 3.0's platform tuple, which is also the platform's name on the command line.
    pub fn tuple(self) -> &'static str {
        match self {
            Platform::X86_64Linux => "x86_64-linux",
            Platform::X86_64Windows => "x86_64-windows",
            Platform::Aarch64Linux => "aarch64-linux",
        }
    }

    /// The folder under `binaries/` in an FMU of `version`.
    pub fn folder(self, version: Version) -> &'static str {
        match (version, self) {
            (Version::Fmi2, Platform::X86_64Linux) => "linux64",
            (Version::Fmi2, Platform::X86_64Windows) => "win64",
            _ => self.tuple(),
        }
    }

    /// A name given to `--platform`: FMI 3.0's tuple or FMI 2.0's name.
    pub fn parse(name: &str) -> Option<Platform> {
        Platform::ALL.into_iter().find(|p| {
            name == p.tuple() || name == p.folder(Version::Fmi2) || name == p.rust_target()
        })
    }

    pub fn rust_target(self) -> &'static str {
        match self {
            Platform::X86_64Linux => "x86_64-unknown-linux-gnu",
            Platform::X86_64Windows => "x86_64-pc-windows-gnu",
            Platform::Aarch64Linux => "aarch64-unknown-linux-gnu",
        }
    }

    /// The extension of a shared library.
    pub fn extension(self) -> &'static str {
        match self {
            Platform::X86_64Windows => "dll",
            _ => "so",
        }
    }

    /// The C compiler cargo links with when cross-compiling, and the Debian package with it.
    fn cross_linker(self) -> (&'static str, &'static str) {
        match self {
            Platform::X86_64Linux => ("x86_64-linux-gnu-gcc", "gcc-x86-64-linux-gnu"),
            Platform::X86_64Windows => ("x86_64-w64-mingw32-gcc", "gcc-mingw-w64-x86-64"),
            Platform::Aarch64Linux => ("aarch64-linux-gnu-gcc", "gcc-aarch64-linux-gnu"),
        }
    }

    /// `CARGO_TARGET_<TRIPLE>_<key>`, cargo's per-target settings in the environment.
    fn cargo_variable(self, key: &str) -> String {
        format!(
            "CARGO_TARGET_{}_{key}",
            self.rust_target().to_uppercase().replace('-', "_")
        )
    }

    /// What this machine lacks to build the platform's binary: the Rust target's standard
    /// library and, unless it is this machine's own platform or cargo has been given a
    /// linker for it, the cross linker.
    pub fn missing_toolchain(self) -> Option<MissingToolchain> {
        let mut missing = Vec::new();
        if !rust_target_installed(self.rust_target()) {
            missing.push((
                format!("the Rust target {}", self.rust_target()),
                format!("rustup target add {}", self.rust_target()),
            ));
        }
        if Platform::host() != Some(self)
            && std::env::var_os(self.cargo_variable("LINKER")).is_none()
        {
            let (linker, package) = self.cross_linker();
            if !on_path(linker) {
                missing.push((
                    format!("the linker {linker}"),
                    format!("apt-get install {package}"),
                ));
            }
        }
        (!missing.is_empty()).then_some(MissingToolchain {
            platform: self,
            missing,
        })
    }

    /// Sets the environment of a `cargo build --target` for this platform: the cross linker
    /// (the runtime's build script makes the binary carry libgcc's unwinder on Linux).
    pub fn configure(self, cargo: &mut Command) {
        if Platform::host() != Some(self)
            && std::env::var_os(self.cargo_variable("LINKER")).is_none()
        {
            cargo.env(self.cargo_variable("LINKER"), self.cross_linker().0);
        }
    }

    /// The libraries a binary of this platform may depend on: those every installation of
    /// the system has (glibc's on Linux; on Windows, DLLs of a stock Windows 10).
    pub fn system_libraries(self) -> &'static [&'static str] {
        match self {
            Platform::X86_64Linux => &[
                "libc.so.6",
                "libm.so.6",
                "libdl.so.2",
                "libpthread.so.0",
                "librt.so.1",
                "ld-linux-x86-64.so.2",
            ],
            Platform::Aarch64Linux => &[
                "libc.so.6",
                "libm.so.6",
                "libdl.so.2",
                "libpthread.so.0",
                "librt.so.1",
                "ld-linux-aarch64.so.1",
            ],
            Platform::X86_64Windows => &[
                "kernel32.dll",
                "ntdll.dll",
                "msvcrt.dll",
                "advapi32.dll",
                "userenv.dll",
                "ws2_32.dll",
                "bcrypt.dll",
                "bcryptprimitives.dll",
                "api-ms-win-core-synch-l1-2-0.dll",
            ],
        }
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

/// The platforms `--platform` names (comma-separated tuples or FMI 2.0 names, or `all`).
pub fn parse_list(text: &str) -> Result<Vec<Platform>, String> {
    if text == "all" {
        return Ok(Platform::ALL.to_vec());
    }
    let mut platforms = Vec::new();
    for name in text.split(',').map(str::trim).filter(|n| !n.is_empty()) {
        let platform = Platform::parse(name).ok_or_else(|| {
            let known: Vec<&str> = Platform::ALL.iter().map(|p| p.tuple()).collect();
            format!(
                "unknown platform `{name}` (known: {}, or all; FMI 2.0's linux64 and win64 are accepted too)",
                known.join(", ")
            )
        })?;
        if !platforms.contains(&platform) {
            platforms.push(platform);
        }
    }
    if platforms.is_empty() {
        return Err("--platform names no platform".into());
    }
    platforms.sort();
    Ok(platforms)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn folders_follow_each_standard() {
        assert_eq!(Platform::X86_64Linux.folder(Version::Fmi2), "linux64");
        assert_eq!(Platform::X86_64Windows.folder(Version::Fmi2), "win64");
        assert_eq!(
            Platform::Aarch64Linux.folder(Version::Fmi2),
            "aarch64-linux"
        );
        assert_eq!(
            Platform::X86_64Windows.folder(Version::Fmi3),
            "x86_64-windows"
        );
    }

    #[test]
    fn platform_lists_parse_and_name_the_unknown() {
        assert_eq!(parse_list("all").unwrap(), Platform::ALL.to_vec());
        assert_eq!(
            parse_list("win64,x86_64-linux,win64").unwrap(),
            vec![Platform::X86_64Linux, Platform::X86_64Windows]
        );
        let err = parse_list("linux64,darwin64").unwrap_err();
        assert!(err.contains("`darwin64`"), "{err}");
        assert!(parse_list(",").is_err());
    }

    #[test]
    fn this_machine_is_a_platform() {
        if cfg!(all(target_arch = "x86_64", target_os = "linux")) {
            assert_eq!(Platform::host(), Some(Platform::X86_64Linux));
        }
        if cfg!(all(target_arch = "aarch64", target_os = "linux")) {
            assert_eq!(Platform::host(), Some(Platform::Aarch64Linux));
        }
    }
}
