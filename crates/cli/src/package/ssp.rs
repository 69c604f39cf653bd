//! Writing a system as an SSP (System Structure and Parameterization 1.0): the archive that
//! FMPy, libcosim, Ecos and OMSimulator each run without edits.
//!
//! - `SystemStructure.ssd`: the components (`type="application/x-fmu-sharedlibrary"`, their
//!   FMUs in `resources/`), a connector for each output and each connected input (FMPy fails
//!   on an input left unconnected), the connections, the units, the default experiment with
//!   the OSP `FixedStepAlgorithm` annotation (libcosim and Ecos need a step) and the system
//!   with OpenModelica's `FixedStepMaster` annotation (OMSimulator's step). The namespaces are
//!   declared on the root: libcosim reads an attribute of an annotation's element as an
//!   unknown algorithm.
//! - Parameter sets: each component's values of each set in `resources/<set>/<component>.ssv`,
//!   every set giving a value to every variable any set gives one to (the default set takes
//!   the FMU's start value where the declaration gives none). Each SSD binds one set, one
//!   binding per component: `SystemStructure.ssd` the default set, the variant `<set>.ssd`
//!   every other one (libcosim and OMSimulator run a variant by name). The tools apply
//!   several bindings each its own way (libcosim the first, OMSimulator's Python API every
//!   one in turn, the last winning; its command line ran a set other than the default
//!   whenever one was bound, first or last; Ecos the one its `init` names), so that binding
//!   more than one set in
//!   `SystemStructure.ssd` makes one of them run another set than the default.
//!   Bindings are the components': libcosim ignores a system's.

use super::archive::write_zip;
use crate::system::{Component, Declaration, ParameterSet};
use mechfmu::model::units;
use mechfmu::system::DEFAULT_SET;
use std::collections::BTreeMap;
use std::fmt::Write;
use std::path::Path;

const NAMESPACES: &str = concat!(
    r#"xmlns:ssd="http://ssp-standard.org/SSP1/SystemStructureDescription" "#,
    r#"xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon" "#,
    r#"xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues" "#,
    r#"xmlns:osp="http://opensimulationplatform.com/SSP/OSPAnnotations" "#,
    r#"xmlns:oms="https://raw.githubusercontent.com/OpenModelica/OMSimulator/master/schema/oms.xsd""#,
);

/// The file name of the SSD every tool opens.
pub const DEFAULT_SSD: &str = "SystemStructure.ssd";

/// Writes `system` with its `components` as the SSP `path`.
pub fn write_ssp(
    path: &Path,
    system: &Declaration,
    components: &[Component],
) -> Result<(), String> {
    let completed = Declaration {
        parameter_sets: complete_sets(system, components)?,
        ..system.clone()
    };
    let system = &completed;
    let mut entries: Vec<(String, Vec<u8>)> = Vec::new();
    for set in &system.parameter_sets {
        let ssd = structure(system, components, &set.name);
        let name = if set.name == DEFAULT_SET {
            DEFAULT_SSD.to_string()
        } else {
            format!("{}.ssd", set.name)
        };
        entries.push((name, ssd.into_bytes()));
    }
    for set in &system.parameter_sets {
        for component in components {
            let values: Vec<(&str, f64)> = (set.values.iter())
                .filter(|(c, _, _)| c == &component.declaration.name)
                .map(|(_, v, x)| (v.as_str(), *x))
                .collect();
            if !values.is_empty() {
                entries.push((
                    values_file(&set.name, &component.declaration.name),
                    parameter_values(&set.name, &set.description, &values).into_bytes(),
                ));
            }
        }
    }
    let mut fmus: BTreeMap<String, &Path> = BTreeMap::new();
    for component in components {
        let file = component.file_name();
        match fmus.get(&file) {
            Some(other) if *other != component.path.as_path() => {
                return Err(format!(
                    "system `{}`: two components' FMUs are called {file} ({} and {})",
                    system.name,
                    other.display(),
                    component.path.display()
                ))
            }
            _ => {
                fmus.insert(file, &component.path);
            }
        }
    }
    for (file, fmu) in &fmus {
        let bytes =
            std::fs::read(fmu).map_err(|e| format!("cannot read {}: {e}", fmu.display()))?;
        entries.push((format!("resources/{file}"), bytes));
    }
    let entries: Vec<(String, &[u8])> = entries
        .iter()
        .map(|(p, b)| (p.clone(), b.as_slice()))
        .collect();
    write_zip(path, &entries).map_err(|e| format!("cannot write {}: {e}", path.display()))
}

