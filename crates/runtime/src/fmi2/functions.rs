//! The FMI 2.0 functions (Model Exchange and Co-Simulation), each written once: its C
//! signature (as in `fmi2FunctionTypes.h`) and its guarded call, one `extern "C" fn` of
//! [`fmi2_functions!`](crate::fmi2_functions).
//!
//! The table is expanded twice. Here, into generic `extern "C"` functions (`fmi2DoStep::<M>`,
//! ...): the harness and the tests call these. In a mechanism crate, by
//! [`export_fmu!`](crate::export_fmu), into the unmangled symbols an importer loads, each
//! forwarding to its generic function. A row's body converts every pointer argument with
//! one checked conversion of [`boundary`](crate::fmi::boundary) and hands the result to the safe
//! body in [`calls`](super::calls) or [`shared_calls`](crate::fmi::shared_calls);
//! [`guarded`](crate::fmi::boundary::guarded) puts it behind the boundary.

#![allow(non_snake_case, clippy::missing_safety_doc)]

use super::calls;
use super::ffi::*;
use super::instantiate;
use super::state::*;
use crate::fmi::boundary::{
    self, fmu_state, guarded, out, slice, slice_mut, strings, Buffer, StateSlot,
};
use crate::fmi::model_exchange as me;
use crate::fmi::{shared_calls, Version};
use crate::model::Mechanism;

