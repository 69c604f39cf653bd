//! `mechfmu-fmi-run`: one experiment on an FMI 2.0 FMU, run through the [`fmi`] crate
//! (rust-fmi), in Co-Simulation ([`run`], the default) or in Model Exchange ([`run_me`],
//! `--interface me`).
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
//! An [`Experiment`] (JSON, written by `mechfmu_validate.importers.run_fmi_crate`) is run the
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
//! The same experiment, the same CSV, with the FMU's `<ModelExchange>` interface and this
//! crate's own integrator, a fixed-step classical Runge-Kutta (RK4):
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

use fmi::fmi2::import::Fmi2Import;
use fmi::fmi2::instance::{CoSimulation, Common, InstanceME, ModelExchange};
use fmi::fmi2::schema::{Causality, Initial, ScalarVariable, ScalarVariableElement, Variability};
use fmi::fmi2::{Fmi2Error, Fmi2Res};
use fmi::traits::FmiImport;
use fmi::EventFlags;
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
    /// The tolerance passed to `fmi2SetupExperiment`; `null`: none (the FMU's default).
    pub relative_tolerance: Option<f64>,
    /// The stop time passed to `fmi2SetupExperiment`; `null` or absent: none.
    #[serde(default)]
    pub stop_time: Option<f64>,
    /// The communication step h.
    pub step_size: f64,
    /// The number of communication steps n: the result has n + 1 rows, t = 0, h, ..., n·h.
    pub steps: usize,
    /// Start values by variable name.
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

/// FMI 2.0's default `initial` (the table FMPy applies too); `None` where there is none.
fn initial(v: &ScalarVariable) -> Option<Initial> {
    if let Some(i) = &v.initial {
        return Some(i.clone());
    }
    use Causality as C;
    use Variability as V;
    match (variability(v), &v.causality) {
        (V::Constant, C::Output | C::Local) => Some(Initial::Exact),
        (V::Fixed | V::Tunable, C::Parameter) => Some(Initial::Exact),
        (V::Fixed | V::Tunable, C::CalculatedParameter | C::Local) => Some(Initial::Calculated),
        (V::Discrete | V::Continuous, C::Input) => Some(Initial::Exact),
        (V::Discrete | V::Continuous, C::Output | C::Local) => Some(Initial::Calculated),
        _ => None,
    }
}

fn variability(v: &ScalarVariable) -> Variability {
    v.variability.unwrap_or(Variability::Continuous)
}

/// FMPy's `settable_in_instantiated`.
fn settable_before_initialization(v: &ScalarVariable) -> bool {
    v.causality == Causality::Input
        || (variability(v) != Variability::Constant
            && matches!(initial(v), Some(Initial::Exact | Initial::Approx)))
}

/// FMPy's `settable_in_initialization_mode`.
fn settable_in_initialization(v: &ScalarVariable) -> bool {
    v.causality == Causality::Input
        || (v.causality != Causality::Parameter && variability(v) == Variability::Tunable)
        || (variability(v) != Variability::Constant && initial(v) == Some(Initial::Exact))
}

/// The status of an FMI call: `Ok` for `fmi2OK` only.
fn ok(call: impl FnOnce() -> String, r: Result<Fmi2Res, Fmi2Error>) -> Result<(), String> {
    let status = match r {
        Ok(Fmi2Res::OK) => return Ok(()),
        Ok(Fmi2Res::Warning) => "fmi2Warning".to_string(),
        Ok(Fmi2Res::Pending) => "fmi2Pending (asynchronous steps are not supported)".to_string(),
        Err(Fmi2Error::Discard) => "fmi2Discard".to_string(),
        Err(Fmi2Error::Error) => "fmi2Error".to_string(),
        Err(Fmi2Error::Fatal) => "fmi2Fatal".to_string(),
        Err(e) => e.to_string(),
    };
    Err(format!("{} returned {status}", call()))
}

/// The FMI interface an experiment runs through (`--interface`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Interface {
    /// Co-Simulation (`cs`, the default): the FMU's own solver, one `fmi2DoStep` per
    /// communication step ([`run`]).
    #[default]
    CoSimulation,
    /// Model Exchange (`me`): this crate's fixed-step RK4 with event handling ([`run_me`]).
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

