//! The 75 FMI 3.0 functions (`fmi3Functions.h`), each written once: its C signature and its
//! guarded call, one `extern "C" fn` of [`fmi3_functions!`](crate::fmi3_functions), expanded
//! as FMI 2.0's table is (see [`fmi2::functions`](crate::fmi2::functions)): into generic
//! `extern "C"` functions here,
//! and into the unmangled symbols of a mechanism crate by [`export_fmu!`](crate::export_fmu).
//! The functions of features this FMU does not offer (clocks, configuration mode,
//! Scheduled Execution) are exported too, as an importer loads every function of the
//! interface types it uses, and refuse with a message.

#![allow(non_snake_case, clippy::missing_safety_doc)]

use super::ffi::*;
use super::instantiate::{self, CoSimulationOptions};
use super::state::*;
use super::{calls, variables};
use crate::fmi::boundary::{
    self, fmu_state, guarded, out, out_or_null, slice, slice_mut, strings, Buffer, StateSlot,
};
use crate::fmi::model_exchange as me;
use crate::fmi::{shared_calls, Version};
use crate::model::Mechanism;

/// The table of FMI 3.0 functions, as [`fmi2_functions!`](crate::fmi2_functions).
#[doc(hidden)]
#[macro_export]
macro_rules! fmi3_functions {
    ($emit:path) => {
        $emit!(
            pub unsafe extern "C" fn fmi3GetVersion() -> *const ::std::os::raw::c_char {
                calls::get_version()
            }
            pub unsafe extern "C" fn fmi3SetDebugLogging(
                instance: fmi3Instance,
                loggingOn: fmi3Boolean,
                nCategories: usize,
                categories: *const fmi3String,
            ) -> fmi3Status {
                guarded::<M>(instance, &SET_DEBUG_LOGGING, |inst| {
                    shared_calls::set_debug_logging(
                        inst,
                        loggingOn,
                        &strings(categories, nCategories, "categories[]", "a category")?,
                    )
                })
            }
            #[before_export(shared_calls::silence_panic_messages)]
            pub unsafe extern "C" fn fmi3InstantiateModelExchange(
                instanceName: fmi3String,
                instantiationToken: fmi3String,
                resourcePath: fmi3String,
                visible: fmi3Boolean,
                loggingOn: fmi3Boolean,
                instanceEnvironment: fmi3InstanceEnvironment,
                logMessage: fmi3LogMessageCallback,
            ) -> fmi3Instance {
                instantiate::instantiate::<M>(
                    "fmi3InstantiateModelExchange",
                    instanceName,
                    instantiationToken,
                    loggingOn,
                    instanceEnvironment,
                    logMessage,
                    None,
                )
            }
            #[before_export(shared_calls::silence_panic_messages)]
            pub unsafe extern "C" fn fmi3InstantiateCoSimulation(
                instanceName: fmi3String,
                instantiationToken: fmi3String,
                resourcePath: fmi3String,
                visible: fmi3Boolean,
                loggingOn: fmi3Boolean,
                eventModeUsed: fmi3Boolean,
                earlyReturnAllowed: fmi3Boolean,
                requiredIntermediateVariables: *const fmi3ValueReference,
                nRequiredIntermediateVariables: usize,
                instanceEnvironment: fmi3InstanceEnvironment,
                logMessage: fmi3LogMessageCallback,
                intermediateUpdate: fmi3IntermediateUpdateCallback,
            ) -> fmi3Instance {
                instantiate::instantiate::<M>(
                    "fmi3InstantiateCoSimulation",
                    instanceName,
                    instantiationToken,
                    loggingOn,
                    instanceEnvironment,
                    logMessage,
                    Some(CoSimulationOptions {
                        event_mode_used: eventModeUsed,
                        early_return_allowed: earlyReturnAllowed,
                        required_intermediate_variables: requiredIntermediateVariables,
                        n_required_intermediate_variables: nRequiredIntermediateVariables,
                    }),
                )
            }
            pub unsafe extern "C" fn fmi3InstantiateScheduledExecution(
                instanceName: fmi3String,
                instantiationToken: fmi3String,
                resourcePath: fmi3String,
                visible: fmi3Boolean,
                loggingOn: fmi3Boolean,
                instanceEnvironment: fmi3InstanceEnvironment,
                logMessage: fmi3LogMessageCallback,
                clockUpdate: fmi3ClockUpdateCallback,
                lockPreemption: fmi3LockPreemptionCallback,
                unlockPreemption: fmi3UnlockPreemptionCallback,
            ) -> fmi3Instance {
                instantiate::instantiate_scheduled_execution(
                    loggingOn,
                    instanceEnvironment,
                    logMessage,
                )
            }
            pub unsafe extern "C" fn fmi3FreeInstance(instance: fmi3Instance) {
                boundary::free_component::<M>(instance, &FREE_INSTANCE)
            }
            pub unsafe extern "C" fn fmi3EnterInitializationMode(
                instance: fmi3Instance,
                toleranceDefined: fmi3Boolean,
                tolerance: fmi3Float64,
                startTime: fmi3Float64,
                stopTimeDefined: fmi3Boolean,
                stopTime: fmi3Float64,
            ) -> fmi3Status {
                guarded::<M>(instance, &ENTER_INITIALIZATION_MODE, |inst| {
                    calls::enter_initialization_mode(
                        inst,
                        toleranceDefined,
                        tolerance,
                        startTime,
                        stopTimeDefined,
                        stopTime,
                    )
                })
            }
            pub unsafe extern "C" fn fmi3ExitInitializationMode(
                instance: fmi3Instance,
            ) -> fmi3Status {
                guarded::<M>(
                    instance,
                    &EXIT_INITIALIZATION_MODE,
                    shared_calls::exit_initialization_mode,
                )
            }
            pub unsafe extern "C" fn fmi3EnterEventMode(instance: fmi3Instance) -> fmi3Status {
                guarded::<M>(instance, &ENTER_EVENT_MODE, calls::enter_event_mode)
            }
            pub unsafe extern "C" fn fmi3Terminate(instance: fmi3Instance) -> fmi3Status {
                guarded::<M>(instance, &TERMINATE, shared_calls::terminate)
            }
            pub unsafe extern "C" fn fmi3Reset(instance: fmi3Instance) -> fmi3Status {
                guarded::<M>(instance, &RESET, shared_calls::reset)
            }
            pub unsafe extern "C" fn fmi3GetFloat32(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                values: *mut fmi3Float32,
                nValues: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &GET_FLOAT32, |_| {
                    let vrs = slice(valueReferences, nValueReferences, "valueReferences[]")?;
                    slice_mut(values, nValues, "values[]")?;
                    variables::no_variables(GET_FLOAT32.name, vrs, nValues)
                })
            }
            pub unsafe extern "C" fn fmi3GetFloat64(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                values: *mut fmi3Float64,
                nValues: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &GET_FLOAT64, |inst| {
                    variables::get_float64(
                        inst,
                        slice(valueReferences, nValueReferences, "valueReferences[]")?,
                        slice_mut(values, nValues, "values[]")?,
                    )
                })
            }
            pub unsafe extern "C" fn fmi3GetInt8(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                values: *mut fmi3Int8,
                nValues: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &GET_INT8, |_| {
                    let vrs = slice(valueReferences, nValueReferences, "valueReferences[]")?;
                    slice_mut(values, nValues, "values[]")?;
                    variables::no_variables(GET_INT8.name, vrs, nValues)
                })
            }
            pub unsafe extern "C" fn fmi3GetUInt8(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                values: *mut fmi3UInt8,
                nValues: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &GET_UINT8, |_| {
                    let vrs = slice(valueReferences, nValueReferences, "valueReferences[]")?;
                    slice_mut(values, nValues, "values[]")?;
                    variables::no_variables(GET_UINT8.name, vrs, nValues)
                })
            }
            pub unsafe extern "C" fn fmi3GetInt16(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                values: *mut fmi3Int16,
                nValues: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &GET_INT16, |_| {
                    let vrs = slice(valueReferences, nValueReferences, "valueReferences[]")?;
                    slice_mut(values, nValues, "values[]")?;
                    variables::no_variables(GET_INT16.name, vrs, nValues)
                })
            }
            pub unsafe extern "C" fn fmi3GetUInt16(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                values: *mut fmi3UInt16,
                nValues: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &GET_UINT16, |_| {
                    let vrs = slice(valueReferences, nValueReferences, "valueReferences[]")?;
                    slice_mut(values, nValues, "values[]")?;
                    variables::no_variables(GET_UINT16.name, vrs, nValues)
                })
            }
            pub unsafe extern "C" fn fmi3GetInt32(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                values: *mut fmi3Int32,
                nValues: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &GET_INT32, |_| {
                    let vrs = slice(valueReferences, nValueReferences, "valueReferences[]")?;
                    slice_mut(values, nValues, "values[]")?;
                    variables::no_variables(GET_INT32.name, vrs, nValues)
                })
            }
            pub unsafe extern "C" fn fmi3GetUInt32(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                values: *mut fmi3UInt32,
                nValues: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &GET_UINT32, |_| {
                    let vrs = slice(valueReferences, nValueReferences, "valueReferences[]")?;
                    slice_mut(values, nValues, "values[]")?;
                    variables::no_variables(GET_UINT32.name, vrs, nValues)
                })
            }
            pub unsafe extern "C" fn fmi3GetInt64(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                values: *mut fmi3Int64,
                nValues: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &GET_INT64, |_| {
                    let vrs = slice(valueReferences, nValueReferences, "valueReferences[]")?;
                    slice_mut(values, nValues, "values[]")?;
                    variables::no_variables(GET_INT64.name, vrs, nValues)
                })
            }
            pub unsafe extern "C" fn fmi3GetUInt64(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                values: *mut fmi3UInt64,
                nValues: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &GET_UINT64, |_| {
                    let vrs = slice(valueReferences, nValueReferences, "valueReferences[]")?;
                    slice_mut(values, nValues, "values[]")?;
                    variables::no_variables(GET_UINT64.name, vrs, nValues)
                })
            }
            pub unsafe extern "C" fn fmi3GetBoolean(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                values: *mut fmi3Boolean,
                nValues: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &GET_BOOLEAN, |_| {
                    let vrs = slice(valueReferences, nValueReferences, "valueReferences[]")?;
                    slice_mut(values as *mut u8, nValues, "values[]")?;
                    variables::no_variables(GET_BOOLEAN.name, vrs, nValues)
                })
            }
            pub unsafe extern "C" fn fmi3GetString(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                values: *mut fmi3String,
                nValues: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &GET_STRING, |_| {
                    let vrs = slice(valueReferences, nValueReferences, "valueReferences[]")?;
                    slice_mut(values, nValues, "values[]")?;
                    variables::no_variables(GET_STRING.name, vrs, nValues)
                })
            }
            pub unsafe extern "C" fn fmi3GetBinary(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                valueSizes: *mut usize,
                values: *mut fmi3Binary,
                nValues: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &GET_BINARY, |_| {
                    let vrs = slice(valueReferences, nValueReferences, "valueReferences[]")?;
                    slice_mut(valueSizes, nValues, "valueSizes[]")?;
                    slice_mut(values, nValues, "values[]")?;
                    variables::no_variables(GET_BINARY.name, vrs, nValues)
                })
            }
            pub unsafe extern "C" fn fmi3GetClock(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                values: *mut fmi3Clock,
            ) -> fmi3Status {
                guarded::<M>(instance, &GET_CLOCK, |_| calls::unsupported("no clocks"))
            }
            pub unsafe extern "C" fn fmi3SetFloat32(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                values: *const fmi3Float32,
                nValues: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &SET_FLOAT32, |_| {
                    let vrs = slice(valueReferences, nValueReferences, "valueReferences[]")?;
                    slice(values, nValues, "values[]")?;
                    variables::no_variables(SET_FLOAT32.name, vrs, nValues)
                })
            }
            pub unsafe extern "C" fn fmi3SetFloat64(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                values: *const fmi3Float64,
                nValues: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &SET_FLOAT64, |inst| {
                    variables::set_float64(
                        inst,
                        slice(valueReferences, nValueReferences, "valueReferences[]")?,
                        slice(values, nValues, "values[]")?,
                    )
                })
            }
            pub unsafe extern "C" fn fmi3SetInt8(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                values: *const fmi3Int8,
                nValues: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &SET_INT8, |_| {
                    let vrs = slice(valueReferences, nValueReferences, "valueReferences[]")?;
                    slice(values, nValues, "values[]")?;
                    variables::no_variables(SET_INT8.name, vrs, nValues)
                })
            }
            pub unsafe extern "C" fn fmi3SetUInt8(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                values: *const fmi3UInt8,
                nValues: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &SET_UINT8, |_| {
                    let vrs = slice(valueReferences, nValueReferences, "valueReferences[]")?;
                    slice(values, nValues, "values[]")?;
                    variables::no_variables(SET_UINT8.name, vrs, nValues)
                })
            }
            pub unsafe extern "C" fn fmi3SetInt16(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                values: *const fmi3Int16,
                nValues: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &SET_INT16, |_| {
                    let vrs = slice(valueReferences, nValueReferences, "valueReferences[]")?;
                    slice(values, nValues, "values[]")?;
                    variables::no_variables(SET_INT16.name, vrs, nValues)
                })
            }
            pub unsafe extern "C" fn fmi3SetUInt16(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                values: *const fmi3UInt16,
                nValues: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &SET_UINT16, |_| {
                    let vrs = slice(valueReferences, nValueReferences, "valueReferences[]")?;
                    slice(values, nValues, "values[]")?;
                    variables::no_variables(SET_UINT16.name, vrs, nValues)
                })
            }
            pub unsafe extern "C" fn fmi3SetInt32(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                values: *const fmi3Int32,
                nValues: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &SET_INT32, |_| {
                    let vrs = slice(valueReferences, nValueReferences, "valueReferences[]")?;
                    slice(values, nValues, "values[]")?;
                    variables::no_variables(SET_INT32.name, vrs, nValues)
                })
            }
            pub unsafe extern "C" fn fmi3SetUInt32(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                values: *const fmi3UInt32,
                nValues: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &SET_UINT32, |_| {
                    let vrs = slice(valueReferences, nValueReferences, "valueReferences[]")?;
                    slice(values, nValues, "values[]")?;
                    variables::no_variables(SET_UINT32.name, vrs, nValues)
                })
            }
            pub unsafe extern "C" fn fmi3SetInt64(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                values: *const fmi3Int64,
                nValues: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &SET_INT64, |_| {
                    let vrs = slice(valueReferences, nValueReferences, "valueReferences[]")?;
                    slice(values, nValues, "values[]")?;
                    variables::no_variables(SET_INT64.name, vrs, nValues)
                })
            }
            pub unsafe extern "C" fn fmi3SetUInt64(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                values: *const fmi3UInt64,
                nValues: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &SET_UINT64, |_| {
                    let vrs = slice(valueReferences, nValueReferences, "valueReferences[]")?;
                    slice(values, nValues, "values[]")?;
                    variables::no_variables(SET_UINT64.name, vrs, nValues)
                })
            }
            pub unsafe extern "C" fn fmi3SetBoolean(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                values: *const fmi3Boolean,
                nValues: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &SET_BOOLEAN, |_| {
                    let vrs = slice(valueReferences, nValueReferences, "valueReferences[]")?;
                    slice(values as *const u8, nValues, "values[]")?;
                    variables::no_variables(SET_BOOLEAN.name, vrs, nValues)
                })
            }
            pub unsafe extern "C" fn fmi3SetString(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                values: *const fmi3String,
                nValues: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &SET_STRING, |_| {
                    let vrs = slice(valueReferences, nValueReferences, "valueReferences[]")?;
                    slice(values, nValues, "values[]")?;
                    variables::no_variables(SET_STRING.name, vrs, nValues)
                })
            }
            pub unsafe extern "C" fn fmi3SetBinary(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                valueSizes: *const usize,
                values: *const fmi3Binary,
                nValues: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &SET_BINARY, |_| {
                    let vrs = slice(valueReferences, nValueReferences, "valueReferences[]")?;
                    slice(valueSizes, nValues, "valueSizes[]")?;
                    slice(values, nValues, "values[]")?;
                    variables::no_variables(SET_BINARY.name, vrs, nValues)
                })
            }
            pub unsafe extern "C" fn fmi3SetClock(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                values: *const fmi3Clock,
            ) -> fmi3Status {
                guarded::<M>(instance, &SET_CLOCK, |_| calls::unsupported("no clocks"))
            }
            pub unsafe extern "C" fn fmi3GetNumberOfVariableDependencies(
                instance: fmi3Instance,
                valueReference: fmi3ValueReference,
                nDependencies: *mut usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &GET_NUMBER_OF_VARIABLE_DEPENDENCIES, |_| {
                    calls::variable_dependencies()
                })
            }
            pub unsafe extern "C" fn fmi3GetVariableDependencies(
                instance: fmi3Instance,
                dependent: fmi3ValueReference,
                elementIndicesOfDependent: *mut usize,
                independents: *mut fmi3ValueReference,
                elementIndicesOfIndependents: *mut usize,
                dependencyKinds: *mut fmi3DependencyKind,
                nDependencies: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &GET_VARIABLE_DEPENDENCIES, |_| {
                    calls::variable_dependencies()
                })
            }
            pub unsafe extern "C" fn fmi3GetFMUState(
                instance: fmi3Instance,
                FMUState: *mut fmi3FMUState,
            ) -> fmi3Status {
                guarded::<M>(instance, &GET_FMU_STATE, |inst| {
                    shared_calls::get_fmu_state(inst, StateSlot::named(FMUState, "FMUState"))
                })
            }
            pub unsafe extern "C" fn fmi3SetFMUState(
                instance: fmi3Instance,
                FMUState: fmi3FMUState,
            ) -> fmi3Status {
                guarded::<M>(instance, &SET_FMU_STATE, |inst| {
                    shared_calls::set_fmu_state(inst, fmu_state(FMUState)?)
                })
            }
            pub unsafe extern "C" fn fmi3FreeFMUState(
                instance: fmi3Instance,
                FMUState: *mut fmi3FMUState,
            ) -> fmi3Status {
                guarded::<M>(instance, &FREE_FMU_STATE, |_| {
                    StateSlot::named(FMUState, "FMUState").free()
                })
            }
            pub unsafe extern "C" fn fmi3SerializedFMUStateSize(
                instance: fmi3Instance,
                FMUState: fmi3FMUState,
                size: *mut usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &SERIALIZED_FMU_STATE_SIZE, |_| {
                    shared_calls::serialized_fmu_state_size::<M>(
                        fmu_state(FMUState)?,
                        out(size, "size")?,
                    )
                })
            }
            pub unsafe extern "C" fn fmi3SerializeFMUState(
                instance: fmi3Instance,
                FMUState: fmi3FMUState,
                serializedState: *mut fmi3Byte,
                size: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &SERIALIZE_FMU_STATE, |_| {
                    shared_calls::serialize_fmu_state::<M>(
                        fmu_state(FMUState)?,
                        Buffer::new(serializedState, size),
                    )
                })
            }
            pub unsafe extern "C" fn fmi3DeserializeFMUState(
                instance: fmi3Instance,
                serializedState: *const fmi3Byte,
                size: usize,
                FMUState: *mut fmi3FMUState,
            ) -> fmi3Status {
                guarded::<M>(instance, &DESERIALIZE_FMU_STATE, |_| {
                    shared_calls::deserialize_fmu_state::<M>(
                        Version::Fmi3,
                        slice(serializedState, size, "serializedState[]")?,
                        StateSlot::named(FMUState, "FMUState"),
                    )
                })
            }
            pub unsafe extern "C" fn fmi3GetDirectionalDerivative(
                instance: fmi3Instance,
                unknowns: *const fmi3ValueReference,
                nUnknowns: usize,
                knowns: *const fmi3ValueReference,
                nKnowns: usize,
                seed: *const fmi3Float64,
                nSeed: usize,
                sensitivity: *mut fmi3Float64,
                nSensitivity: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &GET_DIRECTIONAL_DERIVATIVE, |inst| {
                    variables::get_directional_derivative(
                        inst,
                        slice(unknowns, nUnknowns, "unknowns[]")?,
                        slice(knowns, nKnowns, "knowns[]")?,
                        slice(seed, nSeed, "seed[]")?,
                        slice_mut(sensitivity, nSensitivity, "sensitivity[]")?,
                    )
                })
            }
            pub unsafe extern "C" fn fmi3GetAdjointDerivative(
                instance: fmi3Instance,
                unknowns: *const fmi3ValueReference,
                nUnknowns: usize,
                knowns: *const fmi3ValueReference,
                nKnowns: usize,
                seed: *const fmi3Float64,
                nSeed: usize,
                sensitivity: *mut fmi3Float64,
                nSensitivity: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &GET_ADJOINT_DERIVATIVE, |inst| {
                    variables::get_adjoint_derivative(
                        inst,
                        slice(unknowns, nUnknowns, "unknowns[]")?,
                        slice(knowns, nKnowns, "knowns[]")?,
                        slice(seed, nSeed, "seed[]")?,
                        slice_mut(sensitivity, nSensitivity, "sensitivity[]")?,
                    )
                })
            }
            pub unsafe extern "C" fn fmi3EnterConfigurationMode(
                instance: fmi3Instance,
            ) -> fmi3Status {
                guarded::<M>(instance, &ENTER_CONFIGURATION_MODE, |_| {
                    calls::unsupported("no structural parameters")
                })
            }
            pub unsafe extern "C" fn fmi3ExitConfigurationMode(
                instance: fmi3Instance,
            ) -> fmi3Status {
                guarded::<M>(instance, &EXIT_CONFIGURATION_MODE, |_| {
                    calls::unsupported("no structural parameters, so no configuration mode")
                })
            }
            pub unsafe extern "C" fn fmi3GetIntervalDecimal(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                intervals: *mut fmi3Float64,
                qualifiers: *mut fmi3IntervalQualifier,
            ) -> fmi3Status {
                guarded::<M>(instance, &GET_INTERVAL_DECIMAL, |_| {
                    calls::unsupported("no clocks")
                })
            }
            pub unsafe extern "C" fn fmi3GetIntervalFraction(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                counters: *mut fmi3UInt64,
                resolutions: *mut fmi3UInt64,
                qualifiers: *mut fmi3IntervalQualifier,
            ) -> fmi3Status {
                guarded::<M>(instance, &GET_INTERVAL_FRACTION, |_| {
                    calls::unsupported("no clocks")
                })
            }
            pub unsafe extern "C" fn fmi3GetShiftDecimal(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                shifts: *mut fmi3Float64,
            ) -> fmi3Status {
                guarded::<M>(instance, &GET_SHIFT_DECIMAL, |_| {
                    calls::unsupported("no clocks")
                })
            }
            pub unsafe extern "C" fn fmi3GetShiftFraction(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                counters: *mut fmi3UInt64,
                resolutions: *mut fmi3UInt64,
            ) -> fmi3Status {
                guarded::<M>(instance, &GET_SHIFT_FRACTION, |_| {
                    calls::unsupported("no clocks")
                })
            }
            pub unsafe extern "C" fn fmi3SetIntervalDecimal(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                intervals: *const fmi3Float64,
            ) -> fmi3Status {
                guarded::<M>(instance, &SET_INTERVAL_DECIMAL, |_| {
                    calls::unsupported("no clocks")
                })
            }
            pub unsafe extern "C" fn fmi3SetIntervalFraction(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                counters: *const fmi3UInt64,
                resolutions: *const fmi3UInt64,
            ) -> fmi3Status {
                guarded::<M>(instance, &SET_INTERVAL_FRACTION, |_| {
                    calls::unsupported("no clocks")
                })
            }
            pub unsafe extern "C" fn fmi3SetShiftDecimal(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                shifts: *const fmi3Float64,
            ) -> fmi3Status {
                guarded::<M>(instance, &SET_SHIFT_DECIMAL, |_| {
                    calls::unsupported("no clocks")
                })
            }
            pub unsafe extern "C" fn fmi3SetShiftFraction(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                counters: *const fmi3UInt64,
                resolutions: *const fmi3UInt64,
            ) -> fmi3Status {
                guarded::<M>(instance, &SET_SHIFT_FRACTION, |_| {
                    calls::unsupported("no clocks")
                })
            }
            pub unsafe extern "C" fn fmi3EvaluateDiscreteStates(
                instance: fmi3Instance,
            ) -> fmi3Status {
                guarded::<M>(instance, &EVALUATE_DISCRETE_STATES, |_| Ok(fmi3OK))
            }
            pub unsafe extern "C" fn fmi3UpdateDiscreteStates(
                instance: fmi3Instance,
                discreteStatesNeedUpdate: *mut fmi3Boolean,
                terminateSimulation: *mut fmi3Boolean,
                nominalsOfContinuousStatesChanged: *mut fmi3Boolean,
                valuesOfContinuousStatesChanged: *mut fmi3Boolean,
                nextEventTimeDefined: *mut fmi3Boolean,
                nextEventTime: *mut fmi3Float64,
            ) -> fmi3Status {
                guarded::<M>(instance, &UPDATE_DISCRETE_STATES, |inst| {
                    calls::update_discrete_states(
                        inst,
                        out_or_null(discreteStatesNeedUpdate, "discreteStatesNeedUpdate")?,
                        out_or_null(terminateSimulation, "terminateSimulation")?,
                        out_or_null(
                            nominalsOfContinuousStatesChanged,
                            "nominalsOfContinuousStatesChanged",
                        )?,
                        out_or_null(
                            valuesOfContinuousStatesChanged,
                            "valuesOfContinuousStatesChanged",
                        )?,
                        out_or_null(nextEventTimeDefined, "nextEventTimeDefined")?,
                        out_or_null(nextEventTime, "nextEventTime")?,
                    )
                })
            }
            pub unsafe extern "C" fn fmi3EnterContinuousTimeMode(
                instance: fmi3Instance,
            ) -> fmi3Status {
                guarded::<M>(
                    instance,
                    &ENTER_CONTINUOUS_TIME_MODE,
                    me::enter_continuous_time_mode,
                )
            }
            pub unsafe extern "C" fn fmi3CompletedIntegratorStep(
                instance: fmi3Instance,
                noSetFMUStatePriorToCurrentPoint: fmi3Boolean,
                enterEventMode: *mut fmi3Boolean,
                terminateSimulation: *mut fmi3Boolean,
            ) -> fmi3Status {
                guarded::<M>(instance, &COMPLETED_INTEGRATOR_STEP, |inst| {
                    calls::completed_integrator_step(
                        inst,
                        out(enterEventMode, "enterEventMode")?,
                        out(terminateSimulation, "terminateSimulation")?,
                    )
                })
            }
            pub unsafe extern "C" fn fmi3SetTime(
                instance: fmi3Instance,
                time: fmi3Float64,
            ) -> fmi3Status {
                guarded::<M>(instance, &SET_TIME, |inst| me::set_time(inst, time))
            }
            pub unsafe extern "C" fn fmi3SetContinuousStates(
                instance: fmi3Instance,
                continuousStates: *const fmi3Float64,
                nContinuousStates: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &SET_CONTINUOUS_STATES, |inst| {
                    me::set_continuous_states(
                        inst,
                        slice(continuousStates, nContinuousStates, "continuousStates[]")?,
                    )
                })
            }
            pub unsafe extern "C" fn fmi3GetContinuousStateDerivatives(
                instance: fmi3Instance,
                derivatives: *mut fmi3Float64,
                nContinuousStates: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &GET_CONTINUOUS_STATE_DERIVATIVES, |inst| {
                    me::get_derivatives(
                        inst,
                        slice_mut(derivatives, nContinuousStates, "derivatives[]")?,
                    )
                })
            }
            pub unsafe extern "C" fn fmi3GetEventIndicators(
                instance: fmi3Instance,
                eventIndicators: *mut fmi3Float64,
                nEventIndicators: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &GET_EVENT_INDICATORS, |inst| {
                    me::get_event_indicators(
                        inst,
                        slice_mut(eventIndicators, nEventIndicators, "eventIndicators[]")?,
                    )
                })
            }
            pub unsafe extern "C" fn fmi3GetContinuousStates(
                instance: fmi3Instance,
                continuousStates: *mut fmi3Float64,
                nContinuousStates: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &GET_CONTINUOUS_STATES, |inst| {
                    me::get_continuous_states(
                        inst,
                        slice_mut(continuousStates, nContinuousStates, "continuousStates[]")?,
                    )
                })
            }
            pub unsafe extern "C" fn fmi3GetNominalsOfContinuousStates(
                instance: fmi3Instance,
                nominals: *mut fmi3Float64,
                nContinuousStates: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &GET_NOMINALS_OF_CONTINUOUS_STATES, |inst| {
                    me::get_nominals_of_continuous_states(
                        inst,
                        slice_mut(nominals, nContinuousStates, "nominals[]")?,
                    )
                })
            }
            pub unsafe extern "C" fn fmi3GetNumberOfEventIndicators(
                instance: fmi3Instance,
                nEventIndicators: *mut usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &GET_NUMBER_OF_EVENT_INDICATORS, |inst| {
                    calls::get_number_of_event_indicators(
                        inst,
                        out(nEventIndicators, "nEventIndicators")?,
                    )
                })
            }
            pub unsafe extern "C" fn fmi3GetNumberOfContinuousStates(
                instance: fmi3Instance,
                nContinuousStates: *mut usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &GET_NUMBER_OF_CONTINUOUS_STATES, |inst| {
                    calls::get_number_of_continuous_states(
                        inst,
                        out(nContinuousStates, "nContinuousStates")?,
                    )
                })
            }
            pub unsafe extern "C" fn fmi3EnterStepMode(instance: fmi3Instance) -> fmi3Status {
                guarded::<M>(instance, &ENTER_STEP_MODE, calls::enter_step_mode)
            }
            pub unsafe extern "C" fn fmi3GetOutputDerivatives(
                instance: fmi3Instance,
                valueReferences: *const fmi3ValueReference,
                nValueReferences: usize,
                orders: *const fmi3Int32,
                values: *mut fmi3Float64,
                nValues: usize,
            ) -> fmi3Status {
                guarded::<M>(instance, &GET_OUTPUT_DERIVATIVES, |inst| {
                    variables::get_output_derivatives(
                        inst,
                        slice(valueReferences, nValueReferences, "valueReferences[]")?,
                        slice(orders, nValueReferences, "orders[]")?,
                        slice_mut(values, nValues, "values[]")?,
                    )
                })
            }
            pub unsafe extern "C" fn fmi3DoStep(
                instance: fmi3Instance,
                currentCommunicationPoint: fmi3Float64,
                communicationStepSize: fmi3Float64,
                noSetFMUStatePriorToCurrentPoint: fmi3Boolean,
                eventHandlingNeeded: *mut fmi3Boolean,
                terminateSimulation: *mut fmi3Boolean,
                earlyReturn: *mut fmi3Boolean,
                lastSuccessfulTime: *mut fmi3Float64,
            ) -> fmi3Status {
                guarded::<M>(instance, &DO_STEP, |inst| {
                    calls::do_step(
                        inst,
                        currentCommunicationPoint,
                        communicationStepSize,
                        out(eventHandlingNeeded, "eventHandlingNeeded")?,
                        out(terminateSimulation, "terminateSimulation")?,
                        out(earlyReturn, "earlyReturn")?,
                        out(lastSuccessfulTime, "lastSuccessfulTime")?,
                    )
                })
            }
            pub unsafe extern "C" fn fmi3ActivateModelPartition(
                instance: fmi3Instance,
                clockReference: fmi3ValueReference,
                activationTime: fmi3Float64,
            ) -> fmi3Status {
                guarded::<M>(instance, &ACTIVATE_MODEL_PARTITION, |_| {
                    calls::unsupported("no model partitions (Scheduled Execution is not offered)")
                })
            }
        );
    };
}

fmi3_functions!(crate::fmi_generic_functions);
