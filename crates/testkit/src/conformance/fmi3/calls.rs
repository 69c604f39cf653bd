//! FMU states through FMI 3.0 (continuing bit for bit, never crossing to FMI 2.0), instances
//! of one standard refused by the other's functions, and the state machine (event mode in
//! Co-Simulation among it).

use super::{bits, run, started, started_fmi2};
use crate::fmi3::{Fmi3Harness, Kind};
use mechfmu::fmi2::ffi::{fmi2Error, fmi2OK};
use mechfmu::fmi3::ffi::*;
use mechfmu::fmi3::functions as f3;
use mechfmu::model::Mechanism;

/// Runs every check of FMU states, foreign instances and the state machine.
pub fn check<M: Mechanism>() {
    fmu_state_continues_bit_for_bit::<M>();
    states_and_instances_do_not_cross_standards::<M>();
    calls_follow_the_state_machine::<M>();
}

/// `fmi3GetFMUState`/`fmi3SetFMUState` roll an instance back, and a state serialized and
/// deserialized into another instance continues there: bit for bit as the first run.
pub fn fmu_state_continues_bit_for_bit<M: Mechanism>() {
    let name = M::NAME;
    let mut fmu = started::<M>();
    run(&mut fmu, 0.2);
    let t1 = fmu.time();
    let state = fmu.get_fmu_state().expect("fmi3GetFMUState");
    let bytes = fmu.serialize(state).expect("fmi3SerializeFMUState");
    run(&mut fmu, 0.4);
    let first = bits(&fmu.all_values());
    assert_eq!(fmu.set_fmu_state(state), fmi3OK, "{name}: fmi3SetFMUState");
    fmu.rewind(t1);
    assert_eq!(
        fmu.get_values(&[fmu.time_vr()]),
        Ok(vec![t1]),
        "{name}: time after fmi3SetFMUState"
    );
    run(&mut fmu, 0.4);
    assert_eq!(
        bits(&fmu.all_values()),
        first,
        "{name}: a rolled-back run differs"
    );
    assert_eq!(fmu.free_fmu_state(state), fmi3OK);

    let mut other = Fmi3Harness::<M>::new();
    let restored = other.deserialize(&bytes).expect("fmi3DeserializeFMUState");
    assert_eq!(
        other.set_fmu_state(restored),
        fmi3OK,
        "{name}: {:?}",
        other.messages()
    );
    assert_eq!(
        other.serialize(restored),
        Ok(bytes),
        "{name}: serialization is not stable"
    );
    assert_eq!(other.free_fmu_state(restored), fmi3OK);
    other.rewind(t1);
    run(&mut other, 0.4);
    assert_eq!(
        bits(&other.all_values()),
        first,
        "{name}: a deserialized state runs differently"
    );
}

