//! FMI 3.0 serialized FMU states: `FmuState::from_bytes::<Oscillator>(bytes,
//! Version::Fmi3)` (whatever it accepts serializes again to bytes that re-read to the same
//! state), then fmi3DeserializeFMUState through the FMI function and the state in use:
//! restored into a Model Exchange instance or a Co-Simulation one (with or without event
//! mode and early return), every variable read by FMI 3.0 value reference, a step
//! (Co-Simulation: out of event mode first if there) or the continuous states,
//! derivatives, event indicators and nominals, an RK4 step and an event (Model Exchange);
//! the state saved and serialized again, freed, the instance reset.
//!
//! The input is raw bytes (checksum repaired or not), or (offset, byte) edits of one of
//! six real serialized states with the checksum repaired (or not): FMI 3.0 Co-Simulation
//! after steps and after instantiation, Co-Simulation in event mode, Model Exchange in
//! event mode and in continuous-time mode, and an FMI 2.0 Co-Simulation state with the
//! FMI 3.0 instantiation token forged in (the format is the same but for the token).
//! Nothing may panic, no NaN may come back with fmi3OK, a state saved by an instance of
//! the other interface type (or in event mode, for a Co-Simulation instance without it)
//! is refused, and every instance must be resettable at the end.
#![no_main]
#![allow(non_upper_case_globals)] // fmi3OK & co. in patterns are constants

use libfuzzer_sys::fuzz_target;
use mechfmu::fmi::fmu_state::{reseal, FmuState};
use mechfmu::fmi::machine::{Interface, ModelState};
use mechfmu::fmi::Version;
use mechfmu::fmi3::ffi::*;
use mechfmu_testkit::fmi3::{Fmi3Harness, Kind};
use mechfmu_testkit::harness::Harness;
use oscillator::Oscillator;
use std::sync::OnceLock;

type Fmu = Fmi3Harness<Oscillator>;

/// The instance kinds an input's first byte picks from (bits 0 and 1).
const KINDS: [Kind; 4] = [
    Kind::ModelExchange,
    Kind::CoSimulation {
        event_mode_used: false,
        early_return_allowed: false,
    },
    Kind::CoSimulation {
        event_mode_used: true,
        early_return_allowed: false,
    },
    Kind::CoSimulation {
        event_mode_used: true,
        early_return_allowed: true,
    },
];

fn serialize(fmu: &mut Fmu) -> Vec<u8> {
    let s = fmu.get_fmu_state().unwrap();
    let bytes = fmu.serialize(s).unwrap();
    assert_eq!(fmu.free_fmu_state(s), fmi3OK);
    bytes
}

/// `bytes` with their token (the second string) replaced by `token`, resealed.
fn with_token(bytes: &[u8], token: &str) -> Vec<u8> {
    let len = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().unwrap()) as usize;
    let token_at = 12 + 4 + len(12);
    let rest = token_at + 4 + len(token_at);
    let mut out = bytes[..token_at].to_vec();
    out.extend_from_slice(&(token.len() as u32).to_le_bytes());
    out.extend_from_slice(token.as_bytes());
    out.extend_from_slice(&bytes[rest..]);
    reseal(&mut out);
    out
}

