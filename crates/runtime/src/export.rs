//! What a mechanism crate's binary exports: [`export_fmu!`](crate::export_fmu) puts the
//! FMI 2.0 and FMI 3.0 functions (the rows of [`fmi2_functions!`](crate::fmi2_functions)
//! and [`fmi3_functions!`](crate::fmi3_functions)) into the crate under their C names
//! (one binary serves an FMU of either version): all that a shipped binary exports. With
//! the runtime's `describe` feature, which the `mechfmu` command turns on in a build of its
//! own for this machine (never shipped), also the documented extras it reads the FMU's
//! files from:
//!
//! - `mechfmu_model_description`, `mechfmu_model_description_fmi3`: the binary's own
//!   `modelDescription.xml` of each version (`mechfmu build`);
//! - `mechfmu_documentation`, `mechfmu_documentation_fmi3`: its `documentation/index.html`
//!   of each version (`mechfmu build`);
//! - `mechfmu_terminals_and_icons`: its FMI 3.0 FMU's `terminalsAndIcons.xml`, empty without
//!   terminals (`mechfmu build`);
//! - `mechfmu_interface`: its interface page in Markdown
//!   ([`docs::interface`](crate::docs::interface()), `mechfmu docs`).
//!
//! With the runtime's `bench` feature (`mechfmu bench` turns it on), also
//! `mechfmu_counters` and `mechfmu_bench` ([`bench`]), which shipped FMUs do not have.

use std::panic::catch_unwind;

/// Exports a mechanism as an FMU: the 44 FMI 2.0 functions and the 75 FMI 3.0 functions
/// (Model Exchange and Co-Simulation) under their C names, plus the extras of
/// [`export`](crate::export) with the `describe` feature. Checks the mechanism's event indicators, arrays and moving
/// case at compile time.
///
/// A mechanism crate that can be a component of a system's FMU exports under
/// `#[cfg(not(feature = "component"))]`, and a system crate under `#[cfg(feature = "fmu")]`
/// (a [`system!`](crate::system) whose components are all mechanisms is one): the system's
/// feature `fmu` turns its components' feature `component` on, so that its binary exports the
/// system's functions and none of theirs.
///
/// ```ignore
/// #[cfg(not(feature = "component"))]
/// mechfmu::export_fmu!(Oscillator);
/// ```
#[macro_export]
macro_rules! export_fmu {
    ($mechanism:ty) => {
        const _: () = $crate::model::check_event_indicators(
            <$mechanism as $crate::model::Declaration>::VARIABLES,
            <$mechanism as $crate::model::Mechanism>::EVENT_INDICATORS,
        );
        const _: () = $crate::model::check_arrays(
            <$mechanism as $crate::model::Declaration>::VARIABLES,
            <$mechanism as $crate::model::Mechanism>::ARRAYS,
        );
        const _: () = $crate::model::check_terminals(
            <$mechanism as $crate::model::Declaration>::VARIABLES,
            <$mechanism as $crate::model::Mechanism>::TERMINALS,
        );
        const _: () = $crate::model::check_moving_case(
            <$mechanism as $crate::model::Declaration>::VARIABLES,
            <$mechanism as $crate::model::Mechanism>::EXPERIMENT,
            <$mechanism as $crate::model::Mechanism>::MOVING_CASE,
        );

        /// The C functions of this FMU.
        #[allow(non_snake_case, clippy::missing_safety_doc)]
        pub mod fmi2_exports {
            use super::*;
            use $crate::fmi2::ffi::*;

            use $crate::fmi2::functions;
            type ExportedMechanism = $mechanism;
            $crate::fmi2_functions!($crate::exported_functions);

            $crate::describe_exports!($mechanism);
            $crate::bench_exports!($mechanism);
        }

        /// The FMI 3.0 C functions of this FMU.
        #[allow(non_snake_case, clippy::missing_safety_doc)]
        pub mod fmi3_exports {
            use super::*;
            use $crate::fmi3::ffi::*;

            use $crate::fmi3::functions;
            type ExportedMechanism = $mechanism;
            $crate::fmi3_functions!($crate::exported_functions);
        }
    };
}

