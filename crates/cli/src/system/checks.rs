//! What `mechfmu build` checks of a system once its components' model descriptions are
//! read: what `system!` checks at compile time, again (an FMU file's variables are known
//! only now), and the loops of direct feedthrough (`mechfmu::system::feedthrough_cycle`).

use super::{Component, Declaration, Port};
use mechfmu::system::{feedthrough_cycle, units_alike, Feedthrough, PortName};
use mechfmu_host::description::{ModelDescription, Variable};

/// Every mistake of `system` whose components are `components`, one per line, or `Ok`.
pub fn check(system: &Declaration, components: &[Component]) -> Result<(), String> {
    let mut mistakes = Vec::new();
    let find = |(component, variable): &Port| -> Result<(&Component, &Variable), String> {
        let c = components
            .iter()
            .find(|c| &c.declaration.name == component)
            .ok_or_else(|| format!("there is no component `{component}`"))?;
        let v = c.description.variable(variable).ok_or_else(|| {
            format!(
                "component `{component}` ({}) has no variable `{variable}`",
                c.file_name()
            )
        })?;
        Ok((c, v))
    };
    for connection in &system.connections {
        let text = format!(
            "connection {} => {}",
            dotted(&connection.from),
            dotted(&connection.to)
        );
        match (find(&connection.from), find(&connection.to)) {
            (Err(e), _) | (_, Err(e)) => mistakes.push(format!("{text}: {e}")),
            (Ok((_, from)), Ok((_, to))) => {
                if from.causality != "output" {
                    mistakes.push(format!(
                        "{text}: `{}` is {}, not an output: a connection runs from an output to an input",
                        dotted(&connection.from),
                        causality(&from.causality)
                    ));
                } else if to.causality != "input" {
                    mistakes.push(format!(
                        "{text}: `{}` is {}, not an input: a connection runs from an output to an input",
                        dotted(&connection.to),
                        causality(&to.causality)
                    ));
                } else if let (Some(a), Some(b)) = (&from.unit, &to.unit) {
                    if !units_alike(a, b) {
                        mistakes.push(format!(
                            "{text}: it joins unlike units: `{}` is in `{a}`, `{}` in `{b}`",
                            dotted(&connection.from),
                            dotted(&connection.to)
                        ));
                    }
                }
            }
        }
    }
    for (i, connection) in system.connections.iter().enumerate() {
        let feeding: Vec<String> = (system.connections.iter())
            .filter(|c| c.to == connection.to)
            .map(|c| format!("`{}`", dotted(&c.from)))
            .collect();
        let first = system
            .connections
            .iter()
            .position(|c| c.to == connection.to);
        if feeding.len() > 1 && first == Some(i) {
            mistakes.push(format!(
                "input `{}` is fed by {}: an input takes one output",
                dotted(&connection.to),
                feeding.join(" and ")
            ));
        }
    }
    for set in &system.parameter_sets {
        for (component, variable, _) in &set.values {
            let port = (component.clone(), variable.clone());
            match find(&port) {
                Err(e) => mistakes.push(format!("parameter set `{}`: {e}", set.name)),
                Ok((_, v)) if !settable(v) => mistakes.push(format!(
                    "parameter set `{}`: `{}` is {} the model computes: a parameter set gives parameters, inputs and the start values of states",
                    set.name,
                    dotted(&port),
                    causality(&v.causality)
                )),
                Ok(_) => {}
            }
        }
    }
    if mistakes.is_empty() {
        let connections: Vec<(PortName, PortName)> = (system.connections.iter())
            .map(|c| {
                (
                    (c.from.0.as_str(), c.from.1.as_str()),
                    (c.to.0.as_str(), c.to.1.as_str()),
                )
            })
            .collect();
        let feedthrough: Vec<Feedthrough> = components
            .iter()
            .flat_map(|c| direct_feedthrough(&c.declaration.name, &c.description))
            .collect();
        mistakes.extend(feedthrough_cycle(&connections, &feedthrough));
    }
    if mistakes.is_empty() {
        return Ok(());
    }
    Err(format!(
        "system `{}`:\n  {}",
        system.name,
        mistakes.join("\n  ")
    ))
}

/// For each output of `description`, the inputs it depends on directly: those of its
/// `<ModelStructure>` dependencies, or every input where it lists none.
fn direct_feedthrough<'a>(
    component: &'a str,
    description: &'a ModelDescription,
) -> Vec<Feedthrough<'a>> {
    let inputs: Vec<&str> = description
        .with_causality("input")
        .into_iter()
        .map(|v| v.name.as_str())
        .collect();
    description
        .output_dependencies
        .iter()
        .map(|(output, dependencies)| Feedthrough {
            component,
            output,
            inputs: match dependencies {
                Some(names) => names
                    .iter()
                    .map(String::as_str)
                    .filter(|n| inputs.contains(n))
                    .collect(),
                None => inputs.clone(),
            },
        })
        .collect()
}

