//! FMI 2.0: the header's C types ([`ffi`]), every function of a loaded binary typed as the
//! header declares it ([`api`]), those a well-behaved importer calls ([`functions`]), and
//! an instance of it whose calls are safe to make ([`instance`]).

pub use mechfmu::fmi2::ffi;

pub mod api;
pub mod functions;
pub mod instance;
