//! A dylib's symbols: those its export trie names (what `dyld` and `dlsym` look in), and its
//! symbol table's defined external and undefined ones.

use super::bytes::{cstr, le32, span};

/// sizeof(nlist_64): `n_strx u32, n_type u8, n_sect u8, n_desc u16, n_value u64`.
pub(super) const NLIST: usize = 16;
const N_STAB: u8 = 0xe0;
const N_PEXT: u8 = 0x10;
const N_TYPE: u8 = 0x0e;
const N_EXT: u8 = 0x01;
const N_UNDF: u8 = 0x0;
const N_ABS: u8 = 0x2;
const N_SECT: u8 = 0xe;

const EXPORT_SYMBOL_FLAGS_REEXPORT: u64 = 0x08;
/// At most this many bytes of names from one trie: a few nodes chained with one-letter
/// edges, each a symbol, would otherwise name O(n²) bytes.
const MAX_NAMES: usize = 64 << 20;

/// The external symbols of a symbol table, names as written (with their underscore).
#[derive(Default)]
pub(super) struct Table {
    /// Defined in a section or absolute, external and not private.
    pub(super) defined: Vec<String>,
    /// Undefined and external: the imports (common symbols, undefined with a size, left out).
    pub(super) undefined: Vec<String>,
}

/// The symbol table of file `m` that LC_SYMTAB places (`nsyms` nlist_64 at `symoff`, their
/// names in the `strsize` bytes at `stroff`).
pub(super) fn table(
    m: &[u8],
    symoff: u32,
    nsyms: u32,
    stroff: u32,
    strsize: u32,
) -> Result<Table, String> {
    let symbols = span(m, symoff as usize, nsyms as usize * NLIST)
        .map_err(|e| format!("the symbol table: {e}"))?;
    let strings =
        span(m, stroff as usize, strsize as usize).map_err(|e| format!("the string table: {e}"))?;
    let mut table = Table::default();
    for (i, nlist) in symbols.chunks_exact(NLIST).enumerate() {
        let n_type = nlist[4];
        if n_type & N_STAB != 0 || n_type & N_EXT == 0 {
            continue;
        }
        let name = || {
            let strx = le32(nlist, 0)? as usize;
            cstr(strings, strx)
                .map(String::from)
                .map_err(|e| format!("symbol {i}'s name: {e}"))
        };
        match n_type & N_TYPE {
            N_UNDF if nlist[8..].iter().all(|&b| b == 0) => table.undefined.push(name()?),
            N_SECT | N_ABS if n_type & N_PEXT == 0 => table.defined.push(name()?),
            _ => {}
        }
    }
    Ok(table)
}

/// The names of the symbols the export trie `trie` says the image defines (re-exports of
/// other libraries' symbols left out), as written (with their underscore), in no order.
pub(super) fn trie(trie: &[u8]) -> Result<Vec<String>, String> {
    let mut names = Vec::new();
    if trie.is_empty() {
        return Ok(names);
    }
    let mut seen = vec![false; trie.len()];
    let mut total = 0usize;
    let mut stack: Vec<(usize, Vec<u8>)> = vec![(0, Vec::new())];
    while let Some((node, name)) = stack.pop() {
        if std::mem::replace(&mut seen[node], true) {
            return Err(format!("node {node} is reached twice"));
        }
        let mut at = node;
        let terminal = uleb(trie, &mut at)? as usize;
        let children = at
            .checked_add(terminal)
            .filter(|&end| end < trie.len())
            .ok_or_else(|| format!("node {node}'s export info runs past the trie"))?;
        if terminal > 0 && uleb(trie, &mut at)? & EXPORT_SYMBOL_FLAGS_REEXPORT == 0 {
            total += name.len();
            if total > MAX_NAMES {
                return Err(format!("more than {MAX_NAMES} bytes of names"));
            }
            let name = String::from_utf8(name.clone())
                .map_err(|_| format!("the name at node {node} is not UTF-8"))?;
            names.push(name);
        }
        at = children;
        let count = trie[at];
        at += 1;
        for _ in 0..count {
            let rest = trie.get(at..).unwrap_or_default();
            let len = rest
                .iter()
                .position(|&c| c == 0)
                .ok_or_else(|| format!("an edge of node {node} has no terminating NUL"))?;
            let mut child_name = name.clone();
            child_name.extend_from_slice(&rest[..len]);
            at += len + 1;
            let child = uleb(trie, &mut at)? as usize;
            if child >= trie.len() {
                return Err(format!("node {node} has a child at {child}, past the trie"));
            }
            stack.push((child, child_name));
        }
    }
    Ok(names)
}

/// The ULEB128 number at `*at`, moving `*at` past it.
fn uleb(b: &[u8], at: &mut usize) -> Result<u64, String> {
    let start = *at;
    let mut value = 0u64;
    for shift in (0..64).step_by(7) {
        let byte = *b
            .get(*at)
            .ok_or_else(|| format!("the number at byte {start} runs past the end"))?;
        *at += 1;
        value |= u64::from(byte & 0x7f) << shift;
        if byte & 0x80 == 0 {
            return Ok(value);
        }
    }
    Err(format!("the number at byte {start} is longer than 64 bits"))
}
