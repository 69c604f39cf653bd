//! The experiment on an FMI 3.0 FMU: Co-Simulation ([`run`]) and Model Exchange
//! ([`run_me`], through [`crate::me`]), with `Float64` variables that may be arrays.
//!
//! The experiment names scalars: a scalar variable by its name, an array element as FMI 3.0
//! writes it, `name[i]` or `name[i,j]` (1-based, row-major). An array is set whole (an FMI
//! 3.0 value reference stands for all its elements): its start values, or its inputs' row,
//! are the model description's start values with the elements the experiment names
//! replaced. Recorded elements are read with their array.

use crate::me::{self, ok, CallNames, Event, MeInstance, Outcome, Status};
use crate::{column_names, Experiment, MeOptions, MeStats, Table};
use fmi::fmi3::import::Fmi3Import;
use fmi::fmi3::instance::{InstanceCS, InstanceME};
use fmi::fmi3::schema::{
    AbstractVariableTrait, Causality, Dimension, FmiFloat64, Initial, Variability, Variable,
};
use fmi::fmi3::{CoSimulation, Common, Fmi3Model, GetSet, ModelExchange};
use fmi::traits::FmiImport;
use mechfmu_host::model_exchange::Instance;
use std::collections::BTreeMap;

/// FMI 3.0's default `initial` where the model description gives none.
fn initial(v: &FmiFloat64) -> Option<Initial> {
    if let Some(i) = v.initial {
        return Some(i);
    }
    use Causality as C;
    use Variability as V;
    match (v.variability(), v.causality()) {
        (_, C::Parameter | C::StructuralParameter) => Some(Initial::Exact),
        (V::Constant, C::Output | C::Local) => Some(Initial::Exact),
        (_, C::CalculatedParameter) => Some(Initial::Calculated),
        (_, C::Output | C::Local) => Some(Initial::Calculated),
        _ => None,
    }
}

/// FMPy's `settable_in_instantiated`.
fn settable_before_initialization(v: &FmiFloat64) -> bool {
    v.causality() == Causality::Input
        || (v.variability() != Variability::Constant
            && matches!(initial(v), Some(Initial::Exact | Initial::Approx)))
}

/// FMPy's `settable_in_initialization_mode`.
fn settable_in_initialization(v: &FmiFloat64) -> bool {
    v.causality() == Causality::Input
        || (v.causality() != Causality::Parameter && v.variability() == Variability::Tunable)
        || (v.variability() != Variability::Constant && initial(v) == Some(Initial::Exact))
}

/// The number of elements of a variable (1 for a scalar); `Err` for a dimension given by a
/// structural parameter.
fn len(v: &FmiFloat64) -> Result<usize, String> {
    v.dimensions.iter().try_fold(1usize, |n, d| match d {
        Dimension::Fixed(size) => Ok(n * *size as usize),
        Dimension::Variable(_) => Err(format!(
            "`{}` has a dimension given by a structural parameter (not supported)",
            v.name
        )),
    })
}

