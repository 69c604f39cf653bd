//! What each FMI 3.0 call does, in safe Rust over checked arguments, where it differs from
//! FMI 2.0's: variables by FMI 3.0 value reference (arrays, the independent `time`),
//! typed getters and setters, out arguments, the instantiation flags, adjoint
//! derivatives, the features not offered. What both standards do alike is in
//! [`common`](crate::fmi::common) and [`model_exchange`](crate::fmi::model_exchange).

use super::ffi::*;
use crate::fmi::common::{self, Stepped};
use crate::fmi::instance::Instance;
use crate::fmi::logger::Logger;
use crate::fmi::machine::{Interface, ModelState};
use crate::fmi::model_exchange as me;
use crate::fmi::wall::{discard, error, Failure, Outcome};
use crate::fmi::{Version, OK, WARNING};
use crate::model::{Mechanism, Shapes, ValueSet};

pub fn get_version() -> fmi3String {
    VERSION.as_ptr()
}

/// `fmi3InstantiateModelExchange` and `fmi3InstantiateCoSimulation` once the callback is
/// known (see [`common::instantiate`]), with the Co-Simulation flags and the number of
/// required intermediate variables (none may be: there is no intermediate update).
pub fn instantiate<'a, M: Mechanism>(
    logger: Logger,
    instance_name: Option<&str>,
    interface: Interface,
    token: impl FnOnce() -> Option<&'a str>,
    event_mode_used: bool,
    early_return_allowed: bool,
    required_intermediate_variables: usize,
) -> Result<Box<Instance<M>>, (Logger, String)> {
    if required_intermediate_variables > 0 {
        return Err((
            logger,
            format!(
                "nRequiredIntermediateVariables = {required_intermediate_variables}, but this FMU provides no intermediate update"
            ),
        ));
    }
    let shapes = match Shapes::new(M::VARIABLES, M::ARRAYS) {
        Ok(shapes) => shapes,
        Err(message) => return Err((logger, message)),
    };
    let mut inst = common::instantiate(Version::Fmi3, logger, instance_name, interface, token)?;
    inst.shapes = Some(Box::new(shapes));
    inst.event_mode_used = event_mode_used;
    inst.early_return_allowed = early_return_allowed;
    Ok(inst)
}

pub fn enter_initialization_mode<M: Mechanism>(
    inst: &mut Instance<M>,
    tolerance_defined: fmi3Boolean,
    tolerance: fmi3Float64,
    start_time: fmi3Float64,
    stop_time_defined: fmi3Boolean,
    stop_time: fmi3Float64,
) -> Outcome {
    common::setup(
        inst,
        tolerance_defined.then_some(tolerance),
        start_time,
        stop_time_defined.then_some(stop_time),
    )?;
    common::enter_initialization_mode(inst)
}

/// Model Exchange always; Co-Simulation if the importer said it uses event mode.
pub fn enter_event_mode<M: Mechanism>(inst: &mut Instance<M>) -> Outcome {
    if inst.interface == Interface::CoSimulation && !inst.event_mode_used {
        return Err(error(
            "the instance was instantiated with eventModeUsed = false, so it has no event mode",
        ));
    }
    me::enter_event_mode(inst)
}

pub fn enter_step_mode<M: Mechanism>(inst: &mut Instance<M>) -> Outcome {
    inst.state = ModelState::StepComplete;
    Ok(OK)
}

// ---------------------------------------------------------------------------------------
// Variables by FMI 3.0 value reference
// ---------------------------------------------------------------------------------------

/// Stands for the independent variable among scalar value references.
const TIME: u32 = u32::MAX;

fn shapes<M: Mechanism>(inst: &Instance<M>) -> Result<&Shapes, Failure> {
    inst.shapes
        .as_deref()
        .ok_or_else(|| error("the instance has no FMI 3.0 variables"))
}

