//! The load commands of a thin Mach-O file that say what it is, each checked to lie inside
//! the file: its install name, libraries, minimum macOS, where its export trie, symbol table
//! and code signature are.

use super::bytes::{be32, cstr, le32, span};
use super::{symbols, Arch, FAT_MAGIC, FAT_MAGIC_64};

pub(super) const MH_MAGIC_64: u32 = 0xfeed_facf;
pub(super) const MH_DYLIB: u32 = 6;
/// sizeof(mach_header_64).
pub(super) const HEADER: usize = 32;

const LC_SYMTAB: u32 = 0x2;
pub(super) const LC_LOAD_DYLIB: u32 = 0xc;
pub(super) const LC_ID_DYLIB: u32 = 0xd;
pub(super) const LC_CODE_SIGNATURE: u32 = 0x1d;
const LC_LAZY_LOAD_DYLIB: u32 = 0x20;
const LC_DYLD_INFO: u32 = 0x22;
const LC_VERSION_MIN_MACOSX: u32 = 0x24;
const LC_BUILD_VERSION: u32 = 0x32;
const LC_LOAD_WEAK_DYLIB: u32 = 0x8000_0018;
const LC_RPATH: u32 = 0x8000_001c;
const LC_REEXPORT_DYLIB: u32 = 0x8000_001f;
const LC_DYLD_INFO_ONLY: u32 = 0x8000_0022;
const LC_LOAD_UPWARD_DYLIB: u32 = 0x8000_0023;
const LC_DYLD_EXPORTS_TRIE: u32 = 0x8000_0033;
const PLATFORM_MACOS: u32 = 1;

/// A load command: its `cmd` and where its bytes are in the file.
#[derive(Clone, Copy)]
pub(super) struct Command {
    pub(super) cmd: u32,
    pub(super) at: usize,
    pub(super) size: usize,
}

/// The load commands of a thin file that matter here, each checked to lie inside the file.
pub(super) struct Commands {
    pub(super) arch: Arch,
    pub(super) filetype: u32,
    /// LC_ID_DYLIB: the command, and its name's offset from the command's start.
    pub(super) id_dylib: Option<(Command, usize, String)>,
    pub(super) dependencies: Vec<String>,
    /// LC_RPATH: the folders `@rpath` stands for.
    pub(super) rpaths: Vec<String>,
    pub(super) build_minos: Option<u32>,
    pub(super) version_min: Option<u32>,
    /// Where the export trie is: offset and size.
    pub(super) trie: Option<(u32, u32)>,
    /// LC_SYMTAB: symoff, nsyms, stroff, strsize.
    pub(super) symtab: Option<[u32; 4]>,
    /// LC_CODE_SIGNATURE: dataoff, datasize.
    pub(super) signature: Option<(u32, u32)>,
}

/// The load commands of the thin 64-bit little-endian Mach-O file `m`.
pub(super) fn commands(m: &[u8]) -> Result<Commands, String> {
    match (le32(m, 0), be32(m, 0)) {
        (Ok(MH_MAGIC_64), _) => {}
        (_, Ok(FAT_MAGIC | FAT_MAGIC_64)) => {
            return Err("a universal (fat) file, not a thin one".into())
        }
        (Ok(0xfeed_face), _) => {
            return Err("a 32-bit Mach-O file: only 64-bit ones are read".into())
        }
        (_, Ok(0xfeed_face | MH_MAGIC_64)) => {
            return Err("a big-endian Mach-O file: only little-endian ones are read".into())
        }
        (Ok(magic), _) => return Err(format!("not a Mach-O file (magic {magic:#010x})")),
        (Err(_), _) => return Err(format!("not a Mach-O file ({} bytes)", m.len())),
    }
    let header = span(m, 0, HEADER)
        .map_err(|_| format!("truncated: {} bytes, less than a Mach-O header", m.len()))?;
    let mut c = Commands {
        arch: Arch::of_cputype(le32(header, 4)?)?,
        filetype: le32(header, 12)?,
        id_dylib: None,
        dependencies: Vec::new(),
        rpaths: Vec::new(),
        build_minos: None,
        version_min: None,
        trie: None,
        symtab: None,
        signature: None,
    };
    let ncmds = le32(header, 16)?;
    let sizeofcmds = le32(header, 20)? as usize;
    let end = HEADER + sizeofcmds;
    span(m, 0, end).map_err(|_| {
        format!(
            "the load commands ({sizeofcmds} bytes) run past the end of the file ({} bytes)",
            m.len()
        )
    })?;
    let mut at = HEADER;
    for i in 0..ncmds {
        let (cmd, size) = match (le32(m, at), le32(m, at + 4)) {
            (Ok(cmd), Ok(size)) if at + 8 <= end => (cmd, size as usize),
            _ => {
                return Err(format!(
                    "load command #{i} at byte {at}: past the {ncmds} commands' {sizeofcmds} bytes"
                ))
            }
        };
        if size < 8 || size % 8 != 0 || size > end - at {
            return Err(format!(
                "load command #{i} ({cmd:#x}) at byte {at}: size {size} is not a multiple of 8 inside the load commands"
            ));
        }
        let command = Command { cmd, at, size };
        c.take(m, command)
            .map_err(|e| format!("load command #{i} ({cmd:#x}) at byte {at}: {e}"))?;
        at += size;
    }
    Ok(c)
}