/// The parameter sets, each giving a value to every variable any of them gives one to: the
/// default set's missing ones are the FMUs' start values (every other set is the default
/// set with its own values over it, so they are complete then).
fn complete_sets(
    system: &Declaration,
    components: &[Component],
) -> Result<Vec<ParameterSet>, String> {
    let mut sets = system.parameter_sets.clone();
    let mut wanted: Vec<(String, String)> = Vec::new();
    for (c, v, _) in sets.iter().flat_map(|s| &s.values) {
        if !wanted.iter().any(|(wc, wv)| wc == c && wv == v) {
            wanted.push((c.clone(), v.clone()));
        }
    }
    for (c, v) in wanted {
        let start = components
            .iter()
            .find(|k| k.declaration.name == c)
            .and_then(|k| k.description.variable(&v))
            .and_then(|var| var.start)
            .ok_or_else(|| {
                format!(
                    "system `{}`: `{c}.{v}` has a value in a parameter set but no start value in its FMU",
                    system.name
                )
            })?;
        for set in sets.iter_mut() {
            if !set.values.iter().any(|(sc, sv, _)| sc == &c && sv == &v) {
                set.values.push((c.clone(), v.clone(), start));
            }
        }
    }
    Ok(sets)
}

/// Where a component's values of a set are.
fn values_file(set: &str, component: &str) -> String {
    format!("resources/{set}/{component}.ssv")
}

