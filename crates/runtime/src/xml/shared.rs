//! What the FMI 2.0 and FMI 3.0 model descriptions write alike: numbers, one-line texts, the
//! checks of a declaration both standards make, `<UnitDefinitions>`, `<LogCategories>` and
//! `<DefaultExperiment>` (the same elements, with the same attributes, in both schemas).

use std::io;

use quick_xml::events::{BytesDecl, Event};
use quick_xml::Writer;

use super::units::{self, BaseUnit, DisplayUnit};
use crate::model::{Experiment, Layout, Variable};

/// Attributes of one element, in the order they are written.
pub(super) type Attributes = Vec<(&'static str, String)>;

pub(super) fn pairs(attributes: &Attributes) -> impl Iterator<Item = (&str, &str)> {
    attributes.iter().map(|(k, v)| (*k, v.as_str()))
}

/// Whitespace runs (doc-comment line breaks, indentation) as single spaces, trimmed.
pub(super) fn one_line(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// A real number as `xs:double`: Rust's shortest round-trip form (`20.0`, `0.01`, `1e-8`).
pub(super) fn real(x: f64) -> String {
    if x == 0.0 {
        "0.0".into()
    } else {
        format!("{x:?}")
    }
}

/// The `generationTool` attribute: the runtime and its version.
pub(super) fn generation_tool() -> String {
    format!("mechfmu {}", env!("CARGO_PKG_VERSION"))
}

/// A unit used by the model, with the name of its type definition.
pub(super) struct UnitInfo<'a> {
    pub name: &'a str,
    pub base: BaseUnit,
    pub display: Option<DisplayUnit>,
    pub quantity: Option<&'static str>,
    /// The quantity, else `Dimensionless` or `Real_<unit>` (FMI 2.0 types every unit).
    pub type_name: String,
}

impl<'a> UnitInfo<'a> {
    fn new(name: &'a str) -> Result<Self, String> {
        let quantity = units::quantity(name);
        let type_name = match (quantity, name) {
            (Some(q), _) => q.to_string(),
            (None, "1") => "Dimensionless".to_string(),
            (None, _) => format!("Real_{}", name.replace('.', "_").replace('/', "_per_")),
        };
        Ok(UnitInfo {
            name,
            base: units::parse(name)?,
            display: units::display_unit(name)?,
            quantity,
            type_name,
        })
    }
}

/// Checks what both standards require of a declaration (a model name, a layout, one state
/// per derivative, a finite DefaultExperiment, finite start values and bounds, known units)
/// and collects the units in order of first use. `Err` starts with the model's name.
pub(super) fn check_declaration<'a>(
    name: &str,
    variables: &'a [Variable],
    experiment: Experiment,
) -> Result<Vec<UnitInfo<'a>>, String> {
    if name.is_empty() {
        return Err("the model name is empty".into());
    }
    let layout = Layout::new(variables).map_err(|e| format!("{name}: {e}"))?;
    for (i, &d) in layout.derivatives.iter().enumerate() {
        if layout.derivatives[..i].contains(&d) {
            return Err(format!(
                "{name}: `{}` is the derivative of two states",
                variables[d].name
            ));
        }
    }
    let e = experiment;
    for (what, x) in [
        ("start", e.start),
        ("stop", e.stop),
        ("step", e.step),
        ("tolerance", e.tolerance),
    ] {
        if !x.is_finite() {
            return Err(format!(
                "{name}: DefaultExperiment {what} = {x} is not finite"
            ));
        }
    }
    let mut units: Vec<UnitInfo> = Vec::new();
    for v in variables {
        for (what, x) in [("start", v.start), ("min", v.min), ("max", v.max)] {
            if let Some(x) = x.filter(|x| !x.is_finite()) {
                return Err(format!(
                    "{name}: {what} of `{}` = {x} is not finite",
                    v.name
                ));
            }
        }
        if !v.unit.is_empty() && !units.iter().any(|u| u.name == v.unit) {
            units.push(
                UnitInfo::new(v.unit).map_err(|e| format!("{name}: variable `{}`: {e}", v.name))?,
            );
        }
    }
    Ok(units)
}

/// A writer of indented XML, with the XML declaration written.
pub(super) fn writer() -> io::Result<Writer<Vec<u8>>> {
    let mut w = Writer::new_with_indent(Vec::new(), b' ', 2);
    w.write_event(Event::Decl(BytesDecl::new("1.0", Some("UTF-8"), None)))?;
    Ok(w)
}

/// `<element>` holding what `write` writes of each item.
pub(super) fn write_each<T>(
    w: &mut Writer<Vec<u8>>,
    element: &str,
    items: impl IntoIterator<Item = T>,
    mut write: impl FnMut(&mut Writer<Vec<u8>>, T) -> io::Result<()>,
) -> io::Result<()> {
    w.create_element(element)
        .write_inner_content(|w| items.into_iter().try_for_each(|item| write(w, item)))?;
    Ok(())
}

/// `<outer>` holding one empty `<inner>`.
pub(super) fn write_holding(
    w: &mut Writer<Vec<u8>>,
    (outer, outer_attributes): (&str, &Attributes),
    (inner, inner_attributes): (&str, &Attributes),
) -> io::Result<()> {
    w.create_element(outer)
        .with_attributes(pairs(outer_attributes))
        .write_inner_content(|w| {
            w.create_element(inner)
                .with_attributes(pairs(inner_attributes))
                .write_empty()?;
            Ok(())
        })?;
    Ok(())
}

/// The document a writer wrote, as text ending with a line break.
pub(super) fn finish(name: &str, written: io::Result<Vec<u8>>) -> Result<String, String> {
    let bytes = written.map_err(|e| format!("{name}: {e}"))?;
    let mut xml = String::from_utf8(bytes).map_err(|e| e.to_string())?;
    xml.push('\n');
    Ok(xml)
}

pub(super) fn write_units(w: &mut Writer<Vec<u8>>, units: &[UnitInfo]) -> io::Result<()> {
    if units.is_empty() {
        return Ok(());
    }
    write_each(w, "UnitDefinitions", units, |w, u| {
        w.create_element("Unit")
            .with_attribute(("name", u.name))
            .write_inner_content(|w| {
                let exponents: Attributes = u
                    .base
                    .exponents()
                    .into_iter()
                    .map(|(k, e)| (k, e.to_string()))
                    .collect();
                w.create_element("BaseUnit")
                    .with_attributes(pairs(&exponents))
                    .write_empty()?;
                if let Some(d) = &u.display {
                    w.create_element("DisplayUnit")
                        .with_attributes(pairs(&vec![
                            ("name", d.name.clone()),
                            ("factor", real(d.factor)),
                        ]))
                        .write_empty()?;
                }
                Ok(())
            })?;
        Ok(())
    })
}

pub(super) fn write_log_categories(
    w: &mut Writer<Vec<u8>>,
    categories: &[(&str, &str)],
) -> io::Result<()> {
    if categories.is_empty() {
        return Ok(());
    }
    write_each(w, "LogCategories", categories, |w, &(name, description)| {
        w.create_element("Category")
            .with_attributes([("name", name), ("description", description)])
            .write_empty()?;
        Ok(())
    })
}

pub(super) fn write_default_experiment(w: &mut Writer<Vec<u8>>, e: &Experiment) -> io::Result<()> {
    w.create_element("DefaultExperiment")
        .with_attributes(pairs(&vec![
            ("startTime", real(e.start)),
            ("stopTime", real(e.stop)),
            ("tolerance", real(e.tolerance)),
            ("stepSize", real(e.step)),
        ]))
        .write_empty()?;
    Ok(())
}