impl Commands {
    /// Notes what `command` of file `m` says, if it matters here.
    fn take(&mut self, m: &[u8], command: Command) -> Result<(), String> {
        let body = span(m, command.at, command.size)?;
        let once = |taken: bool, name: &str| {
            if taken {
                Err(format!("a second {name}"))
            } else {
                Ok(())
            }
        };
        match command.cmd {
            LC_ID_DYLIB => {
                once(self.id_dylib.is_some(), "LC_ID_DYLIB")?;
                let (offset, name) = dylib_name(body)?;
                self.id_dylib = Some((command, offset, name.to_string()));
            }
            LC_LOAD_DYLIB | LC_LOAD_WEAK_DYLIB | LC_REEXPORT_DYLIB | LC_LOAD_UPWARD_DYLIB
            | LC_LAZY_LOAD_DYLIB => self.dependencies.push(dylib_name(body)?.1.to_string()),
            LC_RPATH => {
                // {cmd, cmdsize, path.offset} then the string
                let offset = le32(body, 8)? as usize;
                if offset < 12 || offset >= body.len() {
                    return Err(format!(
                        "the path's offset {offset} is not inside the command"
                    ));
                }
                self.rpaths.push(cstr(body, offset)?.to_string());
            }
            LC_BUILD_VERSION if le32(body, 8)? == PLATFORM_MACOS => {
                self.build_minos = Some(le32(body, 12)?);
            }
            LC_VERSION_MIN_MACOSX => self.version_min = Some(le32(body, 8)?),
            LC_DYLD_INFO | LC_DYLD_INFO_ONLY | LC_DYLD_EXPORTS_TRIE => {
                once(self.trie.is_some(), "export trie")?;
                let (offset, size) = if command.cmd == LC_DYLD_EXPORTS_TRIE {
                    (le32(body, 8)?, le32(body, 12)?)
                } else {
                    (le32(body, 40)?, le32(body, 44)?)
                };
                span(m, offset as usize, size as usize)
                    .map_err(|e| format!("the export trie: {e}"))?;
                self.trie = Some((offset, size));
            }
            LC_SYMTAB => {
                once(self.symtab.is_some(), "LC_SYMTAB")?;
                let s = [
                    le32(body, 8)?,
                    le32(body, 12)?,
                    le32(body, 16)?,
                    le32(body, 20)?,
                ];
                span(m, s[0] as usize, s[1] as usize * symbols::NLIST)
                    .map_err(|e| format!("the symbol table: {e}"))?;
                span(m, s[2] as usize, s[3] as usize)
                    .map_err(|e| format!("the string table: {e}"))?;
                self.symtab = Some(s);
            }
            LC_CODE_SIGNATURE => {
                once(self.signature.is_some(), "LC_CODE_SIGNATURE")?;
                self.signature = Some((le32(body, 8)?, le32(body, 12)?));
            }
            _ => {}
        }
        Ok(())
    }
}

/// A dylib_command's name (`{cmd, cmdsize, name.offset, timestamp, current_version,
/// compatibility_version}` then the string) and its offset in the command.
fn dylib_name(body: &[u8]) -> Result<(usize, &str), String> {
    let offset = le32(body, 8)? as usize;
    if offset < 24 || offset >= body.len() {
        return Err(format!(
            "the name's offset {offset} is not inside the command"
        ));
    }
    Ok((offset, cstr(body, offset)?))
}
