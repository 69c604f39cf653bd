//! The arguments of a live instance's calls: NULL, misaligned or absurdly long arrays and
//! NULL or misaligned out pointers are refused with fmi3Error and a message naming them,
//! and the instance goes on.

use super::{f, refused, started, started_model_exchange, Decay};
use mechfmu::fmi3::ffi::*;

#[test]
fn null_arrays_with_a_length_are_refused_by_name() {
    let mut fmu = started();
    let c = fmu.instance();
    let (vr, mut x, orders) = ([1u32], [0.0; 2], [1i32]);
    let (null_vr, null_x) = (std::ptr::null::<u32>(), std::ptr::null_mut::<f64>());
    let statuses = unsafe {
        [
            f::fmi3GetFloat64::<Decay>(c, null_vr, 1, x.as_mut_ptr(), 2),
            f::fmi3GetFloat64::<Decay>(c, vr.as_ptr(), 1, null_x, 2),
            f::fmi3SetFloat64::<Decay>(c, vr.as_ptr(), 1, null_x, 2),
            f::fmi3GetInt8::<Decay>(c, vr.as_ptr(), 1, std::ptr::null_mut(), 1),
            f::fmi3GetBinary::<Decay>(
                c,
                vr.as_ptr(),
                1,
                std::ptr::null_mut(),
                [std::ptr::null()].as_mut_ptr(),
                1,
            ),
            f::fmi3SetDebugLogging::<Decay>(c, true, 1, std::ptr::null()),
            f::fmi3DeserializeFMUState::<Decay>(c, std::ptr::null(), 10, &mut std::ptr::null_mut()),
            f::fmi3GetDirectionalDerivative::<Decay>(
                c,
                vr.as_ptr(),
                1,
                vr.as_ptr(),
                1,
                null_x,
                2,
                x.as_mut_ptr(),
                2,
            ),
            f::fmi3GetAdjointDerivative::<Decay>(
                c,
                vr.as_ptr(),
                1,
                null_vr,
                1,
                x.as_ptr(),
                2,
                x.as_mut_ptr(),
                2,
            ),
            f::fmi3GetOutputDerivatives::<Decay>(c, vr.as_ptr(), 1, orders.as_ptr(), null_x, 2),
            f::fmi3GetOutputDerivatives::<Decay>(
                c,
                vr.as_ptr(),
                1,
                std::ptr::null(),
                x.as_mut_ptr(),
                2,
            ),
        ]
    };
    refused(
        &fmu,
        &statuses,
        &[
            "fmi3GetFloat64: valueReferences[] is NULL but its length is 1",
            "fmi3GetFloat64: values[] is NULL but its length is 2",
            "fmi3SetFloat64: values[] is NULL but its length is 2",
            "fmi3GetInt8: values[] is NULL but its length is 1",
            "fmi3GetBinary: valueSizes[] is NULL but its length is 1",
            "fmi3SetDebugLogging: categories[] is NULL but its length is 1",
            "fmi3DeserializeFMUState: serializedState[] is NULL but its length is 10",
            "fmi3GetDirectionalDerivative: seed[] is NULL but its length is 2",
            "fmi3GetAdjointDerivative: knowns[] is NULL but its length is 1",
            "fmi3GetOutputDerivatives: values[] is NULL but its length is 2",
            "fmi3GetOutputDerivatives: orders[] is NULL but its length is 1",
        ],
    );
    assert_eq!(fmu.do_step(0.0, 0.1).status, fmi3OK, "{:?}", fmu.messages());

    let fmu = started_model_exchange();
    let c = fmu.instance();
    let statuses = unsafe {
        [
            f::fmi3SetContinuousStates::<Decay>(c, null_x, 2),
            f::fmi3GetContinuousStateDerivatives::<Decay>(c, null_x, 2),
            f::fmi3GetContinuousStates::<Decay>(c, null_x, 2),
            f::fmi3GetNominalsOfContinuousStates::<Decay>(c, null_x, 2),
            f::fmi3GetEventIndicators::<Decay>(c, null_x, 1),
        ]
    };
    refused(
        &fmu,
        &statuses,
        &[
            "fmi3SetContinuousStates: continuousStates[] is NULL but its length is 2",
            "fmi3GetContinuousStateDerivatives: derivatives[] is NULL but its length is 2",
            "fmi3GetContinuousStates: continuousStates[] is NULL but its length is 2",
            "fmi3GetNominalsOfContinuousStates: nominals[] is NULL but its length is 2",
            "fmi3GetEventIndicators: eventIndicators[] is NULL but its length is 1",
        ],
    );
    // No event indicators: an empty array is the only right one, NULL or not.
    assert_eq!(
        unsafe { f::fmi3GetEventIndicators::<Decay>(c, null_x, 0) },
        fmi3OK
    );
}

