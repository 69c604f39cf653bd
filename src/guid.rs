//! The GUID of an FMU, derived from its declaration: the same declaration always gives the
//! same GUID, and any change an importer could see gives another.

use crate::model::Mechanism;

/// Bump when the modelDescription generator changes what it writes from the same
/// declaration, so binaries and XML of different generator versions never match.
const GENERATOR_VERSION: &str = "mechfmu-md-2";

/// 64-bit FNV-1a over a stream of fields (each prefixed by its length, so field boundaries
/// count).
struct Fnv(u64);

impl Fnv {
    fn new(seed: u64) -> Self {
        Fnv(0xcbf2_9ce4_8422_2325 ^ seed.wrapping_mul(0x0100_0000_01b3))
    }
    fn bytes(&mut self, b: &[u8]) {
        for &x in (b.len() as u64).to_le_bytes().iter().chain(b) {
            self.0 ^= x as u64;
            self.0 = self.0.wrapping_mul(0x0100_0000_01b3);
        }
    }
    fn f64(&mut self, x: Option<f64>) {
        match x {
            Some(x) => self.bytes(&x.to_bits().to_le_bytes()),
            None => self.bytes(b"-"),
        }
    }
}

fn hash<M: Mechanism>(seed: u64) -> u64 {
    let mut h = Fnv::new(seed);
    h.bytes(GENERATOR_VERSION.as_bytes());
    h.bytes(M::NAME.as_bytes());
    h.bytes(M::DESCRIPTION.as_bytes());
    h.bytes(format!("{:?}", crate::xml::CAPABILITIES).as_bytes());
    let e = M::EXPERIMENT;
    for x in [e.start, e.stop, e.step, e.tolerance] {
        h.f64(Some(x));
    }
    for v in M::VARIABLES {
        h.bytes(v.name.as_bytes());
        h.bytes(v.description.as_bytes());
        h.bytes(v.causality.as_str().as_bytes());
        h.bytes(v.variability.as_str().as_bytes());
        h.bytes(v.initial.map_or("", |i| i.as_str()).as_bytes());
        h.bytes(v.unit.as_bytes());
        h.f64(v.start);
        h.f64(v.min);
        h.f64(v.max);
        h.bytes(&[v.positive as u8]);
        h.bytes(v.derivative.unwrap_or("").as_bytes());
    }
    h.0
}

/// The GUID, formatted as `{xxxxxxxx-xxxx-xxxx-xxxx-xxxxxxxxxxxx}`.
pub fn guid<M: Mechanism>() -> String {
    let (a, b) = (hash::<M>(1), hash::<M>(2));
    format!(
        "{{{:08x}-{:04x}-{:04x}-{:04x}-{:012x}}}",
        a >> 32,
        (a >> 16) & 0xffff,
        a & 0xffff,
        b >> 48,
        b & 0xffff_ffff_ffff
    )
}