/// The scalars of `vrs` (the time as [`TIME`]), in order, into `scalars`.
fn expand(shapes: &Shapes, vrs: &[u32], scalars: &mut Vec<u32>) -> Result<(), Failure> {
    scalars.clear();
    for &vr in vrs {
        if vr as usize == shapes.time_reference() {
            scalars.push(TIME);
            continue;
        }
        let Some(shaped) = shapes.get(vr as usize) else {
            return Err(error(format!(
                "value reference {vr} is not a variable of this FMU"
            )));
        };
        scalars.extend(shaped.elements.iter().map(|&e| e as u32));
    }
    Ok(())
}

/// `n` (named `what`) values given for `expected` (the elements of the variables asked).
fn check_values(what: &str, n: usize, expected: usize) -> Result<(), Failure> {
    if n == expected {
        return Ok(());
    }
    Err(error(format!(
        "{what} = {n}, but the value references given have {expected} values (arrays count each element)"
    )))
}

/// The name of the `position`-th value of `vrs` (an array element as `name[i,j]`).
fn value_name(shapes: &Shapes, vrs: &[u32], position: usize) -> String {
    let mut at = 0;
    for &vr in vrs {
        match shapes.get(vr as usize) {
            Some(shaped) if position < at + shaped.elements.len() => {
                return shaped.element_name(position - at)
            }
            Some(shaped) => at += shaped.elements.len(),
            None if position == at => return "time".into(),
            None => at += 1,
        }
    }
    format!("value {position}")
}

pub fn get_float64<M: Mechanism>(
    inst: &mut Instance<M>,
    vrs: &[fmi3ValueReference],
    values: &mut [fmi3Float64],
) -> Outcome {
    let mut scalars = std::mem::take(&mut inst.scratch);
    let read = (|| {
        expand(shapes(inst)?, vrs, &mut scalars)?;
        check_values("nValues", values.len(), scalars.len())?;
        inst.sim.update()?;
        let (t, v) = (inst.sim.time(), inst.sim.values());
        for (out, &s) in values.iter_mut().zip(&scalars) {
            *out = if s == TIME {
                t
            } else {
                v.get(s as usize).unwrap_or(f64::NAN)
            };
        }
        Ok(OK)
    })();
    inst.scratch = scalars;
    read
}

pub fn set_float64<M: Mechanism>(
    inst: &mut Instance<M>,
    vrs: &[fmi3ValueReference],
    values: &[fmi3Float64],
) -> Outcome {
    let mut scalars = std::mem::take(&mut inst.scratch);
    let set = (|| {
        let shapes = shapes(inst)?;
        expand(shapes, vrs, &mut scalars)?;
        check_values("nValues", values.len(), scalars.len())?;
        if scalars.contains(&TIME) {
            return Err(error(
                "time is the independent variable: it cannot be set (fmi3SetTime sets it in Model Exchange)",
            ));
        }
        // One scalar at several places (a symmetric matrix's off-diagonal) takes one value.
        if let Some((first, second)) = disagreeing(&scalars, values) {
            return Err(error(format!(
                "{} = {} and {} = {} are the same variable `{}`: they must be equal",
                value_name(shapes, vrs, first),
                values[first],
                value_name(shapes, vrs, second),
                values[second],
                M::VARIABLES[scalars[first] as usize].name
            )));
        }
        common::set_real(inst, &scalars, values)
    })();
    inst.scratch = scalars;
    set
}

/// The first two positions of the same scalar with different values, if any.
fn disagreeing(scalars: &[u32], values: &[f64]) -> Option<(usize, usize)> {
    let mut order: Vec<usize> = (0..scalars.len()).collect();
    order.sort_by_key(|&i| (scalars[i], i));
    order.windows(2).find_map(|w| {
        let (a, b) = (w[0], w[1]);
        (scalars[a] == scalars[b] && values[a].to_bits() != values[b].to_bits())
            .then_some((a.min(b), a.max(b)))
    })
}

/// A get or set of a type this FMU has no variables of.
pub fn no_variables(function: &str, vrs: &[fmi3ValueReference], n_values: usize) -> Outcome {
    common::no_variables(
        function,
        vrs,
        function
            .trim_start_matches("fmi3Get")
            .trim_start_matches("fmi3Set"),
    )?;
    check_values("nValues", n_values, 0)?;
    Ok(OK)
}

