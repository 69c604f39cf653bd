//! Deterministic scenarios: instantiate/free cycles (for valgrind), long runs, a tour of
//! every function for the silence check, runs compared bit for bit across threads, and
//! serialized FMU states for the fuzzing corpus; an importer's fixed-step Model Exchange
//! integrator ([`MeIntegrator`]) for them. Each for FMI 2.0 and FMI 3.0.

mod cycles;
mod cycles3;
mod dump;
mod me;
mod runs;
mod runs3;
mod tour;

pub use cycles::{cycles, me_cycle, ME_EVERY};
pub use cycles3::{cycles3, me_cycle3};
pub use dump::{serialized_state, serialized_state3, Dump};
pub use me::MeIntegrator;
pub use runs::{fingerprint, long_run, me_fingerprint, pushed_inputs, LongRun};
pub use runs3::{fingerprint3, me_fingerprint3, pushed_inputs3};
pub use tour::{tour, tour3};