/// The variables of an experiment resolved against the model description.
struct Prepared<'e> {
    /// Start values set before `fmi2EnterInitializationMode`: (index, vr, name, value).
    before: Vec<(usize, u32, &'e str, f64)>,
    /// Start values set in initialization mode.
    during: Vec<(usize, u32, &'e str, f64)>,
    input_vrs: Vec<u32>,
    record_vrs: Vec<u32>,
    input_list: String,
    record_list: String,
}

/// Resolves the experiment's variables (Real only) and splits the start values as FMPy does.
fn prepare<'e>(
    md: &fmi::fmi2::schema::Fmi2ModelDescription,
    model: &str,
    exp: &'e Experiment,
) -> Result<Prepared<'e>, String> {
    let real = |name: &str, role: &str| -> Result<(usize, u32), String> {
        let (index, v) = md
            .model_variables
            .variables
            .iter()
            .enumerate()
            .find(|(_, v)| v.name == name)
            .ok_or_else(|| {
                format!("unknown variable `{name}` ({role}): not in the modelDescription.xml of {model}")
            })?;
        if !matches!(v.elem, ScalarVariableElement::Real(_)) {
            return Err(format!(
                "variable `{name}` ({role}) is not a Real: only Real variables are set and recorded"
            ));
        }
        Ok((index, v.value_reference))
    };
    // the start values in the model description's order, split as FMPy splits them
    let mut starts = Vec::new();
    for (name, &value) in &exp.start_values {
        let (index, vr) = real(name, "start value")?;
        starts.push((index, vr, name.as_str(), value));
    }
    starts.sort_by_key(|s| s.0);
    let (before, during): (Vec<_>, Vec<_>) = starts
        .into_iter()
        .partition(|s| settable_before_initialization(&md.model_variables.variables[s.0]));
    if let Some(s) = during
        .iter()
        .find(|s| !settable_in_initialization(&md.model_variables.variables[s.0]))
    {
        let v = &md.model_variables.variables[s.0];
        return Err(format!(
            "start value of `{}`: a variable of causality {:?}, variability {:?}, initial {:?} cannot be set",
            s.2,
            v.causality,
            variability(v),
            initial(v)
        ));
    }
    let input_vrs = exp
        .inputs
        .iter()
        .map(|n| real(n, "input").map(|(_, vr)| vr))
        .collect::<Result<Vec<_>, _>>()?;
    let record_vrs = exp
        .record
        .iter()
        .map(|n| real(n, "recorded").map(|(_, vr)| vr))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Prepared {
        before,
        during,
        input_vrs,
        record_vrs,
        input_list: exp.inputs.join(", "),
        record_list: exp.record.join(", "),
    })
}

/// `fmi2SetupExperiment` (with `tolerance`, start 0 and the experiment's stop time), the
/// start values, the inputs' row 0 and `fmi2ExitInitializationMode`: steps 1 to 3 of the
/// experiment, the same under both interfaces.
fn initialize(
    fmu: &mut impl Common,
    exp: &Experiment,
    prep: &Prepared,
    tolerance: Option<f64>,
) -> Result<(), String> {
    ok(
        || {
            format!(
                "fmi2SetupExperiment(tolerance {:?}, start 0, stop {:?})",
                tolerance, exp.stop_time
            )
        },
        fmu.setup_experiment(tolerance, 0.0, exp.stop_time),
    )?;
    for &(_, vr, name, value) in &prep.before {
        ok(
            || format!("fmi2SetReal({name} = {value:?}) before initialization"),
            fmu.set_real(&[vr], &[value]),
        )?;
    }
    ok(
        || "fmi2EnterInitializationMode".into(),
        Common::enter_initialization_mode(fmu),
    )?;
    for &(_, vr, name, value) in &prep.during {
        ok(
            || format!("fmi2SetReal({name} = {value:?}) in initialization mode"),
            fmu.set_real(&[vr], &[value]),
        )?;
    }
    if !prep.input_vrs.is_empty() {
        ok(
            || format!("fmi2SetReal({}) in initialization mode", prep.input_list),
            fmu.set_real(&prep.input_vrs, &exp.input_values[0]),
        )?;
    }
    ok(
        || "fmi2ExitInitializationMode".into(),
        Common::exit_initialization_mode(fmu),
    )
}

