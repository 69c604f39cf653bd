//! `mechfmu-fmi-run`: one experiment on an FMI 2.0 Co-Simulation FMU, run through the
//! [`fmi`] crate (rust-fmi).
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

use fmi::fmi2::import::Fmi2Import;
use fmi::fmi2::instance::{CoSimulation, Common};
use fmi::fmi2::schema::{Causality, Initial, ScalarVariable, ScalarVariableElement, Variability};
use fmi::fmi2::{Fmi2Error, Fmi2Res};
use fmi::traits::FmiImport;
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

/// Runs the experiment; the table has `time` then `record`, n + 1 rows.
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
    let input_list = exp.inputs.join(", ");
    let record_list = exp.record.join(", ");

    let mut fmu = import
        .instantiate_cs(&model, false, false)
        .map_err(|e| format!("fmi2Instantiate of {model} failed: {e}"))?;
    ok(
        || {
            format!(
                "fmi2SetupExperiment(tolerance {:?}, start 0, stop {:?})",
                exp.relative_tolerance, exp.stop_time
            )
        },
        fmu.setup_experiment(exp.relative_tolerance, 0.0, exp.stop_time),
    )?;
    for &(_, vr, name, value) in &before {
        ok(
            || format!("fmi2SetReal({name} = {value:?}) before initialization"),
            fmu.set_real(&[vr], &[value]),
        )?;
    }
    ok(
        || "fmi2EnterInitializationMode".into(),
        fmu.enter_initialization_mode(),
    )?;
    for &(_, vr, name, value) in &during {
        ok(
            || format!("fmi2SetReal({name} = {value:?}) in initialization mode"),
            fmu.set_real(&[vr], &[value]),
        )?;
    }
    if !input_vrs.is_empty() {
        ok(
            || format!("fmi2SetReal({input_list}) in initialization mode"),
            fmu.set_real(&input_vrs, &exp.input_values[0]),
        )?;
    }
    ok(
        || "fmi2ExitInitializationMode".into(),
        fmu.exit_initialization_mode(),
    )?;

    let h = exp.step_size;
    let time = |k: usize| k as f64 * h;
    let mut names = vec!["time".to_string()];
    names.extend(exp.record.iter().cloned());
    let mut rows = Vec::with_capacity(exp.steps + 1);
    let mut values = vec![0.0; record_vrs.len()];
    for k in 0..=exp.steps {
        let t = time(k);
        if k > 0 {
            let t0 = time(k - 1);
            if !input_vrs.is_empty() {
                ok(
                    || format!("fmi2SetReal({input_list}) before the step from t = {t0:?}"),
                    fmu.set_real(&input_vrs, &exp.input_values[k - 1]),
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
        if !record_vrs.is_empty() {
            ok(
                || format!("fmi2GetReal({record_list}) at t = {t:?}"),
                fmu.get_real(&record_vrs, &mut values),
            )?;
        }
        let mut row = Vec::with_capacity(values.len() + 1);
        row.push(t);
        row.extend_from_slice(&values);
        rows.push(row);
    }
    ok(|| "fmi2Terminate".into(), fmu.terminate())?;
    Ok(Table { names, rows })
}
