//! What a built binary is, read from its bytes (ELF, PE or Mach-O, thin or universal): its
//! machine, the libraries it loads, the functions it exports and imports and, on macOS, its
//! install name, minimum macOS and code signature. `mechfmu build` checks every binary with
//! it before packaging (one that needs a library a stock system lacks, that exports other
//! functions than this machine's binary of the same crate, or, for macOS, that is not
//! loadable as it stands, is never shipped), and `mechfmu inspect` prints it for any FMU.

use super::macho::{self, Arch, Signature};
use crate::build::toolchain::LIBSYSTEM_TBD;
use mechfmu_host::platform::Platform;
use object::{Architecture, BinaryFormat, NameOrOrdinal, Object};

/// What a shared library (or one slice of a universal Mach-O file) is made of, as a loader
/// sees it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Facts {
    /// The platform its format and machine are for, when one of ours.
    pub platform: Option<Platform>,
    /// The libraries it loads, as it names them.
    pub dependencies: Vec<String>,
    /// The functions it exports, sorted.
    pub exports: Vec<String>,
    /// The symbols it imports, as its format names them (Mach-O's with their leading
    /// underscore), sorted.
    pub imports: Vec<String>,
    /// What only a Mach-O file says.
    pub mac: Option<MacFacts>,
}

/// What a macOS loader also reads of a dylib.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MacFacts {
    /// Its install name (`LC_ID_DYLIB`).
    pub install_name: Option<String>,
    /// The folders it searches for libraries (`LC_RPATH`).
    pub rpaths: Vec<String>,
    /// The oldest macOS it loads on, (major, minor, patch).
    pub minimum_macos: Option<(u32, u32, u32)>,
    pub signature: Signature,
}

/// The oldest macOS each Mac binary is built for (rustc's defaults: Apple silicon came with
/// macOS 11; 10.12 Sierra for x86-64), and so the newest one a shipped binary may ask for.
pub fn minimum_macos(platform: Platform) -> (u32, u32, u32) {
    match platform {
        Platform::Aarch64Darwin => (11, 0, 0),
        _ => (10, 12, 0),
    }
}

/// The install name a shipped dylib carries: `@rpath/` and its own file name, so that
/// nothing of the machine that built it is in it.
pub fn install_name(file_name: &str) -> String {
    format!("@rpath/{file_name}")
}

/// What the binary `bytes` is: one [`Facts`] per slice of a universal Mach-O file, else one.
pub fn inspect(bytes: &[u8]) -> Result<Vec<Facts>, String> {
    if macho::is_macho(bytes) {
        return Ok(macho::read(bytes)?.into_iter().map(mac_facts).collect());
    }
    Ok(vec![inspect_object(bytes)?])
}

/// The CPU of each Mac platform.
const MAC_PLATFORMS: [(Arch, Platform); 2] = [
    (Arch::X86_64, Platform::X86_64Darwin),
    (Arch::Arm64, Platform::Aarch64Darwin),
];

fn mac_facts(slice: macho::Slice) -> Facts {
    Facts {
        platform: (MAC_PLATFORMS.iter())
            .find(|(arch, _)| *arch == slice.arch)
            .map(|&(_, platform)| platform)
            .filter(|_| slice.is_dylib),
        dependencies: slice.dependencies,
        exports: slice.exports,
        imports: slice.imports,
        mac: Some(MacFacts {
            install_name: slice.install_name,
            rpaths: slice.rpaths,
            minimum_macos: slice.minimum_macos,
            signature: slice.signature,
        }),
    }
}

/// An ELF or PE file, through `object`.
fn inspect_object(bytes: &[u8]) -> Result<Facts, String> {
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
    let exports = file
        .exports()
        .map_err(|e| format!("cannot read its exports: {e}"))?;
    let exports = sorted_names(exports.map(|e| e.map(|e| named(e.name()))), "its exports")?;
    let imports = file
        .imports()
        .map_err(|e| format!("cannot read its imports: {e}"))?;
    let imports = sorted_names(imports.map(|i| i.map(|i| named(i.name()))), "its imports")?;
    Ok(Facts {
        platform,
        dependencies,
        exports,
        imports,
        mac: None,
    })
}

