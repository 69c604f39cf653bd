//! The C boundary checks a call's arguments in the order the standard's functions take them
//! and reads no pointer it has not yet accepted: through the generic C functions, in-process.

use mechfmu::fmi2::ffi::*;
use mechfmu::fmi2::functions;
use mechfmu::model::{Experiment, Mechanism, Scalar, Variable};
use mechfmu_testkit::harness::{Harness, MessageLog, ONE_SECOND};

mechfmu::mechanism! {
    /// Decay: y' = -k y.
    pub struct Decay / DecayValues {
        /// Rate
        k: Variable::parameter("1/s", 1.0),
        /// Amount
        y: Variable::state("1", 1.0, "y_dot"),
        /// Rate of change
        y_dot: Variable::output("1/s"),
    }
}

impl Mechanism for Decay {
    const EXPERIMENT: Experiment = ONE_SECOND;
    fn evaluate<S: Scalar>(v: &mut DecayValues<S>) {
        v.y_dot = -v.k * v.y;
    }
}

fn started() -> Harness<Decay> {
    let mut fmu = Harness::<Decay>::new();
    fmu.initialize(None, 0.0, &[]).unwrap();
    fmu
}

#[test]
fn a_wrong_size_is_refused_before_the_buffer_is_looked_at() {
    let mut fmu = started();
    let state = fmu.get_fmu_state().unwrap();
    let size = fmu.serialize(state).unwrap().len();
    // A NULL buffer with a wrong size: the size is what is wrong.
    let status = unsafe {
        functions::fmi2SerializeFMUstate::<Decay>(
            fmu.component(),
            state,
            std::ptr::null_mut(),
            size + 5,
        )
    };
    assert_eq!(status, fmi2Error);
    assert!(
        fmu.logged(&format!(
            "size = {}, but the serialized state has {size} bytes",
            size + 5
        )),
        "{:?}",
        fmu.messages()
    );
    // The right size with a NULL buffer: now the buffer is.
    let status = unsafe {
        functions::fmi2SerializeFMUstate::<Decay>(
            fmu.component(),
            state,
            std::ptr::null_mut(),
            size,
        )
    };
    assert_eq!(status, fmi2Error);
    assert!(
        fmu.logged("serializedState[] is NULL"),
        "{:?}",
        fmu.messages()
    );
    assert_eq!(fmu.free_fmu_state(state), fmi2OK);
}

#[test]
fn bytes_that_are_no_state_are_refused_before_the_slot_is_looked_at() {
    let fmu = started();
    let bytes = [0u8; 16];
    let status = unsafe {
        functions::fmi2DeSerializeFMUstate::<Decay>(
            fmu.component(),
            bytes.as_ptr() as *const fmi2Byte,
            bytes.len(),
            std::ptr::null_mut(),
        )
    };
    assert_eq!(status, fmi2Error);
    assert!(!fmu.logged("FMUstate is NULL"), "{:?}", fmu.messages());
    assert!(
        fmu.logged("not a serialized mechfmu FMU state"),
        "{:?}",
        fmu.messages()
    );
}

#[test]
fn a_null_category_is_named_as_one() {
    let fmu = started();
    let categories = [c"logEvents".as_ptr(), std::ptr::null()];
    let status = unsafe {
        functions::fmi2SetDebugLogging::<Decay>(fmu.component(), fmi2True, 2, categories.as_ptr())
    };
    assert_eq!(status, fmi2Error);
    assert!(
        fmu.logged("a category is NULL or not UTF-8"),
        "{:?}",
        fmu.messages()
    );
}

/// A call that names an unknown category changes none: the error categories it would
/// switch off stay on, so its own error and the next ones are logged.
#[test]
fn an_unknown_category_changes_no_category() {
    let fmu = started();
    let categories = [c"logStatusError".as_ptr(), c"noSuchCategory".as_ptr()];
    let status = unsafe {
        functions::fmi2SetDebugLogging::<Decay>(fmu.component(), fmi2False, 2, categories.as_ptr())
    };
    assert_eq!(status, fmi2Error);
    assert!(
        fmu.logged("unknown log category \"noSuchCategory\""),
        "{:?}",
        fmu.messages()
    );
    let mut value = [0.0];
    let status = unsafe {
        functions::fmi2GetReal::<Decay>(fmu.component(), [12345].as_ptr(), 1, value.as_mut_ptr())
    };
    assert_eq!(status, fmi2Error);
    assert!(fmu.logged("value reference 12345"), "{:?}", fmu.messages());
}

