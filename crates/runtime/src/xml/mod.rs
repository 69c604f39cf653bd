//! The FMI 2.0 `modelDescription.xml` (Model Exchange and Co-Simulation) of a mechanism, generated from its
//! declaration: deterministic, byte for byte (no timestamp).
//!
//! - [`model_description`]: the XML of a mechanism, with the [`CAPABILITIES`] the runtime
//!   implements;
//! - [`model_description_for`]: the same with other capability flags (tests of the flags' effect);
//! - [`model_description_with`]: the writer itself, from a plain [`FmuInfo`].
//!
//! Units come from [`units`] (base-unit exponents, `deg` display units, quantities), the
//! `<ModelStructure>` dependencies from [`structure`] (found numerically). The FMI 3.0
//! model description of the same declaration is [`fmi3`]'s; what both write alike (units,
//! log categories, the default experiment, numbers) is written by one private module.

pub mod fmi3;
mod shared;
pub mod structure;
pub mod units;

use std::io;

use quick_xml::Writer;

pub use structure::{ModelStructure, Unknown};

use crate::contract::{Capabilities, CAPABILITIES, LOG_CATEGORIES};
use crate::model::{Experiment, Mechanism, Variable};
use shared::{
    generation_tool, one_line, pairs, real, write_default_experiment, write_log_categories,
    write_units, Attributes, UnitInfo,
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
    let lists = [
        Some(&s.outputs),
        Some(&s.derivatives),
        Some(&s.initial_unknowns),
    ];
    for unknown in lists.into_iter().flatten().flatten() {
        let n = info.variables.len();
        if unknown.vr >= n || unknown.dependencies.iter().any(|&d| d >= n) {
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
            write_variables(w, info, units)?;
            write_structure(w, info.structure)
        })?;
    Ok(w.into_inner())
}

fn write_types(w: &mut Writer<Vec<u8>>, units: &[UnitInfo]) -> io::Result<()> {
    if units.is_empty() {
        return Ok(());
    }
    w.create_element("TypeDefinitions")
        .write_inner_content(|w| {
            for u in units {
                let mut typed: Attributes = Vec::new();
                if let Some(q) = u.quantity {
                    typed.push(("quantity", q.into()));
                }
                typed.push(("unit", u.name.into()));
                if let Some(d) = &u.display {
                    typed.push(("displayUnit", d.name.clone()));
                }
                w.create_element("SimpleType")
                    .with_attribute(("name", u.type_name.as_str()))
                    .write_inner_content(|w| {
                        w.create_element("Real")
                            .with_attributes(pairs(&typed))
                            .write_empty()?;
                        Ok(())
                    })?;
            }
            Ok(())
        })?;
    Ok(())
}

fn write_variables(w: &mut Writer<Vec<u8>>, info: &FmuInfo, units: &[UnitInfo]) -> io::Result<()> {
    let variables = info.variables;
    // For a state derivative: the state (value reference) it is the derivative of.
    let state_of = |vr: usize| {
        variables
            .iter()
            .position(|v| v.derivative == Some(variables[vr].name))
    };
    w.create_element("ModelVariables")
        .write_inner_content(|w| {
            for (vr, v) in variables.iter().enumerate() {
                let mut sv: Attributes =
                    vec![("name", v.name.into()), ("valueReference", vr.to_string())];
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
                }
                if let Some(start) = v.start {
                    typed.push(("start", real(start)));
                }
                if let Some(min) = v.min {
                    typed.push(("min", real(min)));
                }
                if let Some(max) = v.max {
                    typed.push(("max", real(max)));
                }
                if let Some(d) = unit.and_then(|u| u.display.as_ref()) {
                    typed.push(("displayUnit", d.name.clone()));
                }
                if let Some(state) = state_of(vr) {
                    typed.push(("derivative", (state + 1).to_string()));
                }
                w.create_element("ScalarVariable")
                    .with_attributes(pairs(&sv))
                    .write_inner_content(|w| {
                        w.create_element("Real")
                            .with_attributes(pairs(&typed))
                            .write_empty()?;
                        Ok(())
                    })?;
            }
            Ok(())
        })?;
    Ok(())
}

fn write_unknowns(w: &mut Writer<Vec<u8>>, element: &str, unknowns: &[Unknown]) -> io::Result<()> {
    if unknowns.is_empty() {
        return Ok(());
    }
    w.create_element(element).write_inner_content(|w| {
        for u in unknowns {
            let indices: Vec<String> = u.dependencies.iter().map(|d| (d + 1).to_string()).collect();
            let kinds = vec!["dependent"; u.dependencies.len()];
            w.create_element("Unknown")
                .with_attributes(pairs(&vec![
                    ("index", (u.vr + 1).to_string()),
                    ("dependencies", indices.join(" ")),
                    ("dependenciesKind", kinds.join(" ")),
                ]))
                .write_empty()?;
        }
        Ok(())
    })?;
    Ok(())
}

fn write_structure(w: &mut Writer<Vec<u8>>, s: &ModelStructure) -> io::Result<()> {
    let derivatives = &s.derivatives;
    if s.outputs.is_empty() && derivatives.is_empty() && s.initial_unknowns.is_empty() {
        w.create_element("ModelStructure").write_empty()?;
        return Ok(());
    }
    w.create_element("ModelStructure")
        .write_inner_content(|w| {
            write_unknowns(w, "Outputs", &s.outputs)?;
            write_unknowns(w, "Derivatives", derivatives)?;
            write_unknowns(w, "InitialUnknowns", &s.initial_unknowns)
        })?;
    Ok(())
}

#[cfg(test)]
mod tests;