/// A symbol's name, if it has one (not an ordinal).
fn named(name: NameOrOrdinal<&[u8]>) -> Option<String> {
    match name {
        NameOrOrdinal::Name(name) => Some(String::from_utf8_lossy(name).into_owned()),
        NameOrOrdinal::Ordinal(_) => None,
    }
}

/// The names among `names` (an ordinal has none), sorted and deduplicated; `what` they are,
/// for the error.
fn sorted_names(
    names: impl Iterator<Item = object::Result<Option<String>>>,
    what: &str,
) -> Result<Vec<String>, String> {
    let mut found = Vec::new();
    for name in names {
        found.extend(name.map_err(|e| format!("cannot read {what}: {e}"))?);
    }
    found.sort();
    found.dedup();
    Ok(found)
}

/// Checks a binary built for `platforms` (one, or for a universal Mach-O file both Mac
/// platforms, one slice each) against what an FMU may ship: see [`check_facts`].
pub fn check(
    bytes: &[u8],
    platforms: &[Platform],
    expected_exports: &[String],
) -> Result<Vec<Facts>, String> {
    let all = inspect(bytes)?;
    let found: Vec<Option<Platform>> = all.iter().map(|f| f.platform).collect();
    if found.len() != platforms.len() || platforms.iter().any(|p| !found.contains(&Some(*p))) {
        let names = |p: &[Option<Platform>]| -> String {
            let names: Vec<&str> = p
                .iter()
                .map(|p| p.map_or("unknown", Platform::tuple))
                .collect();
            names.join(" and ")
        };
        let wanted: Vec<Option<Platform>> = platforms.iter().copied().map(Some).collect();
        return Err(format!(
            "built for {}, not {}",
            names(&found),
            names(&wanted)
        ));
    }
    for facts in &all {
        let platform = facts.platform.expect("checked above");
        check_facts(facts, platform, expected_exports).map_err(|e| match all.len() {
            1 => e,
            _ => format!("its {} slice: {e}", platform.tuple()),
        })?;
    }
    Ok(all)
}

/// The checks of one binary (or slice) for `platform`: the right machine, no library beyond
/// the platform's own, exactly the functions of `expected_exports` (those of this machine's
/// binary of the same crate); for macOS also an install name of `@rpath/`, no `LC_RPATH`
/// (a folder of the building machine to load from), a minimum macOS
/// no newer than [`minimum_macos`], every import one the libSystem stub lists, and a valid
/// code signature (required on Apple silicon, which refuses to load unsigned code).
pub fn check_facts(
    facts: &Facts,
    platform: Platform,
    expected_exports: &[String],
) -> Result<(), String> {
    if facts.platform != Some(platform) {
        return Err(format!(
            "built for {:?}, not {}",
            facts.platform.map(Platform::tuple),
            platform.tuple()
        ));
    }
    let foreign = foreign_dependencies(facts, platform);
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
    match &facts.mac {
        Some(mac) => check_mac(facts, mac, platform),
        None => Ok(()),
    }
}

