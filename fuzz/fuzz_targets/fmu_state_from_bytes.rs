//! `FmuState::from_bytes` (what fmi2DeSerializeFMUstate parses) on arbitrary bytes, raw and
//! with the checksum repaired (so the fuzzer reaches the fields behind it). Whatever it
//! accepts must serialize again to bytes that parse to the same state.
#![no_main]

use libfuzzer_sys::fuzz_target;
use mechfmu::fmi2::fmu_state::FmuState;
use oscillator::Oscillator;

/// FNV-1a 64 over everything but the last 8 bytes, written there (the format's checksum).
fn repair(bytes: &mut [u8]) {
    if bytes.len() < 8 {
        return;
    }
    let n = bytes.len() - 8;
    let h = bytes[..n].iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| {
        (h ^ b as u64).wrapping_mul(0x0100_0000_01b3)
    });
    bytes[n..].copy_from_slice(&h.to_le_bytes());
}

fn check(bytes: &[u8]) {
    if let Ok(state) = FmuState::from_bytes::<Oscillator>(bytes) {
        let again = state.to_bytes::<Oscillator>();
        let reread = FmuState::from_bytes::<Oscillator>(&again)
            .unwrap_or_else(|e| panic!("a state it accepted does not re-read: {e}"));
        assert_eq!(
            reread.to_bytes::<Oscillator>(),
            again,
            "serialization is not stable"
        );
    }
}

fuzz_target!(|data: &[u8]| {
    check(data);
    let mut repaired = data.to_vec();
    repair(&mut repaired);
    check(&repaired);
});
