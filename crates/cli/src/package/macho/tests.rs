//! The reader, the install-name setter and the universal writer on the tiny dylibs of
//! `tests/data/macho` (its README says how they were built), whole and doctored.

use super::fixtures::{command_at, with, ARM64, STUB, X86_64};
use super::load::{HEADER, LC_CODE_SIGNATURE, LC_ID_DYLIB, LC_LOAD_DYLIB};
use super::*;
use sha2::{Digest, Sha256};

/// SHA-256 of `llvm-lipo-14 -create libtiny-arm64.dylib libtiny-x86_64.dylib` (66352 bytes).
const LIPO_SHA256: &str = "74e1abb88ba6e76fddc77c47659c1a0eb2c548835980f12a3f244f198ed24a4c";
/// SHA-256 of what the prototype `set_install_name.py <fixture> out @rpath/Tiny.dylib` wrote.
const RPATH_ARM64_SHA256: &str = "28cd49b5ae2262556b9b67bbab4985ed9cd2c2f7ac6a3de62fc268775dc7ab2c";
const RPATH_X86_64_SHA256: &str =
    "557f336412b5f8c08d05aa1cfc117da70008084e7a190726cea57a105c981ddb";
/// The build path rustc gave the arm64 fixture as its install name.
const ARM64_NAME: &str = "/tmp/tiny/target/aarch64-apple-darwin/release/deps/libtiny.dylib";
const LIBSYSTEM: &str = "/usr/lib/libSystem.B.dylib";

