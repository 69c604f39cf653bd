//! `mechfmu-fmi-run`: one experiment on an FMI 2.0 or FMI 3.0 FMU, run through the [`fmi`]
//! crate (rust-fmi), in Co-Simulation ([`run`], the default) or in Model Exchange
//! ([`run_me`], `--interface me`). The FMU's `fmiVersion` decides (see "FMI 3.0" below).
//!
//! # Why it exists
//!
//! `mechfmu validate` runs every reference case of an FMU under FMPy and compares other
//! importers with it. libcosim is one; this is the third: an importer that shares no code
//! with FMPy (Python, ctypes, its own XML reader) nor with libcosim (C++, its own loader).
//! The `fmi` crate unpacks the archive itself, parses `modelDescription.xml` with its own
//! schema (`fmi-schema`, strict about unknown attributes and elements), loads the binary with
//! `libloading` and calls the FMI functions through bindings generated from the official
//! headers (`fmi-sys`). An FMU that only works because of one importer's leniency, or a
//! result that depends on how an importer drives the FMU, shows up as a disagreement.
//!
//! # The experiment
//!
//! An [`Experiment`] (JSON, written by `mechfmu_validate.fmi_crate.run_fmi_crate`) is run the
//! way FMPy's `simulate_fmu` runs a Co-Simulation FMU, so that the two must agree to rounding:
//!
//! 1. `fmi2Instantiate` (instance name: the model identifier), `fmi2SetupExperiment` with the
//!    relative tolerance (none when `null`: the FMU uses its own default), start time 0 and the
//!    stop time (none when `null`);
//! 2. the start values FMPy sets before initialization (inputs, and variables with
//!    `initial` exact or approx that are not constants), then `fmi2EnterInitializationMode`,
//!    then the others (tunable non-parameters, `initial="exact"`), in the model description's
//!    order, with FMPy's default `initial` for each causality and variability;
//! 3. the inputs' row 0, `fmi2ExitInitializationMode`, the recorded variables at t = 0;
//! 4. for k = 0 .. n-1: the inputs' row k, `fmi2DoStep(t_k, t_{k+1} − t_k)`, the recorded
//!    variables at t_{k+1}. Every time is `t_k = k as f64 * h`, never accumulated, and each step
//!    ends exactly on the next one: its size is `t_{k+1} − t_k` (FMPy's too), which may differ
//!    from h in the last bit. With `h` itself, an adaptive integrator inside the FMU sees
//!    different step sizes and the results differ from FMPy's by ~1e-13 instead of not at
//!    all. Row n of the inputs (the value at the stop time) is not applied: no step follows
//!    it (FMPy does the same);
//! 5. `fmi2Terminate`.
//!
//! Every FMI call must return `fmi2OK`; any other status (`fmi2Warning` included) ends the
//! run with an error naming the call, the variables and the time. Only Real variables are
//! set and recorded.
//!
//! # Model Exchange (`--interface me`)
//!
//! The same experiment, the same CSV, with the FMU's `<ModelExchange>` interface and the
//! importers' one Model Exchange driver (`mechfmu_host::model_exchange`, with this crate's
//! options), a fixed-step classical Runge-Kutta (RK4):
//!
//! 1. to 3. as above, with two differences: `fmi2Instantiate` as Model Exchange, and
//!    `fmi2SetupExperiment` without a tolerance (a fixed-step integrator controls no error;
//!    FMPy's Model Exchange passes none either, so the FMU uses its own default); the
//!    experiment's `relative_tolerance` is not used. `fmi2ExitInitializationMode` leaves
//!    the FMU in event mode: the event iteration (`fmi2NewDiscreteStates` until
//!    `newDiscreteStatesNeeded` is false), `fmi2EnterContinuousTimeMode`, the states
//!    (`fmi2GetContinuousStates`), the event indicators, the recorded variables at t = 0;
//! 4. for k = 0 .. n-1, the step from t_k to t_{k+1} (the same times as above):
//!    - the inputs' row k, held over the step. Row 0 was set in initialization mode; a row
//!      that differs from the previous one (in any bit) is an input event at t_k:
//!      `fmi2EnterEventMode`, `fmi2SetReal` of the inputs, the event iteration,
//!      `fmi2EnterContinuousTimeMode` (as FMPy's Model Exchange at an input event). The
//!      recorded variables at t_k were read before, as in Co-Simulation;
//!    - [`MeOptions::substeps`] RK4 steps (`--substeps`, default 1: the RK4 step is the
//!      communication step, since the Co-Simulation path has no finer grid of its own; the
//!      substeps end at t_k + (t_{k+1} − t_k)·j/m, the last exactly on t_{k+1}). Each stage
//!      is `fmi2SetTime`, `fmi2SetContinuousStates`, `fmi2GetDerivatives`; then the new
//!      states are set at the step's end and the event indicators read;
//!    - an event indicator whose domain (`z > 0` or `z ≤ 0`) differs between the step's
//!      start and end is a state event: bisection on the step's length, re-integrating from
//!      the step's start with one RK4 step of the shorter length, brackets the first sign
//!      change to [`EVENT_LOCATION_TOLERANCE`] (1e-12 s); the step is accepted at the end of
//!      the bracket, past the change (the FMU is set there);
//!    - `fmi2CompletedIntegratorStep` at the accepted point, unless the FMU declares
//!      `completedIntegratorStepNotNeeded` (after the location, so that the FMU judges the
//!      point the integrator keeps: the standard's order, and a stop at the crossing rather
//!      than at the end of a step that went past it);
//!    - at a state event, a step event (`enterEventMode`) or a time event (`nextEventTime`
//!      reached: the step ends there): `fmi2EnterEventMode`, the event iteration,
//!      `fmi2EnterContinuousTimeMode`; when `valuesOfContinuousStatesChanged`, the states
//!      are read again (`fmi2GetContinuousStates`); the event indicators are read again. The
//!      rest of the step follows, from the event;
//!    - the recorded variables at t_{k+1};
//! 5. `fmi2Terminate`.
//!
//! `terminateSimulation` (from `fmi2CompletedIntegratorStep` or `fmi2NewDiscreteStates`,
//! whose status may then be `fmi2Warning`, the FMU's way of logging the reason) ends the run
//! there: `fmi2Terminate`, and an error naming the call and the time the simulation stopped
//! at, as a `fmi2Discard` of `fmi2DoStep` ends a Co-Simulation run; no CSV is written. Any
//! other status than `fmi2OK` is an error, as in Co-Simulation.
//!
//! Inputs are held over each communication step in both interfaces: an input that varies
//! continuously between the rows (FMPy interpolates it linearly) is not reproduced between
//! communication points. RK4's global error is O(h⁴): about n (h λ)⁵ / 120 for a mode
//! of rate |λ| over n steps; `--substeps` refines it without changing the output grid.
//!
//! # FMI 3.0
//!
//! An FMI 3.0 FMU (`fmus/fmi3/<Name>.fmu`) runs the same experiment the way FMPy's
//! `simulate_fmu` runs it under FMI 3.0, with the calls of that version:
//!
//! * Co-Simulation: `fmi3InstantiateCoSimulation` without event mode and without early
//!   return (FMPy's defaults); the start values FMPy sets before initialization, then
//!   `fmi3EnterInitializationMode` with the tolerance, start 0 and the stop time, then the
//!   others, the inputs' row 0, `fmi3ExitInitializationMode` (step mode); then as above,
//!   `fmi3SetFloat64` and `fmi3DoStep`. A step that returns `terminateSimulation`,
//!   `earlyReturn` or `eventHandlingNeeded` ends the run with an error naming the flags,
//!   the status and `lastSuccessfulTime`, as any status but `fmi3OK` does;
//! * Model Exchange: `fmi3InstantiateModelExchange`, `fmi3EnterInitializationMode` without
//!   a tolerance, and the same RK4 with the same events (`fmi3GetContinuousStateDerivatives`,
//!   `fmi3UpdateDiscreteStates`, `fmi3CompletedIntegratorStep` when the FMU declares
//!   `needsCompletedIntegratorStep`); the numbers of states and event indicators are the
//!   FMU's (`fmi3GetNumberOf...`).
//!
//! Only `Float64` variables are set and recorded. The experiment names scalars: a scalar
//! variable by its name, an array element as FMI 3.0 writes it, `q[2]` or `I_C[1,2]`
//! (1-based, row-major), and the CSV's columns are these names. An array is set whole (its
//! value reference stands for all its elements): the model description's start values with
//! the named elements replaced (for an input, at every row). An element that is one variable
//! of the FMU at several places (a symmetric matrix's off-diagonal) must be named at each
//! with the same value: the FMU refuses the array otherwise, and so the run.
//!
//! # What the crate cannot read
//!
//! The crate reads the model description strictly and its schema refuses some attributes a
//! legal one may carry: XML's namespace declarations (`xmlns:xsi` on `<fmiModelDescription>`,
//! which many exporters write), FMI 2.0's `canHandleMultipleSetPerTimeInstant`, and FMI
//! 3.0's unit attributes of `<Float64>` (which every mechfmu FMU has).
//! `src/schema_gaps.rs` removes exactly these from the model description the crate is given,
//! in both versions (nothing a run uses), so that the crate's limits are not reported as the
//! FMU's faults.