/// Expands a table of FMI functions into unmangled symbols, each forwarding to its generic
/// function in `functions` (the layer's module) for `ExportedMechanism`, both of which the
/// module invoking the table has in scope.
#[doc(hidden)]
#[macro_export]
macro_rules! exported_functions {
    ($(
        $(#[before_export($($before:ident)::+)])?
        pub unsafe extern "C" fn $name:ident($($param:ident: $type:ty),* $(,)?) $(-> $ret:ty)? $body:block
    )*) => {
        $(
            #[no_mangle]
            pub unsafe extern "C" fn $name($($param: $type),*) $(-> $ret)? {
                $( $crate::fmi::$($before)::+(); )?
                // SAFETY: the importer's arguments, forwarded as received.
                unsafe { functions::$name::<ExportedMechanism>($($param),*) }
            }
        )*
    };
}

/// Copies the text `make` gives (or `"error: <message>"`) into `buffer`, NUL-terminated,
/// when it fits; returns its length in bytes (without the NUL). A NULL buffer asks for the
/// length only. Never panics (a panic gives 0).
///
/// # Safety
/// `buffer` is NULL or points to `capacity` writable bytes.
pub unsafe fn write_text(
    make: impl FnOnce() -> Result<String, String> + std::panic::UnwindSafe,
    buffer: *mut u8,
    capacity: usize,
) -> usize {
    catch_unwind(|| {
        let text = make().unwrap_or_else(|e| format!("error: {e}"));
        let bytes = text.as_bytes();
        if !buffer.is_null() && capacity > bytes.len() {
            // SAFETY: the caller gives `capacity` writable bytes at `buffer`.
            unsafe {
                std::ptr::copy_nonoverlapping(bytes.as_ptr(), buffer, bytes.len());
                *buffer.add(bytes.len()) = 0;
            }
        }
        bytes.len()
    })
    .unwrap_or(0)
}

/// Exports a system's declaration ([`system!`](crate::system)) for the `mechfmu` command,
/// which packages the system as an SSP: `mechfmu_system_declaration`, its
/// [JSON](crate::system::declaration_json) through a buffer (see [`write_text`]).
///
/// ```ignore
/// mechfmu::export_system!(TwoOscillators);
/// ```
#[macro_export]
macro_rules! export_system {
    ($system:ty) => {
        /// Not FMI: this system's declaration as JSON, through a buffer (see
        /// [`write_text`]($crate::export::write_text)). Used by `mechfmu build`.
        #[no_mangle]
        pub unsafe extern "C" fn mechfmu_system_declaration(
            buffer: *mut u8,
            capacity: usize,
        ) -> usize {
            // SAFETY: the caller's buffer, as `write_text` asks.
            unsafe {
                $crate::export::write_text(
                    || {
                        $crate::system::declaration_json(
                            &<$system as $crate::system::System>::DECLARATION,
                        )
                    },
                    buffer,
                    capacity,
                )
            }
        }
    };
}

/// The documented extras of [`export`](crate::export) (what the `mechfmu` command reads of a
/// binary it built), with the `describe` feature: a shipped binary carries the FMI functions
/// alone, and the command builds one with the extras, for this machine, to read them from.
#[cfg(feature = "describe")]
#[doc(hidden)]
#[macro_export]
macro_rules! describe_exports {
    ($mechanism:ty) => {
        /// Not FMI: the modelDescription.xml of this binary, through a buffer (see
        /// [`write_text`]($crate::export::write_text)). Used by `mechfmu build`.
        #[no_mangle]
        pub unsafe extern "C" fn mechfmu_model_description(
            buffer: *mut u8,
            capacity: usize,
        ) -> usize {
            // SAFETY: the caller's buffer, as `write_text` asks.
            unsafe {
                $crate::export::write_text(
                    $crate::xml::model_description::<$mechanism>,
                    buffer,
                    capacity,
                )
            }
        }

        /// Not FMI: this FMU's documentation/index.html, through a buffer (see
        /// [`write_text`]($crate::export::write_text)). Used by `mechfmu build`.
        #[no_mangle]
        pub unsafe extern "C" fn mechfmu_documentation(buffer: *mut u8, capacity: usize) -> usize {
            // SAFETY: the caller's buffer, as `write_text` asks.
            unsafe {
                $crate::export::write_text(
                    $crate::docs::documentation::<$mechanism>,
                    buffer,
                    capacity,
                )
            }
        }

        /// Not FMI: this mechanism's interface page (Markdown), through a buffer (see
        /// [`write_text`]($crate::export::write_text)). Used by `mechfmu docs`.
        #[no_mangle]
        pub unsafe extern "C" fn mechfmu_interface(buffer: *mut u8, capacity: usize) -> usize {
            // SAFETY: the caller's buffer, as `write_text` asks.
            unsafe {
                $crate::export::write_text($crate::docs::interface::<$mechanism>, buffer, capacity)
            }
        }

        /// Not FMI: the FMI 3.0 modelDescription.xml of this binary, as
        /// `mechfmu_model_description`. Used by `mechfmu build`.
        #[no_mangle]
        pub unsafe extern "C" fn mechfmu_model_description_fmi3(
            buffer: *mut u8,
            capacity: usize,
        ) -> usize {
            // SAFETY: the caller's buffer, as `write_text` asks.
            unsafe {
                $crate::export::write_text(
                    $crate::xml::fmi3::model_description::<$mechanism>,
                    buffer,
                    capacity,
                )
            }
        }

        /// Not FMI: the documentation/index.html of this binary's FMI 3.0 FMU, as
        /// `mechfmu_documentation`. Used by `mechfmu build`.
        #[no_mangle]
        pub unsafe extern "C" fn mechfmu_documentation_fmi3(
            buffer: *mut u8,
            capacity: usize,
        ) -> usize {
            // SAFETY: the caller's buffer, as `write_text` asks.
            unsafe {
                $crate::export::write_text(
                    $crate::docs::documentation_fmi3::<$mechanism>,
                    buffer,
                    capacity,
                )
            }
        }

        /// Not FMI: the terminalsAndIcons/terminalsAndIcons.xml of this binary's FMI 3.0
        /// FMU, empty for a mechanism without terminals. Used by `mechfmu build`.
        #[no_mangle]
        pub unsafe extern "C" fn mechfmu_terminals_and_icons(
            buffer: *mut u8,
            capacity: usize,
        ) -> usize {
            // SAFETY: the caller's buffer, as `write_text` asks.
            unsafe {
                $crate::export::write_text(
                    || {
                        $crate::xml::terminals_and_icons::<$mechanism>()
                            .map(::core::option::Option::unwrap_or_default)
                    },
                    buffer,
                    capacity,
                )
            }
        }
    };
}

/// Without the `describe` feature: no extras.
#[cfg(not(feature = "describe"))]
#[doc(hidden)]
#[macro_export]
macro_rules! describe_exports {
    ($mechanism:ty) => {};
}

#[cfg(feature = "bench")]
pub mod bench;

/// The benchmark entry points of [`bench`], with the `bench` feature.
#[cfg(feature = "bench")]
#[doc(hidden)]
#[macro_export]
macro_rules! bench_exports {
    ($mechanism:ty) => {
        /// Not FMI, `bench` feature only: see [`counters`]($crate::export::bench::counters).
        #[no_mangle]
        pub unsafe extern "C" fn mechfmu_counters(
            c: fmi2Component,
            out: *mut u64,
            n: usize,
        ) -> usize {
            // SAFETY: the caller's arguments, forwarded.
            unsafe { $crate::export::bench::counters::<$mechanism>(c, out, n) }
        }
        /// Not FMI, `bench` feature only: see [`bench`]($crate::export::bench::bench).
        #[no_mangle]
        pub unsafe extern "C" fn mechfmu_bench(
            c: fmi2Component,
            part: u32,
            n: u64,
            h: fmi2Real,
        ) -> fmi2Status {
            // SAFETY: the caller's arguments, forwarded.
            unsafe { $crate::export::bench::bench::<$mechanism>(c, part, n, h) }
        }
    };
}

/// Without the `bench` feature: no benchmark entry points.
#[cfg(not(feature = "bench"))]
#[doc(hidden)]
#[macro_export]
macro_rules! bench_exports {
    ($mechanism:ty) => {};
}
