//! What one element of a model description says: a variable (FMI 2.0's `ScalarVariable`
//! and its type element, FMI 3.0's variable element), a declared type, an attribute.

use mechfmu::contract::Version;
use quick_xml::events::BytesStart;
use quick_xml::XmlVersion;

/// A variable of the model description.
#[derive(Clone, Debug, PartialEq)]
pub struct Variable {
    pub name: String,
    pub vr: u32,
    pub causality: String,
    pub variability: String,
    /// The start value of a real scalar (FMI 2.0's `Real`, FMI 3.0's scalar `Float64`).
    pub start: Option<f64>,
    /// An FMI 3.0 array's dimensions (empty: a scalar).
    pub dimensions: Vec<usize>,
    /// The FMI 2.0 scalars an FMI 3.0 array is made of, row-major (its annotation
    /// `org.mechfmu.scalars`; empty without one).
    pub scalars: Vec<String>,
    /// Its type: FMI 2.0's type element (`Real`, `Integer`, ...), FMI 3.0's variable
    /// element (`Float64`, ...).
    pub kind: String,
    pub initial: Option<String>,
    pub min: Option<f64>,
    pub max: Option<f64>,
    /// Its own, else its declared type's (`declaredType`).
    pub unit: Option<String>,
    pub quantity: Option<String>,
    pub declared_type: Option<String>,
    /// What it is the derivative of, as written: FMI 2.0's 1-based index of the variable,
    /// FMI 3.0's value reference.
    pub derivative: Option<u32>,
    /// An FMI 3.0 float's start values, one per element (empty: none declared).
    pub start_values: Vec<f64>,
}

/// A variable's element: FMI 2.0's `ScalarVariable` (its start in its type's child), or
/// FMI 3.0's element named by its type (a scalar `Float64`'s start an attribute).
pub(super) fn variable(e: &BytesStart, version: Version) -> Result<Variable, String> {
    let name = attribute(e, "name").unwrap_or_default();
    let vr = attribute(e, "valueReference")
        .and_then(|v| v.parse().ok())
        .ok_or_else(|| format!("the variable `{name}` has no valueReference"))?;
    let float = e.name().into_inner().starts_with("Float");
    let default_variability = if version == Version::Fmi2 || float {
        "continuous"
    } else {
        "discrete"
    };
    let start = match version {
        Version::Fmi3 if float => attribute(e, "start").and_then(|v| v.parse().ok()),
        _ => None,
    };
    let start_values = match attribute(e, "start") {
        Some(s) if version == Version::Fmi3 && float => (s.split_whitespace())
            .map(|x| {
                x.parse::<f64>()
                    .map_err(|err| format!("`{name}`: start {s:?}: {err}"))
            })
            .collect::<Result<_, _>>()?,
        _ => Vec::new(),
    };
    let mut v = Variable {
        name,
        vr,
        causality: attribute(e, "causality").unwrap_or_else(|| "local".into()),
        variability: attribute(e, "variability").unwrap_or_else(|| default_variability.into()),
        start,
        dimensions: Vec::new(),
        scalars: Vec::new(),
        kind: e.name().into_inner().to_string(),
        initial: attribute(e, "initial"),
        min: None,
        max: None,
        unit: None,
        quantity: None,
        declared_type: None,
        derivative: None,
        start_values,
    };
    if version == Version::Fmi3 {
        typed(&mut v, e);
    }
    Ok(v)
}

/// The attributes of a variable's type (FMI 2.0's type element, FMI 3.0's variable
/// element) into `v`.
pub(super) fn typed(v: &mut Variable, e: &BytesStart) {
    let number = |name: &str| attribute(e, name).and_then(|x| x.parse::<f64>().ok());
    v.min = number("min");
    v.max = number("max");
    v.unit = attribute(e, "unit");
    v.quantity = attribute(e, "quantity");
    v.declared_type = attribute(e, "declaredType");
    v.derivative = attribute(e, "derivative").and_then(|x| x.parse().ok());
}

/// A declared type named `name` (FMI 2.0's `SimpleType` around `e`, FMI 3.0's
/// `Float64Type`): its name, unit and quantity.
pub(super) fn declared_type(
    e: &BytesStart,
    name: Option<String>,
) -> Option<(String, Option<String>, Option<String>)> {
    Some((name?, attribute(e, "unit"), attribute(e, "quantity")))
}

/// A boolean attribute: true where it says `true`.
pub(super) fn flag(e: &BytesStart, key: &str) -> bool {
    attribute(e, key).as_deref() == Some("true")
}

/// An attribute's value, unescaped and normalized (None: absent or unreadable).
pub(super) fn attribute(e: &BytesStart, key: &str) -> Option<String> {
    e.attributes()
        .flatten()
        .find(|a| a.key.into_inner() == key)
        .and_then(|a| a.normalized_value(XmlVersion::Explicit1_0).ok())
        .map(|v| v.into_owned())
}