mod fmi2;
mod fmi3;
mod me;
mod schema_gaps;

use fmi::schema::{traits::FmiModelDescription, MajorVersion};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::io::Write;
use std::path::PathBuf;

/// One experiment (the JSON file given to `mechfmu-fmi-run`).
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Experiment {
    /// The FMU file.
    pub fmu: PathBuf,
    /// The tolerance passed to `fmi2SetupExperiment` (`fmi3EnterInitializationMode`);
    /// `null`: none (the FMU's default).
    pub relative_tolerance: Option<f64>,
    /// The stop time passed to `fmi2SetupExperiment`; `null` or absent: none.
    #[serde(default)]
    pub stop_time: Option<f64>,
    /// The communication step h.
    pub step_size: f64,
    /// The number of communication steps n: the result has n + 1 rows, t = 0, h, ..., n·h.
    pub steps: usize,
    /// Start values by variable name (FMI 3.0: or array element, `q[2]`).
    #[serde(default)]
    pub start_values: BTreeMap<String, f64>,
    /// The input variables, in the order of the columns of `input_values`.
    #[serde(default)]
    pub inputs: Vec<String>,
    /// n + 1 rows, one value per input each: row k is set before the step from t = k·h.
    #[serde(default)]
    pub input_values: Vec<Vec<f64>>,
    /// The variables to record, after `time`.
    pub record: Vec<String>,
}

