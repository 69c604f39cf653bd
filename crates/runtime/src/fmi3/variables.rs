//! FMI 3.0's variables by value reference ([`Shapes`] maps them: each variable's 1-based place
//! in the model description, `time` 0): an array stands for its elements (row-major, `nValues` counts them), the independent
//! `time` is read-only; the typed getters and setters of types this FMU has none of;
//! directional, adjoint and output derivatives over the same references. Each call expands the references into the
//! simulation's scalar ones and hands them to [`shared_calls`](crate::fmi::shared_calls).

use super::ffi::*;
use crate::fmi::boundary::{error, Failure, Outcome};
use crate::fmi::instance::Instance;
use crate::fmi::shared_calls;
use crate::fmi::OK;
use crate::model::{Mechanism, Shapes, ValueSet};

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
        if vr as usize == Shapes::TIME_REFERENCE {
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
        // One scalar at several places (a symmetric matrix's off-diagonal, or a variable
        // named twice in one call) takes one value.
        if let Some((first, second)) = disagreeing(&scalars, values) {
            // A variable that cannot be set at all is refused for that.
            shared_calls::check_set_real(inst, &scalars, values)?;
            return Err(error(format!(
                "{} = {} and {} = {} are the same variable `{}`: they must be equal",
                value_name(shapes, vrs, first),
                values[first],
                value_name(shapes, vrs, second),
                values[second],
                M::VARIABLES[scalars[first] as usize].name
            )));
        }
        shared_calls::set_real(inst, &scalars, values)
    })();
    inst.scratch = scalars;
    set
}

/// Up to this many values, pairs are compared in place (no allocation: every step's inputs
/// pass here); beyond, through a sorted copy.
const COMPARED_IN_PLACE: usize = 64;

/// The first two positions of the same scalar with different values, if any.
fn disagreeing(scalars: &[u32], values: &[f64]) -> Option<(usize, usize)> {
    let differ =
        |i: usize, j: usize| scalars[i] == scalars[j] && values[i].to_bits() != values[j].to_bits();
    if scalars.len() <= COMPARED_IN_PLACE {
        return (0..scalars.len())
            .flat_map(|j| (0..j).map(move |i| (i, j)))
            .find(|&(i, j)| differ(i, j));
    }
    let mut order: Vec<usize> = (0..scalars.len()).collect();
    order.sort_by_key(|&i| (scalars[i], i));
    (order.windows(2))
        .find(|w| differ(w[0], w[1]))
        .map(|w| (w[0].min(w[1]), w[0].max(w[1])))
}

/// A get or set of a type this FMU has no variables of.
pub fn no_variables(function: &str, vrs: &[fmi3ValueReference], n_values: usize) -> Outcome {
    shared_calls::no_variables(
        function,
        vrs,
        function
            .trim_start_matches("fmi3Get")
            .trim_start_matches("fmi3Set"),
    )?;
    check_values("nValues", n_values, 0)?;
    Ok(OK)
}

/// The scalar value references of `vrs`, the time among them as [`TIME`].
fn scalars_of<M: Mechanism>(inst: &Instance<M>, vrs: &[u32]) -> Result<Vec<u32>, Failure> {
    let mut scalars = Vec::with_capacity(vrs.len());
    expand(shapes(inst)?, vrs, &mut scalars)?;
    Ok(scalars)
}

/// The scalar unknowns of `vrs`: the time is a known only.
fn unknowns_of<M: Mechanism>(inst: &Instance<M>, vrs: &[u32]) -> Result<Vec<u32>, Failure> {
    let scalars = scalars_of(inst, vrs)?;
    if scalars.contains(&TIME) {
        return Err(error(
            "the unknowns include time, the independent variable: it is a known only",
        ));
    }
    Ok(scalars)
}

/// `seed` split between the scalar knowns and the time (the sum of the seeds given it).
fn split_time(knowns: &[u32], seed: &[f64]) -> (Vec<u32>, Vec<f64>, f64) {
    let (mut scalars, mut seeds, mut time_seed) = (Vec::new(), Vec::new(), 0.0);
    for (&k, &s) in knowns.iter().zip(seed) {
        if k == TIME {
            time_seed += s;
        } else {
            scalars.push(k);
            seeds.push(s);
        }
    }
    (scalars, seeds, time_seed)
}

/// `J seed` for the Jacobian `J` of the unknowns by the knowns; the knowns may include the
/// time (section 2.4.8 counts the independent variable among the knowns of outputs and
/// derivatives).
pub fn get_directional_derivative<M: Mechanism>(
    inst: &mut Instance<M>,
    unknowns: &[fmi3ValueReference],
    knowns: &[fmi3ValueReference],
    seed: &[fmi3Float64],
    sensitivity: &mut [fmi3Float64],
) -> Outcome {
    let unknowns = unknowns_of(inst, unknowns)?;
    let knowns = scalars_of(inst, knowns)?;
    check_values("nSeed", seed.len(), knowns.len())?;
    check_values("nSensitivity", sensitivity.len(), unknowns.len())?;
    let (knowns, seed, time_seed) = split_time(&knowns, seed);
    shared_calls::directional_derivative(inst, &unknowns, &knowns, &seed, time_seed, sensitivity)
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
    let unknowns = unknowns_of(inst, unknowns)?;
    let knowns = scalars_of(inst, knowns)?;
    check_values("nSeed", seed.len(), unknowns.len())?;
    check_values("nSensitivity", sensitivity.len(), knowns.len())?;
    if let Some(x) = seed.iter().find(|x| !x.is_finite()) {
        return Err(error(format!(
            "the seed contains {x}: every seed must be finite"
        )));
    }
    let mut column = vec![0.0; unknowns.len()];
    for (j, out) in sensitivity.iter_mut().enumerate() {
        let (known, known_seed, time_seed): (&[u32], &[f64], f64) = match knowns[j] {
            TIME => (&[], &[], 1.0),
            _ => (&knowns[j..=j], &[1.0], 0.0),
        };
        shared_calls::directional_derivative(
            inst,
            &unknowns,
            known,
            known_seed,
            time_seed,
            &mut column,
        )?;
        *out = seed.iter().zip(&column).map(|(s, c)| s * c).sum();
    }
    if let Some(j) = sensitivity.iter().position(|x| !x.is_finite()) {
        return Err(error(format!(
            "the sensitivity to `{}` is not a finite number (a seed too large?)",
            M::VARIABLES
                .get(knowns[j] as usize)
                .map_or("time", |v| v.name)
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
    shared_calls::output_derivatives(inst, &scalars, &scalar_orders, values)
}
