//! The GUID (FMI 2.0) and the instantiation token (FMI 3.0): a hash of everything the
//! model description of each version is written from, so that the same declaration always
//! gives the same token and any change an importer could see gives another.

use super::{CAPABILITIES, FMI3_CAPABILITIES};
use crate::model::Mechanism;

/// Bump when the modelDescription generator changes what it writes from the same
/// declaration, so binaries and XML of different generator versions never match.
const GENERATOR_VERSION: &str = "mechfmu-md-4";

/// The same for what only the FMI 3.0 model description writes (the arrays, the
/// independent variable, the FMI 3.0 model structure).
const FMI3_GENERATOR_VERSION: &str = "mechfmu-md3-3";

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
    declaration_hash::<M>(Fnv::new(seed)).0
}

/// The stream of everything FMI 2.0's model description is written from.
fn declaration_hash<M: Mechanism>(mut h: Fnv) -> Fnv {
    h.bytes(GENERATOR_VERSION.as_bytes());
    h.bytes(M::NAME.as_bytes());
    h.bytes(M::DESCRIPTION.as_bytes());
    h.bytes(format!("{:?}", CAPABILITIES).as_bytes());
    let e = M::EXPERIMENT;
    for x in [e.start, e.stop, e.step, e.tolerance] {
        h.f64(Some(x));
    }
    for indicator in M::EVENT_INDICATORS {
        h.bytes(indicator.as_bytes());
    }
    h.bytes(&[M::MONITORED as u8, M::PROJECTED as u8]);
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
    h
}

/// The stream of everything FMI 3.0's model description is written from: FMI 2.0's, the
/// FMI 3.0 capabilities and the arrays.
fn fmi3_hash<M: Mechanism>(seed: u64) -> u64 {
    let mut h = declaration_hash::<M>(Fnv::new(seed));
    h.bytes(FMI3_GENERATOR_VERSION.as_bytes());
    h.bytes(format!("{:?}", FMI3_CAPABILITIES).as_bytes());
    for array in M::ARRAYS {
        h.bytes(array.name.as_bytes());
        h.bytes(array.description.as_bytes());
        for &d in array.dimensions {
            h.bytes(&(d as u64).to_le_bytes());
        }
        for element in array.elements {
            h.bytes(element.as_bytes());
        }
    }
    h.0
}

/// The GUID, formatted as `{xxxxxxxx-xxxx-xxxx-xxxx-xxxxxxxxxxxx}`.
pub fn guid<M: Mechanism>() -> String {
    braced_uuid(hash::<M>(1), hash::<M>(2))
}

/// FMI 3.0's `instantiationToken`, as [`guid`] but over what FMI 3.0's model description
/// is written from (arrays too), so it differs from the GUID: an FMI 2.0 model description
/// never matches an FMI 3.0 binary call, nor the other way round.
pub fn instantiation_token<M: Mechanism>() -> String {
    braced_uuid(fmi3_hash::<M>(3), fmi3_hash::<M>(4))
}

fn braced_uuid(a: u64, b: u64) -> String {
    format!(
        "{{{:08x}-{:04x}-{:04x}-{:04x}-{:012x}}}",
        a >> 32,
        (a >> 16) & 0xffff,
        a & 0xffff,
        b >> 48,
        b & 0xffff_ffff_ffff
    )
}
