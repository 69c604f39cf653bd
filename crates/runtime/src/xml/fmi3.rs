//! The FMI 3.0 `modelDescription.xml` (Model Exchange and Co-Simulation) of a mechanism,
//! generated from the same declaration as FMI 2.0's: deterministic, byte for byte.
//!
//! What FMI 3.0 sees differs from FMI 2.0 in three ways:
//! - the variables are [`Shapes`]: the declared scalars, but those grouped into
//!   [`Mechanism::ARRAYS`] shown as one `<Float64>` array each (`<Dimension>`, a start value
//!   per element in row-major order, FMI 3.0 section 2.4.7.2), and an annotation
//!   ([`SCALARS_ANNOTATION`]) naming the FMI 2.0 scalars its elements are; the variables
//!   are listed in declaration order, each state before its derivative, as in FMI 2.0's,
//!   their value references 1, 2, ... in that order (a variable's value reference is its
//!   1-based place in the list), and the independent variable `time` comes last, with value
//!   reference 0 ([`Shapes::TIME_REFERENCE`]), as the Reference-FMUs number it;
//! - the names follow `variableNamingConvention="structured"` (section 2.4.7.5.1): every
//!   name is an identifier, and an array's element is named `I_C[1,2]` (1-based);
//! - `<ModelStructure>` (section 2.4.8) lists variables by value reference, an array once,
//!   and its dependencies have FMI 3.0's knowns ([`Knowns::Fmi3`]: the parameters and the
//!   time too), found numerically scalar by scalar and taken over to the variables the
//!   scalars belong to (an array depends on what any element depends on, by the least
//!   particular kind of any pair of elements); `<EventIndicator>`s have their
//!   dependencies too, with the knowns of `<Output>`.

use std::collections::{BTreeMap, BTreeSet};
use std::io;

use quick_xml::events::BytesText;
use quick_xml::Writer;

use super::shared::{
    self, generation_tool, one_line, pairs, real, write_default_experiment, write_each,
    write_log_categories, write_units, Attributes, UnitInfo,
};
use super::structure::{self, Dependency, DependencyKind, Knowns, Unknown};
use crate::contract::{self, FMI3_CAPABILITIES};
use crate::model::{Mechanism, Shaped, Shapes, Variable};

/// The FMI 3.0 modelDescription.xml of mechanism `M`, with the runtime's
/// [`FMI3_CAPABILITIES`].
///
/// `Err` names the problem: what the FMI 2.0 writer refuses (an unknown unit, a start value
/// that is not finite or that `calculate` rejects, ...), arrays [`Shapes::new`] refuses, a
/// name that is no identifier, a type named like a variable, an event indicator inside an
/// array.
pub fn model_description<M: Mechanism>() -> Result<String, String> {
    let name = M::NAME;
    let variables = M::VARIABLES;
    let units = shared::check_declaration(name, variables, M::EXPERIMENT)?;
    let shapes = Shapes::new(variables, M::ARRAYS).map_err(|e| format!("{name}: {e}"))?;
    check_names(name, &shapes, &units)?;
    for indicator in M::EVENT_INDICATORS {
        let owner = (variables.iter().position(|v| v.name == *indicator))
            .and_then(|vr| shapes.owner(vr))
            .ok_or_else(|| format!("{name}: event indicator `{indicator}` is not a variable"))?;
        if owner.is_array() {
            return Err(format!(
                "{name}: event indicator `{indicator}` is an element of array `{}`, and FMI 3.0 \
                 lists whole variables as event indicators",
                owner.name
            ));
        }
    }
    let structure = structure::model_structure_with::<M>(Knowns::Fmi3)?;
    let lists = Lists {
        outputs: by_variable(name, &shapes, &structure.outputs, "output")?,
        derivatives: by_variable(name, &shapes, &structure.derivatives, "state derivative")?,
        initial_unknowns: by_variable(
            name,
            &shapes,
            &structure.initial_unknowns,
            "initial unknown",
        )?,
        event_indicators: by_variable(
            name,
            &shapes,
            &structure.event_indicators,
            "event indicator",
        )?,
        knowns: by_variable_knowns(&shapes, &structure.knowns),
        initial_knowns: by_variable_knowns(&shapes, &structure.initial_knowns),
    };
    // In the order of the value references (`Shapes`: each state before its derivative).
    let rows = (shapes.variables.iter())
        .map(|shaped| row(name, variables, &shapes, shaped, &units))
        .collect::<Result<Vec<_>, String>>()?;
    shared::finish(name, write::<M>(&rows, &units, &lists))
}

