//! The FMI 3.0 layer, Model Exchange and Co-Simulation, the sibling of [`fmi2`](crate::fmi2)
//! over the same instance and simulation ([`fmi`](crate::fmi)). It mirrors the standard
//! and knows nothing of any mechanism: `ffi` (the C types), `state` (the state machines'
//! table, one row per function), `instantiate` (the instantiation functions at the C
//! boundary), `calls` (what each call does where FMI 3.0 differs from FMI 2.0: the
//! instantiation flags, event and step mode, out arguments, early return, what is not
//! offered), `variables` (variables and derivatives by FMI 3.0 value
//! reference: arrays, the independent time, typed getters and setters) and
//! `functions` (the table of the 75 C signatures). [`export_fmu!`](crate::export_fmu)
//! exports them.

pub mod calls;
pub mod ffi;
pub mod functions;
pub mod instantiate;
pub mod state;
pub mod variables;
