//! The importer's side of a built FMU, for the tools that run the FMUs mechfmu builds on
//! this machine (`mechfmu build`, `docs`, `inspect`, `bench`, `sweep-worker`, the
//! robustness suite): an FMU as an importer opens it, and nothing of the mechanism's Rust
//! crate linked in. It is the one place that loads an FMU's binary.
//!
//! - [`archive`]: the `.fmu` file, its model description and this machine's binary taken out
//!   of it, the binaries it carries;
//! - [`description`]: the model description of either FMI version, read by one parser;
//! - [`library`]: the binary loaded as an importer loads it, and the texts it renders of
//!   itself when built to describe itself (the documented extras of `export_fmu!`);
//! - [`fmi2`] and [`fmi3`]: each standard's C types and functions, typed as its header
//!   declares them (over `mechfmu::fmi2::ffi` and `mechfmu::fmi3::ffi`): every function in
//!   one table (`api`) for an importer that calls them as it likes, and an instance whose
//!   calls are safe to make; [`log`]: the importer's logger both instantiate with;
//! - [`model_exchange`]: the importers' one Model Exchange driver (fixed-step RK4, state
//!   events located by bisection, the event iteration), over an instance of either version;
//! - [`platform`]: where each platform's binary is in an FMU of each version;
//! - [`cpu_clock`]: the thread's CPU time the tools time calls with.
//!
//! The unsafe code is here, each block with the argument it rests on: loading a binary,
//! resolving its symbols as the types the headers give them, and calling them with
//! arguments those types describe. A function table holds the library it was resolved from,
//! so no pointer outlives its code.

#[macro_use]
mod table;

pub mod archive;
pub mod cpu_clock;
pub mod description;
pub mod fmi2;
pub mod fmi3;
pub mod library;
pub mod log;
pub mod model_exchange;
/// The platforms and their folders in an FMU of each version: the runtime's one map.
pub use mechfmu::contract::platform;
