//! # mechfmu-testkit
//!
//! What a mechanism crate's tests use (as a dev-dependency):
//!
//! - [`harness`]: an in-process importer that drives a mechanism through the very C
//!   functions its FMU exports, recording every logged message;
//! - [`model_exchange`]: the same importer instantiating Model Exchange, integrated by the
//!   importers' one driver (`mechfmu_host::model_exchange`: fixed-step Runge–Kutta that
//!   locates events);
//! - [`fmi3`]: the same importer through FMI 3.0's functions (Co-Simulation, Model
//!   Exchange, arrays, the independent `time`);
//! - [`conformance`]: the checks every mechanism passes whatever its physics (reset, FMU
//!   state and its bytes, derivatives against finite differences, threads, Model
//!   Exchange, FMI 3.0 against FMI 2.0);
//! - [`golden`]: committed files generated from the declaration (modelDescription,
//!   interface page) checked to be current, or regenerated with `MECHFMU_BLESS=1`;
//! - [`documented`]: what a mechanism's interface page says of its runs (a default
//!   experiment that stands still, a moving case that moves), checked;
//! - [`rng`]: a deterministic generator for checks at random points;
//! - [`formulas`]: a mechanism without states against its formulas at random points, and
//!   its model descriptions' direct feedthrough;
//! - [`allocations`]: a counting allocator, and [`allocation_tests!`], the proof that the
//!   calls of an importer's loop never allocate.

pub mod allocations;
pub mod conformance;
pub mod documented;
pub mod fmi3;
pub mod formulas;
pub mod golden;
pub mod harness;
pub mod model_exchange;
pub mod rng;
