//! Checks, at compile time, that the 44 FMI 2.0 functions `mechfmu::export_fmu!` exports have
//! exactly the signatures of the official FMI 2.0 headers (`fmi2FunctionTypes.h`, as bindgen reads
//! them in `fmi-sys`). Building this crate is the test; the shipped FMUs do not depend on
//! it (nor on libclang).

pub mod fmi3;

use fmi_sys::fmi2 as header;
use oscillator::fmi2_exports as exports;

const _: header::fmi2GetTypesPlatformTYPE = Some(exports::fmi2GetTypesPlatform);
const _: header::fmi2GetVersionTYPE = Some(exports::fmi2GetVersion);
const _: header::fmi2SetDebugLoggingTYPE = Some(exports::fmi2SetDebugLogging);
const _: header::fmi2FreeInstanceTYPE = Some(exports::fmi2FreeInstance);
const _: header::fmi2SetupExperimentTYPE = Some(exports::fmi2SetupExperiment);
const _: header::fmi2EnterInitializationModeTYPE = Some(exports::fmi2EnterInitializationMode);
const _: header::fmi2ExitInitializationModeTYPE = Some(exports::fmi2ExitInitializationMode);
const _: header::fmi2TerminateTYPE = Some(exports::fmi2Terminate);
const _: header::fmi2ResetTYPE = Some(exports::fmi2Reset);
const _: header::fmi2GetRealTYPE = Some(exports::fmi2GetReal);
const _: header::fmi2GetIntegerTYPE = Some(exports::fmi2GetInteger);
const _: header::fmi2GetBooleanTYPE = Some(exports::fmi2GetBoolean);
const _: header::fmi2GetStringTYPE = Some(exports::fmi2GetString);
const _: header::fmi2SetRealTYPE = Some(exports::fmi2SetReal);
const _: header::fmi2SetIntegerTYPE = Some(exports::fmi2SetInteger);
const _: header::fmi2SetBooleanTYPE = Some(exports::fmi2SetBoolean);
const _: header::fmi2SetStringTYPE = Some(exports::fmi2SetString);
const _: header::fmi2GetFMUstateTYPE = Some(exports::fmi2GetFMUstate);
const _: header::fmi2SetFMUstateTYPE = Some(exports::fmi2SetFMUstate);
const _: header::fmi2FreeFMUstateTYPE = Some(exports::fmi2FreeFMUstate);
const _: header::fmi2SerializedFMUstateSizeTYPE = Some(exports::fmi2SerializedFMUstateSize);
const _: header::fmi2SerializeFMUstateTYPE = Some(exports::fmi2SerializeFMUstate);
const _: header::fmi2DeSerializeFMUstateTYPE = Some(exports::fmi2DeSerializeFMUstate);
const _: header::fmi2GetDirectionalDerivativeTYPE = Some(exports::fmi2GetDirectionalDerivative);
const _: header::fmi2SetRealInputDerivativesTYPE = Some(exports::fmi2SetRealInputDerivatives);
const _: header::fmi2GetRealOutputDerivativesTYPE = Some(exports::fmi2GetRealOutputDerivatives);
const _: header::fmi2DoStepTYPE = Some(exports::fmi2DoStep);
const _: header::fmi2CancelStepTYPE = Some(exports::fmi2CancelStep);
const _: header::fmi2GetStatusTYPE = Some(exports::fmi2GetStatus);
const _: header::fmi2GetRealStatusTYPE = Some(exports::fmi2GetRealStatus);
const _: header::fmi2GetIntegerStatusTYPE = Some(exports::fmi2GetIntegerStatus);
const _: header::fmi2GetBooleanStatusTYPE = Some(exports::fmi2GetBooleanStatus);
const _: header::fmi2GetStringStatusTYPE = Some(exports::fmi2GetStringStatus);
const _: header::fmi2EnterEventModeTYPE = Some(exports::fmi2EnterEventMode);
const _: header::fmi2EnterContinuousTimeModeTYPE = Some(exports::fmi2EnterContinuousTimeMode);
const _: header::fmi2CompletedIntegratorStepTYPE = Some(exports::fmi2CompletedIntegratorStep);
const _: header::fmi2SetTimeTYPE = Some(exports::fmi2SetTime);
const _: header::fmi2SetContinuousStatesTYPE = Some(exports::fmi2SetContinuousStates);
const _: header::fmi2GetDerivativesTYPE = Some(exports::fmi2GetDerivatives);
const _: header::fmi2GetEventIndicatorsTYPE = Some(exports::fmi2GetEventIndicators);
const _: header::fmi2GetContinuousStatesTYPE = Some(exports::fmi2GetContinuousStates);
const _: header::fmi2GetNominalsOfContinuousStatesTYPE =
    Some(exports::fmi2GetNominalsOfContinuousStates);

// fmi2NewDiscreteStates takes the header's event-info struct: as for the callbacks below,
// the signature through the header's aliases and the struct's layout field by field.
const _: unsafe extern "C" fn(
    header::fmi2Component,
    *mut mechfmu::fmi2::ffi::fmi2EventInfo,
) -> header::fmi2Status = exports::fmi2NewDiscreteStates;

