//! The experiment on an FMI 2.0 FMU: Co-Simulation ([`run`]) and Model Exchange
//! ([`run_me`], through [`crate::me`]).

use crate::me::{self, ok, CallNames, Event, MeInstance, Outcome, Status};
use crate::{column_names, Experiment, MeOptions, MeStats, Table};
use fmi::fmi2::import::Fmi2Import;
use fmi::fmi2::instance::{CoSimulation, Common, InstanceME, ModelExchange};
use fmi::fmi2::schema::{Causality, Initial, ScalarVariable, ScalarVariableElement, Variability};
use fmi::traits::FmiImport;
use mechfmu_host::model_exchange::Instance;

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
fn record(fmu: &mut impl Common, prep: &Prepared, t: f64) -> Result<Vec<f64>, String> {
    let mut values = vec![0.0; prep.record_vrs.len()];
    if !prep.record_vrs.is_empty() {
        ok(
            || format!("fmi2GetReal({}) at t = {t:?}", prep.record_list),
            fmu.get_real(&prep.record_vrs, &mut values),
        )?;
    }
    let mut row = Vec::with_capacity(values.len() + 1);
    row.push(t);
    row.extend_from_slice(&values);
    Ok(row)
}

/// The crate's import of the FMU, its model description without the XML attributes the
/// crate's schema does not know ([`crate::schema_gaps`]).
fn import(exp: &Experiment) -> Result<Fmi2Import, String> {
    crate::schema_gaps::import(&exp.fmu)
}

/// Runs the experiment in Co-Simulation; the table has `time` then `record`, n + 1 rows.
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
    let input_vrs = &prep.input_vrs;
    let input_list = &prep.input_list;

    let mut fmu = import
        .instantiate_cs(&model, false, false)
        .map_err(|e| format!("fmi2Instantiate of {model} failed: {e}"))?;
    initialize(&mut fmu, exp, &prep, exp.relative_tolerance)?;

    let h = exp.step_size;
    let time = |k: usize| k as f64 * h;
    let mut rows = Vec::with_capacity(exp.steps + 1);
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
        rows.push(record(&mut fmu, &prep, t)?);
    }
    ok(|| "fmi2Terminate".into(), fmu.terminate())?;
    Ok(Table {
        names: column_names(exp),
        rows,
    })
}

/// An FMI 2.0 Model Exchange instance with the experiment's variables.
struct Fmi2Me<'e> {
    fmu: InstanceME,
    prep: Prepared<'e>,
}

impl Instance for Fmi2Me<'_> {
    const NAMES: CallNames = CallNames::FMI2;

    fn set_time(&mut self, t: f64) -> Status {
        self.fmu.set_time(t).status()
    }

    fn set_continuous_states(&mut self, x: &[f64]) -> Status {
        self.fmu.set_continuous_states(x).status()
    }

    fn get_derivatives(&mut self, dx: &mut [f64]) -> Status {
        self.fmu.get_derivatives(dx).status()
    }

    fn get_event_indicators(&mut self, z: &mut [f64]) -> Status {
        match self.fmu.get_event_indicators(z) {
            Ok(true) => Status::Ok,
            // the fmi crate reports fmi2Discard as `false`
            Ok(false) => Status::Fail("fmi2Discard".into()),
            Err(e) => Err(e).status(),
        }
    }

    fn completed_integrator_step(&mut self, enter: &mut bool, terminate: &mut bool) -> Status {
        self.fmu
            .completed_integrator_step(true, enter, terminate)
            .status()
    }

    fn enter_event_mode(&mut self) -> Status {
        self.fmu.enter_event_mode().status()
    }

    fn update_discrete_states(&mut self, event: &mut Event) -> Status {
        let mut flags = fmi::EventFlags::default();
        let r = self.fmu.new_discrete_states(&mut flags).status();
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
        self.fmu.terminate().status()
    }
}

impl MeInstance for Fmi2Me<'_> {
    const SET_INPUTS: &'static str = "fmi2SetReal";

    fn set_inputs(&mut self, row: &[f64]) -> Status {
        self.fmu.set_real(&self.prep.input_vrs, row).status()
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
    let needs_completed_integrator_step = !me.completed_integrator_step_not_needed.unwrap_or(false);
    let prep = prepare(md, &model, exp)?;
    let sizes = (md.num_states(), md.num_event_indicators());

    let mut fmu = import
        .instantiate_me(&model, false, false)
        .map_err(|e| format!("fmi2Instantiate of {model} (Model Exchange) failed: {e}"))?;
    // a fixed-step integrator controls no error: no tolerance (FMPy's ME does the same)
    initialize(&mut fmu, exp, &prep, None)?;
    me::integrate(
        Fmi2Me { fmu, prep },
        needs_completed_integrator_step,
        sizes,
        exp,
        options,
    )
}
