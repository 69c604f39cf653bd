//! The code signature LC_CODE_SIGNATURE places: a big-endian SuperBlob (`{0xfade0cc0,
//! length, count}` then `count` `{type, offset}`) whose CodeDirectories (magic 0xfade0c02;
//! type 0, and 0x1000.. for alternates) hash every page of the file before the signature.
//! Checked as the kernel checks a page when it maps it; the CMS signature of a
//! certificate-signed file, if any, is not checked.

use super::bytes::{be32, be64, cstr, span};
use super::Signature;
use sha2::{Digest, Sha256, Sha384};
use std::collections::BTreeSet;
use std::ops::Range;

const CSMAGIC_EMBEDDED_SIGNATURE: u32 = 0xfade_0cc0;
const CSMAGIC_CODEDIRECTORY: u32 = 0xfade_0c02;
const CSSLOT_CODEDIRECTORY: u32 = 0;
const CSSLOT_ALTERNATE_CODEDIRECTORIES: Range<u32> = 0x1000..0x1005;
/// Special slots that hash files outside the binary (Info.plist, the resources).
const EXTERNAL_SLOTS: [usize; 2] = [1, 3];
const CS_ADHOC: u32 = 0x2;
/// The size of a CodeDirectory's fields up to `pageSize`/`spare2`, which every version has.
const CD_HEADER: usize = 44;

/// A hash a CodeDirectory can use that is checked here (not SHA-1).
#[derive(Clone, Copy)]
enum Hash {
    Sha256,
    Sha256Truncated,
    Sha384,
}

impl Hash {
    /// The hash of `hashType`, its size checked against `hashSize`: `None` for SHA-1.
    fn of(hash_type: u8, hash_size: u8) -> Result<Option<Hash>, String> {
        let (hash, size) = match hash_type {
            1 => return Ok(None),
            2 => (Hash::Sha256, 32),
            3 => (Hash::Sha256Truncated, 20),
            4 => (Hash::Sha384, 48),
            other => return Err(format!("unknown hash type {other}")),
        };
        if hash_size != size {
            return Err(format!(
                "hash type {hash_type} with hashes of {hash_size} bytes"
            ));
        }
        Ok(Some(hash))
    }

    fn digest(self, data: &[u8]) -> Vec<u8> {
        match self {
            Hash::Sha256 => Sha256::digest(data).to_vec(),
            Hash::Sha256Truncated => Sha256::digest(data)[..20].to_vec(),
            Hash::Sha384 => Sha384::digest(data).to_vec(),
        }
    }
}

/// A CodeDirectory, checked to be well formed and to cover the file up to the signature.
struct Directory {
    /// Its slot in the SuperBlob: 0, or 0x1000.. for an alternate.
    slot: u32,
    flags: u32,
    /// `None` when SHA-1, not checked.
    hash: Option<Hash>,
    hash_size: usize,
    /// Where in the file its code slot 0 is (special slot `i` is `i` hashes before).
    hashes: usize,
    n_special: usize,
    n_code: usize,
    code_limit: usize,
    page_size: usize,
    identifier: String,
}

impl Directory {
    /// The bytes page `k` hashes.
    fn page(&self, k: usize) -> Range<usize> {
        let start = k * self.page_size;
        start..(start + self.page_size).min(self.code_limit)
    }

    /// Where in the file the hash of code slot `k` is.
    fn slot_at(&self, k: usize) -> Range<usize> {
        let at = self.hashes + k * self.hash_size;
        at..at + self.hash_size
    }

    /// "", or which alternate CodeDirectory this is, to start a message with.
    fn which(&self) -> String {
        if self.slot == CSSLOT_CODEDIRECTORY {
            String::new()
        } else {
            format!("CodeDirectory {:#x}: ", self.slot)
        }
    }
}

/// The blobs of a signature: its CodeDirectories, and the others by type (where in the file).
struct Blobs {
    directories: Vec<Directory>,
    others: Vec<(u32, Range<usize>)>,
}