/// The checks only a Mach-O dylib has (see [`check_facts`]).
fn check_mac(facts: &Facts, mac: &MacFacts, platform: Platform) -> Result<(), String> {
    match &mac.install_name {
        Some(name) if name.starts_with("@rpath/") => {}
        other => {
            return Err(format!(
                "its install name is {other:?}, not one of its own (`@rpath/` and its file name)"
            ))
        }
    }
    if !mac.rpaths.is_empty() {
        return Err(format!(
            "it searches {:?} for libraries (LC_RPATH), folders of the machine that built it",
            mac.rpaths
        ));
    }
    let (major, minor, patch) = minimum_macos(platform);
    match mac.minimum_macos {
        Some(v) if v <= (major, minor, patch) => {}
        other => {
            return Err(format!(
                "it asks for macOS {}, newer than {major}.{minor}.{patch}",
                other.map_or("(not stated)".into(), |(a, b, c)| format!("{a}.{b}.{c}"))
            ))
        }
    }
    let (arch, _) = *(MAC_PLATFORMS.iter())
        .find(|(_, p)| *p == platform)
        .expect("a Mac platform");
    let libsystem = macho::tbd_exports(LIBSYSTEM_TBD, arch);
    let unknown: Vec<&String> = (facts.imports.iter())
        .filter(|s| !libsystem.contains(s.as_str()))
        .collect();
    if !unknown.is_empty() {
        return Err(format!(
            "it imports {unknown:?}, which the stub of /usr/lib/libSystem.B.dylib does not list"
        ));
    }
    match (&mac.signature, arch) {
        (Signature::Invalid(why), _) => Err(format!("its code signature is not valid: {why}")),
        (Signature::Missing, Arch::Arm64) => {
            Err("it has no code signature, and Apple silicon refuses to load unsigned code".into())
        }
        _ => Ok(()),
    }
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
        Platform::X86_64Darwin | Platform::Aarch64Darwin => &["/usr/lib/libSystem.B.dylib"],
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
        let [facts] = &inspect(&this_executable()).unwrap()[..] else {
            panic!("one")
        };
        assert_eq!(facts.platform, Platform::host());
        assert!(
            facts.dependencies.iter().any(|d| d == "libc.so.6"),
            "{facts:?}"
        );
    }

    #[test]
    fn refuses_what_is_not_a_library_or_not_for_the_platform() {
        assert!(inspect(b"not a binary").is_err());
        let err = check(&this_executable(), &[Platform::X86_64Windows], &[]).unwrap_err();
        assert!(err.contains("not x86_64-windows"), "{err}");
    }

    /// The tiny arm64 dylib as packaging makes it (its install name set), and what it
    /// exports.
    fn packaged_tiny() -> (Vec<u8>, Vec<String>) {
        let mut bytes = macho::fixtures::ARM64.to_vec();
        macho::set_install_name(&mut bytes, &install_name("libtiny.dylib")).unwrap();
        let [facts] = &inspect(&bytes).unwrap()[..] else {
            panic!("one slice")
        };
        (bytes, facts.exports.clone())
    }

    /// Asserts `check` refuses `bytes` for Apple silicon, saying `why`.
    fn assert_refused(bytes: &[u8], exports: &[String], why: &str) {
        let err = check(bytes, &[Platform::Aarch64Darwin], exports).unwrap_err();
        assert!(err.contains(why), "{err}");
    }

    /// Asserts `check_facts` refuses `facts` for Apple silicon, saying `why`.
    fn assert_facts_refused(facts: &Facts, exports: &[String], why: &str) {
        let err = check_facts(facts, Platform::Aarch64Darwin, exports).unwrap_err();
        assert!(err.contains(why), "{err}");
    }

    #[test]
    fn a_mac_dylib_as_packaged_passes_every_check() {
        let (bytes, exports) = packaged_tiny();
        let [facts] = &check(&bytes, &[Platform::Aarch64Darwin], &exports).unwrap()[..] else {
            panic!("one slice")
        };
        let mac = facts.mac.as_ref().unwrap();
        assert_eq!(mac.install_name.as_deref(), Some("@rpath/libtiny.dylib"));
        assert_eq!(mac.minimum_macos, Some((11, 0, 0)));
        assert!(matches!(
            mac.signature,
            Signature::Valid { adhoc: true, .. }
        ));
        assert_eq!(facts.dependencies, ["/usr/lib/libSystem.B.dylib"]);
        // as the linker wrote it, with the build path as its install name: refused
        assert_refused(
            macho::fixtures::ARM64,
            &exports,
            "its install name is Some(\"/tmp/tiny/",
        );
    }

    #[test]
    fn a_mac_dylib_with_an_export_the_host_binary_lacks_is_refused() {
        let (bytes, exports) = packaged_tiny();
        let fewer: Vec<String> = exports
            .iter()
            .filter(|e| *e != "tiny_alloc")
            .cloned()
            .collect();
        assert_refused(&bytes, &fewer, "extra [\"tiny_alloc\"]");
    }

    #[test]
    fn a_mac_dylib_without_its_signature_is_refused_on_apple_silicon() {
        let (bytes, exports) = packaged_tiny();
        let at = macho::fixtures::command_at(&bytes, 0x1d); // LC_CODE_SIGNATURE
        let unsigned = macho::fixtures::with(&bytes, at, &0x7fff_fff0u32.to_le_bytes());
        assert_refused(
            &unsigned,
            &exports,
            "no code signature, and Apple silicon refuses",
        );
        let mut tampered = bytes.clone();
        tampered[5000] ^= 1;
        assert_refused(
            &tampered,
            &exports,
            "its code signature is not valid: page 1",
        );
    }

    #[test]
    fn a_mac_dylib_loading_another_library_is_refused() {
        let (bytes, exports) = packaged_tiny();
        let at = macho::fixtures::command_at(&bytes, 0xc) + 24; // LC_LOAD_DYLIB's name
        let other = macho::fixtures::with(&bytes, at, b"/usr/lib/libz.1.2.11.dylib");
        assert_refused(
            &other,
            &exports,
            "it loads /usr/lib/libz.1.2.11.dylib (not part of every aarch64-darwin",
        );
    }

    #[test]
    fn a_mac_dylib_importing_what_libsystem_lacks_or_asking_too_much_is_refused() {
        let (bytes, exports) = packaged_tiny();
        let [facts] = &inspect(&bytes).unwrap()[..] else {
            panic!("one slice")
        };
        let mut facts = facts.clone();
        facts.imports.push("_not_in_libsystem".into());
        assert_facts_refused(&facts, &exports, "it imports [\"_not_in_libsystem\"]");
        facts.imports.pop();
        let mac = facts.mac.as_mut().unwrap();
        assert_eq!(mac.rpaths, Vec::<String>::new());
        mac.rpaths.push("/tmp/tiny/target/release/deps".into());
        assert_facts_refused(
            &facts,
            &exports,
            "it searches [\"/tmp/tiny/target/release/deps\"] for libraries",
        );
        let mac = facts.mac.as_mut().unwrap();
        mac.rpaths.clear();
        mac.minimum_macos = Some((12, 0, 0));
        assert_facts_refused(
            &facts,
            &exports,
            "it asks for macOS 12.0.0, newer than 11.0.0",
        );
    }

    #[test]
    fn a_universal_file_is_checked_slice_by_slice() {
        let (arm64, exports) = packaged_tiny();
        let mut x86_64 = macho::fixtures::X86_64.to_vec();
        macho::set_install_name(&mut x86_64, &install_name("libtiny.dylib")).unwrap();
        let both = [Platform::X86_64Darwin, Platform::Aarch64Darwin];
        let universal = macho::universal(&[&x86_64, &arm64]).unwrap();
        assert_eq!(check(&universal, &both, &exports).unwrap().len(), 2);
        let err = check(&arm64, &both, &exports).unwrap_err();
        assert!(
            err.contains("built for aarch64-darwin, not x86_64-darwin and aarch64-darwin"),
            "{err}"
        );
        let mut tampered = universal.clone();
        let last = tampered.len() - arm64.len() + 5000;
        tampered[last] ^= 1;
        let err = check(&tampered, &both, &exports).unwrap_err();
        assert!(
            err.starts_with("its aarch64-darwin slice: its code signature is not valid"),
            "{err}"
        );
    }

    #[test]
    fn windows_names_compare_without_case() {
        let facts = Facts {
            platform: Some(Platform::X86_64Windows),
            dependencies: vec!["KERNEL32.dll".into(), "libgcc_s_seh-1.dll".into()],
            exports: vec![],
            imports: vec![],
            mac: None,
        };
        assert_eq!(
            foreign_dependencies(&facts, Platform::X86_64Windows),
            vec!["libgcc_s_seh-1.dll".to_string()]
        );
    }
}
