//! FMI 3.0's C boundary: whatever pointers an importer passes (NULL, misaligned, freed, of
//! absurd lengths), a call refuses them with fmi3Error (NULL from an instantiation, nothing
//! from fmi3FreeInstance) and a message naming the argument where there is an instance to
//! log to, and never crashes; the instance goes on. Through the generic C functions,
//! in-process.

use mechfmu::fmi3::ffi::*;
use mechfmu::fmi3::functions as f;
use mechfmu::model::{Array, Experiment, Mechanism, Scalar, Variable};
use mechfmu_testkit::fmi3::{self, Fmi3Harness};
use mechfmu_testkit::harness::{MessageLog, ONE_SECOND};

mechfmu::mechanism! {
    /// Decay of two amounts: y' = -k y.
    pub struct Decay / DecayValues {
        /// Rate
        k: Variable::parameter("1/s", 1.0),
        /// First amount
        y1: Variable::state("1", 1.0, "y1_dot"),
        /// Second amount
        y2: Variable::state("1", 2.0, "y2_dot"),
        /// Rate of change of the first amount
        y1_dot: Variable::output("1/s"),
        /// Rate of change of the second amount
        y2_dot: Variable::output("1/s"),
    }
}

impl Mechanism for Decay {
    const EXPERIMENT: Experiment = ONE_SECOND;
    const ARRAYS: &'static [Array] = &[
        Array::new("y", "Amounts", &[2], &["y1", "y2"]),
        Array::new("y_dot", "Rates of change", &[2], &["y1_dot", "y2_dot"]),
    ];
    fn evaluate<S: Scalar>(v: &mut DecayValues<S>) {
        v.y1_dot = -v.k * v.y1;
        v.y2_dot = -v.k * v.y2;
    }
}

#[path = "wall_fmi3/arguments.rs"]
mod arguments;

type Fmu = Fmi3Harness<Decay>;

fn started() -> Fmu {
    let mut fmu = Fmu::new();
    fmu.initialize(None, 0.0, &[]).unwrap();
    fmu
}

fn started_model_exchange() -> Fmu {
    let mut fmu = Fmu::model_exchange();
    fmu.initialize_model_exchange(None, 0.0, &[]).unwrap();
    fmu
}

/// Asserts every status is fmi3Error and every text was logged.
fn refused(fmu: &Fmu, statuses: &[fmi3Status], texts: &[&str]) {
    for (i, &status) in statuses.iter().enumerate() {
        assert_eq!(status, fmi3Error, "call {i}: {:?}", fmu.messages());
    }
    for text in texts {
        assert!(fmu.logged(text), "{text}: {:?}", fmu.messages());
    }
}

