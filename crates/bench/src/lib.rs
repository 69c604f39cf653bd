//! The benchmark lab of `mechfmu bench`: where the time of an FMU goes.
//!
//! Every figure comes from a built FMU binary (the `.so` inside the `.fmu` files the command
//! builds with the runtime's `bench` feature, by default `target/bench/fmus/<Name>.fmu`),
//! loaded through `mechfmu-host` and called through its C symbols exactly as an importer
//! calls it; nothing of the mechanism's Rust crate is linked into the benchmark. The
//! command selects and builds the FMUs and hands them to [`lab::run`] with a [`lab::Plan`];
//! the lab measures them and gives back the [`report::Report`] it prints and writes.
//!
//! - [`binary`] and [`instance`]: an FMU's binary loaded with its model descriptions, and
//!   an FMI 2.0 instance of it started as an importer starts one.
//! - [`native`]: ns per `fmi2DoStep` at communication steps 1e-3 and 1e-2 and tolerances
//!   1e-6 and 1e-10, with the work behind a step (model evaluations, solver steps) from the
//!   FMU's own counters (`mechfmu_counters`, not an FMI function), and the parts of a step
//!   each timed alone in the FMU's own compiled code (`mechfmu_bench`): the split into the
//!   model's equations, copying, the solver's arithmetic, the step's checks and the FMI
//!   layer; the plumbing is copying, checks and the FMI layer. Also ns per
//!   `fmi2GetReal`/`fmi2SetReal` and per co-simulation cycle.
//! - [`fmi3`]: ns per `fmi3DoStep` of the same binary, timed in the same runs as
//!   `fmi2DoStep` (the same calls of the simulation, the FMI layer apart).
//! - [`model_exchange`]: ns per derivative evaluation through Model Exchange
//!   (`fmi2SetTime` + `fmi2SetContinuousStates` + `fmi2GetDerivatives`) next to the
//!   model's equations alone at the same points, and the difference.
//! - [`instructions`]: the same split in instructions counted by valgrind, repeatable on a
//!   busy machine.
//! - [`energies`]: instructions per step and per Model Exchange evaluation of the
//!   mechanisms declared again from their energies (`tests/energies`), against the
//!   hand-written ones'.
//! - [`python`] (`scripts/bench_fmpy.py`): µs per step under FMPy's low-level loop, and
//!   scipy `solve_ivp` on the Oscillator for the [`precision`] diagram.
//! - [`build_time`]: a clean release build of every FMU for every platform, timed.
//! - [`c_step`]: the yardstick, the Oscillator's step written plainly in C (an adaptive
//!   Dormand–Prince with DOPRI5's control), timed and counted like the FMUs' steps.
//!
//! Times are thread CPU time ([`clock`]), medians of repeated runs ([`effort`]: how many,
//! on which instances); [`figures`] gathers them per mechanism; [`report`] prints the table
//! and writes the JSON that runs are compared with, and the Markdown.

pub mod binary;
pub mod build_time;
pub mod c_step;
pub mod clock;
pub mod effort;
pub mod energies;
pub mod figures;
pub mod fmi3;
pub mod instance;
pub mod instructions;
pub mod lab;
pub mod model_exchange;
pub mod native;
pub mod precision;
pub mod progress;
pub mod python;
pub mod report;