/// A state serialized by FMI 2.0 is refused by `fmi3DeserializeFMUState`, and the reverse,
/// with a message; so is a state handle of the other standard. An instance of one standard
/// passed to the other's functions is refused (its magic number differs) and left as it
/// was: it still steps, and can still be freed by its own standard.
pub fn states_and_instances_do_not_cross_standards<M: Mechanism>() {
    let (name, e) = (M::NAME, M::EXPERIMENT);
    let mut fmi2 = started_fmi2::<M>();
    let mut fmi3 = started::<M>();
    let state2 = fmi2.get_fmu_state().expect("fmi2GetFMUstate");
    let state3 = fmi3.get_fmu_state().expect("fmi3GetFMUState");
    let bytes2 = fmi2.serialize(state2).expect("fmi2SerializeFMUstate");
    let bytes3 = fmi3.serialize(state3).expect("fmi3SerializeFMUState");
    assert_eq!(
        fmi3.deserialize(&bytes2),
        Err(fmi3Error),
        "{name}: FMI 2.0's bytes accepted by FMI 3.0"
    );
    assert_eq!(
        fmi2.deserialize(&bytes3),
        Err(fmi2Error),
        "{name}: FMI 3.0's bytes accepted by FMI 2.0"
    );
    let message = "or of its other FMI version (instantiation token";
    assert!(
        fmi3.logged(message),
        "{name}: {message}: {:?}",
        fmi3.messages()
    );
    let message = "or of its other FMI version (GUID";
    assert!(
        fmi2.logged(message),
        "{name}: {message}: {:?}",
        fmi2.messages()
    );
    assert_eq!(
        fmi3.set_fmu_state(state2),
        fmi3Error,
        "{name}: an FMI 2.0 state set by FMI 3.0"
    );
    assert!(
        fmi3.logged("saved by an FMI 2.0 instance"),
        "{name}: {:?}",
        fmi3.messages()
    );
    assert_eq!(
        fmi2.set_fmu_state(state3),
        fmi2Error,
        "{name}: an FMI 3.0 state set by FMI 2.0"
    );
    assert!(
        fmi2.logged("saved by an FMI 3.0 instance"),
        "{name}: {:?}",
        fmi2.messages()
    );
    assert_eq!(
        (fmi2.free_fmu_state(state2), fmi3.free_fmu_state(state3)),
        (fmi2OK, fmi3OK)
    );

    let (c2, c3) = (fmi2.component(), fmi3.instance());
    let (logged2, logged3) = (fmi2.messages().len(), fmi3.messages().len());
    let (mut flag, mut time, mut value, vr) = (false, 0.0, [0.0], [0u32]);
    // SAFETY: live instances of M (of the other standard, which the wall refuses), valid
    // out-pointers and arrays of the given lengths.
    let statuses = unsafe {
        [
            f3::fmi3DoStep::<M>(
                c2, e.start, e.step, true, &mut flag, &mut flag, &mut flag, &mut time,
            ),
            f3::fmi3GetFloat64::<M>(c2, vr.as_ptr(), 1, value.as_mut_ptr(), 1),
            f3::fmi3Terminate::<M>(c2),
            f3::fmi3Reset::<M>(c2),
            mechfmu::fmi2::functions::fmi2DoStep::<M>(c3, e.start, e.step, 1),
            mechfmu::fmi2::functions::fmi2GetReal::<M>(c3, vr.as_ptr(), 1, value.as_mut_ptr()),
            mechfmu::fmi2::functions::fmi2Terminate::<M>(c3),
            mechfmu::fmi2::functions::fmi2Reset::<M>(c3),
        ]
    };
    assert_eq!(
        statuses, [fmi3Error; 8],
        "{name}: an instance of the other standard was accepted"
    );
    // SAFETY: as above; refused, so neither instance is freed.
    unsafe {
        f3::fmi3FreeInstance::<M>(c2);
        mechfmu::fmi2::functions::fmi2FreeInstance::<M>(c3);
    }
    assert_eq!(
        (fmi2.messages().len(), fmi3.messages().len()),
        (logged2, logged3),
        "{name}: a foreign call reached an instance's logger"
    );
    assert_eq!(
        fmi2.do_step(e.start, e.step),
        fmi2OK,
        "{name}: FMI 2.0 after foreign calls: {:?}",
        fmi2.messages()
    );
    assert_eq!(
        fmi3.do_step(e.start, e.step).status,
        fmi3OK,
        "{name}: FMI 3.0 after foreign calls: {:?}",
        fmi3.messages()
    );
}