/// `name` (a scalar) or `name[i,j]` (an element, 1-based): the `Float64` variable and the
/// element's offset in row-major order.
fn resolve<'m>(
    md: &'m fmi::fmi3::schema::Fmi3ModelDescription,
    model: &str,
    name: &str,
    role: &str,
) -> Result<(&'m FmiFloat64, usize), String> {
    let (base, index) = match name.strip_suffix(']').and_then(|s| s.split_once('[')) {
        Some((base, index)) => (base, Some(index)),
        None => (name, None),
    };
    let unknown = || {
        format!("unknown variable `{name}` ({role}): not in the modelDescription.xml of {model}")
    };
    let mv = &md.model_variables;
    let (variable, _) = (mv.variables.iter().zip(mv.iter_abstract()))
        .find(|(_, a)| a.name() == base)
        .ok_or_else(unknown)?;
    let Variable::Float64(v) = variable else {
        return Err(format!(
            "variable `{base}` ({role}) is not a Float64: only Float64 variables are set and recorded"
        ));
    };
    let dims: Vec<usize> = v
        .dimensions
        .iter()
        .map(|d| d.as_fixed().map(|n| n as usize))
        .collect::<Option<_>>()
        .ok_or_else(|| len(v).unwrap_err())?;
    let Some(index) = index else {
        if dims.is_empty() {
            return Ok((v, 0));
        }
        return Err(format!(
            "`{name}` ({role}) is an array of {} elements: name its elements (`{name}[1]`, ...)",
            len(v)?
        ));
    };
    let index: Vec<usize> = index
        .split(',')
        .map(|i| i.trim().parse::<usize>())
        .collect::<Result<_, _>>()
        .map_err(|_| format!("`{name}` ({role}): the index is not a list of numbers"))?;
    if index.len() != dims.len() || index.iter().zip(&dims).any(|(&i, &d)| i < 1 || i > d) {
        return Err(format!(
            "`{name}` ({role}): no such element of `{base}`, whose dimensions are {dims:?} (indices from 1)"
        ));
    }
    let offset = index
        .iter()
        .zip(&dims)
        .fold(0, |o, (&i, &d)| o * d + (i - 1));
    Ok((v, offset))
}

/// An array's values to set: its start values (or zeros) with some elements replaced.
struct Whole<'m> {
    v: &'m FmiFloat64,
    base: Vec<f64>,
}

impl<'m> Whole<'m> {
    fn new(v: &'m FmiFloat64, role: &str) -> Result<Self, String> {
        let n = len(v)?;
        let base = match v.start.as_ref().map(|s| s.0.clone()) {
            Some(s) if s.len() == n => s,
            Some(s) if s.len() == 1 => vec![s[0]; n],
            None if n == 1 => vec![0.0],
            _ => {
                return Err(format!(
                    "`{}` ({role}): the model description gives no start value for each of its {n} elements, \
                     so the elements the experiment does not name are unknown",
                    v.name
                ))
            }
        };
        Ok(Whole { v, base })
    }
}

/// A variable set whole: its value reference, its values, its name.
struct Setting {
    vr: u32,
    values: Vec<f64>,
    name: String,
}

/// The variables of an experiment resolved against the model description.
struct Prepared {
    /// Start values set before `fmi3EnterInitializationMode`, and in initialization mode.
    before: Vec<Setting>,
    during: Vec<Setting>,
    /// The input variables (each set whole), their values but for the experiment's columns,
    /// and for each column its variable and offset.
    input_vrs: Vec<u32>,
    input_base: Vec<f64>,
    input_place: Vec<usize>,
    /// The recorded variables, the number of their elements, and for each recorded name
    /// its position among them.
    record_vrs: Vec<u32>,
    record_len: usize,
    record_pick: Vec<usize>,
    input_list: String,
    record_list: String,
}

impl Prepared {
    /// The inputs' values of one row of the experiment: every element of every input variable.
    fn inputs(&self, row: &[f64]) -> Vec<f64> {
        let mut values = self.input_base.clone();
        for (&place, &value) in self.input_place.iter().zip(row) {
            values[place] = value;
        }
        values
    }
}