impl Experiment {
    /// Parses and checks an experiment.
    pub fn from_json(text: &str) -> Result<Self, String> {
        let exp: Experiment =
            serde_json::from_str(text).map_err(|e| format!("invalid experiment JSON: {e}"))?;
        exp.check()?;
        Ok(exp)
    }

    /// The consistency of the fields (not against the FMU: that is [`run`]'s).
    pub fn check(&self) -> Result<(), String> {
        if !(self.step_size.is_finite() && self.step_size > 0.0) {
            return Err(format!(
                "step_size must be positive and finite, not {}",
                self.step_size
            ));
        }
        if let Some(tol) = self.relative_tolerance {
            if !(tol.is_finite() && tol > 0.0) {
                return Err(format!(
                    "relative_tolerance must be positive and finite (or null), not {tol}"
                ));
            }
        }
        if let Some(stop) = self.stop_time {
            if !stop.is_finite() {
                return Err(format!("stop_time must be finite (or null), not {stop}"));
            }
        }
        if self.inputs.is_empty() {
            if self.input_values.iter().any(|row| !row.is_empty()) {
                return Err("input_values given without inputs".into());
            }
            return Ok(());
        }
        if self.input_values.len() != self.steps + 1 {
            return Err(format!(
                "input_values has {} rows: expected steps + 1 = {} (one per communication point)",
                self.input_values.len(),
                self.steps + 1
            ));
        }
        if let Some((k, row)) = self
            .input_values
            .iter()
            .enumerate()
            .find(|(_, row)| row.len() != self.inputs.len())
        {
            return Err(format!(
                "input_values row {k} has {} values: expected one per input ({})",
                row.len(),
                self.inputs.len()
            ));
        }
        Ok(())
    }
}

/// A result: `names[0]` is `time`; one row per communication point.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    pub names: Vec<String>,
    pub rows: Vec<Vec<f64>>,
}

