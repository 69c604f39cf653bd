//! fmi2SetDebugLogging's category strings: arbitrary bytes split at NUL into C strings
//! (NULL entries and non-UTF-8 included), through the FMI function. The answer is fmi2OK
//! exactly when every category is known, otherwise fmi2Error with a message; never a panic.
#![no_main]

use libfuzzer_sys::fuzz_target;
use mechfmu::contract::LOG_CATEGORIES as CATEGORIES;
use mechfmu::fmi2::ffi::*;
use mechfmu::fmi2::functions;
use mechfmu_testkit::harness::Harness;
use oscillator::Oscillator;
use std::ffi::CString;

fuzz_target!(|data: &[u8]| {
    let Some((&flags, rest)) = data.split_first() else {
        return;
    };
    let parts: Vec<&[u8]> = if rest.is_empty() {
        vec![]
    } else {
        rest.split(|&b| b == 0).collect()
    };
    let strings: Vec<CString> = parts.iter().map(|p| CString::new(*p).unwrap()).collect();
    let mut pointers: Vec<fmi2String> = strings.iter().map(|s| s.as_ptr()).collect();
    // An empty part stands for a NULL entry when flag bit 1 says so.
    let mut has_null = false;
    if flags & 2 != 0 {
        for (p, s) in pointers.iter_mut().zip(&parts) {
            if s.is_empty() {
                *p = std::ptr::null();
                has_null = true;
            }
        }
    }
    let fmu = Harness::<Oscillator>::new();
    let before = fmu.messages().len();
    // SAFETY: `pointers.len()` C strings (or NULL entries) at `pointers`.
    let status = unsafe {
        functions::fmi2SetDebugLogging::<Oscillator>(
            fmu.component(),
            (flags & 1) as fmi2Boolean,
            pointers.len(),
            pointers.as_ptr(),
        )
    };
    let all_known = !has_null
        && parts
            .iter()
            .all(|p| std::str::from_utf8(p).is_ok_and(|s| CATEGORIES.iter().any(|(c, _)| *c == s)));
    if all_known {
        assert_eq!(status, fmi2OK);
    } else {
        assert_eq!(status, fmi2Error);
        // With every category off, even the error message is (rightly) filtered out.
        let messages = fmu.messages();
        assert!(
            messages.len() > before || flags & 1 == 0,
            "fmi2Error without a message"
        );
        for (_, _, m) in &messages {
            assert!(!m.contains("internal error"), "{m}");
        }
    }
});
