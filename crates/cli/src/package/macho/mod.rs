//! The macOS dylibs `mechfmu` links on Linux (`rust-lld` against a libSystem text stub), read
//! and shaped without Apple's tools: what a thin Mach-O file, or each slice of a universal one,
//! is (`read`: CPU, install name, libraries, minimum macOS, exports, imports, and its code
//! signature checked page by page), its install name set in place keeping its ad-hoc
//! signature valid (`set_install_name`), a universal file laid out as `llvm-lipo -create`
//! lays it out (`universal`), and the symbols a `.tbd` stub says a system library exports
//! (`tbd_exports`, to check a dylib's imports against).

mod bytes;
mod fat;
mod load;
mod signature;
mod symbols;
mod tbd;

pub use fat::universal;
pub use tbd::tbd_exports;

use bytes::{be32, le32, span};
use load::{commands, MH_DYLIB, MH_MAGIC_64};

/// The CPU a Mach-O slice is for.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Arch {
    X86_64,
    Arm64,
}

/// The code signature of a slice.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Signature {
    /// No LC_CODE_SIGNATURE.
    Missing,
    /// A CodeDirectory whose every page hash matches (ad-hoc when `adhoc`): its identifier.
    Valid { identifier: String, adhoc: bool },
    /// Present but not valid: why (e.g. "page 5 (bytes 20480..) does not match its hash").
    Invalid(String),
}

/// What one thin Mach-O dylib (or one slice of a universal file) is.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Slice {
    pub arch: Arch,
    /// MH_DYLIB or not.
    pub is_dylib: bool,
    /// LC_ID_DYLIB's name, if any.
    pub install_name: Option<String>,
    /// LC_LOAD_DYLIB / LC_LOAD_WEAK_DYLIB / LC_REEXPORT_DYLIB (and LC_LOAD_UPWARD_DYLIB,
    /// LC_LAZY_LOAD_DYLIB) names, in order.
    pub dependencies: Vec<String>,
    /// LC_RPATH paths (the folders `@rpath` stands for), in order.
    pub rpaths: Vec<String>,
    /// The minimum macOS version (LC_BUILD_VERSION minos for platform macOS, or
    /// LC_VERSION_MIN_MACOSX), as (major, minor, patch).
    pub minimum_macos: Option<(u32, u32, u32)>,
    /// Exported (defined, external) symbol names, without the leading underscore, sorted,
    /// deduplicated: the export trie's (what `dlsym` looks in) less its re-exports, or, with
    /// no trie, the symbol table's defined external symbols.
    pub exports: Vec<String>,
    /// Undefined (imported) symbol names exactly as in the symbol table (with the leading
    /// underscore, e.g. "_malloc", "dyld_stub_binder"), sorted, deduplicated.
    pub imports: Vec<String>,
    pub signature: Signature,
}

const FAT_MAGIC: u32 = 0xcafe_babe;
const FAT_MAGIC_64: u32 = 0xcafe_babf;
const CPU_TYPE_X86_64: u32 = 0x0100_0007;
const CPU_TYPE_ARM64: u32 = 0x0100_000c;

impl Arch {
    fn of_cputype(cputype: u32) -> Result<Arch, String> {
        match cputype {
            CPU_TYPE_X86_64 => Ok(Arch::X86_64),
            CPU_TYPE_ARM64 => Ok(Arch::Arm64),
            other => Err(format!("CPU type {other:#x} is neither x86_64 nor arm64")),
        }
    }

    fn cputype(self) -> u32 {
        match self {
            Arch::X86_64 => CPU_TYPE_X86_64,
            Arch::Arm64 => CPU_TYPE_ARM64,
        }
    }

    /// log2 of the alignment `llvm-lipo` gives a slice of this CPU: its page size.
    fn alignment(self) -> u32 {
        match self {
            Arch::X86_64 => 12,
            Arch::Arm64 => 14,
        }
    }
}

/// Whether `bytes` start like a Mach-O file (thin 64-bit or fat).
pub fn is_macho(bytes: &[u8]) -> bool {
    le32(bytes, 0) == Ok(MH_MAGIC_64)
        || matches!(be32(bytes, 0), Ok(FAT_MAGIC | FAT_MAGIC_64))
            && be32(bytes, 4).is_ok_and(fat::plausible_slice_count)
}