/// The signature at `dataoff` (`datasize` bytes) of file `m`, its structure checked.
fn parse(m: &[u8], dataoff: u32, datasize: u32) -> Result<Blobs, String> {
    let (dataoff, datasize) = (dataoff as usize, datasize as usize);
    let sb = span(m, dataoff, datasize).map_err(|_| {
        format!(
            "the signature (bytes {dataoff}..{}) runs past the end of the file ({} bytes)",
            dataoff + datasize,
            m.len()
        )
    })?;
    let magic = be32(sb, 0)?;
    if magic != CSMAGIC_EMBEDDED_SIGNATURE {
        return Err(format!(
            "the signature's magic is {magic:#010x}, not a SuperBlob's {CSMAGIC_EMBEDDED_SIGNATURE:#x}"
        ));
    }
    let length = be32(sb, 4)? as usize;
    let sb = sb.get(..length).ok_or_else(|| {
        format!("the SuperBlob's {length} bytes overrun LC_CODE_SIGNATURE's {datasize}")
    })?;
    let count = be32(sb, 8)? as usize;
    if count > sb.len() / 8 {
        return Err(format!(
            "{count} blobs in a SuperBlob of {} bytes",
            sb.len()
        ));
    }
    let mut blobs = Blobs {
        directories: Vec::new(),
        others: Vec::new(),
    };
    for i in 0..count {
        let (kind, offset) = (be32(sb, 12 + 8 * i)?, be32(sb, 16 + 8 * i)? as usize);
        let blob_length = be32(sb, offset + 4)? as usize;
        let blob =
            span(sb, offset, blob_length).map_err(|e| format!("blob {i} (type {kind:#x}): {e}"))?;
        let is_directory =
            kind == CSSLOT_CODEDIRECTORY || CSSLOT_ALTERNATE_CODEDIRECTORIES.contains(&kind);
        if is_directory {
            let d = directory(blob, kind, dataoff + offset)
                .map_err(|e| format!("the CodeDirectory of slot {kind:#x}: {e}"))?;
            if d.code_limit != dataoff {
                return Err(format!(
                    "{}it covers {} bytes, the signature starts at byte {dataoff}",
                    d.which(),
                    d.code_limit
                ));
            }
            blobs.directories.push(d);
        } else {
            blobs
                .others
                .push((kind, dataoff + offset..dataoff + offset + blob_length));
        }
    }
    if !blobs
        .directories
        .iter()
        .any(|d| d.slot == CSSLOT_CODEDIRECTORY)
    {
        return Err("the signature has no CodeDirectory".into());
    }
    Ok(blobs)
}

/// The CodeDirectory `cd` of slot `slot`, `at` that byte of the file.
fn directory(cd: &[u8], slot: u32, at: usize) -> Result<Directory, String> {
    let magic = be32(cd, 0)?;
    if magic != CSMAGIC_CODEDIRECTORY || cd.len() < CD_HEADER {
        return Err(format!("magic {magic:#010x}, {} bytes", cd.len()));
    }
    let version = be32(cd, 8)?;
    let hash_offset = be32(cd, 16)? as usize;
    let n_special = be32(cd, 24)? as usize;
    let n_code = be32(cd, 28)? as usize;
    let mut code_limit = u64::from(be32(cd, 32)?);
    let (hash_type, hash_size, page_shift) = (cd[37], cd[36], cd[39]);
    if version >= 0x20300 {
        let wide = be64(cd, 56)?;
        if wide != 0 {
            code_limit = wide;
        }
    }
    let code_limit = usize::try_from(code_limit).map_err(|_| "a code limit too large")?;
    let page_size = match page_shift {
        0 => code_limit.max(1),
        1..=30 => 1 << page_shift,
        _ => return Err(format!("pages of 2^{page_shift} bytes")),
    };
    if n_code != code_limit.div_ceil(page_size) {
        return Err(format!(
            "{n_code} hashes of pages for {code_limit} bytes in pages of {page_size}"
        ));
    }
    let hash_size_usize = usize::from(hash_size);
    let first = n_special
        .checked_mul(hash_size_usize)
        .filter(|&s| s <= hash_offset);
    let end = n_code
        .checked_mul(hash_size_usize)
        .and_then(|s| s.checked_add(hash_offset));
    if first.is_none() || end.is_none_or(|end| end > cd.len()) {
        return Err(format!(
            "{n_special} special and {n_code} code hashes at {hash_offset} overrun its {} bytes",
            cd.len()
        ));
    }
    Ok(Directory {
        slot,
        flags: be32(cd, 12)?,
        hash: Hash::of(hash_type, hash_size)?,
        hash_size: hash_size_usize,
        hashes: at + hash_offset,
        n_special,
        n_code,
        code_limit,
        page_size,
        identifier: cstr(cd, be32(cd, 20)? as usize)
            .map_err(|e| format!("the identifier: {e}"))?
            .to_string(),
    })
}