/// The six real states the edits start from.
fn bases() -> &'static [Vec<u8>; 6] {
    static BASES: OnceLock<[Vec<u8>; 6]> = OnceLock::new();
    BASES.get_or_init(|| {
        let mut cs = Fmu::new();
        let fresh = serialize(&mut cs);
        cs.initialize(Some(1e-6), 0.0, &[("F0", 1.0)]).unwrap();
        cs.step_to(0.5, 0.1).unwrap();
        let stepped = serialize(&mut cs);
        let mut ev = Fmu::of_kind(KINDS[2]);
        ev.initialize(Some(1e-6), 0.0, &[("F0", 1.0)]).unwrap();
        let cs_event_mode = serialize(&mut ev);
        let mut me = Fmu::model_exchange();
        me.initialize(Some(1e-6), 0.0, &[("F0", 1.0)]).unwrap();
        let me_event_mode = serialize(&mut me);
        assert_eq!(me.update_discrete_states().0, fmi3OK);
        assert_eq!(me.enter_continuous_time_mode(), fmi3OK);
        let x = me.continuous_states().unwrap();
        let dx = me.derivatives().unwrap();
        let x: Vec<f64> = x.iter().zip(&dx).map(|(x, d)| x + 0.01 * d).collect();
        assert_eq!(me.set_time(0.01), fmi3OK);
        assert_eq!(me.set_continuous_states(&x), fmi3OK);
        let continuous_time_mode = serialize(&mut me);
        let mut fmi2 = Harness::<Oscillator>::new();
        fmi2.initialize(Some(1e-6), 0.0, &[("F0", 1.0)]).unwrap();
        fmi2.step_to(0.2, 0.1).unwrap();
        let s = fmi2.get_fmu_state().unwrap();
        let fmi2_state = fmi2.serialize(s).unwrap();
        fmi2.free_fmu_state(s);
        let token = mechfmu::contract::instantiation_token::<Oscillator>();
        [
            stepped,
            fresh,
            cs_event_mode,
            me_event_mode,
            continuous_time_mode,
            with_token(&fmi2_state, &token),
        ]
    })
}

/// Whatever the parser accepts serializes again to bytes that re-read to the same state.
fn round_trip(bytes: &[u8]) -> Option<FmuState> {
    let state = FmuState::from_bytes::<Oscillator>(bytes, Version::Fmi3).ok()?;
    let again = state.to_bytes::<Oscillator>();
    let reread = FmuState::from_bytes::<Oscillator>(&again, Version::Fmi3)
        .unwrap_or_else(|e| panic!("a state it accepted does not re-read: {e}"));
    assert_eq!(
        reread.to_bytes::<Oscillator>(),
        again,
        "serialization is not stable"
    );
    Some(state)
}

fn no_internal_error(fmu: &Fmu) {
    for (_, _, m) in fmu.messages() {
        assert!(!m.contains("internal error"), "a panic inside the FMU: {m}");
    }
}

/// What a getter of Model Exchange returned: a number everywhere with fmi3OK.
fn finite(what: &str, got: Result<Vec<f64>, fmi3Status>) {
    match got {
        Ok(v) => assert!(
            v.iter().all(|x| x.is_finite()),
            "{what} returned fmi3OK with {v:?}"
        ),
        Err(s) => assert!(matches!(s, fmi3Discard | fmi3Error), "{what}: {s}"),
    }
}

fn no_nan_values(fmu: &mut Fmu, after: &str) {
    let vrs: Vec<u32> = (0..fmu.shapes().time_reference() as u32 + 1)
        .filter(|&vr| {
            vr as usize == fmu.shapes().time_reference() || fmu.shapes().get(vr as usize).is_some()
        })
        .collect();
    if let Ok(values) = fmu.get_values(&vrs) {
        assert!(
            values.iter().all(|x| !x.is_nan()),
            "NaN with fmi3OK {after}"
        );
    }
}