/// Checks the names FMI 3.0 sees: `structured` names without quotes, identifiers joined by
/// dots (a system's `component.variable`), unique, none `time` but the independent
/// variable, none the name of a type.
fn check_names(model: &str, shapes: &Shapes, units: &[UnitInfo]) -> Result<(), String> {
    let mut seen = BTreeSet::from(["time"]);
    for s in &shapes.variables {
        let identifier = |part: &str| {
            let mut chars = part.chars();
            chars
                .next()
                .is_some_and(|c| c == '_' || c.is_ascii_alphabetic())
                && chars.all(|c| c == '_' || c.is_ascii_alphanumeric())
        };
        if !s.name.split('.').all(identifier) {
            return Err(format!(
                "{model}: `{}` is not a name of variableNamingConvention=\"structured\" \
                 (identifiers of ASCII letters, digits and `_`, not starting with a digit, \
                 joined by `.`)",
                s.name
            ));
        }
        if !seen.insert(s.name) {
            return Err(format!(
                "{model}: two variables of FMI 3.0 are named `{}`",
                s.name
            ));
        }
    }
    for u in units.iter().filter(|u| u.quantity.is_some()) {
        if seen.contains(u.type_name.as_str()) {
            return Err(format!(
                "{model}: variable `{}` has the name of the type of unit \"{}\"",
                u.type_name, u.name
            ));
        }
    }
    Ok(())
}

/// The lists of `<ModelStructure>`, by FMI 3.0 value reference, and the knowns of each.
struct Lists {
    outputs: Vec<Unknown>,
    derivatives: Vec<Unknown>,
    initial_unknowns: Vec<Unknown>,
    event_indicators: Vec<Unknown>,
    /// The knowns of `<Output>`, `<ContinuousStateDerivative>` and `<EventIndicator>`.
    knowns: BTreeSet<usize>,
    /// The knowns of `<InitialUnknown>`.
    initial_knowns: BTreeSet<usize>,
}

/// The FMI 3.0 value reference of a scalar's variable (the time for `VARIABLES.len()`).
fn variable_reference(shapes: &Shapes, vr: usize) -> usize {
    match shapes.owner(vr) {
        Some(owner) => owner.reference,
        None => Shapes::TIME_REFERENCE,
    }
}

/// Scalar knowns taken over to the variables they belong to.
fn by_variable_knowns(shapes: &Shapes, knowns: &[usize]) -> BTreeSet<usize> {
    (knowns.iter())
        .map(|&vr| variable_reference(shapes, vr))
        .collect()
}

/// Scalar unknowns taken over to the variables they belong to, in order of first
/// appearance: an array once, depending on the union of its elements' dependencies, each
/// dependency the value reference of the variable its scalar belongs to (the time its
/// own), of the least particular kind among the pairs of scalars it stands for. Every
/// element of an array must be in `unknowns` if one is.
fn by_variable(
    model: &str,
    shapes: &Shapes,
    unknowns: &[Unknown],
    what: &str,
) -> Result<Vec<Unknown>, String> {
    let reference = |vr: usize| variable_reference(shapes, vr);
    type Kinds = BTreeMap<usize, DependencyKind>;
    let mut grouped: Vec<(&Shaped, BTreeSet<usize>, Kinds)> = Vec::new();
    for u in unknowns {
        let Some(owner) = shapes.owner(u.vr) else {
            return Err(format!(
                "{model}: the model structure refers to a variable that does not exist"
            ));
        };
        let i = match grouped
            .iter()
            .position(|(s, _, _)| s.reference == owner.reference)
        {
            Some(i) => i,
            None => {
                grouped.push((owner, BTreeSet::new(), BTreeMap::new()));
                grouped.len() - 1
            }
        };
        grouped[i].1.insert(u.vr);
        for d in &u.dependencies {
            let kind = grouped[i].2.entry(reference(d.known)).or_insert(d.kind);
            *kind = (*kind).max(d.kind);
        }
    }
    grouped
        .into_iter()
        .map(|(owner, members, dependencies)| {
            if members.len() != owner.elements.iter().collect::<BTreeSet<_>>().len() {
                return Err(format!(
                    "{model}: only some elements of array `{}` are {what}s",
                    owner.name
                ));
            }
            Ok(Unknown {
                vr: owner.reference,
                dependencies: (dependencies.into_iter())
                    .map(|(known, kind)| Dependency { known, kind })
                    .collect(),
            })
        })
        .collect()
}

/// One `<Float64>` of `<ModelVariables>`: its attributes, its dimensions and, for an
/// array, the names of the declared scalars its elements are (FMI 2.0's variables).
struct Row {
    attributes: Attributes,
    dimensions: &'static [usize],
    scalars: Vec<&'static str>,
}

/// The annotation type that names, for an array, the FMI 2.0 variables its elements are,
/// in row-major order (space-separated): what maps results, start values and reference
/// files between the FMU's two versions.
pub const SCALARS_ANNOTATION: &str = "org.mechfmu.scalars";

