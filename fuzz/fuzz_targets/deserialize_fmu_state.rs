//! fmi2DeSerializeFMUstate through the FMI function, then the state in use: restore it,
//! read every variable, step (Co-Simulation) or integrate and handle an event (Model
//! Exchange), save and serialize it again, free it. The input is either raw bytes, or
//! edits (offset, byte) of a real serialized state with the checksum repaired, so the
//! fuzzer explores states that parse; the real states include Model Exchange ones (event
//! mode, continuous-time mode), and the instance that restores is either type, so a state
//! of the other interface type is tried too. Nothing may panic, no NaN may come back with
//! fmi2OK, a state saved by an instance of the other interface type is refused, and every
//! instance must be freeable at the end.
#![no_main]
#![allow(non_upper_case_globals)] // fmi2OK & co. in patterns are constants

use libfuzzer_sys::fuzz_target;
use mechfmu::fmi::fmu_state::{reseal, FmuState};
use mechfmu::fmi::machine::Interface;
use mechfmu::fmi::Version;
use mechfmu::fmi2::ffi::*;
use mechfmu::model::Declaration;
use mechfmu_testkit::harness::Harness;
use mechfmu_testkit::model_exchange::ModelExchange;
use oscillator::Oscillator;
use std::sync::OnceLock;

type Fmu = Harness<Oscillator>;
type Me = ModelExchange<Oscillator>;

/// Real serialized states: Co-Simulation after a few steps and right after
/// instantiation; Model Exchange in event mode after initialization and in
/// continuous-time mode after a few integrator steps.
fn bases() -> &'static [Vec<u8>; 4] {
    static BASES: OnceLock<[Vec<u8>; 4]> = OnceLock::new();
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
        let mut me = Me::new();
        me.fmu.initialize(Some(1e-6), 0.0, &[("F0", 1.0)]).unwrap();
        let s = me.fmu.get_fmu_state().unwrap();
        let event_mode = me.fmu.serialize(s).unwrap();
        me.fmu.free_fmu_state(s);
        let (status, _) = me.new_discrete_states();
        assert_eq!(status, fmi2OK);
        assert_eq!(me.enter_continuous_time_mode(), fmi2OK);
        let mut x = me.states().unwrap();
        for n in 0..5 {
            x = me.rk4(0.01 * n as f64, &x, 0.01).unwrap();
        }
        assert_eq!(me.set_time(0.05), fmi2OK);
        assert_eq!(me.set_states(&x), fmi2OK);
        let s = me.fmu.get_fmu_state().unwrap();
        let continuous_time_mode = me.fmu.serialize(s).unwrap();
        me.fmu.free_fmu_state(s);
        [b, a, event_mode, continuous_time_mode]
    })
}

fn no_internal_error(messages: &[(fmi2Status, String, String)]) {
    for (_, _, m) in messages {
        assert!(!m.contains("internal error"), "a panic inside the FMU: {m}");
    }
}

/// What a getter of Model Exchange returned: a number everywhere with fmi2OK.
fn finite(what: &str, got: Result<Vec<f64>, fmi2Status>) {
    match got {
        Ok(v) => assert!(
            v.iter().all(|x| x.is_finite()),
            "{what} returned fmi2OK with {v:?}"
        ),
        Err(s) => assert!(matches!(s, fmi2Discard | fmi2Error), "{what}: {s}"),
    }
}

