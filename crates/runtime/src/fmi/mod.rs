//! What the FMI 2.0 and FMI 3.0 layers share: an instance over one simulation and where it
//! is in the state machine (`instance`, `machine`: the states both standards' machines are
//! made of, and a table row's mask of them), FMU states and their portable bytes
//! (`fmu_state`), the importer's logger (`logger`), the C boundary (`boundary`: checked
//! conversions of the importer's pointers, `catch_unwind`, failures to statuses) and what
//! the calls both standards share do (`shared_calls`; `model_exchange` for Model Exchange's). The two
//! layers ([`fmi2`](crate::fmi2), [`fmi3`](crate::fmi3)) are siblings over these: each has
//! its C types, its table of functions and state-machine rows, and the bodies of its calls.
//!
//! Statuses are the C enums of both standards, which agree on the values used here
//! (`OK` 0, `Warning` 1, `Discard` 2, `Error` 3, `Fatal` 4).

pub mod boundary;
pub mod fmu_state;
pub mod instance;
pub mod logger;
pub mod machine;
pub mod model_exchange;
pub mod shared_calls;

use std::os::raw::c_uint;

/// A status of either standard (`fmi2Status`, `fmi3Status`).
pub type Status = c_uint;
pub const OK: Status = 0;
pub const WARNING: Status = 1;
pub const DISCARD: Status = 2;
pub const ERROR: Status = 3;
pub const FATAL: Status = 4;

pub use crate::contract::Version;

/// Expands a table of FMI functions (`fmi2_functions!`, `fmi3_functions!`) into generic
/// `extern "C"` functions, one per row, generic over the mechanism `M`. A row's body names
/// `M`, and the items it uses as the module invoking the table has them in scope.
#[doc(hidden)]
#[macro_export]
macro_rules! fmi_generic_functions {
    ($(
        $(#[before_export($($before:ident)::+)])?
        pub unsafe extern "C" fn $name:ident($($param:ident: $type:ty),* $(,)?) $(-> $ret:ty)? $body:block
    )*) => {
        $(
            #[allow(unused_variables, unused_unsafe)]
            pub unsafe extern "C" fn $name<M: Mechanism>($($param: $type),*) $(-> $ret)? {
                // SAFETY: the arguments are the importer's, valid as the standard promises
                // them; each conversion of `boundary` checks what can be checked and states the
                // rest as its safety contract.
                unsafe { $body }
            }
        )*
    };
}
