//! Hostile-importer tests of mechfmu's built FMUs.
//!
//! This crate is an importer of its own, of FMI 2.0 and FMI 3.0: it unpacks
//! `fmus/<Name>.fmu` (FMI 2.0) and `fmus/fmi3/<Name>.fmu` (FMI 3.0), loads the binary
//! through `mechfmu_host` (the one loader of FMU binaries), resolves all the standard's
//! functions (44 of FMI 2.0, 75 of FMI 3.0), typed there from the headers, and learns the
//! model only from its modelDescription.xml. The `robustness-driver` binary runs the
//! scenarios (random call sequences, instantiate/free cycles for valgrind, long runs, a
//! silent run); the tests in `tests/` run it in child processes, so a crash fails a test
//! with its seed instead of taking the test runner down.

mod c_types;
pub mod fmu;
pub mod importer;
pub mod rng;
pub mod scenarios;
pub use c_types::{ffi, ffi3};
pub mod sequences;
