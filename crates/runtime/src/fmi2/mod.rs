//! The FMI 2.0 layer, Model Exchange and Co-Simulation. It mirrors the standard and knows
//! nothing of any mechanism: `ffi` (the C types), `state` (the state machines' table, one
//! row per function), `instantiate` (`fmi2Instantiate` at the C boundary), `calls` (what
//! each call does, in safe Rust) and
//! `functions` (the table of C signatures, one row per function), over what it shares
//! with FMI 3.0 in [`fmi`](crate::fmi) (the instance, FMU states, the logger, the C boundary,
//! the Model Exchange calls).
//! [`export_fmu!`](crate::export_fmu) exports them.

pub mod calls;
pub mod ffi;
pub mod functions;
pub mod instantiate;
pub mod state;