/// The table of FMI 2.0 functions, written as the `pub unsafe extern "C" fn` items they are
/// (so rustfmt lays them out), for the macro `$emit` to expand: each body may name `M`, the
/// mechanism; `#[before_export(path)]` names a function of [`fmi`](crate::fmi) that the
/// exported symbol calls first.
#[doc(hidden)]
#[macro_export]
macro_rules! fmi2_functions {
    ($emit:path) => {
        $emit!(
            pub unsafe extern "C" fn fmi2GetTypesPlatform() -> fmi2String {
                calls::get_types_platform()
            }
            pub unsafe extern "C" fn fmi2GetVersion() -> fmi2String {
                calls::get_version()
            }
            pub unsafe extern "C" fn fmi2SetDebugLogging(
                c: fmi2Component,
                loggingOn: fmi2Boolean,
                nCategories: usize,
                categories: *const fmi2String,
            ) -> fmi2Status {
                guarded::<M>(c, &SET_DEBUG_LOGGING, |inst| {
                    shared_calls::set_debug_logging(
                        inst,
                        loggingOn != 0,
                        &strings(categories, nCategories, "categories[]", "a category")?,
                    )
                })
            }
            #[before_export(shared_calls::silence_panic_messages)]
            pub unsafe extern "C" fn fmi2Instantiate(
                instanceName: fmi2String,
                fmuType: fmi2Type,
                fmuGUID: fmi2String,
                fmuResourceLocation: fmi2String,
                functions: *const fmi2CallbackFunctions,
                visible: fmi2Boolean,
                loggingOn: fmi2Boolean,
            ) -> fmi2Component {
                instantiate::instantiate::<M>(instanceName, fmuType, fmuGUID, functions, loggingOn)
            }
            pub unsafe extern "C" fn fmi2FreeInstance(c: fmi2Component) {
                boundary::free_component::<M>(c, &FREE_INSTANCE)
            }
            pub unsafe extern "C" fn fmi2SetupExperiment(
                c: fmi2Component,
                toleranceDefined: fmi2Boolean,
                tolerance: fmi2Real,
                startTime: fmi2Real,
                stopTimeDefined: fmi2Boolean,
                stopTime: fmi2Real,
            ) -> fmi2Status {
                guarded::<M>(c, &SETUP_EXPERIMENT, |inst| {
                    calls::setup_experiment(
                        inst,
                        toleranceDefined,
                        tolerance,
                        startTime,
                        stopTimeDefined,
                        stopTime,
                    )
                })
            }
            pub unsafe extern "C" fn fmi2EnterInitializationMode(c: fmi2Component) -> fmi2Status {
                guarded::<M>(
                    c,
                    &ENTER_INITIALIZATION_MODE,
                    shared_calls::enter_initialization_mode,
                )
            }
            pub unsafe extern "C" fn fmi2ExitInitializationMode(c: fmi2Component) -> fmi2Status {
                guarded::<M>(
                    c,
                    &EXIT_INITIALIZATION_MODE,
                    shared_calls::exit_initialization_mode,
                )
            }
            pub unsafe extern "C" fn fmi2Terminate(c: fmi2Component) -> fmi2Status {
                guarded::<M>(c, &TERMINATE, shared_calls::terminate)
            }
            pub unsafe extern "C" fn fmi2Reset(c: fmi2Component) -> fmi2Status {
                guarded::<M>(c, &RESET, shared_calls::reset)
            }
            pub unsafe extern "C" fn fmi2GetReal(
                c: fmi2Component,
                vr: *const fmi2ValueReference,
                nvr: usize,
                value: *mut fmi2Real,
            ) -> fmi2Status {
                guarded::<M>(c, &GET_REAL, |inst| {
                    shared_calls::get_real(
                        inst,
                        slice(vr, nvr, "vr[]")?,
                        slice_mut(value, nvr, "value[]")?,
                    )
                })
            }
            pub unsafe extern "C" fn fmi2GetInteger(
                c: fmi2Component,
                vr: *const fmi2ValueReference,
                nvr: usize,
                value: *mut fmi2Integer,
            ) -> fmi2Status {
                guarded::<M>(c, &GET_INTEGER, |_| {
                    let vr = slice(vr, nvr, "vr[]")?;
                    slice_mut(value, nvr, "value[]")?;
                    shared_calls::no_variables(GET_INTEGER.name, vr, "Integer")
                })
            }
            pub unsafe extern "C" fn fmi2GetBoolean(
                c: fmi2Component,
                vr: *const fmi2ValueReference,
                nvr: usize,
                value: *mut fmi2Boolean,
            ) -> fmi2Status {
                guarded::<M>(c, &GET_BOOLEAN, |_| {
                    let vr = slice(vr, nvr, "vr[]")?;
                    slice_mut(value, nvr, "value[]")?;
                    shared_calls::no_variables(GET_BOOLEAN.name, vr, "Boolean")
                })
            }
            pub unsafe extern "C" fn fmi2GetString(
                c: fmi2Component,
                vr: *const fmi2ValueReference,
                nvr: usize,
                value: *mut fmi2String,
            ) -> fmi2Status {
                guarded::<M>(c, &GET_STRING, |_| {
                    let vr = slice(vr, nvr, "vr[]")?;
                    slice_mut(value, nvr, "value[]")?;
                    shared_calls::no_variables(GET_STRING.name, vr, "String")
                })
            }
            pub unsafe extern "C" fn fmi2SetReal(
                c: fmi2Component,
                vr: *const fmi2ValueReference,
                nvr: usize,
                value: *const fmi2Real,
            ) -> fmi2Status {
                guarded::<M>(c, &SET_REAL, |inst| {
                    shared_calls::set_real(
                        inst,
                        slice(vr, nvr, "vr[]")?,
                        slice(value, nvr, "value[]")?,
                    )
                })
            }
            pub unsafe extern "C" fn fmi2SetInteger(
                c: fmi2Component,
                vr: *const fmi2ValueReference,
                nvr: usize,
                value: *const fmi2Integer,
            ) -> fmi2Status {
                guarded::<M>(c, &SET_INTEGER, |_| {
                    let vr = slice(vr, nvr, "vr[]")?;
                    slice(value, nvr, "value[]")?;
                    shared_calls::no_variables(SET_INTEGER.name, vr, "Integer")
                })
            }
            pub unsafe extern "C" fn fmi2SetBoolean(
                c: fmi2Component,
                vr: *const fmi2ValueReference,
                nvr: usize,
                value: *const fmi2Boolean,
            ) -> fmi2Status {
                guarded::<M>(c, &SET_BOOLEAN, |_| {
                    let vr = slice(vr, nvr, "vr[]")?;
                    slice(value, nvr, "value[]")?;
                    shared_calls::no_variables(SET_BOOLEAN.name, vr, "Boolean")
                })
            }
            pub unsafe extern "C" fn fmi2SetString(
                c: fmi2Component,
                vr: *const fmi2ValueReference,
                nvr: usize,
                value: *const fmi2String,
            ) -> fmi2Status {
                guarded::<M>(c, &SET_STRING, |_| {
                    let vr = slice(vr, nvr, "vr[]")?;
                    slice(value, nvr, "value[]")?;
                    shared_calls::no_variables(SET_STRING.name, vr, "String")
                })
            }
            pub unsafe extern "C" fn fmi2GetFMUstate(
                c: fmi2Component,
                FMUstate: *mut fmi2FMUstate,
            ) -> fmi2Status {
                guarded::<M>(c, &GET_FMU_STATE, |inst| {
                    shared_calls::get_fmu_state(inst, StateSlot::new(FMUstate))
                })
            }
            pub unsafe extern "C" fn fmi2SetFMUstate(
                c: fmi2Component,
                FMUstate: fmi2FMUstate,
            ) -> fmi2Status {
                guarded::<M>(c, &SET_FMU_STATE, |inst| {
                    shared_calls::set_fmu_state(inst, fmu_state(FMUstate)?)
                })
            }
            pub unsafe extern "C" fn fmi2FreeFMUstate(
                c: fmi2Component,
                FMUstate: *mut fmi2FMUstate,
            ) -> fmi2Status {
                guarded::<M>(c, &FREE_FMU_STATE, |_| StateSlot::new(FMUstate).free())
            }
            pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
                c: fmi2Component,
                FMUstate: fmi2FMUstate,
                size: *mut usize,
            ) -> fmi2Status {
                guarded::<M>(c, &SERIALIZED_FMU_STATE_SIZE, |_| {
                    shared_calls::serialized_fmu_state_size::<M>(
                        fmu_state(FMUstate)?,
                        out(size, "size")?,
                    )
                })
            }
            pub unsafe extern "C" fn fmi2SerializeFMUstate(
                c: fmi2Component,
                FMUstate: fmi2FMUstate,
                serializedState: *mut fmi2Byte,
                size: usize,
            ) -> fmi2Status {
                guarded::<M>(c, &SERIALIZE_FMU_STATE, |_| {
                    shared_calls::serialize_fmu_state::<M>(
                        fmu_state(FMUstate)?,
                        Buffer::new(serializedState as *mut u8, size),
                    )
                })
            }
            pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
                c: fmi2Component,
                serializedState: *const fmi2Byte,
                size: usize,
                FMUstate: *mut fmi2FMUstate,
            ) -> fmi2Status {
                guarded::<M>(c, &DESERIALIZE_FMU_STATE, |_| {
                    shared_calls::deserialize_fmu_state::<M>(
                        Version::Fmi2,
                        slice(serializedState as *const u8, size, "serializedState[]")?,
                        StateSlot::new(FMUstate),
                    )
                })
            }
            pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
                c: fmi2Component,
                vUnknown_ref: *const fmi2ValueReference,
                nUnknown: usize,
                vKnown_ref: *const fmi2ValueReference,
                nKnown: usize,
                dvKnown: *const fmi2Real,
                dvUnknown: *mut fmi2Real,
            ) -> fmi2Status {
                guarded::<M>(c, &GET_DIRECTIONAL_DERIVATIVE, |inst| {
                    shared_calls::directional_derivative(
                        inst,
                        slice(vUnknown_ref, nUnknown, "vUnknown_ref[]")?,
                        slice(vKnown_ref, nKnown, "vKnown_ref[]")?,
                        slice(dvKnown, nKnown, "dvKnown[]")?,
                        0.0,
                        slice_mut(dvUnknown, nUnknown, "dvUnknown[]")?,
                    )
                })
            }
            pub unsafe extern "C" fn fmi2EnterEventMode(c: fmi2Component) -> fmi2Status {
                guarded::<M>(c, &ENTER_EVENT_MODE, me::enter_event_mode)
            }
            pub unsafe extern "C" fn fmi2NewDiscreteStates(
                c: fmi2Component,
                fmi2eventInfo: *mut fmi2EventInfo,
            ) -> fmi2Status {
                guarded::<M>(c, &NEW_DISCRETE_STATES, |inst| {
                    calls::new_discrete_states(inst, out(fmi2eventInfo, "fmi2eventInfo")?)
                })
            }
            pub unsafe extern "C" fn fmi2EnterContinuousTimeMode(c: fmi2Component) -> fmi2Status {
                guarded::<M>(
                    c,
                    &ENTER_CONTINUOUS_TIME_MODE,
                    me::enter_continuous_time_mode,
                )
            }
            pub unsafe extern "C" fn fmi2CompletedIntegratorStep(
                c: fmi2Component,
                noSetFMUStatePriorToCurrentPoint: fmi2Boolean,
                enterEventMode: *mut fmi2Boolean,
                terminateSimulation: *mut fmi2Boolean,
            ) -> fmi2Status {
                guarded::<M>(c, &COMPLETED_INTEGRATOR_STEP, |inst| {
                    calls::completed_integrator_step(
                        inst,
                        out(enterEventMode, "enterEventMode")?,
                        out(terminateSimulation, "terminateSimulation")?,
                    )
                })
            }
            pub unsafe extern "C" fn fmi2SetTime(c: fmi2Component, time: fmi2Real) -> fmi2Status {
                guarded::<M>(c, &SET_TIME, |inst| me::set_time(inst, time))
            }
            pub unsafe extern "C" fn fmi2SetContinuousStates(
                c: fmi2Component,
                x: *const fmi2Real,
                nx: usize,
            ) -> fmi2Status {
                guarded::<M>(c, &SET_CONTINUOUS_STATES, |inst| {
                    me::set_continuous_states(inst, slice(x, nx, "x[]")?)
                })
            }
            pub unsafe extern "C" fn fmi2GetDerivatives(
                c: fmi2Component,
                derivatives: *mut fmi2Real,
                nx: usize,
            ) -> fmi2Status {
                guarded::<M>(c, &GET_DERIVATIVES, |inst| {
                    me::get_derivatives(inst, slice_mut(derivatives, nx, "derivatives[]")?)
                })
            }
            pub unsafe extern "C" fn fmi2GetEventIndicators(
                c: fmi2Component,
                eventIndicators: *mut fmi2Real,
                ni: usize,
            ) -> fmi2Status {
                guarded::<M>(c, &GET_EVENT_INDICATORS, |inst| {
                    me::get_event_indicators(
                        inst,
                        slice_mut(eventIndicators, ni, "eventIndicators[]")?,
                    )
                })
            }
            pub unsafe extern "C" fn fmi2GetContinuousStates(
                c: fmi2Component,
                x: *mut fmi2Real,
                nx: usize,
            ) -> fmi2Status {
                guarded::<M>(c, &GET_CONTINUOUS_STATES, |inst| {
                    me::get_continuous_states(inst, slice_mut(x, nx, "x[]")?)
                })
            }
            pub unsafe extern "C" fn fmi2GetNominalsOfContinuousStates(
                c: fmi2Component,
                x_nominal: *mut fmi2Real,
                nx: usize,
            ) -> fmi2Status {
                guarded::<M>(c, &GET_NOMINALS_OF_CONTINUOUS_STATES, |inst| {
                    me::get_nominals_of_continuous_states(
                        inst,
                        slice_mut(x_nominal, nx, "x_nominal[]")?,
                    )
                })
            }
            pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
                c: fmi2Component,
                vr: *const fmi2ValueReference,
                nvr: usize,
                order: *const fmi2Integer,
                value: *const fmi2Real,
            ) -> fmi2Status {
                guarded::<M>(c, &SET_REAL_INPUT_DERIVATIVES, |inst| {
                    calls::set_real_input_derivatives(
                        inst,
                        slice(vr, nvr, "vr[]")?,
                        slice(order, nvr, "order[]")?,
                        slice(value, nvr, "value[]")?,
                    )
                })
            }
            pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
                c: fmi2Component,
                vr: *const fmi2ValueReference,
                nvr: usize,
                order: *const fmi2Integer,
                value: *mut fmi2Real,
            ) -> fmi2Status {
                guarded::<M>(c, &GET_REAL_OUTPUT_DERIVATIVES, |inst| {
                    calls::get_real_output_derivatives(
                        inst,
                        slice(vr, nvr, "vr[]")?,
                        slice(order, nvr, "order[]")?,
                        slice_mut(value, nvr, "value[]")?,
                    )
                })
            }
            pub unsafe extern "C" fn fmi2DoStep(
                c: fmi2Component,
                currentCommunicationPoint: fmi2Real,
                communicationStepSize: fmi2Real,
                noSetFMUStatePriorToCurrentPoint: fmi2Boolean,
            ) -> fmi2Status {
                guarded::<M>(c, &DO_STEP, |inst| {
                    calls::do_step(inst, currentCommunicationPoint, communicationStepSize)
                })
            }
            pub unsafe extern "C" fn fmi2CancelStep(c: fmi2Component) -> fmi2Status {
                guarded::<M>(c, &CANCEL_STEP, calls::cancel_step)
            }
            pub unsafe extern "C" fn fmi2GetStatus(
                c: fmi2Component,
                s: fmi2StatusKind,
                value: *mut fmi2Status,
            ) -> fmi2Status {
                guarded::<M>(c, &GET_STATUS, |inst| {
                    calls::get_status(inst, s, out(value, "value")?)
                })
            }
            pub unsafe extern "C" fn fmi2GetRealStatus(
                c: fmi2Component,
                s: fmi2StatusKind,
                value: *mut fmi2Real,
            ) -> fmi2Status {
                guarded::<M>(c, &GET_REAL_STATUS, |inst| {
                    calls::get_real_status(inst, s, out(value, "value")?)
                })
            }
            pub unsafe extern "C" fn fmi2GetIntegerStatus(
                c: fmi2Component,
                s: fmi2StatusKind,
                value: *mut fmi2Integer,
            ) -> fmi2Status {
                guarded::<M>(c, &GET_INTEGER_STATUS, |inst| {
                    calls::get_integer_status(inst, s)
                })
            }
            pub unsafe extern "C" fn fmi2GetBooleanStatus(
                c: fmi2Component,
                s: fmi2StatusKind,
                value: *mut fmi2Boolean,
            ) -> fmi2Status {
                guarded::<M>(c, &GET_BOOLEAN_STATUS, |inst| {
                    calls::get_boolean_status(inst, s, out(value, "value")?)
                })
            }
            pub unsafe extern "C" fn fmi2GetStringStatus(
                c: fmi2Component,
                s: fmi2StatusKind,
                value: *mut fmi2String,
            ) -> fmi2Status {
                guarded::<M>(c, &GET_STRING_STATUS, |inst| {
                    calls::get_string_status(inst, s, out(value, "value")?)
                })
            }
        );
    };
}

fmi2_functions!(crate::fmi_generic_functions);
