//! The platforms mechfmu builds FMU binaries for, and where each platform's binary is in an
//! FMU of each FMI version.
//!
//! FMI 2.0 names the x86-64 platforms `linux64`, `win64` and `darwin64`; for any other, FMI
//! 2.0.5 (section 2.3) says to use FMI 3.0's platform tuple, so ARM Linux is `aarch64-linux`
//! and Apple silicon `aarch64-darwin` in both versions. (An FMI 2.0 FMU's `darwin64` holds a
//! universal binary of both Mac platforms where both are built: FMPy on Apple silicon loads
//! FMI 2.0 binaries from `darwin64`.)

/// The FMI version whose folder [`Platform::folder`] names.
pub use super::Version;

#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Platform {
    X86_64Linux,
    X86_64Windows,
    Aarch64Linux,
    X86_64Darwin,
    Aarch64Darwin,
}

impl Platform {
    pub const ALL: [Platform; 5] = [
        Platform::X86_64Linux,
        Platform::X86_64Windows,
        Platform::Aarch64Linux,
        Platform::X86_64Darwin,
        Platform::Aarch64Darwin,
    ];

    /// The platform this program runs on, when it is one FMUs are built for.
    pub fn host() -> Option<Platform> {
        let os = match std::env::consts::OS {
            "macos" => "darwin",
            os => os,
        };
        Platform::ALL.into_iter().find(|p| {
            p.rust_target().starts_with(std::env::consts::ARCH) && p.rust_target().contains(os)
        })
    }

    /// A macOS platform (its binaries are Mach-O dylibs).
    pub fn is_darwin(self) -> bool {
        matches!(self, Platform::X86_64Darwin | Platform::Aarch64Darwin)
    }

    /// FMI 3.0's platform tuple, which is also the platform's name on the command line.
    pub fn tuple(self) -> &'static str {
        match self {
            Platform::X86_64Linux => "x86_64-linux",
            Platform::X86_64Windows => "x86_64-windows",
            Platform::Aarch64Linux => "aarch64-linux",
            Platform::X86_64Darwin => "x86_64-darwin",
            Platform::Aarch64Darwin => "aarch64-darwin",
        }
    }

    /// The folder under `binaries/` in an FMU of `version`.
    pub fn folder(self, version: Version) -> &'static str {
        match (version, self) {
            (Version::Fmi2, Platform::X86_64Linux) => "linux64",
            (Version::Fmi2, Platform::X86_64Windows) => "win64",
            (Version::Fmi2, Platform::X86_64Darwin) => "darwin64",
            _ => self.tuple(),
        }
    }

    /// A platform's name: FMI 3.0's tuple, FMI 2.0's folder or Rust's target triple.
    pub fn parse(name: &str) -> Option<Platform> {
        Platform::ALL.into_iter().find(|p| {
            name == p.tuple() || name == p.folder(Version::Fmi2) || name == p.rust_target()
        })
    }

    /// Rust's target triple (the GNU toolchains).
    pub fn rust_target(self) -> &'static str {
        match self {
            Platform::X86_64Linux => "x86_64-unknown-linux-gnu",
            Platform::X86_64Windows => "x86_64-pc-windows-gnu",
            Platform::Aarch64Linux => "aarch64-unknown-linux-gnu",
            Platform::X86_64Darwin => "x86_64-apple-darwin",
            Platform::Aarch64Darwin => "aarch64-apple-darwin",
        }
    }

    /// The extension of a shared library.
    pub fn extension(self) -> &'static str {
        match self {
            Platform::X86_64Windows => "dll",
            Platform::X86_64Darwin | Platform::Aarch64Darwin => "dylib",
            _ => "so",
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn folders_follow_each_standard() {
        let expected = [
            (Platform::X86_64Linux, Version::Fmi2, "linux64"),
            (Platform::X86_64Windows, Version::Fmi2, "win64"),
            (Platform::Aarch64Linux, Version::Fmi2, "aarch64-linux"),
            (Platform::X86_64Windows, Version::Fmi3, "x86_64-windows"),
            (Platform::X86_64Darwin, Version::Fmi2, "darwin64"),
            (Platform::Aarch64Darwin, Version::Fmi2, "aarch64-darwin"),
            (Platform::X86_64Darwin, Version::Fmi3, "x86_64-darwin"),
        ];
        for (platform, version, folder) in expected {
            assert_eq!(platform.folder(version), folder, "{platform:?} {version:?}");
        }
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
