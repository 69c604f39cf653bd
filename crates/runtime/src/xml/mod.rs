//! The FMI 2.0 `modelDescription.xml` (Model Exchange and Co-Simulation) of a mechanism, generated from its
//! declaration: deterministic, byte for byte (no timestamp).
//!
//! - [`model_description`]: the XML of a mechanism, with the [`CAPABILITIES`] the runtime
//!   implements;
//! - [`model_description_for`]: the same with other capability flags (tests of the flags' effect);
//! - [`model_description_with`]: the writer itself, from a plain [`FmuInfo`].
//!
//! Units come from [`units`] (base-unit exponents, `deg` display units, quantities), the
//! `<ModelStructure>` dependencies and their kinds from [`structure`] (found numerically).
//! The FMI 3.0 model description of the same declaration is [`fmi3`]'s; what both write
//! alike (units, log categories, the default experiment, numbers, the order of the
//! variables) is written by one private module.
//!
//! The `ScalarVariable`s keep the declaration's value references (its order), but are
//! written with each state before its derivative (`model::states_before_derivatives`):
//! a `ScalarVariable` index (what `derivative` and `<ModelStructure>` refer to, 1-based)
//! is then the variable's place in that order, not its value reference plus one.

pub mod fmi3;
mod shared;
pub mod structure;
mod terminals;
pub mod units;

use std::io;

use quick_xml::Writer;

pub use structure::{ModelStructure, Unknown};
pub use terminals::terminals_and_icons;

use crate::contract::{Capabilities, CAPABILITIES, LOG_CATEGORIES};
use crate::model::{Experiment, Mechanism, Variable};
use shared::{
    generation_tool, one_line, pairs, real, write_default_experiment, write_each, write_holding,
    write_log_categories, write_units, Attributes, UnitInfo,
};

/// Everything the modelDescription is written from.
#[derive(Clone, Copy, Debug)]
pub struct FmuInfo<'a> {
    /// Model name and `modelIdentifier`.
    pub name: &'a str,
    pub description: &'a str,
    pub guid: &'a str,
    /// In value-reference order.
    pub variables: &'a [Variable],
    pub experiment: Experiment,
    pub capabilities: Capabilities,
    /// `(name, description)` of each `<Category>`.
    pub log_categories: &'a [(&'a str, &'a str)],
    pub structure: &'a ModelStructure,
    /// `numberOfEventIndicators`.
    pub event_indicators: usize,
    /// Whether Model Exchange needs `fmi2CompletedIntegratorStep` (a monitor or a
    /// projection runs there).
    pub needs_completed_integrator_step: bool,
}

/// The modelDescription.xml of mechanism `M`, with [`CAPABILITIES`].
///
/// `Err` names the problem: an unknown unit, a start value that is not finite, a start value
/// `calculate` rejects, ...
pub fn model_description<M: Mechanism>() -> Result<String, String> {
    model_description_for::<M>(&CAPABILITIES)
}

/// The modelDescription.xml of mechanism `M`, declaring `capabilities`.
pub fn model_description_for<M: Mechanism>(capabilities: &Capabilities) -> Result<String, String> {
    let structure = structure::model_structure::<M>()?;
    let guid = crate::contract::guid::<M>();
    model_description_with(&FmuInfo {
        name: M::NAME,
        description: M::DESCRIPTION,
        guid: &guid,
        variables: M::VARIABLES,
        experiment: M::EXPERIMENT,
        capabilities: *capabilities,
        log_categories: &LOG_CATEGORIES,
        structure: &structure,
        event_indicators: M::EVENT_INDICATORS.len(),
        needs_completed_integrator_step: crate::contract::needs_completed_integrator_step::<M>(),
    })
}