impl Table {
    /// CSV: the names quoted on the first line, then one row per communication point, every
    /// value in Rust's shortest round-trip form (reads back to the same `f64`).
    pub fn write_csv(&self, out: &mut impl Write) -> std::io::Result<()> {
        let header: Vec<String> = self
            .names
            .iter()
            .map(|n| format!("\"{}\"", n.replace('"', "\"\"")))
            .collect();
        writeln!(out, "{}", header.join(","))?;
        for row in &self.rows {
            let cells: Vec<String> = row.iter().map(|v| format!("{v:?}")).collect();
            writeln!(out, "{}", cells.join(","))?;
        }
        Ok(())
    }
}

/// The FMI interface an experiment runs through (`--interface`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Interface {
    /// Co-Simulation (`cs`, the default): the FMU's own solver, one `fmi2DoStep` per
    /// communication step ([`run`]).
    #[default]
    CoSimulation,
    /// Model Exchange (`me`): a fixed-step RK4 with event handling ([`run_me`]).
    ModelExchange,
}

impl std::str::FromStr for Interface {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "cs" => Ok(Interface::CoSimulation),
            "me" => Ok(Interface::ModelExchange),
            _ => Err(format!("unknown interface `{s}`: expected `cs` or `me`")),
        }
    }
}

/// The result's column names: `time`, then `record`.
fn column_names(exp: &Experiment) -> Vec<String> {
    let mut names = vec!["time".to_string()];
    names.extend(exp.record.iter().cloned());
    names
}

/// The FMI version of the experiment's FMU, from its model description.
fn version(exp: &Experiment) -> Result<MajorVersion, String> {
    let md = fmi::import::peek_descr_path(&exp.fmu)
        .map_err(|e| format!("cannot import {}: {e}", exp.fmu.display()))?;
    md.major_version()
        .map_err(|e| format!("cannot import {}: {e}", exp.fmu.display()))
}

/// Runs the experiment through the given interface ([`run`] or [`run_me`] with the default
/// [`MeOptions`]).
pub fn run_with(exp: &Experiment, interface: Interface) -> Result<Table, String> {
    match interface {
        Interface::CoSimulation => run(exp),
        Interface::ModelExchange => run_me(exp, &MeOptions::default()).map(|(table, _)| table),
    }
}

/// Runs the experiment in Co-Simulation (FMI 2.0 or 3.0, as the FMU is); the table has
/// `time` then `record`, n + 1 rows.
pub fn run(exp: &Experiment) -> Result<Table, String> {
    exp.check()?;
    match version(exp)? {
        MajorVersion::FMI3 => fmi3::run(exp),
        MajorVersion::FMI2 => fmi2::run(exp),
        v => Err(format!("{}: FMI {v} is not supported", exp.fmu.display())),
    }
}

/// Runs the experiment in Model Exchange (see the crate's documentation, "Model
/// Exchange"): the table has `time` then `record`, n + 1 rows, like [`run`]'s.
pub fn run_me(exp: &Experiment, options: &MeOptions) -> Result<(Table, MeStats), String> {
    exp.check()?;
    if options.substeps == 0 {
        return Err("substeps must be at least 1".into());
    }
    match version(exp)? {
        MajorVersion::FMI3 => fmi3::run_me(exp, options),
        MajorVersion::FMI2 => fmi2::run_me(exp, options),
        v => Err(format!("{}: FMI {v} is not supported", exp.fmu.display())),
    }
}

// ---------------------------------------------------------------------------------------
// Model Exchange

/// How [`run_me`] integrates.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct MeOptions {
    /// RK4 steps per communication step (`--substeps`, at least 1; default 1: the step is
    /// the communication step, as the Co-Simulation path has no finer grid of its own).
    pub substeps: usize,
}

impl Default for MeOptions {
    fn default() -> Self {
        MeOptions { substeps: 1 }
    }
}

/// What happened during a Model Exchange run.
pub use mechfmu_host::model_exchange::Stats as MeStats;

/// The width below which bisection stops locating a sign change of an event indicator (s).
pub const EVENT_LOCATION_TOLERANCE: f64 = 1e-12;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interfaces_parse() {
        assert_eq!("cs".parse(), Ok(Interface::CoSimulation));
        assert_eq!("me".parse(), Ok(Interface::ModelExchange));
        assert!("ME".parse::<Interface>().is_err());
        assert_eq!(Interface::default(), Interface::CoSimulation);
    }
}