const _: () = {
    use core::mem::{align_of, offset_of, size_of};
    use header::fmi2EventInfo as H;
    use mechfmu::fmi2::ffi::fmi2EventInfo as O;
    assert!(size_of::<H>() == size_of::<O>());
    assert!(align_of::<H>() == align_of::<O>());
    assert!(offset_of!(H, newDiscreteStatesNeeded) == offset_of!(O, newDiscreteStatesNeeded));
    assert!(offset_of!(H, terminateSimulation) == offset_of!(O, terminateSimulation));
    assert!(
        offset_of!(H, nominalsOfContinuousStatesChanged)
            == offset_of!(O, nominalsOfContinuousStatesChanged)
    );
    assert!(
        offset_of!(H, valuesOfContinuousStatesChanged)
            == offset_of!(O, valuesOfContinuousStatesChanged)
    );
    assert!(offset_of!(H, nextEventTimeDefined) == offset_of!(O, nextEventTimeDefined));
    assert!(offset_of!(H, nextEventTime) == offset_of!(O, nextEventTime));
};

/// The field types of the event-info struct, checked through the header's aliases.
#[allow(dead_code)]
fn event_info_field_types(o: mechfmu::fmi2::ffi::fmi2EventInfo) {
    let _: header::fmi2Boolean = o.newDiscreteStatesNeeded;
    let _: header::fmi2Boolean = o.terminateSimulation;
    let _: header::fmi2Boolean = o.nominalsOfContinuousStatesChanged;
    let _: header::fmi2Boolean = o.valuesOfContinuousStatesChanged;
    let _: header::fmi2Boolean = o.nextEventTimeDefined;
    let _: header::fmi2Real = o.nextEventTime;
}

// fmi2Instantiate takes the header's callback struct, which is a distinct nominal type in
// Rust: check every scalar argument through the header's aliases and the struct's layout
// field by field.
const _: unsafe extern "C" fn(
    header::fmi2String,
    header::fmi2Type,
    header::fmi2String,
    header::fmi2String,
    *const mechfmu::fmi2::ffi::fmi2CallbackFunctions,
    header::fmi2Boolean,
    header::fmi2Boolean,
) -> header::fmi2Component = exports::fmi2Instantiate;

const _: () = {
    use core::mem::{align_of, offset_of, size_of};
    use header::fmi2CallbackFunctions as H;
    use mechfmu::fmi2::ffi::fmi2CallbackFunctions as O;
    assert!(size_of::<H>() == size_of::<O>());
    assert!(align_of::<H>() == align_of::<O>());
    assert!(offset_of!(H, logger) == offset_of!(O, logger));
    assert!(offset_of!(H, allocateMemory) == offset_of!(O, allocateMemory));
    assert!(offset_of!(H, freeMemory) == offset_of!(O, freeMemory));
    assert!(offset_of!(H, stepFinished) == offset_of!(O, stepFinished));
    assert!(offset_of!(H, componentEnvironment) == offset_of!(O, componentEnvironment));
};

/// The field types of the callback struct, checked through the header's aliases.
#[allow(dead_code)]
fn callback_field_types(o: mechfmu::fmi2::ffi::fmi2CallbackFunctions) {
    let _: header::fmi2CallbackLogger = o.logger;
    let _: header::fmi2CallbackAllocateMemory = o.allocateMemory;
    let _: header::fmi2CallbackFreeMemory = o.freeMemory;
    let _: header::fmi2StepFinished = o.stepFinished;
    let _: header::fmi2ComponentEnvironment = o.componentEnvironment;
}

#[cfg(test)]
mod tests {
    /// The crate compiled, so every signature matches; this test makes the check visible
    /// in the test run and asserts the status codes agree with the header.
    #[test]
    fn exported_signatures_match_the_fmi2_headers() {
        use fmi_sys::fmi2 as h;
        use mechfmu::fmi2::ffi as o;
        assert_eq!(o::fmi2OK, h::fmi2Status_fmi2OK);
        assert_eq!(o::fmi2Warning, h::fmi2Status_fmi2Warning);
        assert_eq!(o::fmi2Discard, h::fmi2Status_fmi2Discard);
        assert_eq!(o::fmi2Error, h::fmi2Status_fmi2Error);
        assert_eq!(o::fmi2Fatal, h::fmi2Status_fmi2Fatal);
        assert_eq!(o::fmi2Pending, h::fmi2Status_fmi2Pending);
        assert_eq!(o::fmi2CoSimulation, h::fmi2Type_fmi2CoSimulation);
        assert_eq!(o::fmi2ModelExchange, h::fmi2Type_fmi2ModelExchange);
        assert_eq!(
            o::fmi2LastSuccessfulTime,
            h::fmi2StatusKind_fmi2LastSuccessfulTime
        );
        assert_eq!(o::fmi2Terminated, h::fmi2StatusKind_fmi2Terminated);
    }
}
