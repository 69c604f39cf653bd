//! `FmuState::from_bytes` (what fmi2DeSerializeFMUstate parses) on arbitrary bytes, raw and
//! with the checksum repaired (so the fuzzer reaches the fields behind it). Whatever it
//! accepts must serialize again to bytes that parse to the same state.
#![no_main]

use libfuzzer_sys::fuzz_target;
use mechfmu::fmi::fmu_state::{reseal, FmuState};
use mechfmu::fmi::Version;
use oscillator::Oscillator;

fn check(bytes: &[u8]) {
    if let Ok(state) = FmuState::from_bytes::<Oscillator>(bytes, Version::Fmi2) {
        let again = state.to_bytes::<Oscillator>();
        let reread = FmuState::from_bytes::<Oscillator>(&again, Version::Fmi2)
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
    reseal(&mut repaired);
    check(&repaired);
});