/// Checks what the schema and the standard require of the declaration, and collects the
/// units in order of first use.
fn check<'a>(info: &FmuInfo<'a>) -> Result<Vec<UnitInfo<'a>>, String> {
    let name = info.name;
    let units = shared::check_declaration(name, info.variables, info.experiment)?;
    for u in &units {
        if let Some(v) = info.variables.iter().find(|v| v.name == u.type_name) {
            return Err(format!(
                "{name}: variable `{}` has the name of the type of unit \"{}\"",
                v.name, u.name
            ));
        }
    }
    let s = info.structure;
    for unknown in [&s.outputs, &s.derivatives, &s.initial_unknowns]
        .into_iter()
        .flatten()
    {
        let n = info.variables.len();
        if unknown.vr >= n || unknown.knowns().any(|d| d >= n) {
            return Err(format!(
                "{name}: the model structure refers to a variable that does not exist"
            ));
        }
    }
    Ok(units)
}

/// The modelDescription.xml written from `info`.
pub fn model_description_with(info: &FmuInfo) -> Result<String, String> {
    let units = check(info)?;
    shared::finish(info.name, write(info, &units))
}

fn write(info: &FmuInfo, units: &[UnitInfo]) -> io::Result<Vec<u8>> {
    let mut w = shared::writer()?;
    let mut root: Attributes = vec![
        ("fmiVersion", "2.0".into()),
        ("modelName", info.name.into()),
        ("guid", info.guid.into()),
    ];
    let description = one_line(info.description);
    if !description.is_empty() {
        root.push(("description", description));
    }
    root.extend([
        ("generationTool", generation_tool()),
        ("variableNamingConvention", "flat".into()),
        ("numberOfEventIndicators", info.event_indicators.to_string()),
    ]);
    w.create_element("fmiModelDescription")
        .with_attributes(pairs(&root))
        .write_inner_content(|w| {
            let mut me: Attributes = vec![("modelIdentifier", info.name.into())];
            me.extend(
                info.capabilities
                    .model_exchange_attributes(info.needs_completed_integrator_step),
            );
            w.create_element("ModelExchange")
                .with_attributes(pairs(&me))
                .write_empty()?;
            let mut cs: Attributes = vec![("modelIdentifier", info.name.into())];
            cs.extend(info.capabilities.attributes());
            w.create_element("CoSimulation")
                .with_attributes(pairs(&cs))
                .write_empty()?;
            write_units(w, units)?;
            write_types(w, units)?;
            write_log_categories(w, info.log_categories)?;
            write_default_experiment(w, &info.experiment)?;
            let order = Order::new(info.variables);
            write_variables(w, info, units, &order)?;
            write_structure(w, info.structure, &order)
        })?;
    Ok(w.into_inner())
}

/// The order the `ScalarVariable`s are written in: each state before its derivative.
struct Order {
    /// Value references, in the order written.
    written: Vec<usize>,
    /// For each value reference, its `ScalarVariable` index (1-based).
    index: Vec<usize>,
}

impl Order {
    fn new(variables: &[Variable]) -> Self {
        let written =
            crate::model::states_before_derivatives(variables.len(), |vr| state_of(variables, vr));
        let mut index = vec![0; variables.len()];
        for (i, &vr) in written.iter().enumerate() {
            index[vr] = i + 1;
        }
        Order { written, index }
    }
}

/// The variable (value reference) that variable `vr` is the derivative of.
fn state_of(variables: &[Variable], vr: usize) -> Option<usize> {
    variables
        .iter()
        .position(|v| v.derivative == Some(variables[vr].name))
}

fn write_types(w: &mut Writer<Vec<u8>>, units: &[UnitInfo]) -> io::Result<()> {
    if units.is_empty() {
        return Ok(());
    }
    write_each(w, "TypeDefinitions", units, |w, u| {
        let mut typed: Attributes = Vec::new();
        if let Some(q) = u.quantity {
            typed.push(("quantity", q.into()));
        }
        typed.push(("unit", u.name.into()));
        if let Some(d) = &u.display {
            typed.push(("displayUnit", d.name.clone()));
        }
        let name: Attributes = vec![("name", u.type_name.clone())];
        write_holding(w, ("SimpleType", &name), ("Real", &typed))
    })
}

