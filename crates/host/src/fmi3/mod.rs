//! FMI 3.0: the headers' C types ([`ffi`]), every function of a loaded binary typed as the
//! headers declare it ([`api`]), the Co-Simulation functions a well-behaved importer calls
//! ([`functions`]), and an instance of it whose calls are safe to make ([`instance`]).

pub use mechfmu::fmi3::ffi;

pub mod api;
pub mod functions;
pub mod instance;
