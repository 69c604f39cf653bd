//! The 75 functions `mechfmu::export_fmu!` exports for FMI 3.0 have exactly the signatures
//! of the official FMI 3.0 headers (`fmi3FunctionTypes.h`, as bindgen reads them in
//! `fmi-sys`): checked at compile time, as FMI 2.0's in the crate root.

use fmi_sys::fmi3 as header;
use oscillator::fmi3_exports as exports;

const _: header::fmi3GetVersionTYPE = Some(exports::fmi3GetVersion);
const _: header::fmi3SetDebugLoggingTYPE = Some(exports::fmi3SetDebugLogging);
const _: header::fmi3InstantiateModelExchangeTYPE = Some(exports::fmi3InstantiateModelExchange);
const _: header::fmi3InstantiateCoSimulationTYPE = Some(exports::fmi3InstantiateCoSimulation);
const _: header::fmi3InstantiateScheduledExecutionTYPE =
    Some(exports::fmi3InstantiateScheduledExecution);
const _: header::fmi3FreeInstanceTYPE = Some(exports::fmi3FreeInstance);
const _: header::fmi3EnterInitializationModeTYPE = Some(exports::fmi3EnterInitializationMode);
const _: header::fmi3ExitInitializationModeTYPE = Some(exports::fmi3ExitInitializationMode);
const _: header::fmi3EnterEventModeTYPE = Some(exports::fmi3EnterEventMode);
const _: header::fmi3TerminateTYPE = Some(exports::fmi3Terminate);
const _: header::fmi3ResetTYPE = Some(exports::fmi3Reset);
const _: header::fmi3GetFloat32TYPE = Some(exports::fmi3GetFloat32);
const _: header::fmi3GetFloat64TYPE = Some(exports::fmi3GetFloat64);
const _: header::fmi3GetInt8TYPE = Some(exports::fmi3GetInt8);
const _: header::fmi3GetUInt8TYPE = Some(exports::fmi3GetUInt8);
const _: header::fmi3GetInt16TYPE = Some(exports::fmi3GetInt16);
const _: header::fmi3GetUInt16TYPE = Some(exports::fmi3GetUInt16);
const _: header::fmi3GetInt32TYPE = Some(exports::fmi3GetInt32);
const _: header::fmi3GetUInt32TYPE = Some(exports::fmi3GetUInt32);
const _: header::fmi3GetInt64TYPE = Some(exports::fmi3GetInt64);
const _: header::fmi3GetUInt64TYPE = Some(exports::fmi3GetUInt64);
const _: header::fmi3GetBooleanTYPE = Some(exports::fmi3GetBoolean);
const _: header::fmi3GetStringTYPE = Some(exports::fmi3GetString);
const _: header::fmi3GetBinaryTYPE = Some(exports::fmi3GetBinary);
const _: header::fmi3GetClockTYPE = Some(exports::fmi3GetClock);
const _: header::fmi3SetFloat32TYPE = Some(exports::fmi3SetFloat32);
const _: header::fmi3SetFloat64TYPE = Some(exports::fmi3SetFloat64);
const _: header::fmi3SetInt8TYPE = Some(exports::fmi3SetInt8);
const _: header::fmi3SetUInt8TYPE = Some(exports::fmi3SetUInt8);
const _: header::fmi3SetInt16TYPE = Some(exports::fmi3SetInt16);
const _: header::fmi3SetUInt16TYPE = Some(exports::fmi3SetUInt16);
const _: header::fmi3SetInt32TYPE = Some(exports::fmi3SetInt32);
const _: header::fmi3SetUInt32TYPE = Some(exports::fmi3SetUInt32);
const _: header::fmi3SetInt64TYPE = Some(exports::fmi3SetInt64);
const _: header::fmi3SetUInt64TYPE = Some(exports::fmi3SetUInt64);
const _: header::fmi3SetBooleanTYPE = Some(exports::fmi3SetBoolean);
const _: header::fmi3SetStringTYPE = Some(exports::fmi3SetString);
const _: header::fmi3SetBinaryTYPE = Some(exports::fmi3SetBinary);
const _: header::fmi3SetClockTYPE = Some(exports::fmi3SetClock);
const _: header::fmi3GetNumberOfVariableDependenciesTYPE =
    Some(exports::fmi3GetNumberOfVariableDependencies);