/// The statuses of a representative set of the 75 functions called on instance `$c` with
/// otherwise valid arguments (FreeInstance last: it returns nothing).
macro_rules! every_call {
    ($c:expr) => {{
        let c: fmi3Instance = $c;
        let (vr, mut x, mut b, mut n) = ([0u32, 1], [0.0f64; 2], [false; 4], 0usize);
        let (mut state, mut bytes, mut i32s) = (std::ptr::null_mut(), [0u8; 8], [0i32; 2]);
        let category = [c"logEvents".as_ptr()];
        let statuses = unsafe {
            [
                f::fmi3SetDebugLogging::<Decay>(c, true, 1, category.as_ptr()),
                f::fmi3EnterInitializationMode::<Decay>(c, false, 0.0, 0.0, false, 0.0),
                f::fmi3ExitInitializationMode::<Decay>(c),
                f::fmi3EnterEventMode::<Decay>(c),
                f::fmi3Terminate::<Decay>(c),
                f::fmi3Reset::<Decay>(c),
                f::fmi3GetFloat64::<Decay>(c, vr.as_ptr(), 1, x.as_mut_ptr(), 2),
                f::fmi3SetFloat64::<Decay>(c, vr.as_ptr(), 1, x.as_ptr(), 2),
                f::fmi3GetFloat32::<Decay>(c, vr.as_ptr(), 0, std::ptr::null_mut(), 0),
                f::fmi3GetInt32::<Decay>(c, vr.as_ptr(), 1, i32s.as_mut_ptr(), 1),
                f::fmi3SetBoolean::<Decay>(c, vr.as_ptr(), 1, b.as_ptr(), 1),
                f::fmi3GetClock::<Decay>(c, vr.as_ptr(), 1, b.as_mut_ptr()),
                f::fmi3GetNumberOfVariableDependencies::<Decay>(c, 0, &mut n),
                f::fmi3GetFMUState::<Decay>(c, &mut state),
                f::fmi3SetFMUState::<Decay>(c, state),
                f::fmi3SerializedFMUStateSize::<Decay>(c, state, &mut n),
                f::fmi3SerializeFMUState::<Decay>(c, state, bytes.as_mut_ptr(), 8),
                f::fmi3DeserializeFMUState::<Decay>(c, bytes.as_ptr(), 8, &mut state),
                f::fmi3FreeFMUState::<Decay>(c, &mut state),
                f::fmi3GetDirectionalDerivative::<Decay>(
                    c,
                    vr.as_ptr(),
                    1,
                    vr.as_ptr(),
                    1,
                    x.as_ptr(),
                    2,
                    x.as_mut_ptr(),
                    2,
                ),
                f::fmi3GetAdjointDerivative::<Decay>(
                    c,
                    vr.as_ptr(),
                    1,
                    vr.as_ptr(),
                    1,
                    x.as_ptr(),
                    2,
                    x.as_mut_ptr(),
                    2,
                ),
                f::fmi3EnterConfigurationMode::<Decay>(c),
                f::fmi3EvaluateDiscreteStates::<Decay>(c),
                f::fmi3UpdateDiscreteStates::<Decay>(
                    c, &mut b[0], &mut b[1], &mut b[2], &mut b[3], &mut b[0], &mut x[0],
                ),
                f::fmi3EnterContinuousTimeMode::<Decay>(c),
                f::fmi3CompletedIntegratorStep::<Decay>(c, true, &mut b[0], &mut b[1]),
                f::fmi3SetTime::<Decay>(c, 0.0),
                f::fmi3SetContinuousStates::<Decay>(c, x.as_ptr(), 2),
                f::fmi3GetContinuousStateDerivatives::<Decay>(c, x.as_mut_ptr(), 2),
                f::fmi3GetEventIndicators::<Decay>(c, x.as_mut_ptr(), 0),
                f::fmi3GetContinuousStates::<Decay>(c, x.as_mut_ptr(), 2),
                f::fmi3GetNominalsOfContinuousStates::<Decay>(c, x.as_mut_ptr(), 2),
                f::fmi3GetNumberOfEventIndicators::<Decay>(c, &mut n),
                f::fmi3GetNumberOfContinuousStates::<Decay>(c, &mut n),
                f::fmi3EnterStepMode::<Decay>(c),
                f::fmi3GetOutputDerivatives::<Decay>(
                    c,
                    vr.as_ptr(),
                    1,
                    i32s.as_ptr(),
                    x.as_mut_ptr(),
                    2,
                ),
                f::fmi3DoStep::<Decay>(
                    c, 0.0, 0.1, true, &mut b[0], &mut b[1], &mut b[2], &mut x[0],
                ),
                f::fmi3ActivateModelPartition::<Decay>(c, 0, 0.0),
            ]
        };
        unsafe { f::fmi3FreeInstance::<Decay>(c) };
        statuses
    }};
}

#[test]
fn a_null_or_misaligned_instance_is_an_error_everywhere() {
    for c in [
        std::ptr::null_mut(),
        std::ptr::without_provenance_mut(1),
        std::ptr::without_provenance_mut(12),
    ] {
        let statuses = every_call!(c);
        assert!(
            statuses.iter().all(|&s| s == fmi3Error),
            "{c:?}: {statuses:?}"
        );
    }
}

/// The instance's memory is released by the first free, whose magic number it clears
/// first: later calls, a second free among them, find no live instance there. The memory
/// (a small allocation, which the allocator keeps mapped) is not yet another instance's:
/// nothing is allocated between the free and the calls.
#[test]
fn a_freed_instance_is_refused_and_a_second_free_does_nothing() {
    for kind in [fmi3::CO_SIMULATION, fmi3::Kind::ModelExchange] {
        let log = MessageLog::new();
        let token =
            std::ffi::CString::new(mechfmu::contract::instantiation_token::<Decay>()).unwrap();
        let c = unsafe {
            match kind {
                fmi3::Kind::ModelExchange => f::fmi3InstantiateModelExchange::<Decay>(
                    c"decay".as_ptr(),
                    token.as_ptr(),
                    std::ptr::null(),
                    false,
                    true,
                    log.environment(),
                    Some(fmi3::record),
                ),
                _ => f::fmi3InstantiateCoSimulation::<Decay>(
                    c"decay".as_ptr(),
                    token.as_ptr(),
                    std::ptr::null(),
                    false,
                    true,
                    false,
                    false,
                    std::ptr::null(),
                    0,
                    log.environment(),
                    Some(fmi3::record),
                    None,
                ),
            }
        };
        assert!(!c.is_null(), "{:?}", log.messages());
        let logged = log.messages().len();
        unsafe { f::fmi3FreeInstance::<Decay>(c) };
        let statuses = every_call!(c);
        assert!(statuses.iter().all(|&s| s == fmi3Error), "{statuses:?}");
        assert_eq!(log.messages().len(), logged, "{:?}", log.messages());
    }
}

