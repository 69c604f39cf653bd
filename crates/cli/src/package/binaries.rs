//! What a built binary is, read from its bytes (ELF or PE): its machine, the libraries it
//! loads and the functions it exports. `mechfmu build` checks every binary with it before
//! packaging (one that needs a library a stock system lacks, or that exports other
//! functions than this machine's binary of the same crate, is never shipped), and
//! `mechfmu inspect` prints it for any FMU.

use mechfmu_host::platform::Platform;
use object::{Architecture, BinaryFormat, NameOrOrdinal, Object};

/// What a shared library is made of, as a loader sees it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Facts {
    /// The platform its format and machine are for, when one of ours.
    pub platform: Option<Platform>,
    /// The libraries it loads, as it names them.
    pub dependencies: Vec<String>,
    /// The functions it exports, sorted.
    pub exports: Vec<String>,
}

pub fn inspect(bytes: &[u8]) -> Result<Facts, String> {
    let file =
        object::File::parse(bytes).map_err(|e| format!("not a shared library we can read: {e}"))?;
    let platform = match (file.format(), file.architecture()) {
        (BinaryFormat::Elf, Architecture::X86_64) => Some(Platform::X86_64Linux),
        (BinaryFormat::Elf, Architecture::Aarch64) => Some(Platform::Aarch64Linux),
        (BinaryFormat::Pe, Architecture::X86_64) => Some(Platform::X86_64Windows),
        _ => None,
    };
    let dependencies = file
        .import_libraries()
        .map_err(|e| format!("cannot read the libraries it loads: {e}"))?
        .map(|library| {
            library
                .map(|l| String::from_utf8_lossy(l.name()).into_owned())
                .map_err(|e| format!("cannot read the libraries it loads: {e}"))
        })
        .collect::<Result<Vec<_>, _>>()?;
    let mut exports: Vec<String> = file
        .exports()
        .map_err(|e| format!("cannot read its exports: {e}"))?
        .filter_map(|export| match export {
            Ok(export) => match export.name() {
                NameOrOrdinal::Name(name) => Some(Ok(String::from_utf8_lossy(name).into_owned())),
                NameOrOrdinal::Ordinal(_) => None,
            },
            Err(e) => Some(Err(format!("cannot read its exports: {e}"))),
        })
        .collect::<Result<_, _>>()?;
    exports.sort();
    exports.dedup();
    Ok(Facts {
        platform,
        dependencies,
        exports,
    })
}

/// Checks a binary built for `platform` against what an FMU may ship: the right machine,
/// no library beyond the platform's own, and exactly the functions of `expected_exports`
/// (those of this machine's binary of the same crate).
pub fn check(
    bytes: &[u8],
    platform: Platform,
    expected_exports: &[String],
) -> Result<Facts, String> {
    let facts = inspect(bytes)?;
    if facts.platform != Some(platform) {
        return Err(format!(
            "built for {:?}, not {}",
            facts.platform.map(Platform::tuple),
            platform.tuple()
        ));
    }
    let foreign = foreign_dependencies(&facts, platform);
    if !foreign.is_empty() {
        return Err(format!(
            "it loads {} (not part of every {} system; it may load only {})",
            foreign.join(", "),
            platform.tuple(),
            system_libraries(platform).join(", ")
        ));
    }
    if facts.exports != expected_exports {
        let missing: Vec<&String> = expected_exports
            .iter()
            .filter(|e| !facts.exports.contains(e))
            .collect();
        let extra: Vec<&String> = facts
            .exports
            .iter()
            .filter(|e| !expected_exports.contains(e))
            .collect();
        return Err(format!(
            "its exports differ from this machine's binary: missing {missing:?}, extra {extra:?}"
        ));
    }
    Ok(facts)
}

/// The libraries `facts` loads that are not among `platform`'s system libraries (Windows
/// compares names without case, as its loader does).
pub fn foreign_dependencies(facts: &Facts, platform: Platform) -> Vec<String> {
    facts
        .dependencies
        .iter()
        .filter(|d| {
            !system_libraries(platform)
                .iter()
                .any(|s| s.eq_ignore_ascii_case(d))
        })
        .cloned()
        .collect()
}

/// The libraries a binary of `platform` may depend on: those every installation of the
/// system has (glibc's on Linux; on Windows, DLLs of a stock Windows 10).
fn system_libraries(platform: Platform) -> &'static [&'static str] {
    match platform {
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

#[cfg(test)]
mod tests {
    use super::*;

    /// This test's own executable: an ELF of this machine that loads glibc.
    fn this_executable() -> Vec<u8> {
        std::fs::read(std::env::current_exe().unwrap()).unwrap()
    }

    #[test]
    fn reads_this_machines_binaries() {
        let facts = inspect(&this_executable()).unwrap();
        assert_eq!(facts.platform, Platform::host());
        assert!(
            facts.dependencies.iter().any(|d| d == "libc.so.6"),
            "{facts:?}"
        );
    }

    #[test]
    fn refuses_what_is_not_a_library_or_not_for_the_platform() {
        assert!(inspect(b"not a binary").is_err());
        let err = check(&this_executable(), Platform::X86_64Windows, &[]).unwrap_err();
        assert!(err.contains("not x86_64-windows"), "{err}");
    }

    #[test]
    fn windows_names_compare_without_case() {
        let facts = Facts {
            platform: Some(Platform::X86_64Windows),
            dependencies: vec!["KERNEL32.dll".into(), "libgcc_s_seh-1.dll".into()],
            exports: vec![],
        };
        assert_eq!(
            foreign_dependencies(&facts, Platform::X86_64Windows),
            vec!["libgcc_s_seh-1.dll".to_string()]
        );
    }
}