/// The attributes of a variable, in the schema's order (`fmi3Float64`: name, valueReference,
/// description, causality, variability, declaredType, initial, unit, displayUnit, min, max,
/// start, derivative).
fn row(
    model: &str,
    variables: &[Variable],
    shapes: &Shapes,
    s: &Shaped,
    units: &[UnitInfo],
) -> Result<Row, String> {
    let v = s.variable(variables);
    let elements: Vec<&Variable> = s.elements.iter().map(|&e| &variables[e]).collect();
    let mut a: Attributes = vec![
        ("name", s.name.into()),
        ("valueReference", s.reference.to_string()),
    ];
    let description = one_line(s.description);
    if !description.is_empty() {
        a.push(("description", description));
    }
    a.push(("causality", v.causality.as_str().into()));
    a.push(("variability", v.variability.as_str().into()));
    let unit = units.iter().find(|u| u.name == v.unit);
    if let Some(u) = unit.filter(|u| u.quantity.is_some()) {
        a.push(("declaredType", u.type_name.clone()));
    }
    if let Some(initial) = v.initial {
        a.push(("initial", initial.as_str().into()));
    }
    if let Some(u) = unit {
        a.push(("unit", u.name.into()));
        if let Some(d) = &u.display {
            a.push(("displayUnit", d.name.clone()));
        }
    }
    // A bound only when every element has it: an array has one `min` and one `max`.
    let common = |bound: fn(&Variable) -> Option<f64>| {
        bound(v).filter(|&x| elements.iter().all(|e| bound(e) == Some(x)))
    };
    if let Some(min) = common(|v| v.min) {
        a.push(("min", real(min)));
    }
    if let Some(max) = common(|v| v.max) {
        a.push(("max", real(max)));
    }
    let starts: Vec<Option<f64>> = elements.iter().map(|e| e.start).collect();
    if starts.iter().all(Option::is_some) {
        let list: Vec<String> = starts.into_iter().flatten().map(real).collect();
        a.push(("start", list.join(" ")));
    } else if starts.iter().any(Option::is_some) {
        return Err(format!(
            "{model}: array `{}` has start values for some elements only",
            s.name
        ));
    }
    if let Some(state) = state_of(variables, shapes, s) {
        a.push(("derivative", state.reference.to_string()));
    }
    Ok(Row {
        attributes: a,
        dimensions: s.dimensions,
        scalars: elements.iter().map(|e| e.name).collect(),
    })
}

/// The variable `s` is the derivative of: a state array's derivative is an array of the
/// same shape (`Shapes::new` checks it), pointing at the state array.
fn state_of<'a>(variables: &[Variable], shapes: &'a Shapes, s: &Shaped) -> Option<&'a Shaped> {
    let v = s.variable(variables);
    (variables.iter())
        .position(|w| w.derivative == Some(v.name))
        .and_then(|vr| shapes.owner(vr))
}

fn write<M: Mechanism>(rows: &[Row], units: &[UnitInfo], lists: &Lists) -> io::Result<Vec<u8>> {
    let mut w = shared::writer()?;
    let token = contract::instantiation_token::<M>();
    let mut root: Attributes = vec![
        ("fmiVersion", "3.0".into()),
        ("modelName", M::NAME.into()),
        ("instantiationToken", token),
    ];
    let description = one_line(M::DESCRIPTION);
    if !description.is_empty() {
        root.push(("description", description));
    }
    root.extend([
        ("generationTool", generation_tool()),
        ("variableNamingConvention", "structured".into()),
    ]);
    let categories = contract::fmi3_log_categories();
    let categories: Vec<(&str, &str)> = categories.iter().map(|(n, d)| (*n, d.as_str())).collect();
    w.create_element("fmiModelDescription")
        .with_attributes(pairs(&root))
        .write_inner_content(|w| {
            let c = FMI3_CAPABILITIES;
            let me = c.model_exchange_attributes(contract::needs_completed_integrator_step::<M>());
            let cs = c.co_simulation_attributes(contract::might_return_early_from_do_step::<M>());
            for (element, capabilities) in [("ModelExchange", me), ("CoSimulation", cs)] {
                let mut a: Attributes = vec![("modelIdentifier", M::NAME.into())];
                a.extend(capabilities);
                w.create_element(element)
                    .with_attributes(pairs(&a))
                    .write_empty()?;
            }
            write_units(w, units)?;
            write_types(w, units)?;
            write_log_categories(w, &categories)?;
            write_default_experiment(w, &M::EXPERIMENT)?;
            write_variables(w, rows)?;
            write_structure(w, lists)
        })?;
    Ok(w.into_inner())
}