/// The signature at `dataoff` (`datasize` bytes) of the thin file `m`, checked.
pub(super) fn verify(m: &[u8], dataoff: u32, datasize: u32) -> Signature {
    match check(m, dataoff, datasize) {
        Ok((identifier, adhoc)) => Signature::Valid { identifier, adhoc },
        Err(why) => Signature::Invalid(why),
    }
}

fn check(m: &[u8], dataoff: u32, datasize: u32) -> Result<(String, bool), String> {
    let blobs = parse(m, dataoff, datasize)?;
    let mut checked = 0;
    for d in &blobs.directories {
        let Some(hash) = d.hash else {
            continue;
        };
        for k in 0..d.n_code {
            if hash.digest(&m[d.page(k)]) != m[d.slot_at(k)] {
                return Err(format!(
                    "{}page {k} (bytes {}..) does not match its hash",
                    d.which(),
                    d.page(k).start
                ));
            }
        }
        for i in 1..=d.n_special {
            let want = &m[d.hashes - i * d.hash_size..][..d.hash_size];
            match blobs.others.iter().find(|(kind, _)| *kind as usize == i) {
                Some((_, blob)) if hash.digest(&m[blob.clone()]) != want => {
                    return Err(format!(
                        "{}special slot {i} does not match its blob's hash",
                        d.which()
                    ))
                }
                None if !EXTERNAL_SLOTS.contains(&i) && want.iter().any(|&b| b != 0) => {
                    return Err(format!(
                        "{}special slot {i} has a hash, the signature no such blob",
                        d.which()
                    ))
                }
                _ => {}
            }
        }
        checked += 1;
    }
    if checked == 0 {
        return Err("only SHA-1 CodeDirectories, which are not checked".into());
    }
    let primary = blobs
        .directories
        .iter()
        .find(|d| d.slot == CSSLOT_CODEDIRECTORY);
    let primary = primary.ok_or("the signature has no CodeDirectory")?;
    Ok((primary.identifier.clone(), primary.flags & CS_ADHOC != 0))
}

/// A hash to write once the file has changed: where, of which bytes, how.
pub(super) struct Rehash {
    slot: Range<usize>,
    page: Range<usize>,
    hash: Hash,
}

/// The hashes to recompute once the bytes at `changed` of the thin file `m` have changed,
/// for its signature at `dataoff` (`datasize` bytes) to stay valid: Err if it cannot (a
/// malformed signature, one signed with a certificate, a SHA-1 hash).
pub(super) fn plan_refresh(
    m: &[u8],
    dataoff: u32,
    datasize: u32,
    changed: &[usize],
) -> Result<Vec<Rehash>, String> {
    let blobs =
        parse(m, dataoff, datasize).map_err(|e| format!("cannot refresh the signature: {e}"))?;
    if blobs.directories.iter().any(|d| d.flags & CS_ADHOC == 0) {
        return Err("the signature is not ad hoc: only its certificate could sign a change".into());
    }
    let mut plan = Vec::new();
    for d in &blobs.directories {
        let hash = d
            .hash
            .ok_or_else(|| format!("{}SHA-1 hashes, which cannot be refreshed here", d.which()))?;
        if changed.iter().any(|&at| at >= d.code_limit) {
            return Err(format!(
                "{}the change is not inside the signed bytes",
                d.which()
            ));
        }
        let pages: BTreeSet<usize> = changed.iter().map(|&at| at / d.page_size).collect();
        plan.extend(pages.into_iter().map(|k| Rehash {
            slot: d.slot_at(k),
            page: d.page(k),
            hash,
        }));
    }
    Ok(plan)
}

/// Writes the hashes `plan` says of the changed file `m`.
pub(super) fn refresh(m: &mut [u8], plan: &[Rehash]) {
    for r in plan {
        let digest = r.hash.digest(&m[r.page.clone()]);
        m[r.slot.clone()].copy_from_slice(&digest);
    }
}
