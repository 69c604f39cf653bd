//! A system's declaration as JSON: what the system crate's binary tells the `mechfmu`
//! command (through `mechfmu_system_declaration`), which packages the system from it.

use super::{Port, Source, SystemDeclaration};
use std::fmt::Write;

/// The declaration as one JSON object: `name`, `description`, `experiment` (`start`,
/// `stop`, `step`, `tolerance`), `components` (`name`, `description`, and `model` for a
/// mechanism or `fmu` for an FMU file's path), `connections` (`from` and `to`, each
/// `[component, variable]`; a terminal connection's members among them) and `parameter_sets` (`name`, `description` and `values`, each
/// `[component, variable, value]`: the set as applied, the `default` set's values with the
/// set's own over them; the `default` set first, also when not declared).
pub fn declaration_json(system: &SystemDeclaration) -> Result<String, String> {
    let mut out = String::from("{");
    let e = &system.experiment;
    let _ = write!(
        out,
        "\"name\":{},\"description\":{},\"experiment\":{{\"start\":{},\"stop\":{},\"step\":{},\"tolerance\":{}}},",
        text(system.name),
        text(system.description.trim()),
        number(e.start)?,
        number(e.stop)?,
        number(e.step)?,
        number(e.tolerance)?
    );
    out.push_str("\"components\":[");
    for (i, c) in system.components.iter().enumerate() {
        let source = match c.source {
            Source::Mechanism { model, .. } => format!("\"model\":{}", text(model)),
            Source::Fmu { path } => format!("\"fmu\":{}", text(path)),
        };
        let _ = write!(
            out,
            "{}{{\"name\":{},\"description\":{},{source}}}",
            comma(i),
            text(c.name),
            text(c.description.trim())
        );
    }
    out.push_str("],\"connections\":[");
    for (i, c) in system.all_connections().iter().enumerate() {
        let _ = write!(
            out,
            "{}{{\"from\":{},\"to\":{}}}",
            comma(i),
            port(c.from),
            port(c.to)
        );
    }
    out.push_str("],\"parameter_sets\":[");
    for (i, name) in system.set_names().into_iter().enumerate() {
        let description = system
            .parameter_sets
            .iter()
            .find(|s| s.name == name)
            .map_or("", |s| s.description.trim());
        let values = system.resolved_set(name).unwrap_or_default();
        let _ = write!(
            out,
            "{}{{\"name\":{},\"description\":{},\"values\":[",
            comma(i),
            text(name),
            text(description)
        );
        for (j, b) in values.iter().enumerate() {
            let _ = write!(
                out,
                "{}[{},{},{}]",
                comma(j),
                text(b.port.component),
                text(b.port.variable),
                number(b.value)?
            );
        }
        out.push_str("]}");
    }
    out.push_str("]}");
    Ok(out)
}

fn comma(i: usize) -> &'static str {
    if i == 0 {
        ""
    } else {
        ","
    }
}

fn port(p: Port) -> String {
    format!("[{},{}]", text(p.component), text(p.variable))
}

/// A finite number as JSON writes it, exactly (Rust's shortest round-trip form).
fn number(x: f64) -> Result<String, String> {
    if !x.is_finite() {
        return Err(format!("{x} is not a number JSON can hold"));
    }
    Ok(format!("{x:?}"))
}

/// A JSON string.
fn text(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            '\n' => out.push_str("\\n"),
            '\r' => out.push_str("\\r"),
            '\t' => out.push_str("\\t"),
            c if (c as u32) < 0x20 => {
                let _ = write!(out, "\\u{:04x}", c as u32);
            }
            c => out.push(c),
        }
    }
    out.push('"');
    out
}
