//! All 44 functions of FMI 2.0 (`fmi2FunctionTypes.h`: the common ones, Co-Simulation's,
//! then Model Exchange's), each typed as the header declares it, in one table resolved
//! from a binary.
#![allow(non_camel_case_types)] // the headers' names

use mechfmu::fmi2::ffi::*;

type C = fmi2Component;
type Vrs = *const fmi2ValueReference;
type State = fmi2FMUstate;
type Kind = fmi2StatusKind;
type Status = fmi2Status;

functions! { 44;
    get_types_platform fmi2GetTypesPlatformTYPE "fmi2GetTypesPlatform" () -> fmi2String;
    get_version fmi2GetVersionTYPE "fmi2GetVersion" () -> fmi2String;
    set_debug_logging fmi2SetDebugLoggingTYPE "fmi2SetDebugLogging"
        (C, fmi2Boolean, usize, *const fmi2String) -> Status;
    instantiate fmi2InstantiateTYPE "fmi2Instantiate" (
        fmi2String, fmi2Type, fmi2String, fmi2String, *const fmi2CallbackFunctions,
        fmi2Boolean, fmi2Boolean
    ) -> C;
    free_instance fmi2FreeInstanceTYPE "fmi2FreeInstance" (C);
    setup_experiment fmi2SetupExperimentTYPE "fmi2SetupExperiment"
        (C, fmi2Boolean, fmi2Real, fmi2Real, fmi2Boolean, fmi2Real) -> Status;
    enter_initialization_mode fmi2EnterInitializationModeTYPE "fmi2EnterInitializationMode"
        (C) -> Status;
    exit_initialization_mode fmi2ExitInitializationModeTYPE "fmi2ExitInitializationMode"
        (C) -> Status;
    terminate fmi2TerminateTYPE "fmi2Terminate" (C) -> Status;
    reset fmi2ResetTYPE "fmi2Reset" (C) -> Status;
    get_real fmi2GetRealTYPE "fmi2GetReal" (C, Vrs, usize, *mut fmi2Real) -> Status;
    get_integer fmi2GetIntegerTYPE "fmi2GetInteger" (C, Vrs, usize, *mut fmi2Integer) -> Status;
    get_boolean fmi2GetBooleanTYPE "fmi2GetBoolean" (C, Vrs, usize, *mut fmi2Boolean) -> Status;
    get_string fmi2GetStringTYPE "fmi2GetString" (C, Vrs, usize, *mut fmi2String) -> Status;
    set_real fmi2SetRealTYPE "fmi2SetReal" (C, Vrs, usize, *const fmi2Real) -> Status;
    set_integer fmi2SetIntegerTYPE "fmi2SetInteger"
        (C, Vrs, usize, *const fmi2Integer) -> Status;
    set_boolean fmi2SetBooleanTYPE "fmi2SetBoolean"
        (C, Vrs, usize, *const fmi2Boolean) -> Status;
    set_string fmi2SetStringTYPE "fmi2SetString" (C, Vrs, usize, *const fmi2String) -> Status;
    get_fmu_state fmi2GetFMUstateTYPE "fmi2GetFMUstate" (C, *mut State) -> Status;
    set_fmu_state fmi2SetFMUstateTYPE "fmi2SetFMUstate" (C, State) -> Status;
    free_fmu_state fmi2FreeFMUstateTYPE "fmi2FreeFMUstate" (C, *mut State) -> Status;
    serialized_fmu_state_size fmi2SerializedFMUstateSizeTYPE "fmi2SerializedFMUstateSize"
        (C, State, *mut usize) -> Status;
    serialize_fmu_state fmi2SerializeFMUstateTYPE "fmi2SerializeFMUstate"
        (C, State, *mut fmi2Byte, usize) -> Status;
    deserialize_fmu_state fmi2DeSerializeFMUstateTYPE "fmi2DeSerializeFMUstate"
        (C, *const fmi2Byte, usize, *mut State) -> Status;
    get_directional_derivative fmi2GetDirectionalDerivativeTYPE "fmi2GetDirectionalDerivative"
        (C, Vrs, usize, Vrs, usize, *const fmi2Real, *mut fmi2Real) -> Status;
    set_real_input_derivatives fmi2SetRealInputDerivativesTYPE "fmi2SetRealInputDerivatives"
        (C, Vrs, usize, *const fmi2Integer, *const fmi2Real) -> Status;
    get_real_output_derivatives fmi2GetRealOutputDerivativesTYPE "fmi2GetRealOutputDerivatives"
        (C, Vrs, usize, *const fmi2Integer, *mut fmi2Real) -> Status;
    do_step fmi2DoStepTYPE "fmi2DoStep" (C, fmi2Real, fmi2Real, fmi2Boolean) -> Status;
    cancel_step fmi2CancelStepTYPE "fmi2CancelStep" (C) -> Status;
    get_status fmi2GetStatusTYPE "fmi2GetStatus" (C, Kind, *mut fmi2Status) -> Status;
    get_real_status fmi2GetRealStatusTYPE "fmi2GetRealStatus" (C, Kind, *mut fmi2Real) -> Status;
    get_integer_status fmi2GetIntegerStatusTYPE "fmi2GetIntegerStatus"
        (C, Kind, *mut fmi2Integer) -> Status;
    get_boolean_status fmi2GetBooleanStatusTYPE "fmi2GetBooleanStatus"
        (C, Kind, *mut fmi2Boolean) -> Status;
    get_string_status fmi2GetStringStatusTYPE "fmi2GetStringStatus"
        (C, Kind, *mut fmi2String) -> Status;
    enter_event_mode fmi2EnterEventModeTYPE "fmi2EnterEventMode" (C) -> Status;
    new_discrete_states fmi2NewDiscreteStatesTYPE "fmi2NewDiscreteStates"
        (C, *mut fmi2EventInfo) -> Status;
    enter_continuous_time_mode fmi2EnterContinuousTimeModeTYPE "fmi2EnterContinuousTimeMode"
        (C) -> Status;
    completed_integrator_step fmi2CompletedIntegratorStepTYPE "fmi2CompletedIntegratorStep"
        (C, fmi2Boolean, *mut fmi2Boolean, *mut fmi2Boolean) -> Status;
    set_time fmi2SetTimeTYPE "fmi2SetTime" (C, fmi2Real) -> Status;
    set_continuous_states fmi2SetContinuousStatesTYPE "fmi2SetContinuousStates"
        (C, *const fmi2Real, usize) -> Status;
    get_derivatives fmi2GetDerivativesTYPE "fmi2GetDerivatives"
        (C, *mut fmi2Real, usize) -> Status;
    get_event_indicators fmi2GetEventIndicatorsTYPE "fmi2GetEventIndicators"
        (C, *mut fmi2Real, usize) -> Status;
    get_continuous_states fmi2GetContinuousStatesTYPE "fmi2GetContinuousStates"
        (C, *mut fmi2Real, usize) -> Status;
    get_nominals_of_continuous_states fmi2GetNominalsOfContinuousStatesTYPE
        "fmi2GetNominalsOfContinuousStates" (C, *mut fmi2Real, usize) -> Status;
}

#[cfg(test)]
mod tests {
    use super::FUNCTION_NAMES;

    #[test]
    fn the_names_are_44_distinct_fmi2_functions() {
        let names: std::collections::BTreeSet<&str> = FUNCTION_NAMES.into_iter().collect();
        assert_eq!(names.len(), 44);
        assert!(names.iter().all(|n| n.starts_with("fmi2")));
    }
}
