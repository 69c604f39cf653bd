//! All 75 functions of FMI 3.0 (`fmi3FunctionTypes.h`), each typed as the header declares
//! it, in one table resolved from a binary.
#![allow(non_camel_case_types)] // the headers' names

use mechfmu::fmi3::ffi::*;

type I = fmi3Instance;
type Vr = fmi3ValueReference;
type Vrs = *const fmi3ValueReference;
type Env = fmi3InstanceEnvironment;
type Log = fmi3LogMessageCallback;
type State = fmi3FMUState;
type Status = fmi3Status;
type Qualifiers = *mut fmi3IntervalQualifier;

functions! { 75;
    get_version fmi3GetVersionTYPE "fmi3GetVersion" () -> fmi3String;
    set_debug_logging fmi3SetDebugLoggingTYPE "fmi3SetDebugLogging"
        (I, fmi3Boolean, usize, *const fmi3String) -> Status;
    instantiate_model_exchange fmi3InstantiateModelExchangeTYPE "fmi3InstantiateModelExchange"
        (fmi3String, fmi3String, fmi3String, fmi3Boolean, fmi3Boolean, Env, Log) -> I;
    instantiate_co_simulation fmi3InstantiateCoSimulationTYPE "fmi3InstantiateCoSimulation" (
        fmi3String, fmi3String, fmi3String, fmi3Boolean, fmi3Boolean, fmi3Boolean, fmi3Boolean,
        Vrs, usize, Env, Log, fmi3IntermediateUpdateCallback
    ) -> I;
    instantiate_scheduled_execution fmi3InstantiateScheduledExecutionTYPE
        "fmi3InstantiateScheduledExecution" (
        fmi3String, fmi3String, fmi3String, fmi3Boolean, fmi3Boolean, Env, Log,
        fmi3ClockUpdateCallback, fmi3LockPreemptionCallback, fmi3UnlockPreemptionCallback
    ) -> I;
    free_instance fmi3FreeInstanceTYPE "fmi3FreeInstance" (I);
    enter_initialization_mode fmi3EnterInitializationModeTYPE "fmi3EnterInitializationMode"
        (I, fmi3Boolean, fmi3Float64, fmi3Float64, fmi3Boolean, fmi3Float64) -> Status;
    exit_initialization_mode fmi3ExitInitializationModeTYPE "fmi3ExitInitializationMode"
        (I) -> Status;
    enter_event_mode fmi3EnterEventModeTYPE "fmi3EnterEventMode" (I) -> Status;
    terminate fmi3TerminateTYPE "fmi3Terminate" (I) -> Status;
    reset fmi3ResetTYPE "fmi3Reset" (I) -> Status;
    get_float32 fmi3GetFloat32TYPE "fmi3GetFloat32"
        (I, Vrs, usize, *mut fmi3Float32, usize) -> Status;
    get_float64 fmi3GetFloat64TYPE "fmi3GetFloat64"
        (I, Vrs, usize, *mut fmi3Float64, usize) -> Status;
    get_int8 fmi3GetInt8TYPE "fmi3GetInt8" (I, Vrs, usize, *mut fmi3Int8, usize) -> Status;
    get_uint8 fmi3GetUInt8TYPE "fmi3GetUInt8" (I, Vrs, usize, *mut fmi3UInt8, usize) -> Status;
    get_int16 fmi3GetInt16TYPE "fmi3GetInt16" (I, Vrs, usize, *mut fmi3Int16, usize) -> Status;
    get_uint16 fmi3GetUInt16TYPE "fmi3GetUInt16"
        (I, Vrs, usize, *mut fmi3UInt16, usize) -> Status;
    get_int32 fmi3GetInt32TYPE "fmi3GetInt32" (I, Vrs, usize, *mut fmi3Int32, usize) -> Status;
    get_uint32 fmi3GetUInt32TYPE "fmi3GetUInt32"
        (I, Vrs, usize, *mut fmi3UInt32, usize) -> Status;
    get_int64 fmi3GetInt64TYPE "fmi3GetInt64" (I, Vrs, usize, *mut fmi3Int64, usize) -> Status;
    get_uint64 fmi3GetUInt64TYPE "fmi3GetUInt64"
        (I, Vrs, usize, *mut fmi3UInt64, usize) -> Status;
    get_boolean fmi3GetBooleanTYPE "fmi3GetBoolean"
        (I, Vrs, usize, *mut fmi3Boolean, usize) -> Status;
    get_string fmi3GetStringTYPE "fmi3GetString"
        (I, Vrs, usize, *mut fmi3String, usize) -> Status;
    get_binary fmi3GetBinaryTYPE "fmi3GetBinary"
        (I, Vrs, usize, *mut usize, *mut fmi3Binary, usize) -> Status;
    get_clock fmi3GetClockTYPE "fmi3GetClock" (I, Vrs, usize, *mut fmi3Clock) -> Status;
    set_float32 fmi3SetFloat32TYPE "fmi3SetFloat32"
        (I, Vrs, usize, *const fmi3Float32, usize) -> Status;
    set_float64 fmi3SetFloat64TYPE "fmi3SetFloat64"
        (I, Vrs, usize, *const fmi3Float64, usize) -> Status;
    set_int8 fmi3SetInt8TYPE "fmi3SetInt8" (I, Vrs, usize, *const fmi3Int8, usize) -> Status;
    set_uint8 fmi3SetUInt8TYPE "fmi3SetUInt8"
        (I, Vrs, usize, *const fmi3UInt8, usize) -> Status;
    set_int16 fmi3SetInt16TYPE "fmi3SetInt16"
        (I, Vrs, usize, *const fmi3Int16, usize) -> Status;
    set_uint16 fmi3SetUInt16TYPE "fmi3SetUInt16"
        (I, Vrs, usize, *const fmi3UInt16, usize) -> Status;
    set_int32 fmi3SetInt32TYPE "fmi3SetInt32"
        (I, Vrs, usize, *const fmi3Int32, usize) -> Status;
    set_uint32 fmi3SetUInt32TYPE "fmi3SetUInt32"
        (I, Vrs, usize, *const fmi3UInt32, usize) -> Status;
    set_int64 fmi3SetInt64TYPE "fmi3SetInt64"
        (I, Vrs, usize, *const fmi3Int64, usize) -> Status;
    set_uint64 fmi3SetUInt64TYPE "fmi3SetUInt64"
        (I, Vrs, usize, *const fmi3UInt64, usize) -> Status;
    set_boolean fmi3SetBooleanTYPE "fmi3SetBoolean"
        (I, Vrs, usize, *const fmi3Boolean, usize) -> Status;
    set_string fmi3SetStringTYPE "fmi3SetString"
        (I, Vrs, usize, *const fmi3String, usize) -> Status;
    set_binary fmi3SetBinaryTYPE "fmi3SetBinary"
        (I, Vrs, usize, *const usize, *const fmi3Binary, usize) -> Status;
    set_clock fmi3SetClockTYPE "fmi3SetClock" (I, Vrs, usize, *const fmi3Clock) -> Status;
    get_number_of_variable_dependencies fmi3GetNumberOfVariableDependenciesTYPE
        "fmi3GetNumberOfVariableDependencies" (I, Vr, *mut usize) -> Status;
    get_variable_dependencies fmi3GetVariableDependenciesTYPE "fmi3GetVariableDependencies"
        (I, Vr, *mut usize, *mut Vr, *mut usize, *mut fmi3DependencyKind, usize) -> Status;
    get_fmu_state fmi3GetFMUStateTYPE "fmi3GetFMUState" (I, *mut State) -> Status;
    set_fmu_state fmi3SetFMUStateTYPE "fmi3SetFMUState" (I, State) -> Status;
    free_fmu_state fmi3FreeFMUStateTYPE "fmi3FreeFMUState" (I, *mut State) -> Status;
    serialized_fmu_state_size fmi3SerializedFMUStateSizeTYPE "fmi3SerializedFMUStateSize"
        (I, State, *mut usize) -> Status;
    serialize_fmu_state fmi3SerializeFMUStateTYPE "fmi3SerializeFMUState"
        (I, State, *mut fmi3Byte, usize) -> Status;
    deserialize_fmu_state fmi3DeserializeFMUStateTYPE "fmi3DeserializeFMUState"
        (I, *const fmi3Byte, usize, *mut State) -> Status;
    get_directional_derivative fmi3GetDirectionalDerivativeTYPE "fmi3GetDirectionalDerivative"
        (I, Vrs, usize, Vrs, usize, *const fmi3Float64, usize, *mut fmi3Float64, usize)
        -> Status;
    get_adjoint_derivative fmi3GetAdjointDerivativeTYPE "fmi3GetAdjointDerivative"
        (I, Vrs, usize, Vrs, usize, *const fmi3Float64, usize, *mut fmi3Float64, usize)
        -> Status;
    enter_configuration_mode fmi3EnterConfigurationModeTYPE "fmi3EnterConfigurationMode"
        (I) -> Status;
    exit_configuration_mode fmi3ExitConfigurationModeTYPE "fmi3ExitConfigurationMode"
        (I) -> Status;
    get_interval_decimal fmi3GetIntervalDecimalTYPE "fmi3GetIntervalDecimal"
        (I, Vrs, usize, *mut fmi3Float64, Qualifiers) -> Status;
    get_interval_fraction fmi3GetIntervalFractionTYPE "fmi3GetIntervalFraction"
        (I, Vrs, usize, *mut fmi3UInt64, *mut fmi3UInt64, Qualifiers) -> Status;
    get_shift_decimal fmi3GetShiftDecimalTYPE "fmi3GetShiftDecimal"
        (I, Vrs, usize, *mut fmi3Float64) -> Status;
    get_shift_fraction fmi3GetShiftFractionTYPE "fmi3GetShiftFraction"
        (I, Vrs, usize, *mut fmi3UInt64, *mut fmi3UInt64) -> Status;
    set_interval_decimal fmi3SetIntervalDecimalTYPE "fmi3SetIntervalDecimal"
        (I, Vrs, usize, *const fmi3Float64) -> Status;
    set_interval_fraction fmi3SetIntervalFractionTYPE "fmi3SetIntervalFraction"
        (I, Vrs, usize, *const fmi3UInt64, *const fmi3UInt64) -> Status;
    set_shift_decimal fmi3SetShiftDecimalTYPE "fmi3SetShiftDecimal"
        (I, Vrs, usize, *const fmi3Float64) -> Status;
    set_shift_fraction fmi3SetShiftFractionTYPE "fmi3SetShiftFraction"
        (I, Vrs, usize, *const fmi3UInt64, *const fmi3UInt64) -> Status;
    evaluate_discrete_states fmi3EvaluateDiscreteStatesTYPE "fmi3EvaluateDiscreteStates"
        (I) -> Status;
    update_discrete_states fmi3UpdateDiscreteStatesTYPE "fmi3UpdateDiscreteStates" (
        I, *mut fmi3Boolean, *mut fmi3Boolean, *mut fmi3Boolean, *mut fmi3Boolean,
        *mut fmi3Boolean, *mut fmi3Float64
    ) -> Status;
    enter_continuous_time_mode fmi3EnterContinuousTimeModeTYPE "fmi3EnterContinuousTimeMode"
        (I) -> Status;
    completed_integrator_step fmi3CompletedIntegratorStepTYPE "fmi3CompletedIntegratorStep"
        (I, fmi3Boolean, *mut fmi3Boolean, *mut fmi3Boolean) -> Status;
    set_time fmi3SetTimeTYPE "fmi3SetTime" (I, fmi3Float64) -> Status;
    set_continuous_states fmi3SetContinuousStatesTYPE "fmi3SetContinuousStates"
        (I, *const fmi3Float64, usize) -> Status;
    get_continuous_state_derivatives fmi3GetContinuousStateDerivativesTYPE
        "fmi3GetContinuousStateDerivatives" (I, *mut fmi3Float64, usize) -> Status;
    get_event_indicators fmi3GetEventIndicatorsTYPE "fmi3GetEventIndicators"
        (I, *mut fmi3Float64, usize) -> Status;
    get_continuous_states fmi3GetContinuousStatesTYPE "fmi3GetContinuousStates"
        (I, *mut fmi3Float64, usize) -> Status;
    get_nominals_of_continuous_states fmi3GetNominalsOfContinuousStatesTYPE
        "fmi3GetNominalsOfContinuousStates" (I, *mut fmi3Float64, usize) -> Status;
    get_number_of_event_indicators fmi3GetNumberOfEventIndicatorsTYPE
        "fmi3GetNumberOfEventIndicators" (I, *mut usize) -> Status;
    get_number_of_continuous_states fmi3GetNumberOfContinuousStatesTYPE
        "fmi3GetNumberOfContinuousStates" (I, *mut usize) -> Status;
    enter_step_mode fmi3EnterStepModeTYPE "fmi3EnterStepMode" (I) -> Status;
    get_output_derivatives fmi3GetOutputDerivativesTYPE "fmi3GetOutputDerivatives"
        (I, Vrs, usize, *const fmi3Int32, *mut fmi3Float64, usize) -> Status;
    do_step fmi3DoStepTYPE "fmi3DoStep" (
        I, fmi3Float64, fmi3Float64, fmi3Boolean, *mut fmi3Boolean, *mut fmi3Boolean,
        *mut fmi3Boolean, *mut fmi3Float64
    ) -> Status;
    activate_model_partition fmi3ActivateModelPartitionTYPE "fmi3ActivateModelPartition"
        (I, Vr, fmi3Float64) -> Status;
}

#[cfg(test)]
mod tests {
    use super::FUNCTION_NAMES;

    #[test]
    fn the_names_are_75_distinct_fmi3_functions() {
        let names: std::collections::BTreeSet<&str> = FUNCTION_NAMES.into_iter().collect();
        assert_eq!(names.len(), 75);
        assert!(names.iter().all(|n| n.starts_with("fmi3")));
    }
}
