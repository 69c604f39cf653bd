//! The FMI 2.0 Co-Simulation layer. It mirrors the standard and knows nothing of any
//! mechanism: `ffi` (the C types), `state` (the state machine's table), `logger`, `instance`,
//! and `api` (one function per FMI call). [`export_fmu!`](crate::export_fmu) exports them.

pub mod api;
pub mod ffi;
pub mod fmu_state;
pub mod instance;
pub mod logger;
pub mod state;

/// Exports the 34 FMI 2.0 Co-Simulation functions of a mechanism under their C names, plus
/// `mechfmu_model_description` (the modelDescription.xml this binary belongs to),
/// `mechfmu_documentation` (its documentation/index.html) and, for
/// `mechfmu bench`, `mechfmu_counters` and `mechfmu_bench`.
///
/// ```ignore
/// mechfmu::export_fmu!(Oscillator);
/// ```
#[macro_export]
macro_rules! export_fmu {
    ($mechanism:ty) => {
        #[allow(non_snake_case, clippy::missing_safety_doc)]
        pub mod fmi2_exports {
            use super::*;
            use $crate::fmi2::api;
            use $crate::fmi2::ffi::*;
            type M = $mechanism;

            #[no_mangle]
            pub extern "C" fn fmi2GetTypesPlatform() -> fmi2String {
                api::get_types_platform()
            }
            #[no_mangle]
            pub extern "C" fn fmi2GetVersion() -> fmi2String {
                api::get_version()
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetDebugLogging(
                c: fmi2Component,
                on: fmi2Boolean,
                n: usize,
                cat: *const fmi2String,
            ) -> fmi2Status {
                unsafe { api::set_debug_logging::<M>(c, on, n, cat) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2Instantiate(
                name: fmi2String,
                ty: fmi2Type,
                guid: fmi2String,
                resources: fmi2String,
                functions: *const fmi2CallbackFunctions,
                visible: fmi2Boolean,
                logging_on: fmi2Boolean,
            ) -> fmi2Component {
                api::silence_panic_messages();
                unsafe {
                    api::instantiate::<M>(name, ty, guid, resources, functions, visible, logging_on)
                }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2FreeInstance(c: fmi2Component) {
                unsafe { api::free_instance::<M>(c) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetupExperiment(
                c: fmi2Component,
                tol_defined: fmi2Boolean,
                tol: fmi2Real,
                start: fmi2Real,
                stop_defined: fmi2Boolean,
                stop: fmi2Real,
            ) -> fmi2Status {
                unsafe {
                    api::setup_experiment::<M>(c, tol_defined, tol, start, stop_defined, stop)
                }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2EnterInitializationMode(c: fmi2Component) -> fmi2Status {
                unsafe { api::enter_initialization_mode::<M>(c) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2ExitInitializationMode(c: fmi2Component) -> fmi2Status {
                unsafe { api::exit_initialization_mode::<M>(c) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2Terminate(c: fmi2Component) -> fmi2Status {
                unsafe { api::terminate::<M>(c) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2Reset(c: fmi2Component) -> fmi2Status {
                unsafe { api::reset::<M>(c) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetReal(
                c: fmi2Component,
                vr: *const fmi2ValueReference,
                nvr: usize,
                value: *mut fmi2Real,
            ) -> fmi2Status {
                unsafe { api::get_real::<M>(c, vr, nvr, value) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetInteger(
                c: fmi2Component,
                vr: *const fmi2ValueReference,
                nvr: usize,
                value: *mut fmi2Integer,
            ) -> fmi2Status {
                unsafe { api::get_integer::<M>(c, vr, nvr, value) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetBoolean(
                c: fmi2Component,
                vr: *const fmi2ValueReference,
                nvr: usize,
                value: *mut fmi2Boolean,
            ) -> fmi2Status {
                unsafe { api::get_boolean::<M>(c, vr, nvr, value) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetString(
                c: fmi2Component,
                vr: *const fmi2ValueReference,
                nvr: usize,
                value: *mut fmi2String,
            ) -> fmi2Status {
                unsafe { api::get_string::<M>(c, vr, nvr, value) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetReal(
                c: fmi2Component,
                vr: *const fmi2ValueReference,
                nvr: usize,
                value: *const fmi2Real,
            ) -> fmi2Status {
                unsafe { api::set_real::<M>(c, vr, nvr, value) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetInteger(
                c: fmi2Component,
                vr: *const fmi2ValueReference,
                nvr: usize,
                value: *const fmi2Integer,
            ) -> fmi2Status {
                unsafe { api::set_integer::<M>(c, vr, nvr, value) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetBoolean(
                c: fmi2Component,
                vr: *const fmi2ValueReference,
                nvr: usize,
                value: *const fmi2Boolean,
            ) -> fmi2Status {
                unsafe { api::set_boolean::<M>(c, vr, nvr, value) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetString(
                c: fmi2Component,
                vr: *const fmi2ValueReference,
                nvr: usize,
                value: *const fmi2String,
            ) -> fmi2Status {
                unsafe { api::set_string::<M>(c, vr, nvr, value) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetFMUstate(
                c: fmi2Component,
                s: *mut fmi2FMUstate,
            ) -> fmi2Status {
                unsafe { api::get_fmu_state::<M>(c, s) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetFMUstate(
                c: fmi2Component,
                s: fmi2FMUstate,
            ) -> fmi2Status {
                unsafe { api::set_fmu_state::<M>(c, s) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2FreeFMUstate(
                c: fmi2Component,
                s: *mut fmi2FMUstate,
            ) -> fmi2Status {
                unsafe { api::free_fmu_state::<M>(c, s) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
                c: fmi2Component,
                s: fmi2FMUstate,
                size: *mut usize,
            ) -> fmi2Status {
                unsafe { api::serialized_fmu_state_size::<M>(c, s, size) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SerializeFMUstate(
                c: fmi2Component,
                s: fmi2FMUstate,
                bytes: *mut fmi2Byte,
                size: usize,
            ) -> fmi2Status {
                unsafe { api::serialize_fmu_state::<M>(c, s, bytes, size) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
                c: fmi2Component,
                bytes: *const fmi2Byte,
                size: usize,
                s: *mut fmi2FMUstate,
            ) -> fmi2Status {
                unsafe { api::deserialize_fmu_state::<M>(c, bytes, size, s) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
                c: fmi2Component,
                unknowns: *const fmi2ValueReference,
                n_unknowns: usize,
                knowns: *const fmi2ValueReference,
                n_knowns: usize,
                dv_known: *const fmi2Real,
                dv_unknown: *mut fmi2Real,
            ) -> fmi2Status {
                unsafe {
                    api::get_directional_derivative::<M>(
                        c, unknowns, n_unknowns, knowns, n_knowns, dv_known, dv_unknown,
                    )
                }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
                c: fmi2Component,
                vr: *const fmi2ValueReference,
                nvr: usize,
                order: *const fmi2Integer,
                value: *const fmi2Real,
            ) -> fmi2Status {
                unsafe { api::set_real_input_derivatives::<M>(c, vr, nvr, order, value) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
                c: fmi2Component,
                vr: *const fmi2ValueReference,
                nvr: usize,
                order: *const fmi2Integer,
                value: *mut fmi2Real,
            ) -> fmi2Status {
                unsafe { api::get_real_output_derivatives::<M>(c, vr, nvr, order, value) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2DoStep(
                c: fmi2Component,
                t: fmi2Real,
                h: fmi2Real,
                no_prior: fmi2Boolean,
            ) -> fmi2Status {
                unsafe { api::do_step::<M>(c, t, h, no_prior) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2CancelStep(c: fmi2Component) -> fmi2Status {
                unsafe { api::cancel_step::<M>(c) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetStatus(
                c: fmi2Component,
                kind: fmi2StatusKind,
                value: *mut fmi2Status,
            ) -> fmi2Status {
                unsafe { api::get_status::<M>(c, kind, value) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetRealStatus(
                c: fmi2Component,
                kind: fmi2StatusKind,
                value: *mut fmi2Real,
            ) -> fmi2Status {
                unsafe { api::get_real_status::<M>(c, kind, value) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetIntegerStatus(
                c: fmi2Component,
                kind: fmi2StatusKind,
                value: *mut fmi2Integer,
            ) -> fmi2Status {
                unsafe { api::get_integer_status::<M>(c, kind, value) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetBooleanStatus(
                c: fmi2Component,
                kind: fmi2StatusKind,
                value: *mut fmi2Boolean,
            ) -> fmi2Status {
                unsafe { api::get_boolean_status::<M>(c, kind, value) }
            }
            #[no_mangle]
            pub unsafe extern "C" fn fmi2GetStringStatus(
                c: fmi2Component,
                kind: fmi2StatusKind,
                value: *mut fmi2String,
            ) -> fmi2Status {
                unsafe { api::get_string_status::<M>(c, kind, value) }
            }

            /// Not FMI: the instance's cumulative work counters (communication steps,
            /// accepted and rejected solver steps, model evaluations), for `mechfmu bench`.
            #[no_mangle]
            pub unsafe extern "C" fn mechfmu_counters(
                c: fmi2Component,
                out: *mut u64,
                n: usize,
            ) -> usize {
                unsafe { api::counters::<M>(c, out, n) }
            }
            /// Not FMI: repeats one part of a step (0: the model equations, 1: the
            /// solver's right-hand side, 2: steps without the FMI layer) `n` times on a
            /// copy of the instance, so `mechfmu bench` can time the parts.
            #[no_mangle]
            pub unsafe extern "C" fn mechfmu_bench(
                c: fmi2Component,
                part: u32,
                n: u64,
                h: fmi2Real,
            ) -> fmi2Status {
                unsafe { api::bench::<M>(c, part, n, h) }
            }

            /// The modelDescription.xml of this binary, copied into `buffer` (NUL-terminated)
            /// if it fits; returns the length it needs (without the NUL). Used by
            /// `mechfmu build` to package the XML that matches this very binary.
            /// Not FMI: this FMU's documentation/index.html (description, notes, variables,
            /// capabilities, a plot of the default experiment run in-process), same buffer
            /// protocol as `mechfmu_model_description`. Used by `mechfmu build`.
            #[no_mangle]
            pub unsafe extern "C" fn mechfmu_documentation(
                buffer: *mut u8,
                capacity: usize,
            ) -> usize {
                unsafe { $crate::docs::write_documentation::<M>(buffer, capacity) }
            }

            #[no_mangle]
            pub unsafe extern "C" fn mechfmu_model_description(
                buffer: *mut u8,
                capacity: usize,
            ) -> usize {
                unsafe { $crate::fmi2::api::model_description::<M>(buffer, capacity) }
            }
        }
    };
}