/// Resolves the experiment's variables and splits the start values as FMPy does.
fn prepare(
    md: &fmi::fmi3::schema::Fmi3ModelDescription,
    model: &str,
    exp: &Experiment,
) -> Result<Prepared, String> {
    let order = |v: &FmiFloat64| {
        let mv = &md.model_variables;
        mv.iter_abstract()
            .position(|w| w.name() == v.name)
            .unwrap_or(usize::MAX)
    };
    // start values: each variable set whole, in the model description's order
    let mut starts: BTreeMap<usize, (Whole, Vec<&str>)> = BTreeMap::new();
    for (name, &value) in &exp.start_values {
        let (v, offset) = resolve(md, model, name, "start value")?;
        let entry = match starts.entry(order(v)) {
            std::collections::btree_map::Entry::Occupied(e) => e.into_mut(),
            std::collections::btree_map::Entry::Vacant(e) => {
                e.insert((Whole::new(v, "start value")?, Vec::new()))
            }
        };
        entry.0.base[offset] = value;
        entry.1.push(name);
    }
    let (mut before, mut during) = (Vec::new(), Vec::new());
    for (whole, names) in starts.into_values() {
        let v = whole.v;
        let setting = Setting {
            vr: v.value_reference,
            name: format!("{} = {:?}", names.join(", "), whole.base),
            values: whole.base,
        };
        if settable_before_initialization(v) {
            before.push(setting);
        } else if settable_in_initialization(v) {
            during.push(setting);
        } else {
            return Err(format!(
                "start value of `{}`: a variable of causality {:?}, variability {:?}, initial {:?} cannot be set",
                v.name,
                v.causality(),
                v.variability(),
                initial(v)
            ));
        }
    }
    // inputs: each input variable set whole, in the order of their first column
    let (mut input_vrs, mut input_base, mut input_place) = (Vec::new(), Vec::new(), Vec::new());
    let mut input_at: BTreeMap<u32, usize> = BTreeMap::new();
    for name in &exp.inputs {
        let (v, offset) = resolve(md, model, name, "input")?;
        let at = match input_at.get(&v.value_reference) {
            Some(&at) => at,
            None => {
                let at = input_base.len();
                input_base.extend(Whole::new(v, "input")?.base);
                input_vrs.push(v.value_reference);
                input_at.insert(v.value_reference, at);
                at
            }
        };
        input_place.push(at + offset);
    }
    // recorded: each variable read whole, once
    let (mut record_vrs, mut record_pick) = (Vec::new(), Vec::new());
    let mut record_at: BTreeMap<u32, usize> = BTreeMap::new();
    let mut record_len = 0;
    for name in &exp.record {
        let (v, offset) = resolve(md, model, name, "recorded")?;
        let at = match record_at.get(&v.value_reference) {
            Some(&at) => at,
            None => {
                record_vrs.push(v.value_reference);
                record_at.insert(v.value_reference, record_len);
                record_len += len(v)?;
                record_len - len(v)?
            }
        };
        record_pick.push(at + offset);
    }
    Ok(Prepared {
        before,
        during,
        input_vrs,
        input_base,
        input_place,
        record_vrs,
        record_len,
        record_pick,
        input_list: exp.inputs.join(", "),
        record_list: exp.record.join(", "),
    })
}

/// The start values, `fmi3EnterInitializationMode` (with `tolerance`, start 0 and the
/// experiment's stop time), the inputs' row 0 and `fmi3ExitInitializationMode`.
fn initialize(
    fmu: &mut impl Common,
    exp: &Experiment,
    prep: &Prepared,
    tolerance: Option<f64>,
) -> Result<(), String> {
    for s in &prep.before {
        ok(
            || format!("fmi3SetFloat64({}) before initialization", s.name),
            fmu.set_float64(&[s.vr], &s.values),
        )?;
    }
    ok(
        || {
            format!(
                "fmi3EnterInitializationMode(tolerance {:?}, start 0, stop {:?})",
                tolerance, exp.stop_time
            )
        },
        fmu.enter_initialization_mode(tolerance, 0.0, exp.stop_time),
    )?;
    for s in &prep.during {
        ok(
            || format!("fmi3SetFloat64({}) in initialization mode", s.name),
            fmu.set_float64(&[s.vr], &s.values),
        )?;
    }
    if !prep.input_vrs.is_empty() {
        ok(
            || format!("fmi3SetFloat64({}) in initialization mode", prep.input_list),
            fmu.set_float64(&prep.input_vrs, &prep.inputs(&exp.input_values[0])),
        )?;
    }
    ok(
        || "fmi3ExitInitializationMode".into(),
        fmu.exit_initialization_mode(),
    )
}