/// An importer's garbage GUID pointer is not read when the name or the type is refused
/// first (reading it would fault: it points nowhere).
#[test]
fn the_guid_is_read_only_once_the_name_and_the_type_are_accepted() {
    let log = MessageLog::new();
    let nowhere = 8 as fmi2String;
    let empty_name = unsafe {
        functions::fmi2Instantiate::<Decay>(
            c"".as_ptr(),
            fmi2CoSimulation,
            nowhere,
            std::ptr::null(),
            log.callbacks(),
            fmi2False,
            fmi2False,
        )
    };
    assert!(empty_name.is_null());
    let wrong_type = unsafe {
        functions::fmi2Instantiate::<Decay>(
            c"decay".as_ptr(),
            7,
            nowhere,
            std::ptr::null(),
            log.callbacks(),
            fmi2False,
            fmi2False,
        )
    };
    assert!(wrong_type.is_null());
    let messages: Vec<String> = log.messages().into_iter().map(|(_, _, m)| m).collect();
    assert!(
        messages[0].contains("instanceName is NULL or empty"),
        "{messages:?}"
    );
    assert!(
        messages[1].contains("neither fmi2ModelExchange (0) nor fmi2CoSimulation (1)"),
        "{messages:?}"
    );
}

/// A GUID that is no UTF-8 text is not called NULL: the message says what was expected.
#[test]
fn a_guid_that_is_not_text_is_named_as_one() {
    let log = MessageLog::new();
    let component = unsafe {
        functions::fmi2Instantiate::<Decay>(
            c"decay".as_ptr(),
            fmi2CoSimulation,
            c"\xff\xfe".as_ptr(),
            std::ptr::null(),
            log.callbacks(),
            fmi2False,
            fmi2False,
        )
    };
    assert!(component.is_null());
    let messages: Vec<String> = log.messages().into_iter().map(|(_, _, m)| m).collect();
    let expected = mechfmu::contract::guid::<Decay>();
    assert!(
        messages[0].contains(&format!(
            "fmuGUID is NULL or not UTF-8 (expected \"{expected}\")"
        )),
        "{messages:?}"
    );
}

/// Model Exchange's pointer arguments: NULL is refused with a message naming it, and the
/// instance goes on.
#[test]
fn model_exchange_refuses_null_arguments_by_name() {
    let mut me = mechfmu_testkit::model_exchange::ModelExchange::<Decay>::new();
    me.initialize(None, 0.0, &[]).unwrap();
    let c = me.fmu.component();
    let null = std::ptr::null_mut::<f64>();
    let mut flag = fmi2False;
    let statuses = unsafe {
        [
            functions::fmi2SetContinuousStates::<Decay>(c, null, 1),
            functions::fmi2GetDerivatives::<Decay>(c, null, 1),
            functions::fmi2GetContinuousStates::<Decay>(c, null, 1),
            functions::fmi2GetNominalsOfContinuousStates::<Decay>(c, null, 1),
            functions::fmi2CompletedIntegratorStep::<Decay>(
                c,
                fmi2True,
                std::ptr::null_mut(),
                &mut flag,
            ),
            functions::fmi2CompletedIntegratorStep::<Decay>(
                c,
                fmi2True,
                &mut flag,
                std::ptr::null_mut(),
            ),
        ]
    };
    assert_eq!(statuses, [fmi2Error; 6]);
    for name in [
        "x[] is NULL",
        "derivatives[] is NULL",
        "x_nominal[] is NULL",
        "enterEventMode is NULL",
        "terminateSimulation is NULL",
    ] {
        assert!(me.fmu.logged(name), "{name}: {:?}", me.messages());
    }
    assert_eq!(me.enter_event_mode(), fmi2OK);
    assert_eq!(
        unsafe { functions::fmi2NewDiscreteStates::<Decay>(c, std::ptr::null_mut()) },
        fmi2Error
    );
    assert!(me.fmu.logged("fmi2eventInfo is NULL"));
    // No event indicators: an empty array is the only right one.
    assert_eq!(
        unsafe { functions::fmi2GetEventIndicators::<Decay>(c, null, 0) },
        fmi2OK
    );
    assert_eq!(me.enter_continuous_time_mode(), fmi2OK);
    assert!(me.derivatives().unwrap()[0] < 0.0);
}

/// Serialized bytes can be edited (the checksum is no secret): a state claiming values up to
/// date that evaluate to a number no more is refused by fmi2SetFMUstate, and the instance
/// stays as it was.
#[test]
fn a_forged_state_whose_values_do_not_hold_is_refused() {
    use mechfmu::fmi::fmu_state::FmuState;
    let mut fmu = started();
    let state = fmu.get_fmu_state().unwrap();
    let bytes = fmu.serialize(state).unwrap();
    let mut forged = FmuState::from_bytes::<Decay>(&bytes, mechfmu::fmi::Version::Fmi2).unwrap();
    // k y overflows: y_dot = -inf.
    forged.sim.values[0] = f64::MAX;
    forged.sim.values[1] = f64::MAX;
    let handle = fmu.deserialize(&forged.to_bytes::<Decay>()).unwrap();
    assert_eq!(fmu.set_fmu_state(handle), fmi2Error);
    assert!(
        fmu.logged("the state's values do not hold"),
        "{:?}",
        fmu.messages()
    );
    assert_eq!((fmu.get("k"), fmu.get("y")), (1.0, 1.0));
    assert_eq!(fmu.do_step(0.0, 0.1), fmi2OK);
    fmu.free_fmu_state(handle);
    fmu.free_fmu_state(state);
}
