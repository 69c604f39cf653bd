//! The unit parser (`"N.s/m"`, `"kg.m2"`, `"1/s"`, ...) and the display-unit lookup on
//! arbitrary text: errors, never panics; parsing is deterministic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use mechfmu::xml::units;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let first = units::parse(text);
    assert_eq!(first, units::parse(text));
    if let Err(message) = &first {
        assert!(!message.is_empty());
    }
    let _ = units::display_unit(text);
    let _ = units::quantity(text);
});
