//! FMI 2.0: the functions of a loaded binary, typed as the standard's header declares them
//! ([`functions`]), and an instance of it whose calls are safe to make ([`instance`]).

pub mod functions;
pub mod instance;
