//! # mechfmu-testkit
//!
//! What a mechanism crate's tests use (as a dev-dependency):
//!
//! - [`harness`]: an in-process importer that drives a mechanism through the very C
//!   functions its FMU exports, recording every logged message;
//! - [`conformance`]: the checks every mechanism passes whatever its physics (reset, FMU
//!   state and its bytes, derivatives against finite differences, threads).

pub mod conformance;
pub mod harness;