/// The `ScalarVariable`s in `order`. Each `<Real>` carries the attributes of FMI 2.0.5
/// section 2.2.7 in the schema's order (`fmi2ScalarVariable.xsd`: declaredType, the real
/// attributes of section 2.2.3, start, derivative): its `unit` and `displayUnit` as well as
/// its `declaredType`, which defines them too, since importers that read `unit` on the
/// variable only (OMSimulator) would see no unit and connect a length to a force.
fn write_variables(
    w: &mut Writer<Vec<u8>>,
    info: &FmuInfo,
    units: &[UnitInfo],
    order: &Order,
) -> io::Result<()> {
    let variables = info.variables;
    write_each(w, "ModelVariables", &order.written, |w, &vr| {
        let v = &variables[vr];
        let mut sv: Attributes = vec![("name", v.name.into()), ("valueReference", vr.to_string())];
        let description = one_line(v.description());
        if !description.is_empty() {
            sv.push(("description", description));
        }
        sv.push(("causality", v.causality.as_str().into()));
        sv.push(("variability", v.variability.as_str().into()));
        if let Some(initial) = v.initial {
            sv.push(("initial", initial.as_str().into()));
        }
        let unit = units.iter().find(|u| u.name == v.unit);
        let mut typed: Attributes = Vec::new();
        if let Some(u) = unit {
            typed.push(("declaredType", u.type_name.clone()));
            typed.push(("unit", u.name.into()));
            if let Some(d) = &u.display {
                typed.push(("displayUnit", d.name.clone()));
            }
        }
        if let Some(min) = v.min {
            typed.push(("min", real(min)));
        }
        if let Some(max) = v.max {
            typed.push(("max", real(max)));
        }
        if let Some(start) = v.start {
            typed.push(("start", real(start)));
        }
        if let Some(state) = state_of(variables, vr) {
            typed.push(("derivative", order.index[state].to_string()));
        }
        write_holding(w, ("ScalarVariable", &sv), ("Real", &typed))
    })
}

/// One list of `<ModelStructure>` in the order given, each `<Unknown>` by `ScalarVariable`
/// index with its dependencies ordered by index ("ordered according to magnitude", FMI
/// 2.0.5 section 2.2.8) and their kinds.
fn write_unknowns(
    w: &mut Writer<Vec<u8>>,
    element: &str,
    unknowns: &[Unknown],
    order: &Order,
) -> io::Result<()> {
    if unknowns.is_empty() {
        return Ok(());
    }
    write_each(w, element, unknowns, |w, u| {
        let mut dependencies: Vec<(usize, &str)> = (u.dependencies.iter())
            .map(|d| (order.index[d.known], d.kind.as_str()))
            .collect();
        dependencies.sort_unstable();
        let (indices, kinds): (Vec<String>, Vec<&str>) = (dependencies.into_iter())
            .map(|(i, kind)| (i.to_string(), kind))
            .unzip();
        w.create_element("Unknown")
            .with_attributes(pairs(&vec![
                ("index", order.index[u.vr].to_string()),
                ("dependencies", indices.join(" ")),
                ("dependenciesKind", kinds.join(" ")),
            ]))
            .write_empty()?;
        Ok(())
    })
}

/// `<Outputs>` in value-reference order, `<Derivatives>` in the states' order (the order
/// of the continuous-state vector), `<InitialUnknowns>` by `ScalarVariable` index, as
/// FMI 2.0.5 section 2.2.8 requires of that list.
fn write_structure(w: &mut Writer<Vec<u8>>, s: &ModelStructure, order: &Order) -> io::Result<()> {
    let derivatives = &s.derivatives;
    if s.outputs.is_empty() && derivatives.is_empty() && s.initial_unknowns.is_empty() {
        w.create_element("ModelStructure").write_empty()?;
        return Ok(());
    }
    let mut initial_unknowns = s.initial_unknowns.clone();
    initial_unknowns.sort_by_key(|u| order.index[u.vr]);
    w.create_element("ModelStructure")
        .write_inner_content(|w| {
            write_unknowns(w, "Outputs", &s.outputs, order)?;
            write_unknowns(w, "Derivatives", derivatives, order)?;
            write_unknowns(w, "InitialUnknowns", &initial_unknowns, order)
        })?;
    Ok(())
}

#[cfg(test)]
mod tests;