const _: header::fmi3GetVariableDependenciesTYPE = Some(exports::fmi3GetVariableDependencies);
const _: header::fmi3GetFMUStateTYPE = Some(exports::fmi3GetFMUState);
const _: header::fmi3SetFMUStateTYPE = Some(exports::fmi3SetFMUState);
const _: header::fmi3FreeFMUStateTYPE = Some(exports::fmi3FreeFMUState);
const _: header::fmi3SerializedFMUStateSizeTYPE = Some(exports::fmi3SerializedFMUStateSize);
const _: header::fmi3SerializeFMUStateTYPE = Some(exports::fmi3SerializeFMUState);
const _: header::fmi3DeserializeFMUStateTYPE = Some(exports::fmi3DeserializeFMUState);
const _: header::fmi3GetDirectionalDerivativeTYPE = Some(exports::fmi3GetDirectionalDerivative);
const _: header::fmi3GetAdjointDerivativeTYPE = Some(exports::fmi3GetAdjointDerivative);
const _: header::fmi3EnterConfigurationModeTYPE = Some(exports::fmi3EnterConfigurationMode);
const _: header::fmi3ExitConfigurationModeTYPE = Some(exports::fmi3ExitConfigurationMode);
const _: header::fmi3GetIntervalDecimalTYPE = Some(exports::fmi3GetIntervalDecimal);
const _: header::fmi3GetIntervalFractionTYPE = Some(exports::fmi3GetIntervalFraction);
const _: header::fmi3GetShiftDecimalTYPE = Some(exports::fmi3GetShiftDecimal);
const _: header::fmi3GetShiftFractionTYPE = Some(exports::fmi3GetShiftFraction);
const _: header::fmi3SetIntervalDecimalTYPE = Some(exports::fmi3SetIntervalDecimal);
const _: header::fmi3SetIntervalFractionTYPE = Some(exports::fmi3SetIntervalFraction);
const _: header::fmi3SetShiftDecimalTYPE = Some(exports::fmi3SetShiftDecimal);
const _: header::fmi3SetShiftFractionTYPE = Some(exports::fmi3SetShiftFraction);
const _: header::fmi3EvaluateDiscreteStatesTYPE = Some(exports::fmi3EvaluateDiscreteStates);
const _: header::fmi3UpdateDiscreteStatesTYPE = Some(exports::fmi3UpdateDiscreteStates);
const _: header::fmi3EnterContinuousTimeModeTYPE = Some(exports::fmi3EnterContinuousTimeMode);
const _: header::fmi3CompletedIntegratorStepTYPE = Some(exports::fmi3CompletedIntegratorStep);
const _: header::fmi3SetTimeTYPE = Some(exports::fmi3SetTime);
const _: header::fmi3SetContinuousStatesTYPE = Some(exports::fmi3SetContinuousStates);
const _: header::fmi3GetContinuousStateDerivativesTYPE =
    Some(exports::fmi3GetContinuousStateDerivatives);
const _: header::fmi3GetEventIndicatorsTYPE = Some(exports::fmi3GetEventIndicators);
const _: header::fmi3GetContinuousStatesTYPE = Some(exports::fmi3GetContinuousStates);
const _: header::fmi3GetNominalsOfContinuousStatesTYPE =
    Some(exports::fmi3GetNominalsOfContinuousStates);
const _: header::fmi3GetNumberOfEventIndicatorsTYPE = Some(exports::fmi3GetNumberOfEventIndicators);
const _: header::fmi3GetNumberOfContinuousStatesTYPE =
    Some(exports::fmi3GetNumberOfContinuousStates);
const _: header::fmi3EnterStepModeTYPE = Some(exports::fmi3EnterStepMode);
const _: header::fmi3GetOutputDerivativesTYPE = Some(exports::fmi3GetOutputDerivatives);
const _: header::fmi3DoStepTYPE = Some(exports::fmi3DoStep);
const _: header::fmi3ActivateModelPartitionTYPE = Some(exports::fmi3ActivateModelPartition);