/// One row of the result: `t`, then the recorded variables as the FMU gives them now.
fn record(fmu: &mut impl GetSet, prep: &Prepared, t: f64) -> Result<Vec<f64>, String> {
    let mut values = vec![0.0; prep.record_len];
    if !prep.record_vrs.is_empty() {
        ok(
            || format!("fmi3GetFloat64({}) at t = {t:?}", prep.record_list),
            fmu.get_float64(&prep.record_vrs, &mut values),
        )?;
    }
    let mut row = Vec::with_capacity(prep.record_pick.len() + 1);
    row.push(t);
    row.extend(prep.record_pick.iter().map(|&i| values[i]));
    Ok(row)
}

/// The crate's import of the FMU, its model description without the attributes the
/// crate's schema does not know ([`crate::schema_gaps`]).
fn import(exp: &Experiment) -> Result<Fmi3Import, String> {
    crate::schema_gaps::import(&exp.fmu)
}

/// Runs the experiment in Co-Simulation (step mode: no event mode, no early return); the
/// table has `time` then `record`, n + 1 rows.
pub(crate) fn run(exp: &Experiment) -> Result<Table, String> {
    let import = import(exp)?;
    let md = import.model_description();
    let model = md
        .co_simulation
        .as_ref()
        .ok_or_else(|| format!("{} is not a Co-Simulation FMU", exp.fmu.display()))?
        .model_identifier
        .clone();
    let prep = prepare(md, &model, exp)?;
    let mut fmu: InstanceCS = import
        .instantiate_cs(&model, false, false, false, false, &[])
        .map_err(|e| format!("fmi3InstantiateCoSimulation of {model} failed: {e}"))?;
    initialize(&mut fmu, exp, &prep, exp.relative_tolerance)?;

    let h = exp.step_size;
    let time = |k: usize| k as f64 * h;
    let mut rows = Vec::with_capacity(exp.steps + 1);
    for k in 0..=exp.steps {
        let t = time(k);
        if k > 0 {
            let t0 = time(k - 1);
            if !prep.input_vrs.is_empty() {
                ok(
                    || {
                        format!(
                            "fmi3SetFloat64({}) before the step from t = {t0:?}",
                            prep.input_list
                        )
                    },
                    fmu.set_float64(&prep.input_vrs, &prep.inputs(&exp.input_values[k - 1])),
                )?;
            }
            let (mut event, mut terminate, mut early, mut last) = (false, false, false, t0);
            let r = fmu.do_step(
                t0,
                t - t0,
                true,
                &mut event,
                &mut terminate,
                &mut early,
                &mut last,
            );
            let call = || {
                format!(
                    "fmi3DoStep(t = {t0:?}, h = {:?}) (step {k} of {})",
                    t - t0,
                    exp.steps
                )
            };
            let flags = [
                (terminate, "terminateSimulation"),
                (early, "earlyReturn"),
                (event, "eventHandlingNeeded"),
            ];
            let raised: Vec<&str> = flags.iter().filter(|f| f.0).map(|f| f.1).collect();
            if !raised.is_empty() {
                let status = match r.status() {
                    Status::Ok => "fmi3OK".to_string(),
                    Status::Warning(name) => name.to_string(),
                    Status::Fail(name) => name,
                };
                return Err(format!(
                    "{} returned {status} with {} = true (lastSuccessfulTime = {last:?})",
                    call(),
                    raised.join(" = true, ")
                ));
            }
            ok(call, r)?;
        }
        rows.push(record(&mut fmu, &prep, t)?);
    }
    ok(|| "fmi3Terminate".into(), fmu.terminate())?;
    Ok(Table {
        names: column_names(exp),
        rows,
    })
}

/// An FMI 3.0 Model Exchange instance with the experiment's variables.
struct Fmi3Me {
    fmu: InstanceME,
    prep: Prepared,
}

impl Instance for Fmi3Me {
    const NAMES: CallNames = CallNames::FMI3;

    fn set_time(&mut self, t: f64) -> Status {
        self.fmu.set_time(t).status()
    }

    fn set_continuous_states(&mut self, x: &[f64]) -> Status {
        self.fmu.set_continuous_states(x).status()
    }

