//! Hostile-importer tests of mechfmu's built FMUs.
//!
//! This crate is an FMI 2.0 importer of its own: it unpacks `fmus/<Name>.fmu`, dlopens the
//! binary, resolves all 44 functions (Model Exchange and Co-Simulation), and learns the
//! model only from its modelDescription.xml. The `robustness-driver` binary runs the scenarios (random call
//! sequences, instantiate/free cycles for valgrind, long runs, a silent run); the tests in
//! `tests/` run it in child processes, so a crash fails a test with its seed instead of
//! taking the test runner down.

pub mod ffi;
pub mod fmu;
pub mod importer;
pub mod rng;
pub mod scenarios;
pub mod sequences;