/// An FMU state freed through one copy of its handle is refused through another (its magic
/// number is cleared when freed; nothing is allocated in between).
#[test]
fn a_freed_fmu_state_is_refused() {
    let mut fmu = started();
    let c = fmu.instance();
    let mut state = fmu.get_fmu_state().unwrap();
    let mut stale = state;
    let mut size = 0usize;
    let statuses = unsafe {
        [
            f::fmi3FreeFMUState::<Decay>(c, &mut state),
            f::fmi3SetFMUState::<Decay>(c, stale),
            f::fmi3SerializedFMUStateSize::<Decay>(c, stale, &mut size),
            f::fmi3FreeFMUState::<Decay>(c, &mut stale),
        ]
    };
    assert_eq!(statuses[0], fmi3OK);
    assert!(state.is_null(), "the slot freed is set to NULL");
    refused(&fmu, &statuses[1..], &["is not a live state of this FMU"]);
    // Freeing a NULL state is nothing to do.
    assert_eq!(
        unsafe { f::fmi3FreeFMUState::<Decay>(c, &mut state) },
        fmi3OK
    );
    assert_eq!(fmu.do_step(0.0, 0.1).status, fmi3OK);
}

#[test]
fn instantiation_refuses_bad_arguments_with_a_message() {
    let token = mechfmu::contract::instantiation_token::<Decay>();
    let token = std::ffi::CString::new(token).unwrap();
    let instantiate = |name: *const std::ffi::c_char,
                       token: *const std::ffi::c_char,
                       required: *const u32,
                       n_required: usize,
                       logged: bool| {
        let log = MessageLog::new();
        let logger: fmi3LogMessageCallback = logged.then_some(fmi3::record as _);
        let c = unsafe {
            f::fmi3InstantiateCoSimulation::<Decay>(
                name,
                token,
                std::ptr::null(),
                false,
                true,
                false,
                false,
                required,
                n_required,
                log.environment(),
                logger,
                None,
            )
        };
        let messages: Vec<String> = log.messages().into_iter().map(|(_, _, m)| m).collect();
        if !c.is_null() {
            unsafe { f::fmi3FreeInstance::<Decay>(c) };
        }
        (c.is_null(), messages)
    };
    let (none, no_vr) = (std::ptr::null(), std::ptr::null());
    let vr = [0u32];
    for (name, tok, required, n, expected) in [
        (
            none,
            token.as_ptr(),
            no_vr,
            0,
            "instanceName is NULL or empty",
        ),
        (
            c"".as_ptr(),
            token.as_ptr(),
            no_vr,
            0,
            "instanceName is NULL or empty",
        ),
        (
            c"decay".as_ptr(),
            none,
            no_vr,
            0,
            "instantiationToken is NULL",
        ),
        (
            c"decay".as_ptr(),
            c"{0}".as_ptr(),
            no_vr,
            0,
            "does not match this binary's",
        ),
        (
            c"decay".as_ptr(),
            token.as_ptr(),
            no_vr,
            1,
            "requiredIntermediateVariables[] is NULL",
        ),
        (
            c"decay".as_ptr(),
            token.as_ptr(),
            vr.as_ptr(),
            1,
            "nRequiredIntermediateVariables = 1",
        ),
        (
            c"decay".as_ptr(),
            token.as_ptr(),
            vr.as_ptr(),
            1 << 40,
            "implausible length",
        ),
    ] {
        let (null, messages) = instantiate(name, tok, required, n, true);
        assert!(null, "{expected}: an instance");
        assert!(
            messages.len() == 1
                && messages[0].starts_with("fmi3InstantiateCoSimulation: ")
                && messages[0].contains(expected),
            "{expected}: {messages:?}"
        );
        // Without a logger: NULL all the same, and nothing to crash on.
        assert_eq!(instantiate(name, tok, required, n, false), (true, vec![]));
    }
    // Without a logger a valid instantiation succeeds: the logger is optional.
    assert!(!instantiate(c"decay".as_ptr(), token.as_ptr(), no_vr, 0, false).0);
}
