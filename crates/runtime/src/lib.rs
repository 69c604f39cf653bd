//! # mechfmu
//!
//! The runtime of a mechfmu FMU: what a mechanism crate depends on.
//!
//! A mechanism is declared once, in Rust, with [`mechanism!`] (its variables) and
//! [`model::Mechanism`] (its equations); [`export_fmu!`] turns it into the C functions of
//! an FMU. The layers, from the physics outwards (each uses only those above it):
//!
//! - [`solver`]: the embedded Runge–Kutta solver with error control;
//! - [`model`]: the declaration API (variables, units, equations generic over the scalar);
//!   [`modal`]: undamped modes, for mechanisms' calculated parameters;
//! - [`simulation`]: a mechanism under the solver: values, set/get rules, communication steps;
//!   [`system`]: mechanisms connected ([`system!`]): components, connections, parameter sets,
//!   checked at compile time;
//! - [`contract`]: what the model description and the binary agree on (capabilities, log
//!   categories, GUID);
//! - [`xml`]: the generated modelDescription.xml;
//! - [`fmi`]: what both FMI layers share: the instance, its states, FMU states, the
//!   importer's logger, the C boundary;
//! - [`fmi2`], [`fmi3`]: the FMI 2.0 and FMI 3.0 layers, Model Exchange and Co-Simulation
//!   (C types, state tables, the calls);
//! - [`docs`]: the documentation page every FMU carries;
//! - [`export`]: what a mechanism crate's binary exports ([`export_fmu!`]).
//!
//! The `mechfmu` command (crate `mechfmu-cli`) builds, packages and validates; the tests
//! of a mechanism crate use `mechfmu-testkit`. See `docs/architecture.md`.

pub mod contract;
pub mod docs;
pub mod export;
pub mod fmi;
pub mod fmi2;
pub mod fmi3;
pub mod lagrange;
pub mod modal;
pub mod model;
pub mod simulation;
pub mod solver;
pub mod system;
pub mod xml;

/// What [`mechanism!`] reports its declaration errors with (at the variable's line, once).
#[doc(hidden)]
pub use mechfmu_macros::{
    at_span as __at_span, source_text as __source_text, unique_variables as __unique_variables,
};

/// nalgebra, re-exported so mechanism crates use the same version as the runtime.
pub use nalgebra;
