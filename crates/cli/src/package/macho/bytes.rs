//! Bounds-checked reads of a Mach-O file's integers and strings: a short file gives an `Err`
//! naming the offset, never a panic.

/// The `len` bytes at `at`.
pub(super) fn span(b: &[u8], at: usize, len: usize) -> Result<&[u8], String> {
    at.checked_add(len)
        .and_then(|end| b.get(at..end))
        .ok_or_else(|| {
            format!(
                "truncated: bytes {at}..{} are past the end ({} bytes)",
                at.saturating_add(len),
                b.len()
            )
        })
}

fn array<const N: usize>(b: &[u8], at: usize) -> Result<[u8; N], String> {
    let mut out = [0; N];
    out.copy_from_slice(span(b, at, N)?);
    Ok(out)
}

/// The little-endian `u32` at `at` (the byte order of x86_64 and arm64 Mach-O files).
pub(super) fn le32(b: &[u8], at: usize) -> Result<u32, String> {
    array(b, at).map(u32::from_le_bytes)
}

/// The big-endian `u32` at `at` (the byte order of fat headers and code signatures).
pub(super) fn be32(b: &[u8], at: usize) -> Result<u32, String> {
    array(b, at).map(u32::from_be_bytes)
}

/// The big-endian `u64` at `at`.
pub(super) fn be64(b: &[u8], at: usize) -> Result<u64, String> {
    array(b, at).map(u64::from_be_bytes)
}

/// The NUL-terminated UTF-8 string at `at`, which must end before the end of `b`.
pub(super) fn cstr(b: &[u8], at: usize) -> Result<&str, String> {
    let rest = b
        .get(at..)
        .ok_or_else(|| format!("a string at byte {at}, past the end ({} bytes)", b.len()))?;
    let len = rest
        .iter()
        .position(|&c| c == 0)
        .ok_or_else(|| format!("the string at byte {at} has no terminating NUL"))?;
    std::str::from_utf8(&rest[..len]).map_err(|_| format!("the string at byte {at} is not UTF-8"))
}
