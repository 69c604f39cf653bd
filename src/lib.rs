//! # mechfmu
//!
//! Turns mechanical models into FMI 2.0 Co-Simulation FMUs.
//!
//! A mechanism is declared once, in Rust, with [`mechanism!`] (its variables) and
//! [`model::Mechanism`] (its equations); [`export_fmu!`] turns it into the 34 C functions of
//! an FMU; the `mechfmu` command builds, packages and validates. The layers, from the
//! physics outwards:
//!
//! - [`model`]: the declaration API (variables, units, equations generic over the scalar);
//! - [`solver`]: the embedded Runge–Kutta solver with error control;
//! - [`simulation`]: a mechanism under the solver: values, set/get rules, communication steps;
//! - [`fmi2`]: the FMI 2.0 Co-Simulation layer (C types, state machine, logger, API);
//! - [`xml`]: the generated modelDescription.xml; [`guid`]: its GUID;
//! - [`package`]: the `.fmu` archive; [`cli`]: the `mechfmu` command; [`bench`]: `mechfmu bench`.
//!
//! See `docs/architecture.md` for how they fit together.

pub mod bench;
pub mod cli;
pub mod conformance;
pub mod docs;
pub mod fmi2;
pub mod guid;
pub mod harness;
pub mod modal;
pub mod model;
pub mod package;
pub mod simulation;
pub mod solver;
pub mod xml;

/// nalgebra, re-exported so mechanism crates use the same version as the runtime.
pub use nalgebra;