/// The SSD of `system` binding the parameter set `set`.
fn structure(system: &Declaration, components: &[Component], set: &str) -> String {
    let mut units_used: Vec<String> = Vec::new();
    let mut x = String::new();
    let _ = writeln!(x, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    // A variant's own name: OMSimulator refuses two variants of one name.
    let name = if set == DEFAULT_SET {
        &system.name
    } else {
        set
    };
    let _ = writeln!(
        x,
        r#"<ssd:SystemStructureDescription {NAMESPACES} version="1.0" name="{}" description="{}" generationTool="mechfmu {}">"#,
        escape(name),
        escape(&system.description),
        env!("CARGO_PKG_VERSION")
    );
    let _ = writeln!(
        x,
        r#"  <ssd:System name="{}" description="{}">"#,
        escape(&system.name),
        escape(&system.description)
    );
    x.push_str("    <ssd:Elements>\n");
    for component in components {
        let name = &component.declaration.name;
        let _ = writeln!(
            x,
            r#"      <ssd:Component name="{}" description="{}" type="application/x-fmu-sharedlibrary" source="resources/{}">"#,
            escape(name),
            escape(&component.declaration.description),
            escape(&component.file_name())
        );
        x.push_str("        <ssd:Connectors>\n");
        for v in &component.description.variables {
            let connected_input = v.causality == "input"
                && system
                    .connections
                    .iter()
                    .any(|c| &c.to.0 == name && c.to.1 == v.name);
            if !(v.causality == "output" || connected_input) || v.kind != "Real" {
                continue;
            }
            let unit = v.unit.as_deref().filter(|u| units::parse(u).is_ok());
            let _ = write!(
                x,
                r#"          <ssd:Connector name="{}" kind="{}"><ssc:Real"#,
                escape(&v.name),
                v.causality
            );
            if let Some(unit) = unit {
                let _ = write!(x, r#" unit="{}""#, escape(unit));
                if !units_used.iter().any(|u| u == unit) {
                    units_used.push(unit.to_string());
                }
            }
            x.push_str("/></ssd:Connector>\n");
        }
        x.push_str("        </ssd:Connectors>\n");
        // each SSD binds its own set alone (see the module's documentation)
        let bound = (system.parameter_sets.iter())
            .find(|s| s.name == set)
            .is_some_and(|s| s.values.iter().any(|(c, _, _)| c == name));
        if bound {
            let _ = writeln!(
                x,
                r#"        <ssd:ParameterBindings><ssd:ParameterBinding source="{}"/></ssd:ParameterBindings>"#,
                escape(&values_file(set, name))
            );
        }
        x.push_str("      </ssd:Component>\n");
    }
    x.push_str("    </ssd:Elements>\n    <ssd:Connections>\n");
    for c in &system.connections {
        let _ = writeln!(
            x,
            r#"      <ssd:Connection startElement="{}" startConnector="{}" endElement="{}" endConnector="{}"/>"#,
            escape(&c.from.0),
            escape(&c.from.1),
            escape(&c.to.0),
            escape(&c.to.1)
        );
    }
    let step = number(system.experiment.step);
    let tolerance = number(system.experiment.tolerance);
    x.push_str("    </ssd:Connections>\n");
    let _ = writeln!(
        x,
        r#"    <ssd:Annotations><ssc:Annotation type="org.openmodelica"><oms:Annotations><oms:SimulationInformation><oms:FixedStepMaster description="oms-ma" stepSize="{step}" absoluteTolerance="{tolerance}" relativeTolerance="{tolerance}"/></oms:SimulationInformation></oms:Annotations></ssc:Annotation></ssd:Annotations>"#
    );
    x.push_str("  </ssd:System>\n");
    if !units_used.is_empty() {
        x.push_str("  <ssd:Units>\n");
        for unit in &units_used {
            let base = units::parse(unit).expect("parsed above");
            let exponents: String = base
                .exponents()
                .iter()
                .map(|(symbol, e)| format!(r#" {symbol}="{e}""#))
                .collect();
            let _ = writeln!(
                x,
                r#"    <ssc:Unit name="{}"><ssc:BaseUnit{exponents}/></ssc:Unit>"#,
                escape(unit)
            );
        }
        x.push_str("  </ssd:Units>\n");
    }
    let _ = writeln!(
        x,
        r#"  <ssd:DefaultExperiment startTime="{}" stopTime="{}"><ssd:Annotations><ssc:Annotation type="com.opensimulationplatform"><osp:Algorithm><osp:FixedStepAlgorithm baseStepSize="{step}"/></osp:Algorithm></ssc:Annotation></ssd:Annotations></ssd:DefaultExperiment>"#,
        number(system.experiment.start),
        number(system.experiment.stop)
    );
    x.push_str("</ssd:SystemStructureDescription>\n");
    x
}

/// An `.ssv` file: the parameter set `set`'s values of one component.
fn parameter_values(set: &str, description: &str, values: &[(&str, f64)]) -> String {
    let mut x = String::new();
    let _ = writeln!(x, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        x,
        r#"<ssv:ParameterSet xmlns:ssc="http://ssp-standard.org/SSP1/SystemStructureCommon" xmlns:ssv="http://ssp-standard.org/SSP1/SystemStructureParameterValues" version="1.0" name="{}" description="{}">"#,
        escape(set),
        escape(description)
    );
    x.push_str("  <ssv:Parameters>\n");
    for (name, value) in values {
        let _ = writeln!(
            x,
            r#"    <ssv:Parameter name="{}"><ssv:Real value="{}"/></ssv:Parameter>"#,
            escape(name),
            number(*value)
        );
    }
    x.push_str("  </ssv:Parameters>\n</ssv:ParameterSet>\n");
    x
}

/// A number as XML Schema's `double` reads it back exactly.
fn number(x: f64) -> String {
    format!("{x:?}")
}

fn escape(text: &str) -> String {
    text.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}