/// One row of the result: `t`, then the recorded variables as the FMU gives them now.
fn record(
    fmu: &mut impl Common,
    prep: &Prepared,
    t: f64,
    values: &mut [f64],
) -> Result<Vec<f64>, String> {
    if !prep.record_vrs.is_empty() {
        ok(
            || format!("fmi2GetReal({}) at t = {t:?}", prep.record_list),
            fmu.get_real(&prep.record_vrs, values),
        )?;
    }
    let mut row = Vec::with_capacity(values.len() + 1);
    row.push(t);
    row.extend_from_slice(values);
    Ok(row)
}

/// The result's column names: `time`, then `record`.
fn column_names(exp: &Experiment) -> Vec<String> {
    let mut names = vec!["time".to_string()];
    names.extend(exp.record.iter().cloned());
    names
}

/// Runs the experiment through the given interface ([`run`] or [`run_me`] with the default
/// [`MeOptions`]).
pub fn run_with(exp: &Experiment, interface: Interface) -> Result<Table, String> {
    match interface {
        Interface::CoSimulation => run(exp),
        Interface::ModelExchange => run_me(exp, &MeOptions::default()).map(|(table, _)| table),
    }
}

/// Runs the experiment in Co-Simulation; the table has `time` then `record`, n + 1 rows.
pub fn run(exp: &Experiment) -> Result<Table, String> {
    exp.check()?;
    let import: Fmi2Import = fmi::import::from_path(&exp.fmu)
        .map_err(|e| format!("cannot import {}: {e}", exp.fmu.display()))?;
    let md = import.model_description();
    let model = md
        .co_simulation
        .as_ref()
        .ok_or_else(|| format!("{} is not a Co-Simulation FMU", exp.fmu.display()))?
        .model_identifier
        .clone();
    let prep = prepare(md, &model, exp)?;
    let input_vrs = &prep.input_vrs;
    let input_list = &prep.input_list;

    let mut fmu = import
        .instantiate_cs(&model, false, false)
        .map_err(|e| format!("fmi2Instantiate of {model} failed: {e}"))?;
    initialize(&mut fmu, exp, &prep, exp.relative_tolerance)?;

    let h = exp.step_size;
    let time = |k: usize| k as f64 * h;
    let mut rows = Vec::with_capacity(exp.steps + 1);
    let mut values = vec![0.0; prep.record_vrs.len()];
    for k in 0..=exp.steps {
        let t = time(k);
        if k > 0 {
            let t0 = time(k - 1);
            if !input_vrs.is_empty() {
                ok(
                    || format!("fmi2SetReal({input_list}) before the step from t = {t0:?}"),
                    fmu.set_real(input_vrs, &exp.input_values[k - 1]),
                )?;
            }
            ok(
                || {
                    format!(
                        "fmi2DoStep(t = {t0:?}, h = {:?}) (step {k} of {})",
                        t - t0,
                        exp.steps
                    )
                },
                fmu.do_step(t0, t - t0, true),
            )?;
        }
        rows.push(record(&mut fmu, &prep, t, &mut values)?);
    }
    ok(|| "fmi2Terminate".into(), fmu.terminate())?;
    Ok(Table {
        names: column_names(exp),
        rows,
    })
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
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct MeStats {
    /// Accepted RK4 steps (a step cut short at an event counts as one).
    pub steps: usize,
    /// `fmi2GetDerivatives` calls (4 per RK4 step, bisection trials included).
    pub derivative_evaluations: usize,
    /// State events: a sign change of an event indicator, located by bisection.
    pub state_events: usize,
    /// Step events: `fmi2CompletedIntegratorStep` returned `enterEventMode`.
    pub step_events: usize,
    /// Time events: the time an event iteration announced (`nextEventTime`) reached.
    pub time_events: usize,
    /// Input events: the inputs changed at a communication point.
    pub input_events: usize,
    /// Event iterations whose `fmi2NewDiscreteStates` set `valuesOfContinuousStatesChanged`.
    pub state_changes: usize,
}

/// The width below which bisection stops locating a sign change of an event indicator (s).
pub const EVENT_LOCATION_TOLERANCE: f64 = 1e-12;

/// The most events handled within one communication step before the run is declared stuck
/// (an event indicator that keeps changing sign: chattering).
const MAX_EVENTS_PER_STEP: usize = 100;

/// The indicators whose domain (`z > 0` or `z <= 0`, the standard's definition of a state
/// event) differs between `before` and `after`.
fn sign_changes(before: &[f64], after: &[f64]) -> Vec<usize> {
    before
        .iter()
        .zip(after)
        .enumerate()
        .filter(|(_, (a, b))| (**a > 0.0) != (**b > 0.0))
        .map(|(i, _)| i)
        .collect()
}

/// "state event of event indicator 0" (or "indicators [0, 1]").
fn state_event(which: &[usize]) -> String {
    match which {
        [i] => format!("state event of event indicator {i}"),
        _ => format!("state event of event indicators {which:?}"),
    }
}

/// A Model Exchange instance being integrated, with its accepted point.
struct MeIntegration {
    fmu: InstanceME,
    /// `completedIntegratorStepNotNeeded` is false (or absent).
    needs_completed_integrator_step: bool,
    /// The accepted time, states and event indicators (the FMU is at this point between
    /// steps).
    t: f64,
    x: Vec<f64>,
    z: Vec<f64>,
    /// `nextEventTime` of the last event iteration, if defined.
    next_event_time: Option<f64>,
    /// The RK4 stages and scratch.
    k: [Vec<f64>; 4],
    stage: Vec<f64>,
    stats: MeStats,
    /// Where the run is, for messages: the communication step (1-based), their number, and
    /// the step's start.
    step: usize,
    steps: usize,
    step_start: f64,
}

/// How an event iteration ended.
enum Iteration {
    Done,
    /// `terminateSimulation`: the message saying which call asked, when.
    Terminate(String),
}

impl MeIntegration {
    fn at(&self, t: f64) -> String {
        if self.step == 0 {
            return format!("at t = {t:?} (initialization)");
        }
        format!(
            "at t = {t:?} (in step {} of {}, from t = {:?})",
            self.step, self.steps, self.step_start
        )
    }

    /// `fmi2SetTime(t)` and `fmi2SetContinuousStates(x)`.
    fn set_point(&mut self, t: f64, x: &[f64]) -> Result<(), String> {
        ok(|| format!("fmi2SetTime({t:?})"), self.fmu.set_time(t))?;
        let r = self.fmu.set_continuous_states(x);
        ok(|| format!("fmi2SetContinuousStates {}", self.at(t)), r)
    }

    /// `fmi2GetEventIndicators` at the FMU's current point, into `z` (none: no call).
    fn read_indicators(fmu: &mut InstanceME, z: &mut [f64]) -> Result<Fmi2Res, Fmi2Error> {
        if z.is_empty() {
            return Ok(Fmi2Res::OK);
        }
        match fmu.get_event_indicators(z) {
            Ok(true) => Ok(Fmi2Res::OK),
            // the fmi crate reports fmi2Discard as `false`
            Ok(false) => Err(Fmi2Error::Discard),
            Err(e) => Err(e),
        }
    }

    /// One classical RK4 step from (`t0`, `x0`) to `t1`: for each stage `fmi2SetTime`,
    /// `fmi2SetContinuousStates` and `fmi2GetDerivatives`; then the FMU is set to (`t1`,
    /// `x1`) and its event indicators read into `z1`.
    fn rk4(
        &mut self,
        t0: f64,
        x0: &[f64],
        t1: f64,
        x1: &mut [f64],
        z1: &mut [f64],
    ) -> Result<(), String> {
        let h = t1 - t0;
        let mid = t0 + 0.5 * h;
        let stages = [(t0, 0.0), (mid, 0.5 * h), (mid, 0.5 * h), (t1, h)];
        for (s, &(ts, a)) in stages.iter().enumerate() {
            // the stage's states: x0 + a k[s-1]
            if s == 0 {
                self.stage.copy_from_slice(x0);
            } else {
                let (done, _) = self.k.split_at(s);
                for ((y, &x), &k) in self.stage.iter_mut().zip(x0).zip(&done[s - 1]) {
                    *y = x + a * k;
                }
            }
            let stage = std::mem::take(&mut self.stage);
            let set = self.set_point(ts, &stage);
            self.stage = stage;
            set?;
            let r = self.fmu.get_derivatives(&mut self.k[s]);
            ok(
                || {
                    format!(
                        "fmi2GetDerivatives {} (RK4 stage {} of 4)",
                        self.at(ts),
                        s + 1
                    )
                },
                r,
            )?;
            self.stats.derivative_evaluations += 1;
        }
        for (i, y) in x1.iter_mut().enumerate() {
            let [k1, k2, k3, k4] = &self.k;
            *y = x0[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
        self.set_point(t1, x1)?;
        let r = Self::read_indicators(&mut self.fmu, z1);
        ok(|| format!("fmi2GetEventIndicators {}", self.at(t1)), r)
    }

    /// The FMU asked to stop: `fmi2Terminate`, and the message that ends the run.
    fn terminate_there(&mut self, why: String) -> String {
        match self.fmu.terminate() {
            Ok(Fmi2Res::OK) => why,
            r => {
                let also = ok(|| "fmi2Terminate".into(), r).err().unwrap_or_default();
                format!("{why}; then {also}")
            }
        }
    }

    /// The event iteration at the current point: `fmi2NewDiscreteStates` until
    /// `newDiscreteStatesNeeded` is false. Whether the states changed, or the stop.
    fn event_iteration(&mut self, what: &str) -> Result<(Iteration, bool), String> {
        let mut changed = false;
        let mut flags = EventFlags::default();
        for iteration in 1.. {
            flags.reset();
            let r = self.fmu.new_discrete_states(&mut flags);
            if flags.terminate_simulation && r.is_ok() {
                return Ok((
                    Iteration::Terminate(format!(
                        "fmi2NewDiscreteStates ({what}, iteration {iteration}) {} returned terminateSimulation = true: \
                         the simulation stopped at t = {:?}",
                        self.at(self.t),
                        self.t
                    )),
                    changed,
                ));
            }
            ok(
                || {
                    format!(
                        "fmi2NewDiscreteStates ({what}, iteration {iteration}) {}",
                        self.at(self.t)
                    )
                },
                r,
            )?;
            changed |= flags.values_of_continuous_states_changed;
            if !flags.discrete_states_need_update {
                break;
            }
            if iteration >= MAX_EVENTS_PER_STEP {
                return Err(format!(
                    "fmi2NewDiscreteStates ({what}) {} still returns newDiscreteStatesNeeded after {iteration} iterations",
                    self.at(self.t)
                ));
            }
        }
        self.next_event_time = flags.next_event_time;
        Ok((Iteration::Done, changed))
    }

    /// An event at the accepted point: `fmi2EnterEventMode` (unless already in event mode),
    /// `set_inputs` in event mode, the event iteration, `fmi2EnterContinuousTimeMode`, the
    /// states again if they changed, the event indicators again.
    fn event(
        &mut self,
        what: &str,
        enter: bool,
        set_inputs: Option<(&[u32], &[f64], &str)>,
    ) -> Result<(), String> {
        if enter {
            let r = self.fmu.enter_event_mode();
            ok(
                || format!("fmi2EnterEventMode ({what}) {}", self.at(self.t)),
                r,
            )?;
        }
        if let Some((vrs, values, names)) = set_inputs {
            let r = self.fmu.set_real(vrs, values);
            ok(
                || format!("fmi2SetReal({names}) in event mode {}", self.at(self.t)),
                r,
            )?;
        }
        let (outcome, changed) = self.event_iteration(what)?;
        if let Iteration::Terminate(why) = outcome {
            return Err(self.terminate_there(why));
        }
        let r = self.fmu.enter_continuous_time_mode();
        ok(
            || format!("fmi2EnterContinuousTimeMode ({what}) {}", self.at(self.t)),
            r,
        )?;
        if changed {
            self.stats.state_changes += 1;
            let r = self.fmu.get_continuous_states(&mut self.x);
            ok(
                || format!("fmi2GetContinuousStates ({what}) {}", self.at(self.t)),
                r,
            )?;
        }
        let r = Self::read_indicators(&mut self.fmu, &mut self.z);
        ok(
            || format!("fmi2GetEventIndicators {} ({what})", self.at(self.t)),
            r,
        )
    }

    /// Integrates from the accepted point to `t_end` with RK4 steps of at most `t_end - t`,
    /// handling every event on the way; the FMU ends at (`t_end`, its states).
    fn integrate_to(&mut self, t_end: f64) -> Result<(), String> {
        let n = self.x.len();
        let (mut x1, mut z1) = (vec![0.0; n], vec![0.0; self.z.len()]);
        let (mut xm, mut zm) = (x1.clone(), z1.clone());
        let mut events = 0;
        while self.t < t_end {
            // a time event announced up to t_end ends the step there
            let time_event = self.next_event_time.filter(|&te| te <= t_end);
            let target = time_event.map_or(t_end, |te| te.max(self.t));
            let (t0, x0) = (self.t, self.x.clone());
            if target > t0 {
                self.rk4(t0, &x0, target, &mut x1, &mut z1)?;
            } else {
                x1.copy_from_slice(&x0);
                z1.copy_from_slice(&self.z);
            }
            let mut accepted = target;
            let crossed = sign_changes(&self.z, &z1);
            if !crossed.is_empty() {
                // bisection on the step's length: re-integrate from t0 with the shorter
                // step; `hi` always ends past a sign change, `lo` before any
                let (mut lo, mut hi) = (t0, target);
                while hi - lo > EVENT_LOCATION_TOLERANCE {
                    let mid = lo + 0.5 * (hi - lo);
                    if mid <= lo || mid >= hi {
                        break;
                    }
                    self.rk4(t0, &x0, mid, &mut xm, &mut zm)?;
                    if sign_changes(&self.z, &zm).is_empty() {
                        lo = mid;
                    } else {
                        hi = mid;
                        std::mem::swap(&mut x1, &mut xm);
                        std::mem::swap(&mut z1, &mut zm);
                    }
                }
                accepted = hi;
                // the FMU is at the last trial: back to the point accepted
                self.set_point(hi, &x1)?;
            }
            let which = sign_changes(&self.z, &z1);
            self.t = accepted;
            self.x.copy_from_slice(&x1);
            self.z.copy_from_slice(&z1);
            self.stats.steps += 1;

            let mut step_event = false;
            if self.needs_completed_integrator_step {
                let (mut enter, mut terminate) = (false, false);
                let r = self
                    .fmu
                    .completed_integrator_step(true, &mut enter, &mut terminate);
                // where, and why the step ended there
                let point = if which.is_empty() {
                    self.at(self.t)
                } else {
                    format!("{} ({})", self.at(self.t), state_event(&which))
                };
                if terminate && r.is_ok() {
                    let why = format!(
                        "fmi2CompletedIntegratorStep {point} returned terminateSimulation = true: \
                         the simulation stopped at t = {:?}",
                        self.t
                    );
                    return Err(self.terminate_there(why));
                }
                ok(|| format!("fmi2CompletedIntegratorStep {point}"), r)?;
                step_event = enter;
            }
            let time_event = time_event.is_some() && accepted == target && which.is_empty();
            let mut kinds = Vec::new();
            if !which.is_empty() {
                self.stats.state_events += 1;
                kinds.push(state_event(&which));
            }
            if step_event {
                self.stats.step_events += 1;
                kinds.push("step event".to_string());
            }
            if time_event {
                self.stats.time_events += 1;
                kinds.push("time event".to_string());
            }
            if !kinds.is_empty() {
                events += 1;
                if events > MAX_EVENTS_PER_STEP {
                    return Err(format!(
                        "more than {MAX_EVENTS_PER_STEP} events {}: the last a {}",
                        self.at(self.t),
                        kinds.join(", ")
                    ));
                }
                if time_event {
                    self.next_event_time = None;
                }
                self.event(&kinds.join(", "), true, None)?;
            }
        }
        Ok(())
    }
}

/// Runs the experiment in Model Exchange (see the crate's documentation, "Model
/// Exchange"): the table has `time` then `record`, n + 1 rows, like [`run`]'s.
pub fn run_me(exp: &Experiment, options: &MeOptions) -> Result<(Table, MeStats), String> {
    exp.check()?;
    if options.substeps == 0 {
        return Err("substeps must be at least 1".into());
    }
    let import: Fmi2Import = fmi::import::from_path(&exp.fmu)
        .map_err(|e| format!("cannot import {}: {e}", exp.fmu.display()))?;
    let md = import.model_description();
    let me = md
        .model_exchange
        .as_ref()
        .ok_or_else(|| format!("{} is not a Model Exchange FMU", exp.fmu.display()))?;
    let model = me.model_identifier.clone();
    let needs_completed_integrator_step = !me.completed_integrator_step_not_needed.unwrap_or(false);
    let prep = prepare(md, &model, exp)?;
    let (nx, nz) = (md.num_states(), md.num_event_indicators());

    let mut fmu = import
        .instantiate_me(&model, false, false)
        .map_err(|e| format!("fmi2Instantiate of {model} (Model Exchange) failed: {e}"))?;
    // a fixed-step integrator controls no error: no tolerance (FMPy's ME does the same)
    initialize(&mut fmu, exp, &prep, None)?;
    let mut me = MeIntegration {
        fmu,
        needs_completed_integrator_step,
        t: 0.0,
        x: vec![0.0; nx],
        z: vec![0.0; nz],
        next_event_time: None,
        k: std::array::from_fn(|_| vec![0.0; nx]),
        stage: vec![0.0; nx],
        stats: MeStats::default(),
        step: 0,
        steps: exp.steps,
        step_start: 0.0,
    };
    // fmi2ExitInitializationMode left the FMU in event mode
    me.event("the initial event iteration", false, None)?;
    ok(
        || "fmi2GetContinuousStates at t = 0.0".into(),
        me.fmu.get_continuous_states(&mut me.x),
    )?;

    let h = exp.step_size;
    let time = |k: usize| k as f64 * h;
    let mut rows = Vec::with_capacity(exp.steps + 1);
    let mut values = vec![0.0; prep.record_vrs.len()];
    rows.push(record(&mut me.fmu, &prep, 0.0, &mut values)?);
    for k in 1..=exp.steps {
        me.step = k;
        me.step_start = time(k - 1);
        // the inputs of the step from t_{k-1}: row 0 was set in initialization mode; a
        // change is an input event at t_{k-1}
        if k > 1 && !prep.input_vrs.is_empty() {
            let (old, new) = (&exp.input_values[k - 2], &exp.input_values[k - 1]);
            if old.iter().zip(new).any(|(a, b)| a.to_bits() != b.to_bits()) {
                me.stats.input_events += 1;
                me.event(
                    "input event",
                    true,
                    Some((&prep.input_vrs, new, &prep.input_list)),
                )?;
            }
        }
        let (t0, t1) = (time(k - 1), time(k));
        let m = options.substeps;
        for j in 1..=m {
            // the substeps' ends, the last exactly t_k
            let tj = if j == m {
                t1
            } else {
                t0 + (t1 - t0) * (j as f64 / m as f64)
            };
            me.integrate_to(tj)?;
        }
        rows.push(record(&mut me.fmu, &prep, t1, &mut values)?);
    }
    ok(|| "fmi2Terminate".into(), me.fmu.terminate())?;
    Ok((
        Table {
            names: column_names(exp),
            rows,
        },
        me.stats,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_state_event_is_a_change_of_domain_z_positive_or_not() {
        assert_eq!(
            sign_changes(&[1.0, -1.0], &[0.5, -2.0]),
            Vec::<usize>::new()
        );
        assert_eq!(sign_changes(&[1.0, -1.0], &[-0.5, -2.0]), [0]);
        assert_eq!(sign_changes(&[1.0, -1.0], &[-0.5, 2.0]), [0, 1]);
        // z = 0 belongs to z <= 0
        assert_eq!(sign_changes(&[1e-300], &[0.0]), [0]);
        assert_eq!(sign_changes(&[0.0], &[-1.0]), Vec::<usize>::new());
        assert_eq!(sign_changes(&[-0.0], &[1e-300]), [0]);
    }

    #[test]
    fn interfaces_parse() {
        assert_eq!("cs".parse(), Ok(Interface::CoSimulation));
        assert_eq!("me".parse(), Ok(Interface::ModelExchange));
        assert!("ME".parse::<Interface>().is_err());
        assert_eq!(Interface::default(), Interface::CoSimulation);
    }
}
