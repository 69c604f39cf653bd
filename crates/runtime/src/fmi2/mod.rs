//! The FMI 2.0 layer, Model Exchange and Co-Simulation. It mirrors the standard and knows
//! nothing of any mechanism: `ffi` (the C types), `state` (the state machines' table),
//! `logger`, `instance`, `fmu_state` (FMU states and their portable bytes), `wall` (the C
//! boundary: checked conversions, `catch_unwind`, failures to statuses), `api` (what each
//! call does, in safe Rust; `model_exchange` for the calls of Model Exchange) and
//! `functions` (the table of C signatures, one row per function).
//! [`export_fmu!`](crate::export_fmu) exports them.

pub mod api;
pub mod ffi;
pub mod fmu_state;
pub mod functions;
pub mod instance;
pub mod logger;
pub mod model_exchange;
pub mod state;
pub mod wall;