/// Clocks, intervals, shifts, configuration mode, Scheduled Execution.
pub fn unsupported(what: &str) -> Outcome {
    Err(error(format!("this FMU has {what}")))
}

// ---------------------------------------------------------------------------------------
// Derivatives
// ---------------------------------------------------------------------------------------

/// The scalar value references of `vrs` (named `what`), which must not include the time.
fn scalars_of<M: Mechanism>(
    inst: &Instance<M>,
    vrs: &[u32],
    what: &str,
) -> Result<Vec<u32>, Failure> {
    let mut scalars = Vec::with_capacity(vrs.len());
    expand(shapes(inst)?, vrs, &mut scalars)?;
    if scalars.contains(&TIME) {
        return Err(error(format!(
            "{what} include time: derivatives are taken with respect to states and inputs"
        )));
    }
    Ok(scalars)
}

pub fn get_directional_derivative<M: Mechanism>(
    inst: &mut Instance<M>,
    unknowns: &[fmi3ValueReference],
    knowns: &[fmi3ValueReference],
    seed: &[fmi3Float64],
    sensitivity: &mut [fmi3Float64],
) -> Outcome {
    let unknowns = scalars_of(inst, unknowns, "the unknowns")?;
    let knowns = scalars_of(inst, knowns, "the knowns")?;
    check_values("nSeed", seed.len(), knowns.len())?;
    check_values("nSensitivity", sensitivity.len(), unknowns.len())?;
    common::directional_derivative(inst, &unknowns, &knowns, seed, sensitivity)
}

/// `seedᵀ J` for the Jacobian `J` of the unknowns by the knowns: one directional
/// derivative per known (exact, by forward-mode automatic differentiation).
pub fn get_adjoint_derivative<M: Mechanism>(
    inst: &mut Instance<M>,
    unknowns: &[fmi3ValueReference],
    knowns: &[fmi3ValueReference],
    seed: &[fmi3Float64],
    sensitivity: &mut [fmi3Float64],
) -> Outcome {
    let unknowns = scalars_of(inst, unknowns, "the unknowns")?;
    let knowns = scalars_of(inst, knowns, "the knowns")?;
    check_values("nSeed", seed.len(), unknowns.len())?;
    check_values("nSensitivity", sensitivity.len(), knowns.len())?;
    if let Some(x) = seed.iter().find(|x| !x.is_finite()) {
        return Err(error(format!(
            "the seed contains {x}: every seed must be finite"
        )));
    }
    let mut column = vec![0.0; unknowns.len()];
    for (j, out) in sensitivity.iter_mut().enumerate() {
        common::directional_derivative(inst, &unknowns, &knowns[j..=j], &[1.0], &mut column)?;
        *out = seed.iter().zip(&column).map(|(s, c)| s * c).sum();
    }
    if let Some(j) = sensitivity.iter().position(|x| !x.is_finite()) {
        return Err(error(format!(
            "the sensitivity to value reference {} is not a finite number (a seed too large?)",
            knowns[j]
        )));
    }
    Ok(OK)
}

/// First time derivatives of outputs (`orders` per variable, for each of its elements).
pub fn get_output_derivatives<M: Mechanism>(
    inst: &mut Instance<M>,
    vrs: &[fmi3ValueReference],
    orders: &[fmi3Int32],
    values: &mut [fmi3Float64],
) -> Outcome {
    let shapes = shapes(inst)?;
    let (mut scalars, mut scalar_orders, mut one) = (Vec::new(), Vec::new(), Vec::new());
    for (&vr, &order) in vrs.iter().zip(orders) {
        expand(shapes, &[vr], &mut one)?;
        scalars.extend(&one);
        scalar_orders.extend(std::iter::repeat_n(order, one.len()));
    }
    if scalars.contains(&TIME) {
        return Err(error("time is not an output"));
    }
    check_values("nValues", values.len(), scalars.len())?;
    common::output_derivatives(inst, &scalars, &scalar_orders, values)
}