#[test]
fn misaligned_arrays_and_out_pointers_are_refused() {
    let mut fmu = started();
    let c = fmu.instance();
    let mut buffer = [0u64; 8];
    let odd = unsafe { (buffer.as_mut_ptr() as *mut u8).add(1) };
    let (vr, mut x, mut flag) = ([1u32], [0.0; 2], false);
    let statuses = unsafe {
        [
            f::fmi3GetFloat64::<Decay>(c, odd as *const u32, 1, x.as_mut_ptr(), 2),
            f::fmi3SetFloat64::<Decay>(c, vr.as_ptr(), 1, odd as *const f64, 2),
            f::fmi3DoStep::<Decay>(
                c,
                0.0,
                0.1,
                true,
                &mut flag,
                &mut flag,
                &mut flag,
                odd as *mut f64,
            ),
            f::fmi3GetFMUState::<Decay>(c, odd as *mut fmi3FMUState),
            f::fmi3SetFMUState::<Decay>(c, odd as fmi3FMUState),
        ]
    };
    refused(
        &fmu,
        &statuses,
        &[
            "fmi3GetFloat64: valueReferences[] is misaligned for its type",
            "fmi3SetFloat64: values[] is misaligned for its type",
            "fmi3DoStep: lastSuccessfulTime is misaligned for its type",
            "fmi3GetFMUState: FMUState is misaligned for its type",
            "fmi3SetFMUState: the FMU state is misaligned for its type",
        ],
    );
    assert_eq!(fmu.do_step(0.0, 0.1).status, fmi3OK, "{:?}", fmu.messages());
}

#[test]
fn null_out_pointers_are_refused_by_name() {
    let mut fmu = started();
    let c = fmu.instance();
    let (mut flag, mut time) = (false, 0.0);
    let null_flag = std::ptr::null_mut::<bool>();
    let state = fmu.get_fmu_state().unwrap();
    let statuses = unsafe {
        [
            f::fmi3DoStep::<Decay>(
                c, 0.0, 0.1, true, null_flag, &mut flag, &mut flag, &mut time,
            ),
            f::fmi3DoStep::<Decay>(
                c, 0.0, 0.1, true, &mut flag, null_flag, &mut flag, &mut time,
            ),
            f::fmi3DoStep::<Decay>(
                c, 0.0, 0.1, true, &mut flag, &mut flag, null_flag, &mut time,
            ),
            f::fmi3DoStep::<Decay>(
                c,
                0.0,
                0.1,
                true,
                &mut flag,
                &mut flag,
                &mut flag,
                std::ptr::null_mut(),
            ),
            f::fmi3GetFMUState::<Decay>(c, std::ptr::null_mut()),
            f::fmi3FreeFMUState::<Decay>(c, std::ptr::null_mut()),
            f::fmi3SerializedFMUStateSize::<Decay>(c, state, std::ptr::null_mut()),
            f::fmi3SetFMUState::<Decay>(c, std::ptr::null_mut()),
        ]
    };
    refused(
        &fmu,
        &statuses,
        &[
            "fmi3DoStep: eventHandlingNeeded is NULL",
            "fmi3DoStep: terminateSimulation is NULL",
            "fmi3DoStep: earlyReturn is NULL",
            "fmi3DoStep: lastSuccessfulTime is NULL",
            "fmi3GetFMUState: FMUState is NULL",
            "fmi3FreeFMUState: FMUState is NULL",
            "fmi3SerializedFMUStateSize: size is NULL",
            "fmi3SetFMUState: the FMU state is NULL",
        ],
    );
    // A refused step did not move the instance: the step from 0 is still the next one.
    assert_eq!(fmu.do_step(0.0, 0.1).status, fmi3OK, "{:?}", fmu.messages());
    assert_eq!(fmu.free_fmu_state(state), fmi3OK);

    let mut me = started_model_exchange();
    let c = me.instance();
    let statuses = unsafe {
        [
            f::fmi3GetNumberOfContinuousStates::<Decay>(c, std::ptr::null_mut()),
            f::fmi3GetNumberOfEventIndicators::<Decay>(c, std::ptr::null_mut()),
            f::fmi3CompletedIntegratorStep::<Decay>(c, true, null_flag, &mut flag),
            f::fmi3CompletedIntegratorStep::<Decay>(c, true, &mut flag, null_flag),
        ]
    };
    refused(
        &me,
        &statuses,
        &[
            "fmi3GetNumberOfContinuousStates: nContinuousStates is NULL",
            "fmi3GetNumberOfEventIndicators: nEventIndicators is NULL",
            "fmi3CompletedIntegratorStep: enterEventMode is NULL",
            "fmi3CompletedIntegratorStep: terminateSimulation is NULL",
        ],
    );
    assert_eq!(me.number_of_continuous_states(), Ok(2));
    // fmi3UpdateDiscreteStates writes only the out arguments the importer passes.
    assert_eq!(me.enter_event_mode(), fmi3OK);
    let status = unsafe {
        f::fmi3UpdateDiscreteStates::<Decay>(
            c,
            null_flag,
            null_flag,
            null_flag,
            null_flag,
            null_flag,
            std::ptr::null_mut(),
        )
    };
    assert_eq!(status, fmi3OK, "{:?}", me.messages());
}

