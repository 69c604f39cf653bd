//! The FMI 2.0 Co-Simulation layer. It mirrors the standard and knows nothing of any
//! mechanism: `ffi` (the C types), `state` (the state machine's table), `logger`,
//! `instance`, `fmu_state` (FMU states and their portable bytes), `wall` (the C boundary:
//! checked conversions, `catch_unwind`, failures to statuses), `api` (what each call does,
//! in safe Rust) and `functions` (the table of C signatures, one row per function).
//! [`export_fmu!`](crate::export_fmu) exports them.

pub mod api;
pub mod ffi;
pub mod fmu_state;
pub mod functions;
pub mod instance;
pub mod logger;
pub mod state;
pub mod wall;