fuzz_target!(|data: &[u8]| {
    let Some((&mode, rest)) = data.split_first() else {
        return;
    };
    // mode bit 0: raw bytes (bit 1: checksum repaired) or edits of base number
    // bit 1 | bit 3 << 1 (bit 2: checksum left as edited); bit 4: the instance that
    // restores is Model Exchange.
    let bytes = if mode & 1 == 0 {
        let mut b = rest.to_vec();
        if mode & 2 != 0 {
            reseal(&mut b);
        }
        b
    } else {
        let base = ((mode >> 1) & 1 | (mode >> 2) & 2) as usize;
        let mut b = bases()[base].clone();
        for edit in rest.chunks_exact(3) {
            let at = u16::from_le_bytes([edit[0], edit[1]]) as usize % b.len();
            b[at] = edit[2];
        }
        if mode & 4 == 0 {
            reseal(&mut b);
        }
        b
    };
    let model_exchange = mode & 16 != 0;
    let interface = if model_exchange {
        Interface::ModelExchange
    } else {
        Interface::CoSimulation
    };
    let mut me = Me::new();
    let mut cs = Fmu::new();
    let fmu = if model_exchange { &mut me.fmu } else { &mut cs };
    let Ok(state) = fmu.deserialize(&bytes) else {
        assert!(!fmu.messages().is_empty(), "refused without a message");
        no_internal_error(&fmu.messages());
        return;
    };
    let parsed = FmuState::from_bytes::<Oscillator>(&bytes, Version::Fmi2)
        .expect("accepted by the FMI function");
    let time = *parsed.sim.values.last().unwrap();
    let status = fmu.set_fmu_state(state);
    assert!(
        status == fmi2OK || status == fmi2Error,
        "fmi2SetFMUstate: {status}"
    );
    if parsed.interface != interface {
        assert_eq!(
            status,
            fmi2Error,
            "a {} state ({:?}) restored into a {} instance",
            parsed.interface.name(),
            parsed.model_state,
            interface.name()
        );
    }
    let vrs: Vec<u32> = (0..Oscillator::VARIABLES.len() as u32).collect();
    let mut values = vec![0.0; vrs.len()];
    if fmu.get_real(&vrs, &mut values) == fmi2OK {
        assert!(
            values.iter().all(|x| !x.is_nan()),
            "NaN with fmi2OK after restoring {bytes:?}"
        );
    }
    if model_exchange {
        // Whatever mode it is in now: read what Model Exchange reads, then integrate a
        // step and handle an event if the mode allows (refusals are fine, panics not).
        finite("fmi2GetContinuousStates", me.states());
        finite("fmi2GetDerivatives", me.derivatives());
        finite("fmi2GetEventIndicators", me.event_indicators());
        if let Ok(n) = me.nominals() {
            assert!(
                n.iter().all(|x| *x > 0.0 && x.is_finite()),
                "nominals {n:?}"
            );
        }
        if let Ok(x) = me.states() {
            if let Ok(x) = me.rk4(time, &x, 0.01) {
                let _ = me.set_time(time + 0.01);
                let _ = me.set_states(&x);
                let _ = me.completed_integrator_step();
                finite("fmi2GetContinuousStates", me.states());
            }
        }
        let _ = me.enter_event_mode();
        let (status, info) = me.new_discrete_states();
        if matches!(status, fmi2OK | fmi2Warning) {
            for b in [
                info.newDiscreteStatesNeeded,
                info.terminateSimulation,
                info.nominalsOfContinuousStatesChanged,
                info.valuesOfContinuousStatesChanged,
                info.nextEventTimeDefined,
            ] {
                assert!(b == fmi2True || b == fmi2False, "{info:?}");
            }
        }
        let _ = me.enter_continuous_time_mode();
        finite("fmi2GetDerivatives", me.derivatives());
    } else {
        let status = fmu.do_step(time, 0.01);
        assert!(
            matches!(status, fmi2OK | fmi2Warning | fmi2Discard | fmi2Error),
            "fmi2DoStep: {status}"
        );
    }
    let fmu = if model_exchange { &mut me.fmu } else { &mut cs };
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
    no_internal_error(&fmu.messages());
    // Whatever state the instance is in now, it must be freeable: a reset must succeed.
    assert_eq!(
        fmu.reset(),
        fmi2OK,
        "the instance cannot be reset: {:?}",
        fmu.messages().last()
    );
});