#[test]
fn huge_lengths_are_refused_before_anything_is_read() {
    let mut fmu = started();
    let c = fmu.instance();
    let huge = 1usize << 40;
    let (vr, mut x, orders, bytes) = ([1u32], [0.0; 2], [1i32], [0u8; 8]);
    let categories = [c"logEvents".as_ptr()];
    let state = fmu.get_fmu_state().unwrap();
    let statuses = unsafe {
        [
            f::fmi3GetFloat64::<Decay>(c, vr.as_ptr(), huge, x.as_mut_ptr(), 2),
            f::fmi3GetFloat64::<Decay>(c, vr.as_ptr(), 1, x.as_mut_ptr(), usize::MAX),
            f::fmi3SetFloat64::<Decay>(c, vr.as_ptr(), 1, x.as_ptr(), huge),
            f::fmi3SetDebugLogging::<Decay>(c, true, huge, categories.as_ptr()),
            f::fmi3DeserializeFMUState::<Decay>(c, bytes.as_ptr(), huge, &mut std::ptr::null_mut()),
            f::fmi3SerializeFMUState::<Decay>(c, state, x.as_mut_ptr() as *mut u8, huge),
            f::fmi3GetDirectionalDerivative::<Decay>(
                c,
                vr.as_ptr(),
                1,
                vr.as_ptr(),
                huge,
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
                huge,
                x.as_mut_ptr(),
                2,
            ),
            f::fmi3GetOutputDerivatives::<Decay>(
                c,
                vr.as_ptr(),
                huge,
                orders.as_ptr(),
                x.as_mut_ptr(),
                2,
            ),
            f::fmi3SetInt64::<Decay>(c, vr.as_ptr(), 1, [0i64].as_ptr(), huge),
        ]
    };
    refused(
        &fmu,
        &statuses,
        &[
            &format!("fmi3GetFloat64: valueReferences[] has an implausible length {huge}"),
            &format!(
                "fmi3GetFloat64: values[] has an implausible length {}",
                usize::MAX
            ),
            &format!("fmi3SetFloat64: values[] has an implausible length {huge}"),
            &format!("fmi3SetDebugLogging: categories[] has an implausible length {huge}"),
            &format!("fmi3DeserializeFMUState: serializedState[] has an implausible length {huge}"),
            &format!("fmi3SerializeFMUState: size = {huge}, but the serialized state has"),
            &format!("fmi3GetDirectionalDerivative: knowns[] has an implausible length {huge}"),
            &format!("fmi3GetAdjointDerivative: seed[] has an implausible length {huge}"),
            &format!(
                "fmi3GetOutputDerivatives: valueReferences[] has an implausible length {huge}"
            ),
            &format!("fmi3SetInt64: values[] has an implausible length {huge}"),
        ],
    );
    assert_eq!(fmu.free_fmu_state(state), fmi3OK);

    let fmu = started_model_exchange();
    let c = fmu.instance();
    let statuses = unsafe {
        [
            f::fmi3SetContinuousStates::<Decay>(c, x.as_ptr(), huge),
            f::fmi3GetContinuousStateDerivatives::<Decay>(c, x.as_mut_ptr(), huge),
        ]
    };
    refused(
        &fmu,
        &statuses,
        &[
            &format!(
                "fmi3SetContinuousStates: continuousStates[] has an implausible length {huge}"
            ),
            &format!(
                "fmi3GetContinuousStateDerivatives: derivatives[] has an implausible length {huge}"
            ),
        ],
    );
}