fuzz_target!(|data: &[u8]| {
    let Some((&mode, rest)) = data.split_first() else {
        return;
    };
    // mode bits 0-1: the instance (KINDS); bit 2: raw bytes (bit 3: checksum repaired) or
    // edits of base (bits 3-5) % 6 (bit 6: checksum left as edited).
    let bytes = if mode & 4 == 0 {
        let mut b = rest.to_vec();
        if mode & 8 != 0 {
            reseal(&mut b);
        }
        b
    } else {
        let mut b = bases()[((mode >> 3) & 7) as usize % 6].clone();
        for edit in rest.chunks_exact(3) {
            let at = u16::from_le_bytes([edit[0], edit[1]]) as usize % b.len();
            b[at] = edit[2];
        }
        if mode & 64 == 0 {
            reseal(&mut b);
        }
        b
    };
    let parsed = round_trip(&bytes);
    let kind = KINDS[(mode & 3) as usize];
    let mut fmu = Fmu::of_kind(kind);
    let Ok(state) = fmu.deserialize(&bytes) else {
        assert!(
            parsed.is_none(),
            "fmi3DeserializeFMUState refused what the parser accepts"
        );
        assert!(!fmu.messages().is_empty(), "refused without a message");
        no_internal_error(&fmu);
        return;
    };
    let parsed = parsed.expect("accepted by the FMI function, so by the parser");
    let time = *parsed.sim.values.last().unwrap();
    let status = fmu.set_fmu_state(state);
    assert!(
        status == fmi3OK || status == fmi3Error,
        "fmi3SetFMUState: {status}"
    );
    let interface = match kind {
        Kind::ModelExchange => Interface::ModelExchange,
        Kind::CoSimulation { .. } => Interface::CoSimulation,
    };
    let without_event_mode = matches!(
        kind,
        Kind::CoSimulation {
            event_mode_used: false,
            ..
        }
    );
    if parsed.interface != interface
        || (parsed.model_state == ModelState::EventMode && without_event_mode)
    {
        assert_eq!(
            status,
            fmi3Error,
            "a {} state ({:?}) restored into {kind:?}",
            parsed.interface.name(),
            parsed.model_state
        );
    }
    no_nan_values(&mut fmu, "after restoring");
    if kind == Kind::ModelExchange {
        // Whatever mode it is in now: read what Model Exchange reads, then integrate a
        // step and handle an event if the mode allows (refusals are fine, panics not).
        finite("fmi3GetContinuousStates", fmu.continuous_states());
        finite("fmi3GetContinuousStateDerivatives", fmu.derivatives());
        finite("fmi3GetEventIndicators", fmu.event_indicators());
        if let Ok(n) = fmu.nominals() {
            assert!(
                n.iter().all(|x| *x > 0.0 && x.is_finite()),
                "nominals {n:?}"
            );
        }
        if let (Ok(x), Ok(dx)) = (fmu.continuous_states(), fmu.derivatives()) {
            let x: Vec<f64> = x.iter().zip(&dx).map(|(x, d)| x + 0.01 * d).collect();
            let _ = fmu.set_time(time + 0.01);
            let _ = fmu.set_continuous_states(&x);
            let _ = fmu.completed_integrator_step();
            finite("fmi3GetContinuousStates", fmu.continuous_states());
        }
        let _ = fmu.enter_event_mode();
        let (status, d) = fmu.update_discrete_states();
        if matches!(status, fmi3OK | fmi3Warning) && d.next_event_time_defined {
            assert!(d.next_event_time.is_finite(), "{d:?}");
        }
        let _ = fmu.enter_continuous_time_mode();
        finite("fmi3GetContinuousStateDerivatives", fmu.derivatives());
    } else {
        let _ = fmu.update_discrete_states();
        let _ = fmu.enter_step_mode();
        let step = fmu.do_step(time, 0.01);
        assert!(
            matches!(step.status, fmi3OK | fmi3Warning | fmi3Discard | fmi3Error),
            "fmi3DoStep: {step:?}"
        );
        if step.status == fmi3OK && !step.early_return {
            assert!(step.last_successful_time.is_finite(), "{step:?}");
        }
    }
    no_nan_values(&mut fmu, "after a step");
    if let Ok(again) = fmu.get_fmu_state() {
        let _ = fmu.serialize(again);
        assert_eq!(fmu.free_fmu_state(again), fmi3OK);
    }
    assert_eq!(
        fmu.free_fmu_state(state),
        fmi3OK,
        "a deserialized state cannot be freed"
    );
    no_internal_error(&fmu);
    // Whatever state the instance is in now, it must be resettable.
    assert_eq!(
        fmu.reset(),
        fmi3OK,
        "the instance cannot be reset: {:?}",
        fmu.messages().last()
    );
});
