//! The serialized FMU state as the runtime documents its format (`fmi::fmu_state`, the
//! same for both standards but for the token that names the build): its checksum, where
//! its fields are, edits of them a forger would make (another standard's token, an
//! instance state or interface type rewritten), and the oracle's reading of bytes it did
//! not serialize itself.

use super::hostile::hostile_f64;
use super::machine::{Kind, Snap, ALL_STATES};
use crate::rng::Rng;

/// FNV-1a 64, the serialized state's checksum (documented in the runtime's format).
pub fn fnv(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325, |h, &b| {
        (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
    })
}

pub fn fix_checksum(b: &mut [u8]) {
    if b.len() < 8 {
        return;
    }
    let n = b.len() - 8;
    let c = fnv(&b[..n]);
    b[n..].copy_from_slice(&c.to_le_bytes());
}

/// Offsets of the fields of a serialized state (format version 4), if it parses.
pub struct Layout {
    /// Where the second string (the GUID or instantiation token) starts, and its length.
    pub token: usize,
    pub token_len: usize,
    pub values: usize,
    pub n_values: usize,
    /// The flags byte is just before it.
    pub state_field: usize,
}

pub fn layout(b: &[u8]) -> Option<Layout> {
    let u32_at = |i: usize| {
        b.get(i..i + 4)
            .map(|x| u32::from_le_bytes(x.try_into().unwrap()) as usize)
    };
    let mut at = 12;
    at += 4 + u32_at(at)?;
    let token_len = u32_at(at)?;
    let token = at + 4;
    at = token + token_len;
    let n_values = u32_at(at)?;
    let values = at + 4;
    at = values + 8 * n_values;
    let n_inputs = u32_at(at)?;
    at += 4 + 24 * n_inputs + 9 + 8 + 16 + 1;
    (at + 2 + 9 + 8 + 4 + 8 == b.len()).then_some(Layout {
        token,
        token_len,
        values,
        n_values,
        state_field: at,
    })
}
/// Corrupts fields of a serialized state with values of the right size.
pub fn mutate_semantically(rng: &mut Rng, b: &mut [u8]) {
    let Some(l) = layout(b) else { return };
    for _ in 0..1 + rng.below(3) {
        match rng.below(4) {
            0 => {
                let bits: u16 = if rng.chance(0.8) {
                    1 << rng.below(ALL_STATES.len())
                } else {
                    rng.next_u64() as u16
                };
                b[l.state_field..l.state_field + 2].copy_from_slice(&bits.to_le_bytes());
            }
            1 if l.n_values > 0 => {
                let k = rng.below(l.n_values);
                let x = hostile_f64(rng);
                b[l.values + 8 * k..l.values + 8 * k + 8]
                    .copy_from_slice(&x.to_bits().to_le_bytes());
            }
            _ => {
                let i = 12 + rng.below(b.len().saturating_sub(20).max(1));
                if i < b.len() - 8 {
                    b[i] = rng.next_u64() as u8;
                }
            }
        }
    }
}

/// The oracle's reading of a serialized state it did not make itself.
pub fn decode_snap(b: &[u8]) -> Option<Snap> {
    let l = layout(b)?;
    let f = |i: usize| f64::from_bits(u64::from_le_bytes(b[i..i + 8].try_into().unwrap()));
    let time = f(l.values + 8 * (l.n_values.checked_sub(1)?));
    let bits = u16::from_le_bytes(b[l.state_field..l.state_field + 2].try_into().unwrap());
    let st = ALL_STATES
        .iter()
        .enumerate()
        .find(|(i, _)| bits == 1 << i)
        .map(|(_, s)| *s)?;
    let stop_at = l.state_field + 2;
    let stop = (b[stop_at] == 1).then(|| f(stop_at + 1));
    let kind = if b[l.state_field - 1] & 16 != 0 {
        Kind::ModelExchange
    } else {
        Kind::CoSimulation
    };
    Some(Snap {
        st,
        time,
        stop,
        kind,
        other_standard: false,
        forged: true,
    })
}

/// Replaces the serialized state's token (the GUID or instantiation token) with `token`
/// and repairs the checksum: an FMI 2.0 state a forger passes off as FMI 3.0's.
pub fn forge_token(b: &mut Vec<u8>, token: &str) {
    let Some(l) = layout(b) else { return };
    let mut forged = b[..l.token - 4].to_vec();
    forged.extend_from_slice(&(token.len() as u32).to_le_bytes());
    forged.extend_from_slice(token.as_bytes());
    forged.extend_from_slice(&b[l.token + l.token_len..]);
    fix_checksum(&mut forged);
    *b = forged;
}

/// Rewrites a serialized FMI 3.0 state's interface type, instance state or both (event
/// mode of Co-Simulation among them, which FMI 3.0 has) and repairs the checksum.
pub fn forge_state(rng: &mut Rng, b: &mut [u8]) {
    let Some(l) = layout(b) else { return };
    if rng.chance(0.5) {
        b[l.state_field - 1] ^= 16; // Model Exchange <-> Co-Simulation
    }
    if rng.chance(0.7) {
        let st = *rng.pick(&ALL_STATES);
        let bits = 1u16 << ALL_STATES.iter().position(|s| *s == st).unwrap_or(0);
        b[l.state_field..l.state_field + 2].copy_from_slice(&bits.to_le_bytes());
    }
    fix_checksum(b);
}
