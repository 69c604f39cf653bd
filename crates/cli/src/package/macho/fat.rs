//! Universal (fat) files: the thin slices of one, and one of thin files laid out as
//! `llvm-lipo -create` lays it out.

use super::bytes::{be32, be64, le32, span};
use super::load::commands;
use super::{Arch, FAT_MAGIC, FAT_MAGIC_64};

/// The capability bits of a cpusubtype (`CPU_SUBTYPE_MASK`), which a fat_arch leaves out.
const CPU_SUBTYPE_MASK: u32 = 0xff00_0000;

/// Whether a fat header's slice count is one: a Java class file starts with 0xcafebabe too,
/// then its version, which reads as 45 or more.
pub(super) fn plausible_slice_count(n: u32) -> bool {
    (1..45).contains(&n)
}

/// A slice of a universal file: its CPU and bytes.
type ThinSlice<'a> = (Arch, &'a [u8]);

/// The slices of a universal file, each checked to be inside it, to be for the CPU the fat
/// header says and for no other slice's; `None` for a file without a fat header.
pub(super) fn slices(bytes: &[u8]) -> Result<Option<Vec<ThinSlice<'_>>>, String> {
    let wide = match be32(bytes, 0) {
        Ok(FAT_MAGIC) => false,
        Ok(FAT_MAGIC_64) => true,
        _ => return Ok(None),
    };
    let n = be32(bytes, 4)?;
    if !plausible_slice_count(n) {
        return Err(format!("a fat header with {n} slices (a Java class file?)"));
    }
    let entry = if wide { 32 } else { 20 };
    let table_end = 8 + entry * n as usize;
    span(bytes, 0, table_end).map_err(|e| format!("the fat header's {n} entries: {e}"))?;
    let mut slices: Vec<ThinSlice> = Vec::new();
    for i in 0..n as usize {
        let at = 8 + entry * i;
        let cputype = be32(bytes, at)?;
        let (offset, size) = if wide {
            (be64(bytes, at + 8)?, be64(bytes, at + 16)?)
        } else {
            (
                u64::from(be32(bytes, at + 8)?),
                u64::from(be32(bytes, at + 12)?),
            )
        };
        let arch = Arch::of_cputype(cputype).map_err(|e| format!("slice {i}: {e}"))?;
        let (Ok(offset), Ok(size)) = (usize::try_from(offset), usize::try_from(size)) else {
            return Err(format!(
                "slice {i} ({arch:?}): offset {offset} size {size} too large"
            ));
        };
        if offset < table_end {
            return Err(format!(
                "slice {i} ({arch:?}) at byte {offset} overlaps the fat header"
            ));
        }
        let slice = span(bytes, offset, size).map_err(|e| format!("slice {i} ({arch:?}): {e}"))?;
        let inner = le32(slice, 4).map_err(|e| format!("slice {i} ({arch:?}): {e}"))?;
        if inner != cputype {
            return Err(format!(
                "slice {i}: the fat header says CPU type {cputype:#x}, the slice is {inner:#x}"
            ));
        }
        if slices.iter().any(|(a, _)| *a == arch) {
            return Err(format!("two {arch:?} slices"));
        }
        slices.push((arch, slice));
    }
    Ok(Some(slices))
}

/// A universal (fat) file of the thin slices given (each a thin Mach-O; at most one per
/// arch), laid out exactly as `llvm-lipo -create` does: big-endian fat_header + fat_arch
/// entries, slices ordered by alignment (x86_64 align 2^12, arm64 2^14), each at the next
/// multiple of its alignment, zero padding, slices copied unchanged (so signatures stay
/// valid). Err on a non-Mach-O slice or a repeated arch.
pub fn universal(slices: &[&[u8]]) -> Result<Vec<u8>, String> {
    if slices.is_empty() {
        return Err("a universal file needs a slice".into());
    }
    let mut thin: Vec<(Arch, u32, &[u8])> = Vec::new();
    for (i, &s) in slices.iter().enumerate() {
        let arch = commands(s).map_err(|e| format!("slice {i}: {e}"))?.arch;
        if thin.iter().any(|(a, _, _)| *a == arch) {
            return Err(format!("two {arch:?} slices"));
        }
        thin.push((arch, le32(s, 8)? & !CPU_SUBTYPE_MASK, s));
    }
    thin.sort_by_key(|(arch, _, _)| arch.alignment());
    let mut entries = Vec::new();
    let mut end = 8 + 20 * thin.len();
    for &(arch, subtype, s) in &thin {
        let align = 1usize << arch.alignment();
        let offset = end.next_multiple_of(align);
        end = offset + s.len();
        let (Ok(offset32), Ok(size32)) = (u32::try_from(offset), u32::try_from(s.len())) else {
            return Err(format!(
                "the {arch:?} slice ends past 4 GiB, too far for a fat header"
            ));
        };
        entries.extend([arch.cputype(), subtype, offset32, size32, arch.alignment()]);
    }
    let mut out = vec![0u8; end];
    let header = [FAT_MAGIC, thin.len() as u32]
        .into_iter()
        .chain(entries.iter().copied());
    for (k, word) in header.enumerate() {
        out[4 * k..4 * k + 4].copy_from_slice(&word.to_be_bytes());
    }
    for (k, &(_, _, s)) in thin.iter().enumerate() {
        let offset = entries[5 * k + 2] as usize;
        out[offset..offset + s.len()].copy_from_slice(s);
    }
    Ok(out)
}