/// Whether an importer may set `v` before initialization: a parameter or an input, or a
/// variable with an exact or approximate start value.
fn settable(v: &Variable) -> bool {
    matches!(v.causality.as_str(), "parameter" | "input")
        || matches!(v.initial.as_deref(), Some("exact" | "approx"))
}

/// `an input`, `a calculatedParameter`: a causality with its article.
fn causality(causality: &str) -> String {
    let article = if causality.starts_with(['a', 'e', 'i', 'o', 'u']) {
        "an"
    } else {
        "a"
    };
    format!("{article} {causality}")
}

fn dotted((component, variable): &Port) -> String {
    format!("{component}.{variable}")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::system::{ComponentDeclaration, Connection, Experiment, ParameterSet};
    use std::path::PathBuf;

    /// An FMU file's model description: a gain `y = k u` (direct feedthrough), with a state
    /// `s` that `y` does not follow.
    const GAIN: &str = r#"<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="Gain" guid="{0}">
  <CoSimulation modelIdentifier="Gain"/>
  <ModelVariables>
    <ScalarVariable name="k" valueReference="0" causality="parameter" variability="fixed" initial="exact"><Real start="1"/></ScalarVariable>
    <ScalarVariable name="u" valueReference="1" causality="input"><Real unit="m" start="0"/></ScalarVariable>
    <ScalarVariable name="y" valueReference="2" causality="output"><Real unit="m"/></ScalarVariable>
    <ScalarVariable name="s" valueReference="3" causality="output" initial="exact"><Real unit="m/s" start="0"/></ScalarVariable>
    <ScalarVariable name="g" valueReference="4" causality="calculatedParameter" variability="fixed"><Real/></ScalarVariable>
  </ModelVariables>
  <ModelStructure>
    <Outputs><Unknown index="3" dependencies="1 2"/><Unknown index="4" dependencies=""/></Outputs>
  </ModelStructure>
</fmiModelDescription>"#;

    fn component(name: &str) -> Component {
        Component {
            declaration: ComponentDeclaration {
                name: name.into(),
                description: String::new(),
                model: None,
                fmu: Some("parts/Gain.fmu".into()),
            },
            path: PathBuf::from("parts/Gain.fmu"),
            description: ModelDescription::parse(GAIN).unwrap(),
        }
    }

    fn port(c: &str, v: &str) -> Port {
        (c.into(), v.into())
    }

    fn system(connections: &[(Port, Port)], values: &[(&str, &str, f64)]) -> Declaration {
        Declaration {
            name: "Gains".into(),
            description: String::new(),
            experiment: Experiment {
                start: 0.0,
                stop: 1.0,
                step: 0.1,
                tolerance: 1e-6,
            },
            components: vec![component("p").declaration, component("q").declaration],
            connections: connections
                .iter()
                .map(|(from, to)| Connection {
                    from: from.clone(),
                    to: to.clone(),
                })
                .collect(),
            parameter_sets: vec![ParameterSet {
                name: "default".into(),
                description: String::new(),
                values: values
                    .iter()
                    .map(|(c, v, x)| (c.to_string(), v.to_string(), *x))
                    .collect(),
            }],
        }
    }

    fn errors(connections: &[(Port, Port)], values: &[(&str, &str, f64)]) -> String {
        let components = [component("p"), component("q")];
        match check(&system(connections, values), &components) {
            Ok(()) => String::new(),
            Err(e) => e,
        }
    }

    #[test]
    fn an_fmu_files_variables_are_checked_from_its_model_description() {
        assert_eq!(
            errors(
                &[(port("p", "y"), port("q", "u"))],
                &[("p", "k", 2.0), ("q", "s", 1.0)]
            ),
            ""
        );
        let e = errors(
            &[
                (port("p", "z"), port("q", "u")),
                (port("p", "u"), port("q", "u")),
                (port("p", "s"), port("q", "u")),
                (port("r", "y"), port("q", "k")),
            ],
            &[("p", "g", 1.0)],
        );
        assert!(e.starts_with("system `Gains`:\n"), "{e}");
        for expected in [
            "connection p.z => q.u: component `p` (Gain.fmu) has no variable `z`",
            "connection p.u => q.u: `p.u` is an input, not an output",
            "connection p.s => q.u: it joins unlike units: `p.s` is in `m/s`, `q.u` in `m`",
            "connection r.y => q.k: there is no component `r`",
            "input `q.u` is fed by `p.z` and `p.u` and `p.s`: an input takes one output",
            "parameter set `default`: `p.g` is a calculatedParameter the model computes",
        ] {
            assert!(e.contains(expected), "{expected}\nnot in\n{e}");
        }
    }

    #[test]
    fn a_loop_through_direct_feedthrough_is_refused() {
        let e = errors(
            &[
                (port("p", "y"), port("q", "u")),
                (port("q", "y"), port("p", "u")),
            ],
            &[],
        );
        assert!(
            e.contains("a loop of direct feedthrough")
                && e.contains("`p.y` => `q.u`; `q.y` follows `q.u` at once"),
            "{e}"
        );
    }
}