/// A `<Float64Type>` per unit that has a quantity (its name), carrying the quantity, the
/// unit and the display unit. Units without one need no type: FMI 3.0 variables carry
/// their unit themselves.
fn write_types(w: &mut Writer<Vec<u8>>, units: &[UnitInfo]) -> io::Result<()> {
    let typed: Vec<&UnitInfo> = units.iter().filter(|u| u.quantity.is_some()).collect();
    if typed.is_empty() {
        return Ok(());
    }
    write_each(w, "TypeDefinitions", typed, |w, u| {
        let mut a: Attributes = vec![("name", u.type_name.clone())];
        a.extend(u.quantity.map(|q| ("quantity", q.to_string())));
        a.push(("unit", u.name.into()));
        if let Some(d) = &u.display {
            a.push(("displayUnit", d.name.clone()));
        }
        w.create_element("Float64Type")
            .with_attributes(pairs(&a))
            .write_empty()?;
        Ok(())
    })
}

/// The variables, then the independent `time`: listed last, it leaves each other variable's
/// value reference its 1-based place in the list, as importers that read FMI 3.0's
/// `derivative` and `dependencies` with FMI 2.0's meaning (OMSimulator's Python API) take it.
fn write_variables(w: &mut Writer<Vec<u8>>, rows: &[Row]) -> io::Result<()> {
    w.create_element("ModelVariables")
        .write_inner_content(|w| {
            rows.iter().try_for_each(|row| write_row(w, row))?;
            w.create_element("Float64")
                .with_attributes(pairs(&vec![
                    ("name", "time".into()),
                    ("valueReference", Shapes::TIME_REFERENCE.to_string()),
                    ("description", "Simulation time".into()),
                    ("causality", "independent".into()),
                    ("variability", "continuous".into()),
                ]))
                .write_empty()?;
            Ok(())
        })?;
    Ok(())
}

/// One `<Float64>`: an array's with its scalars' names and its `<Dimension>`s.
fn write_row(w: &mut Writer<Vec<u8>>, row: &Row) -> io::Result<()> {
    let element = w
        .create_element("Float64")
        .with_attributes(pairs(&row.attributes));
    if row.dimensions.is_empty() {
        element.write_empty()?;
        return Ok(());
    }
    element.write_inner_content(|w| {
        w.create_element("Annotations").write_inner_content(|w| {
            w.create_element("Annotation")
                .with_attribute(("type", SCALARS_ANNOTATION))
                .write_text_content(BytesText::new(&row.scalars.join(" ")))?;
            Ok(())
        })?;
        for d in row.dimensions {
            w.create_element("Dimension")
                .with_attribute(("start", d.to_string().as_str()))
                .write_empty()?;
        }
        Ok(())
    })?;
    Ok(())
}

/// `<Output>`, `<ContinuousStateDerivative>`, `<InitialUnknown>` and `<EventIndicator>`, in
/// the schema's order, each with its dependencies and their kinds.
///
/// An unknown that depends on every known of its list is written without `dependencies`
/// (section 2.4.8: "If not present, it must be assumed that the unknown depends on all
/// knowns"): the same statement, and one that importers which take the list's value
/// references for FMI 2.0's 1-based indices (OMSimulator) do not trip over, as they do on
/// the time's value reference 0.
fn write_structure(w: &mut Writer<Vec<u8>>, lists: &Lists) -> io::Result<()> {
    let empty = lists.outputs.is_empty()
        && lists.derivatives.is_empty()
        && lists.initial_unknowns.is_empty()
        && lists.event_indicators.is_empty();
    if empty {
        w.create_element("ModelStructure").write_empty()?;
        return Ok(());
    }
    w.create_element("ModelStructure")
        .write_inner_content(|w| {
            for (element, unknowns, knowns) in [
                ("Output", &lists.outputs, &lists.knowns),
                (
                    "ContinuousStateDerivative",
                    &lists.derivatives,
                    &lists.knowns,
                ),
                (
                    "InitialUnknown",
                    &lists.initial_unknowns,
                    &lists.initial_knowns,
                ),
                ("EventIndicator", &lists.event_indicators, &lists.knowns),
            ] {
                for u in unknowns {
                    let mut attributes = vec![("valueReference", u.vr.to_string())];
                    if !u.knowns().eq(knowns.iter().copied()) {
                        let references: Vec<String> = u.knowns().map(|k| k.to_string()).collect();
                        let kinds: Vec<&str> =
                            u.dependencies.iter().map(|d| d.kind.as_str()).collect();
                        attributes.push(("dependencies", references.join(" ")));
                        attributes.push(("dependenciesKind", kinds.join(" ")));
                    }
                    w.create_element(element)
                        .with_attributes(pairs(&attributes))
                        .write_empty()?;
                }
            }
            Ok(())
        })?;
    Ok(())
}

#[cfg(test)]
mod tests;