fn sha256(bytes: &[u8]) -> String {
    Sha256::digest(bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

fn one(bytes: &[u8]) -> Slice {
    let mut slices = read(bytes).unwrap();
    assert_eq!(slices.len(), 1);
    slices.remove(0)
}

fn tiny_exports() -> Vec<String> {
    ["tiny_add", "tiny_alloc", "tiny_version"]
        .map(String::from)
        .to_vec()
}

#[test]
fn the_arm64_fixture_is_a_signed_dylib_for_macos_11() {
    let s = one(ARM64);
    assert_eq!(s.arch, Arch::Arm64);
    assert!(s.is_dylib);
    assert_eq!(s.install_name.as_deref(), Some(ARM64_NAME));
    assert_eq!(s.dependencies, [LIBSYSTEM]);
    assert_eq!(s.minimum_macos, Some((11, 0, 0)));
    assert_eq!(s.exports, tiny_exports());
    assert_eq!(s.imports, ["_malloc", "dyld_stub_binder"]);
    assert_eq!(
        s.signature,
        Signature::Valid {
            identifier: "libtiny.dylib".into(),
            adhoc: true
        }
    );
}

#[test]
fn the_x86_64_fixture_is_an_unsigned_dylib_for_macos_10_12() {
    let s = one(X86_64);
    assert_eq!(s.arch, Arch::X86_64);
    assert!(s.is_dylib);
    assert_eq!(
        s.install_name.as_deref(),
        Some("/tmp/tiny/target/x86_64-apple-darwin/release/deps/libtiny.dylib")
    );
    assert_eq!(s.dependencies, [LIBSYSTEM]);
    assert_eq!(s.minimum_macos, Some((10, 12, 0)));
    assert_eq!(s.exports, tiny_exports());
    assert_eq!(s.imports, ["_malloc", "dyld_stub_binder"]);
    assert_eq!(s.signature, Signature::Missing);
}

#[test]
fn the_imports_are_what_the_libsystem_stub_exports() {
    for (m, arch) in [(ARM64, Arch::Arm64), (X86_64, Arch::X86_64)] {
        let stub = tbd_exports(STUB, arch);
        // The runtime's symbols, and the C math library's 118.
        assert_eq!(stub.len(), 60 + 118, "{arch:?}");
        assert!(stub.contains("___sincos_stret") && stub.contains("_atan2"));
        for import in one(m).imports {
            assert!(stub.contains(&import), "{arch:?}: {import}");
        }
    }
    assert!(tbd_exports(STUB, Arch::Arm64).contains("_opendir"));
    assert!(!tbd_exports(STUB, Arch::Arm64).contains("_opendir$INODE64"));
    assert!(tbd_exports(STUB, Arch::X86_64).contains("_opendir$INODE64"));
}

#[test]
fn the_export_trie_and_the_symbol_table_agree() {
    for m in [ARM64, X86_64] {
        let c = commands(m).unwrap();
        let [symoff, nsyms, stroff, strsize] = c.symtab.unwrap();
        let mut table = symbols::table(m, symoff, nsyms, stroff, strsize)
            .unwrap()
            .defined;
        let (offset, size) = c.trie.unwrap();
        let trie = &m[offset as usize..][..size as usize];
        let mut names = symbols::trie(trie).unwrap();
        table.sort();
        names.sort();
        assert_eq!(names, ["_tiny_add", "_tiny_alloc", "_tiny_version"]);
        assert_eq!(table, names);
    }
}

#[test]
fn a_byte_changed_in_a_signed_page_names_the_page() {
    // The first instruction of tiny_add (nm: 0x4d8; __TEXT starts the file).
    let code = with(ARM64, 0x4d8, &[ARM64[0x4d8] ^ 1]);
    assert_eq!(
        one(&code).signature,
        Signature::Invalid("page 0 (bytes 0..) does not match its hash".into())
    );
    let padding = with(ARM64, 20480, &[1]);
    assert_eq!(
        one(&padding).signature,
        Signature::Invalid("page 5 (bytes 20480..) does not match its hash".into())
    );
}

#[test]
fn a_signature_command_made_unknown_is_missing_a_zeroed_blob_invalid() {
    let at = command_at(ARM64, LC_CODE_SIGNATURE);
    let unknown = with(ARM64, at, &0x7fff_fff0u32.to_le_bytes());
    assert_eq!(one(&unknown).signature, Signature::Missing);
    let dataoff = le32(ARM64, at + 8).unwrap() as usize;
    let zeroed = with(ARM64, dataoff, &[0; 4]);
    match one(&zeroed).signature {
        Signature::Invalid(why) => assert!(why.contains("magic is 0x00000000"), "{why}"),
        other => panic!("{other:?}"),
    }
    // The flags of the CodeDirectory are not in a page: no longer ad hoc, still valid.
    let flags = dataoff + 24 + 12;
    assert_eq!(be32(ARM64, flags), Ok(0x20002));
    let certified = with(ARM64, flags, &0x20000u32.to_be_bytes());
    assert_eq!(
        one(&certified).signature,
        Signature::Valid {
            identifier: "libtiny.dylib".into(),
            adhoc: false
        }
    );
    let mut copy = certified.clone();
    assert!(set_install_name(&mut copy, "@rpath/Tiny.dylib")
        .unwrap_err()
        .contains("not ad hoc"));
    assert_eq!(copy, certified);
}

#[test]
fn a_dependency_renamed_shows_and_breaks_the_signature() {
    let other = "/usr/lib/libz.1.2.11.dylib";
    assert_eq!(other.len(), LIBSYSTEM.len());
    for m in [ARM64, X86_64] {
        let at = command_at(m, LC_LOAD_DYLIB) + 24;
        assert_eq!(&m[at..at + LIBSYSTEM.len()], LIBSYSTEM.as_bytes());
        let s = one(&with(m, at, other.as_bytes()));
        assert_eq!(s.dependencies, [other]);
        let expected = match s.arch {
            Arch::Arm64 => Signature::Invalid("page 0 (bytes 0..) does not match its hash".into()),
            Arch::X86_64 => Signature::Missing,
        };
        assert_eq!(s.signature, expected);
    }
}

#[test]
fn the_install_name_is_set_and_the_signature_stays_valid() {
    let mut m = ARM64.to_vec();
    set_install_name(&mut m, "@rpath/Tiny.dylib").unwrap();
    let s = one(&m);
    assert_eq!(s.install_name.as_deref(), Some("@rpath/Tiny.dylib"));
    assert_eq!(
        s,
        Slice {
            install_name: s.install_name.clone(),
            ..one(ARM64)
        }
    );
    // Only the name's bytes (page 0) and the hash of page 0 changed.
    let dataoff = le32(ARM64, command_at(ARM64, LC_CODE_SIGNATURE) + 8).unwrap() as usize;
    let cd = dataoff + be32(ARM64, dataoff + 16).unwrap() as usize;
    let hash0 = cd + be32(ARM64, cd + 16).unwrap() as usize;
    let id = command_at(ARM64, LC_ID_DYLIB);
    for (k, (a, b)) in ARM64.iter().zip(&m).enumerate() {
        if a != b {
            assert!(
                (id + 24..id + 96).contains(&k) || (hash0..hash0 + 32).contains(&k),
                "{k}"
            );
        }
    }
    assert_eq!(sha256(&m), RPATH_ARM64_SHA256);

    let mut m = X86_64.to_vec();
    set_install_name(&mut m, "@rpath/Tiny.dylib").unwrap();
    let s = one(&m);
    assert_eq!(s.install_name.as_deref(), Some("@rpath/Tiny.dylib"));
    assert_eq!(s.signature, Signature::Missing);
    assert_eq!(sha256(&m), RPATH_X86_64_SHA256);
}

#[test]
fn an_install_name_too_long_or_where_there_is_none_is_refused() {
    // LC_ID_DYLIB has 96 bytes, the name 72 of them: 71 and a NUL fit.
    let fits = format!("@rpath/{}", "x".repeat(71 - 7));
    let mut m = ARM64.to_vec();
    set_install_name(&mut m, &fits).unwrap();
    assert_eq!(one(&m).install_name, Some(fits.clone()));
    assert!(matches!(one(&m).signature, Signature::Valid { .. }));
    let too_long = format!("{fits}x");
    let mut m = ARM64.to_vec();
    let err = set_install_name(&mut m, &too_long).unwrap_err();
    assert!(err.contains("does not fit"), "{err}");
    assert_eq!(m, ARM64);
    assert!(set_install_name(&mut m, "a\0b").is_err());
    assert!(set_install_name(&mut m, "").is_err());
    assert_eq!(m, ARM64);

    let mut no_id = with(
        ARM64,
        command_at(ARM64, LC_ID_DYLIB),
        &0x7fff_fff0u32.to_le_bytes(),
    );
    let before = no_id.clone();
    assert!(set_install_name(&mut no_id, "@rpath/Tiny.dylib")
        .unwrap_err()
        .contains("no LC_ID_DYLIB"));
    assert_eq!(no_id, before);
    let mut executable = with(ARM64, 12, &2u32.to_le_bytes());
    assert!(!one(&executable).is_dylib);
    assert!(set_install_name(&mut executable, "@rpath/Tiny.dylib")
        .unwrap_err()
        .contains("not a dylib"));
    let mut fat = universal(&[ARM64, X86_64]).unwrap();
    assert!(set_install_name(&mut fat, "@rpath/Tiny.dylib")
        .unwrap_err()
        .contains("universal"));
}

#[test]
fn the_universal_file_is_lipos_and_reads_as_its_slices() {
    let fat = universal(&[ARM64, X86_64]).unwrap();
    assert_eq!(fat.len(), 66352);
    assert_eq!(sha256(&fat), LIPO_SHA256);
    assert_eq!(universal(&[X86_64, ARM64]).unwrap(), fat);
    assert!(is_macho(&fat));
    assert_eq!(read(&fat).unwrap(), [one(X86_64), one(ARM64)]);

    assert!(universal(&[ARM64, ARM64])
        .unwrap_err()
        .contains("two Arm64"));
    assert!(universal(&[]).is_err());
    assert!(universal(&[ARM64, b"#!/bin/sh\n"])
        .unwrap_err()
        .contains("slice 1"));
    assert!(universal(&[&fat]).unwrap_err().contains("universal"));
    let thin_x86 = universal(&[X86_64]).unwrap();
    assert_eq!(read(&thin_x86).unwrap(), [one(X86_64)]);

    let cut = &fat[..fat.len() - 1];
    assert!(read(cut).unwrap_err().starts_with("slice 1 (Arm64)"));
    let mislabelled = with(&fat, 8, &0x0100_000cu32.to_be_bytes());
    assert!(read(&mislabelled).unwrap_err().contains("CPU type"));
}

#[test]
fn a_universal_file_with_64_bit_offsets_reads_too() {
    // fat_header {0xcafebabf, 2}, then fat_arch_64 {cputype, cpusubtype, offset u64,
    // size u64, align, reserved} per slice, the slices where `universal` puts them.
    let fat = universal(&[ARM64, X86_64]).unwrap();
    let mut wide = fat.clone();
    wide[..8 + 2 * 32].fill(0);
    wide[..8].copy_from_slice(&[0xca, 0xfe, 0xba, 0xbf, 0, 0, 0, 2]);
    for k in 0..2 {
        let (narrow, at) = (8 + 20 * k, 8 + 32 * k);
        let field = |i: usize| be32(&fat, narrow + 4 * i).unwrap();
        wide[at..at + 8].copy_from_slice(&fat[narrow..narrow + 8]);
        wide[at + 8..at + 16].copy_from_slice(&u64::from(field(2)).to_be_bytes());
        wide[at + 16..at + 24].copy_from_slice(&u64::from(field(3)).to_be_bytes());
        wide[at + 24..at + 28].copy_from_slice(&field(4).to_be_bytes());
    }
    assert!(is_macho(&wide));
    assert_eq!(read(&wide).unwrap(), read(&fat).unwrap());
}

#[test]
fn what_is_not_a_macho_file_is_told() {
    assert!(is_macho(ARM64) && is_macho(X86_64));
    assert!(!is_macho(b""));
    assert!(!is_macho(b"\x7fELF\x02\x01\x01\0"));
    // A Java class file (version 52) starts with 0xcafebabe too.
    assert!(!is_macho(b"\xca\xfe\xba\xbe\0\0\0\x34"));
    assert!(read(b"").unwrap_err().contains("not a Mach-O"));
    assert!(read(b"\x7fELF\x02\x01\x01\0")
        .unwrap_err()
        .contains("not a Mach-O"));
    assert!(read(b"\xca\xfe\xba\xbe\0\0\0\x34").is_err());
    assert!(read(&with(ARM64, 0, b"\xce\xfa\xed\xfe"))
        .unwrap_err()
        .contains("32-bit"));
    assert!(read(&with(ARM64, 0, b"\xfe\xed\xfa\xcf"))
        .unwrap_err()
        .contains("big-endian"));
    assert!(read(&with(ARM64, 4, &7u32.to_le_bytes()))
        .unwrap_err()
        .contains("CPU type 0x7"));
    assert!(read(&ARM64[..31]).unwrap_err().contains("truncated"));
    let sizeofcmds = with(ARM64, 20, &u32::MAX.to_le_bytes());
    assert!(read(&sizeofcmds).unwrap_err().contains("run past the end"));
    let cmdsize = with(ARM64, HEADER + 4, &12u32.to_le_bytes());
    assert!(read(&cmdsize).unwrap_err().contains("load command #0"));
}

#[test]
fn a_stub_gives_the_symbols_of_its_items_for_the_arch() {
    let stub = "--- !tapi-tbd
tbd-version:     4
targets:         [ x86_64-macos, arm64e-macos ]
install-name:    '/usr/lib/libSystem.B.dylib'
exports:
  - targets:         [ x86_64-macos, arm64e-macos ]
    symbols:         [ _a, '_b', \"_c\",
                       '_d$INODE64', 'it''s' ]
    objc-classes:    [ OS_x ]
  - targets:         [ x86_64-macos ]
    weak-symbols:    [ _x86_only ]
undefineds:
  - targets:         [ x86_64-macos, arm64e-macos ]
    symbols:         [ _undefined ]
...
--- !tapi-tbd
tbd-version:     4
targets: [ x86_64-macos, arm64-macos, arm64e-maccatalyst ]
install-name:    '/usr/lib/system/libsub.dylib'
reexported-libraries:
  - targets: [ x86_64-macos, arm64-macos ]
    libraries: [ '/usr/lib/system/libother.dylib' ]
exports:
- targets: [ arm64e-maccatalyst ]
  symbols: [ _catalyst_only ]
- targets: [ arm64-macos
           ]
  thread-local-symbols: [ _tls ]
reexports:
  - targets: [ x86_64-macos, arm64-macos ]
    symbols: [ _memcpy ]
...
";
    let names = |arch| tbd_exports(stub, arch).into_iter().collect::<Vec<_>>();
    // The names both architectures export and the one only this architecture does, sorted.
    let expected = |only_this_arch| {
        let mut names = vec![
            "_OBJC_CLASS_$_OS_x",
            "_OBJC_METACLASS_$_OS_x",
            "_a",
            "_b",
            "_c",
            "_d$INODE64",
            "_memcpy",
            "it's",
            only_this_arch,
        ];
        names.sort_unstable();
        names
    };
    assert_eq!(names(Arch::Arm64), expected("_tls"));
    assert_eq!(names(Arch::X86_64), expected("_x86_only"));
}

/// A xorshift generator: the same bytes flipped on every run.
struct Random(u64);

impl Random {
    fn below(&mut self, n: usize) -> usize {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 % n as u64) as usize
    }
}

/// Reads, renames and wraps `m` without looking at the outcome: only that nothing panics.
fn exercise(m: &[u8]) {
    let _ = read(m);
    let _ = is_macho(m);
    let _ = universal(&[m]);
    let mut copy = m.to_vec();
    if set_install_name(&mut copy, "@rpath/Tiny.dylib").is_ok() {
        let _ = read(&copy);
    }
}

#[test]
fn no_truncation_or_flipped_bit_makes_it_panic() {
    let fat = universal(&[ARM64, X86_64]).unwrap();
    let mut random = Random(0x9e37_79b9_7f4a_7c15);
    for m in [ARM64, X86_64, &fat] {
        for n in (0..m.len()).step_by(97) {
            exercise(&m[..n]);
            assert!(read(&m[..n]).map_or(true, |s| s != read(m).unwrap()));
        }
        for round in 0..400 {
            let mut doctored = m.to_vec();
            for _ in 0..1 + random.below(4) {
                // Half the flips in the headers and load commands, half anywhere.
                let at = random.below(if round % 2 == 0 { 4096 } else { m.len() });
                doctored[at] ^= 1 << random.below(8);
            }
            exercise(&doctored);
        }
    }
}