// ---------------------------------------------------------------------------------------
// Events and steps
// ---------------------------------------------------------------------------------------

/// Writes `value` where the importer asked for it (FMI 3.0 lets an importer pass NULL for
/// an out argument of `fmi3UpdateDiscreteStates` it does not want).
fn put<T>(slot: Option<&mut T>, value: T) {
    if let Some(slot) = slot {
        *slot = value;
    }
}

/// The event iteration, in Model Exchange and in Co-Simulation's event mode.
pub fn update_discrete_states<M: Mechanism>(
    inst: &mut Instance<M>,
    discrete_states_need_update: Option<&mut fmi3Boolean>,
    terminate_simulation: Option<&mut fmi3Boolean>,
    nominals_changed: Option<&mut fmi3Boolean>,
    values_changed: Option<&mut fmi3Boolean>,
    next_event_time_defined: Option<&mut fmi3Boolean>,
    next_event_time: Option<&mut fmi3Float64>,
) -> Outcome {
    let (status, update) = me::update_discrete_states(inst, "fmi3UpdateDiscreteStates")?;
    put(discrete_states_need_update, false);
    put(terminate_simulation, update.terminate);
    put(nominals_changed, false);
    put(values_changed, update.states_changed);
    put(next_event_time_defined, false);
    put(next_event_time, 0.0);
    Ok(status)
}

pub fn completed_integrator_step<M: Mechanism>(
    inst: &mut Instance<M>,
    enter_event_mode: &mut fmi3Boolean,
    terminate_simulation: &mut fmi3Boolean,
) -> Outcome {
    let (status, enter, terminate) =
        me::completed_integrator_step(inst, "fmi3CompletedIntegratorStep")?;
    *enter_event_mode = enter;
    *terminate_simulation = terminate;
    Ok(status)
}

/// A communication step. Where the model stops holding inside it (the crane's trolley at
/// the pivot), the importer learns when: with early return allowed, the step returns
/// early there (`earlyReturn`, `lastSuccessfulTime`, `terminateSimulation`, a warning
/// saying why); without, it is discarded with `lastSuccessfulTime` and
/// `terminateSimulation` set.
#[allow(clippy::too_many_arguments)]
pub fn do_step<M: Mechanism>(
    inst: &mut Instance<M>,
    current_communication_point: fmi3Float64,
    communication_step_size: fmi3Float64,
    event_handling_needed: &mut fmi3Boolean,
    terminate_simulation: &mut fmi3Boolean,
    early_return: &mut fmi3Boolean,
    last_successful_time: &mut fmi3Float64,
) -> Outcome {
    *event_handling_needed = false;
    *terminate_simulation = false;
    *early_return = false;
    *last_successful_time = inst.last_successful_time;
    let stepped = common::step(
        inst,
        current_communication_point,
        communication_step_size,
        "fmi3DoStep",
    )?;
    *last_successful_time = inst.last_successful_time;
    match stepped {
        Stepped::Completed(status) => Ok(status),
        Stepped::Stopped { message, .. } => {
            *terminate_simulation = true;
            if inst.early_return_allowed {
                *early_return = true;
                inst.logger
                    .log(WARNING, &format!("fmi3DoStep: returned early: {message}"));
                Ok(WARNING)
            } else {
                Err(discard(message))
            }
        }
    }
}

pub fn get_number_of_continuous_states<M: Mechanism>(
    inst: &mut Instance<M>,
    n: &mut usize,
) -> Outcome {
    *n = inst.sim.state_count();
    Ok(OK)
}

pub fn get_number_of_event_indicators<M: Mechanism>(
    inst: &mut Instance<M>,
    n: &mut usize,
) -> Outcome {
    *n = inst.sim.event_indicator_count();
    Ok(OK)
}

/// Per-element dependencies are not provided (`providesPerElementDependencies` is false):
/// the model description's `<ModelStructure>` lists the dependencies.
pub fn variable_dependencies() -> Outcome {
    Err(error(
        "this FMU does not provide per-element dependencies (providesPerElementDependencies = false): read them from <ModelStructure>",
    ))
}