/// Illegal sequences return fmi3Error with a message and leave the instance as it was: a
/// step before initialization, Model Exchange's calls on a Co-Simulation instance (and the
/// reverse), event mode without `eventModeUsed`. With `eventModeUsed`, initialization ends
/// in event mode, where the event iteration and `fmi3EnterStepMode` lead to steps equal to
/// those of an instance without event mode, and steps lead back to event mode.
pub fn calls_follow_the_state_machine<M: Mechanism>() {
    let (name, e) = (M::NAME, M::EXPERIMENT);
    let refused = |fmu: &Fmi3Harness<M>, status: fmi3Status, message: &str| {
        assert_eq!(
            status, fmi3Error,
            "{name}: accepted where `{message}` was expected"
        );
        assert!(
            fmu.logged(message),
            "{name}: {message}: {:?}",
            fmu.messages()
        );
    };
    let mut cs = Fmi3Harness::<M>::new();
    let status = cs.do_step(e.start, e.step).status;
    refused(
        &cs,
        status,
        "fmi3DoStep: illegal call sequence: the instance is instantiated",
    );
    cs.initialize(Some(e.tolerance), e.start, &[])
        .unwrap_or_else(|m| panic!("{name}: {m}"));
    let status = cs.set_continuous_states(&vec![0.0; M::STATES.len()]);
    let other = "a Model Exchange function, but the instance was instantiated for Co-Simulation";
    refused(&cs, status, &format!("fmi3SetContinuousStates: {other}"));
    let status = cs.enter_event_mode();
    refused(
        &cs,
        status,
        "fmi3EnterEventMode: the instance was instantiated with eventModeUsed = false",
    );
    let status = cs.update_discrete_states().0;
    refused(
        &cs,
        status,
        "fmi3UpdateDiscreteStates: illegal call sequence: the instance is step complete",
    );
    let status = cs.enter_step_mode();
    refused(&cs, status, "fmi3EnterStepMode: illegal call sequence");

    let mut events = Fmi3Harness::<M>::of_kind(Kind::CoSimulation {
        event_mode_used: true,
        early_return_allowed: false,
    });
    events
        .initialize(Some(e.tolerance), e.start, &[])
        .unwrap_or_else(|m| panic!("{name}: {m}"));
    let status = events.do_step(e.start, e.step).status;
    refused(
        &events,
        status,
        "fmi3DoStep: illegal call sequence: the instance is in event mode",
    );
    // A state saved in event mode is no state of an instance without event mode.
    let state = events.get_fmu_state().expect("fmi3GetFMUState");
    let bytes = events.serialize(state).expect("fmi3SerializeFMUState");
    assert_eq!(events.free_fmu_state(state), fmi3OK);
    let foreign = cs.deserialize(&bytes).expect("fmi3DeserializeFMUState");
    let status = cs.set_fmu_state(foreign);
    refused(
        &cs,
        status,
        "fmi3SetFMUState: the FMU state was saved in event mode",
    );
    assert_eq!(cs.free_fmu_state(foreign), fmi3OK);
    for n in 0..2 {
        let t = e.start + n as f64 * e.step;
        if n > 0 {
            assert_eq!(
                events.enter_event_mode(),
                fmi3OK,
                "{name}: fmi3EnterEventMode: {:?}",
                events.messages()
            );
        }
        let (status, update) = events.update_discrete_states();
        assert!(
            status <= fmi3Warning && !update.terminate_simulation,
            "{name}: fmi3UpdateDiscreteStates: {update:?}: {:?}",
            events.messages()
        );
        assert!(
            !update.discrete_states_need_update && !update.next_event_time_defined,
            "{name}: {update:?}"
        );
        assert_eq!(
            events.enter_step_mode(),
            fmi3OK,
            "{name}: fmi3EnterStepMode: {:?}",
            events.messages()
        );
        let step = events.do_step(t, e.step);
        assert_eq!(
            step.status,
            cs.do_step(t, e.step).status,
            "{name}: {step:?}: {:?}",
            events.messages()
        );
        assert_eq!(
            bits(&events.all_values()),
            bits(&cs.all_values()),
            "{name}: steps after event mode differ at t = {}",
            t + e.step
        );
    }

    let mut me = Fmi3Harness::<M>::model_exchange();
    me.initialize_model_exchange(Some(e.tolerance), e.start, &[])
        .unwrap_or_else(|m| panic!("{name}: {m}"));
    let status = me.do_step(e.start, e.step).status;
    let other = "a Co-Simulation function, but the instance was instantiated for Model Exchange";
    refused(&me, status, &format!("fmi3DoStep: {other}"));
    let status = me.set_continuous_states(&vec![0.0; M::STATES.len() + 1]);
    refused(
        &me,
        status,
        &format!(
            "nContinuousStates = {}, but the FMU has {}",
            M::STATES.len() + 1,
            M::STATES.len()
        ),
    );
    assert_eq!(
        me.derivatives().map(|d| d.len()),
        Ok(M::STATES.len()),
        "{name}: {:?}",
        me.messages()
    );
}
