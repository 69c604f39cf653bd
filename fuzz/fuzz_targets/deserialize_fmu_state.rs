//! fmi2DeSerializeFMUstate through the FMI function, then the state in use: restore it,
//! read every variable, step, save and serialize it again, free it. The input is either
//! raw bytes, or edits (offset, byte) of a real serialized state with the checksum
//! repaired, so the fuzzer explores states that parse. Nothing may panic, no NaN may come
//! back with fmi2OK, and every instance must be freeable at the end.
#![no_main]
#![allow(non_upper_case_globals)] // fmi2OK & co. in patterns are constants

use libfuzzer_sys::fuzz_target;
use mechfmu::fmi2::ffi::*;
use mechfmu::fmi2::fmu_state::{reseal, FmuState};
use mechfmu_testkit::harness::Harness;
use mechfmu::model::Declaration;
use oscillator::Oscillator;
use std::sync::OnceLock;

type Fmu = Harness<Oscillator>;

/// Real serialized states: after a few steps, and right after instantiation.
fn bases() -> &'static [Vec<u8>; 2] {
    static BASES: OnceLock<[Vec<u8>; 2]> = OnceLock::new();
    BASES.get_or_init(|| {
        let mut fmu = Fmu::new();
        let fresh = fmu.get_fmu_state().unwrap();
        let a = fmu.serialize(fresh).unwrap();
        fmu.free_fmu_state(fresh);
        fmu.initialize(Some(1e-6), 0.0, &[("F0", 1.0)]).unwrap();
        fmu.step_to(0.5, 0.1).unwrap();
        let s = fmu.get_fmu_state().unwrap();
        let b = fmu.serialize(s).unwrap();
        fmu.free_fmu_state(s);
        [b, a]
    })
}

fn no_internal_error(fmu: &Fmu) {
    for (_, _, m) in fmu.messages() {
        assert!(!m.contains("internal error"), "a panic inside the FMU: {m}");
    }
}

fuzz_target!(|data: &[u8]| {
    let Some((&mode, rest)) = data.split_first() else {
        return;
    };
    let bytes = if mode & 1 == 0 {
        let mut b = rest.to_vec();
        if mode & 2 != 0 {
            reseal(&mut b);
        }
        b
    } else {
        let mut b = bases()[(mode >> 1) as usize & 1].clone();
        for edit in rest.chunks_exact(3) {
            let at = u16::from_le_bytes([edit[0], edit[1]]) as usize % b.len();
            b[at] = edit[2];
        }
        if mode & 4 == 0 {
            reseal(&mut b);
        }
        b
    };
    let mut fmu = Fmu::new();
    let Ok(state) = fmu.deserialize(&bytes) else {
        assert!(!fmu.messages().is_empty(), "refused without a message");
        no_internal_error(&fmu);
        return;
    };
    let parsed = FmuState::from_bytes::<Oscillator>(&bytes).expect("accepted by the FMI function");
    let time = *parsed.sim.values.last().unwrap();
    let status = fmu.set_fmu_state(state);
    assert!(
        status == fmi2OK || status == fmi2Error,
        "fmi2SetFMUstate: {status}"
    );
    let vrs: Vec<u32> = (0..Oscillator::VARIABLES.len() as u32).collect();
    let mut values = vec![0.0; vrs.len()];
    if fmu.get_real(&vrs, &mut values) == fmi2OK {
        assert!(
            values.iter().all(|x| !x.is_nan()),
            "NaN with fmi2OK after restoring {bytes:?}"
        );
    }
    let status = fmu.do_step(time, 0.01);
    assert!(
        matches!(status, fmi2OK | fmi2Warning | fmi2Discard | fmi2Error),
        "fmi2DoStep: {status}"
    );
    if fmu.get_real(&vrs, &mut values) == fmi2OK {
        assert!(
            values.iter().all(|x| !x.is_nan()),
            "NaN with fmi2OK after a step"
        );
    }
    if let Ok(again) = fmu.get_fmu_state() {
        let _ = fmu.serialize(again);
        assert_eq!(fmu.free_fmu_state(again), fmi2OK);
    }
    assert_eq!(
        fmu.free_fmu_state(state),
        fmi2OK,
        "a deserialized state cannot be freed"
    );
    no_internal_error(&fmu);
    // Whatever state the instance is in now, it must be freeable: a reset must succeed.
    assert_eq!(
        fmu.reset(),
        fmi2OK,
        "the instance cannot be reset: {:?}",
        fmu.messages().last()
    );
});