/// Reads a thin Mach-O 64-bit little-endian file (one slice) or a universal (fat,
/// 0xcafebabe) one (each slice). Err names what is wrong (not Mach-O, truncated, a load
/// command out of bounds...).
pub fn read(bytes: &[u8]) -> Result<Vec<Slice>, String> {
    match fat::slices(bytes)? {
        Some(slices) => slices
            .into_iter()
            .enumerate()
            .map(|(i, (arch, s))| read_slice(s).map_err(|e| format!("slice {i} ({arch:?}): {e}")))
            .collect(),
        None => Ok(vec![read_slice(bytes)?]),
    }
}

/// The (major, minor, patch) of a version packed as `xxxx.yy.zz` nibbles.
fn version(v: u32) -> (u32, u32, u32) {
    (v >> 16, (v >> 8) & 0xff, v & 0xff)
}

/// What the thin Mach-O file `m` is.
fn read_slice(m: &[u8]) -> Result<Slice, String> {
    let c = commands(m)?;
    let table = match c.symtab {
        Some([symoff, nsyms, stroff, strsize]) => {
            symbols::table(m, symoff, nsyms, stroff, strsize)?
        }
        None => symbols::Table::default(),
    };
    let mut exports = match c.trie {
        Some((offset, size)) => {
            let trie = span(m, offset as usize, size as usize)?;
            symbols::trie(trie).map_err(|e| format!("the export trie: {e}"))?
        }
        None => table.defined,
    };
    for name in &mut exports {
        if let Some(bare) = name.strip_prefix('_') {
            *name = bare.to_string();
        }
    }
    exports.sort();
    exports.dedup();
    let mut imports = table.undefined;
    imports.sort();
    imports.dedup();
    Ok(Slice {
        arch: c.arch,
        is_dylib: c.filetype == MH_DYLIB,
        install_name: c.id_dylib.map(|(_, _, name)| name),
        dependencies: c.dependencies,
        rpaths: c.rpaths,
        minimum_macos: c.build_minos.or(c.version_min).map(version),
        exports,
        imports,
        signature: match c.signature {
            Some((dataoff, datasize)) => signature::verify(m, dataoff, datasize),
            None => Signature::Missing,
        },
    })
}

/// Sets LC_ID_DYLIB of a thin dylib to `name` in place (the new name, NUL-padded, must fit in
/// the command's existing string space: else Err), then, if it has a code signature,
/// recomputes the hashes of the pages that changed so the signature stays valid (and nothing
/// else changes). Err if not a thin Mach-O dylib or no LC_ID_DYLIB; on Err, `bytes` are
/// unchanged.
pub fn set_install_name(bytes: &mut [u8], name: &str) -> Result<(), String> {
    if name.is_empty() || name.contains('\0') {
        return Err(format!("{name:?} cannot be an install name"));
    }
    let c = commands(bytes)?;
    if c.filetype != MH_DYLIB {
        return Err(format!("not a dylib (Mach-O file type {})", c.filetype));
    }
    let (command, offset, _) = c.id_dylib.ok_or("the dylib has no LC_ID_DYLIB")?;
    let room = command.size - offset;
    if name.len() >= room {
        return Err(format!(
            "the install name {name:?} ({} bytes and a NUL) does not fit in LC_ID_DYLIB's {room}",
            name.len()
        ));
    }
    let start = command.at + offset;
    let mut new = vec![0u8; room];
    new[..name.len()].copy_from_slice(name.as_bytes());
    let old = span(bytes, start, room)?;
    let changed: Vec<usize> = (0..room)
        .filter(|&k| old[k] != new[k])
        .map(|k| start + k)
        .collect();
    let rehash = match c.signature {
        Some((dataoff, datasize)) => signature::plan_refresh(bytes, dataoff, datasize, &changed)?,
        None => Vec::new(),
    };
    bytes[start..start + room].copy_from_slice(&new);
    signature::refresh(bytes, &rehash);
    Ok(())
}

#[cfg(test)]
mod tests;

#[cfg(test)]
pub(crate) mod fixtures;
