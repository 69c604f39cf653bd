//! FMI 3.0: the Co-Simulation functions of a loaded binary, typed as the standard's headers
//! declare them ([`functions`]), and an instance of it whose calls are safe to make
//! ([`instance`]).

pub mod functions;
pub mod instance;