    fn get_derivatives(&mut self, dx: &mut [f64]) -> Status {
        self.fmu.get_continuous_state_derivatives(dx).status()
    }

    fn get_event_indicators(&mut self, z: &mut [f64]) -> Status {
        match self.fmu.get_event_indicators(z) {
            Ok(true) => Status::Ok,
            // the fmi crate reports fmi3Discard as `false`
            Ok(false) => Status::Fail("fmi3Discard".into()),
            Err(e) => Err(e).status(),
        }
    }

    fn completed_integrator_step(&mut self, enter: &mut bool, terminate: &mut bool) -> Status {
        self.fmu
            .completed_integrator_step(true, enter, terminate)
            .status()
    }

    fn enter_event_mode(&mut self) -> Status {
        Common::enter_event_mode(&mut self.fmu).status()
    }

    fn update_discrete_states(&mut self, event: &mut Event) -> Status {
        let mut flags = fmi::EventFlags::default();
        let r = Common::update_discrete_states(&mut self.fmu, &mut flags).status();
        *event = me::event(&flags);
        r
    }

    fn enter_continuous_time_mode(&mut self) -> Status {
        self.fmu.enter_continuous_time_mode().status()
    }

    fn get_continuous_states(&mut self, x: &mut [f64]) -> Status {
        self.fmu.get_continuous_states(x).status()
    }

    fn terminate(&mut self) -> Status {
        Common::terminate(&mut self.fmu).status()
    }
}

impl MeInstance for Fmi3Me {
    const SET_INPUTS: &'static str = "fmi3SetFloat64";

    fn set_inputs(&mut self, row: &[f64]) -> Status {
        let values = self.prep.inputs(row);
        self.fmu.set_float64(&self.prep.input_vrs, &values).status()
    }

    fn input_list(&self) -> &str {
        &self.prep.input_list
    }

    fn record(&mut self, t: f64) -> Result<Vec<f64>, String> {
        record(&mut self.fmu, &self.prep, t)
    }
}

/// Runs the experiment in Model Exchange (see the crate's documentation, "Model
/// Exchange"): the table has `time` then `record`, n + 1 rows, like [`run`]'s.
pub(crate) fn run_me(exp: &Experiment, options: &MeOptions) -> Result<(Table, MeStats), String> {
    let import = import(exp)?;
    let md = import.model_description();
    let me = md
        .model_exchange
        .as_ref()
        .ok_or_else(|| format!("{} is not a Model Exchange FMU", exp.fmu.display()))?;
    let model = me.model_identifier.clone();
    let needs_completed_integrator_step = me.needs_completed_integrator_step.unwrap_or(false);
    let prep = prepare(md, &model, exp)?;
    let mut fmu: InstanceME = import
        .instantiate_me(&model, false, false)
        .map_err(|e| format!("fmi3InstantiateModelExchange of {model} failed: {e}"))?;
    // a fixed-step integrator controls no error: no tolerance (FMPy's ME does the same)
    initialize(&mut fmu, exp, &prep, None)?;
    let nx = fmu
        .get_number_of_continuous_states()
        .map_err(|e| format!("fmi3GetNumberOfContinuousStates failed: {e}"))?;
    let nz = fmu
        .get_number_of_event_indicators()
        .map_err(|e| format!("fmi3GetNumberOfEventIndicators failed: {e}"))?;
    me::integrate(
        Fmi3Me { fmu, prep },
        needs_completed_integrator_step,
        (nx, nz),
        exp,
        options,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn settable_follows_fmpy() {
        let mut v = FmiFloat64::new(
            "p".into(),
            0,
            None,
            Causality::Parameter,
            Variability::Fixed,
            Some(vec![1.0]),
            None,
        );
        assert!(settable_before_initialization(&v));
        v.causality = Some(Causality::Output);
        v.variability = Some(Variability::Continuous);
        assert!(!settable_before_initialization(&v) && !settable_in_initialization(&v));
        v.initial = Some(Initial::Exact);
        assert!(settable_before_initialization(&v) && settable_in_initialization(&v));
    }
}
