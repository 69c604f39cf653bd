use super::*;
use crate::model::{Experiment, Mechanism, Scalar, Terminal, Variable, TRANSLATIONAL};

crate::mechanism! {
    /// A mass on a spring, pushed by a force.
    pub struct Body / BodyValues {
        /// Mass
        m: Variable::parameter("kg", 1.0).positive(),
        /// Force
        F: Variable::input("N", 0.0),
        /// Position
        x: Variable::state("m", 1.0, "v"),
        /// Velocity
        v: Variable::state("m/s", 0.0, "a"),
        /// Acceleration
        a: Variable::output("m/s2"),
        /// Weight
        w: Variable::calculated("N"),
    }
}

impl Mechanism for Body {
    const EXPERIMENT: Experiment = Experiment::until(1.0);
    const TERMINALS: &'static [Terminal] = &[
        Terminal::new("flange", TRANSLATIONAL, "", &[("s", "x"), ("f", "F")]),
        Terminal::new("speed", TRANSLATIONAL, "", &[("s", "v"), ("f", "F")]),
    ];
    fn evaluate<S: Scalar>(v: &mut BodyValues<S>) {
        v.a = v.F / v.m;
    }
}

crate::mechanism! {
    /// A spring between two points.
    pub struct Link / LinkValues {
        /// Stiffness
        k: Variable::tunable("N/m", 1.0).min(0.0),
        /// Position of a
        x_a: Variable::input("m", 0.0),
        /// Position of b
        x_b: Variable::input("m", 0.0),
        /// Force on a
        F_a: Variable::output("N"),
        /// Force on b
        F_b: Variable::output("N"),
    }
}

impl Mechanism for Link {
    const EXPERIMENT: Experiment = Experiment::until(1.0);
    const TERMINALS: &'static [Terminal] = &[
        Terminal::new("a", TRANSLATIONAL, "", &[("s", "x_a"), ("f", "F_a")]),
        Terminal::new("b", TRANSLATIONAL, "", &[("s", "x_b"), ("f", "F_b")]),
        Terminal::new("both", "other", "", &[("s", "x_a")]),
    ];
    fn evaluate<S: Scalar>(v: &mut LinkValues<S>) {
        v.F_a = v.k * (v.x_b - v.x_a);
        v.F_b = -v.F_a;
    }
}

crate::system! {
    /// Two bodies joined by a link.
    pub struct Pair {
        components {
            /// The first body
            a: Body,
            /// The link
            link: Link,
            /// The second body
            b: Body,
            /// An FMU file
            extra: fmu("parts/Extra.fmu"),
        }
        connections {
            a.x => link.x_a,
            b.x => link.x_b,
            link.F_a => a.F,
            link.F_b => b.F,
        }
        parameter_sets {
            /// The defaults
            default { b.x = 0.0, link.k = 2.0 }
            /// Heavier
            heavy { b.m = 3.0, link.k = 5.0 }
        }
        experiment: Experiment::until(10.0).step(0.01),
    }
}

const fn port(component: &'static str, variable: &'static str) -> Port {
    Port {
        component,
        variable,
    }
}

#[test]
fn the_declaration_is_written_down_as_declared() {
    let d = Pair::DECLARATION;
    assert_eq!(
        (d.name, d.description.trim()),
        ("Pair", "Two bodies joined by a link.")
    );
    let names: Vec<_> = d.components.iter().map(|c| c.name).collect();
    assert_eq!(names, ["a", "link", "b", "extra"]);
    assert!(matches!(
        d.components[0].source,
        Source::Mechanism { model: "Body", .. }
    ));
    assert!(matches!(
        d.components[3].source,
        Source::Fmu {
            path: "parts/Extra.fmu"
        }
    ));
    assert_eq!(d.components[1].description.trim(), "The link");
    assert_eq!(d.connections[2].from, port("link", "F_a"));
    assert_eq!(d.connections[2].to, port("a", "F"));
    assert_eq!(d.experiment.step, 0.01);
}

#[test]
fn a_set_is_the_default_set_with_its_own_values_over_it() {
    let d = Pair::DECLARATION;
    let heavy = d.resolved_set("heavy").unwrap();
    let values: Vec<_> = heavy
        .iter()
        .map(|b| (b.port.component, b.port.variable, b.value))
        .collect();
    assert_eq!(
        values,
        [("b", "x", 0.0), ("link", "k", 5.0), ("b", "m", 3.0)]
    );
    assert_eq!(d.resolved_set("default").unwrap().len(), 2);
    assert!(d.resolved_set("light").is_none());
    assert_eq!(d.set_names(), ["default", "heavy"]);
}

/// The declaration with one connection or value changed, for the checks' messages.
fn with_connections(connections: &[Connection]) -> SystemDeclaration {
    SystemDeclaration {
        connections: leak(connections),
        ..Pair::DECLARATION
    }
}

/// A `'static` copy, as a declaration holds.
fn leak<T: Clone>(items: &[T]) -> &'static [T] {
    Box::leak(items.to_vec().into_boxed_slice())
}

fn connection_error(connections: &[Connection], index: usize) -> String {
    connection_mistake(&with_connections(connections), index)
        .map(|m| m.as_str().to_string())
        .unwrap_or_default()
}

#[test]
fn a_connection_names_what_is_wrong_with_it() {
    let unknown_component = &[Connection {
        from: port("a", "x"),
        to: port("lnk", "x_a"),
    }];
    assert_eq!(
        connection_error(unknown_component, 0),
        "system!: connection a.x => lnk.x_a: there is no component `lnk` (did you mean `link`?)"
    );
    let unknown_variable = &[Connection {
        from: port("a", "xx"),
        to: port("link", "x_a"),
    }];
    assert_eq!(
        connection_error(unknown_variable, 0),
        "system!: connection a.xx => link.x_a: component `a` (Body) has no variable `xx` (did you mean `x`?)"
    );
    let backwards = &[Connection {
        from: port("a", "F"),
        to: port("link", "x_a"),
    }];
    assert!(connection_error(backwards, 0).ends_with(
        "`a.F` is an input, not an output: a connection runs from an output to an input"
    ));
    let into_output = &[Connection {
        from: port("a", "x"),
        to: port("link", "F_a"),
    }];
    assert!(connection_error(into_output, 0).contains("`link.F_a` is an output, not an input"));
    let unlike = &[Connection {
        from: port("a", "v"),
        to: port("link", "x_a"),
    }];
    assert!(connection_error(unlike, 0)
        .ends_with("it joins unlike units: `a.v` is in `m/s`, `link.x_a` in `m`"));
    let twice = &[
        Connection {
            from: port("a", "x"),
            to: port("link", "x_a"),
        },
        Connection {
            from: port("b", "x"),
            to: port("link", "x_a"),
        },
    ];
    for i in 0..2 {
        assert!(connection_error(twice, i)
            .ends_with("input `link.x_a` is fed by `a.x` and `b.x`: an input takes one output"));
    }
    // an FMU file's variables are the command's to check
    let foreign = &[Connection {
        from: port("extra", "anything"),
        to: port("a", "F"),
    }];
    assert_eq!(connection_error(foreign, 0), "");
    for i in 0..Pair::DECLARATION.connections.len() {
        assert!(connection_mistake(&Pair::DECLARATION, i).is_none());
    }
}

#[test]
fn a_value_names_what_is_wrong_with_it() {
    fn error(values: &[Binding]) -> String {
        let values = leak(values);
        let sets = leak(&[ParameterSet {
            name: "default",
            description: "",
            values,
        }]);
        let system = SystemDeclaration {
            parameter_sets: sets,
            ..Pair::DECLARATION
        };
        (0..values.len())
            .filter_map(|i| binding_mistake(&system, 0, i))
            .map(|m| m.as_str().to_string())
            .next()
            .unwrap_or_default()
    }
    let value = |c, v, value| Binding {
        port: port(c, v),
        value,
    };
    assert_eq!(
        error(&[value("a", "a", 1.0)]),
        "system!: parameter set `default`: `a.a` is an output the model computes: a parameter set gives parameters, inputs and the start values of states"
    );
    assert!(error(&[value("a", "w", 1.0)]).contains("is a calculatedParameter the model computes"));
    assert!(
        error(&[value("a", "m", 0.0)]).ends_with("`a.m` is given a value not > 0, as it must be")
    );
    assert!(error(&[value("link", "k", -1.0)]).ends_with("below the variable's minimum"));
    assert!(error(&[value("a", "m", f64::NAN)]).ends_with("not a finite number"));
    assert!(error(&[value("a", "m", 2.0), value("a", "m", 3.0)])
        .ends_with("`a.m` is given a value twice"));
    assert!(error(&[value("c", "m", 2.0)]).contains("there is no component `c`"));
    // a state's start value, an input and a tunable parameter are settable
    assert_eq!(
        error(&[
            value("a", "x", 0.0),
            value("a", "F", 1.0),
            value("link", "k", 0.0)
        ]),
        ""
    );
}

#[test]
fn components_and_sets_declared_twice_are_named() {
    let components = leak(&[
        Pair::DECLARATION.components[0],
        Pair::DECLARATION.components[0],
        Component {
            name: "f",
            description: "",
            source: Source::fmu("f.zip"),
        },
    ]);
    let system = SystemDeclaration {
        components,
        ..Pair::DECLARATION
    };
    assert_eq!(
        component_mistake(&system, 1).unwrap().as_str(),
        "system!: component `a` is declared twice: give each component its own name"
    );
    assert_eq!(
        component_mistake(&system, 2).unwrap().as_str(),
        "system!: component `f`: `f.zip` is not an FMU file (`*.fmu`)"
    );
    let sets = leak(&[
        Pair::DECLARATION.parameter_sets[1],
        Pair::DECLARATION.parameter_sets[1],
    ]);
    let system = SystemDeclaration {
        parameter_sets: sets,
        ..Pair::DECLARATION
    };
    assert!(set_mistake(&system, 0)
        .unwrap()
        .as_str()
        .contains("`heavy` is declared twice"));
}

#[test]
fn a_loop_of_direct_feedthrough_is_named_port_by_port() {
    // the link's forces follow its positions at once; the bodies' positions are states
    let connections = [(("a", "x"), ("link", "x_a")), (("link", "F_a"), ("a", "F"))];
    let link = Feedthrough {
        component: "link",
        output: "F_a",
        inputs: vec!["x_a", "x_b"],
    };
    assert_eq!(
        feedthrough_cycle(&connections, std::slice::from_ref(&link)),
        None
    );
    // a body whose acceleration is fed back as the link's position: a loop
    let looped = [(("a", "a"), ("link", "x_a")), (("link", "F_a"), ("a", "F"))];
    let body = Feedthrough {
        component: "a",
        output: "a",
        inputs: vec!["F"],
    };
    let message = feedthrough_cycle(&looped, &[link, body]).unwrap();
    assert!(
        message.contains("`a.a` => `link.x_a`; `link.F_a` follows `link.x_a` at once; `link.F_a` => `a.F`; `a.a` follows `a.F` at once"),
        "{message}"
    );
}

#[test]
fn the_json_holds_every_part_of_the_declaration() {
    let json = declaration_json(&Pair::DECLARATION).unwrap();
    assert!(json.starts_with("{\"name\":\"Pair\",\"description\":\"Two bodies joined by a link.\",\"experiment\":{\"start\":0.0,\"stop\":10.0,\"step\":0.01,\"tolerance\":1e-6},"), "{json}");
    assert!(json.contains(
        "{\"name\":\"extra\",\"description\":\"An FMU file\",\"fmu\":\"parts/Extra.fmu\"}"
    ));
    assert!(json.contains("{\"from\":[\"link\",\"F_b\"],\"to\":[\"b\",\"F\"]}"));
    assert!(json.contains("{\"name\":\"heavy\",\"description\":\"Heavier\",\"values\":[[\"b\",\"x\",0.0],[\"link\",\"k\",5.0],[\"b\",\"m\",3.0]]}"));
}

crate::system! {
    /// The pair joined terminal to terminal.
    pub struct Joined {
        components {
            a: Body,
            link: Link,
            b: Body,
        }
        connections {}
        terminals {
            a.flange <=> link.a,
            link.b <=> b.flange,
        }
        experiment: Experiment::until(1.0),
    }
}

#[test]
fn terminals_join_member_by_member_from_output_to_input() {
    let all: Vec<_> = Joined::DECLARATION
        .all_connections()
        .iter()
        .map(|c| {
            (
                c.from.component,
                c.from.variable,
                c.to.component,
                c.to.variable,
            )
        })
        .collect();
    assert_eq!(
        all,
        [
            ("a", "x", "link", "x_a"),
            ("link", "F_a", "a", "F"),
            ("b", "x", "link", "x_b"),
            ("link", "F_b", "b", "F"),
        ]
    );
    assert!(declaration_json(&Joined::DECLARATION)
        .unwrap()
        .contains("{\"from\":[\"link\",\"F_b\"],\"to\":[\"b\",\"F\"]}"));
}

#[test]
fn a_terminal_connection_names_what_is_wrong_with_it() {
    let error = |a: Port, b: Port, extra: &[Connection]| -> String {
        let system = SystemDeclaration {
            connections: leak(extra),
            terminal_connections: leak(&[TerminalConnection { a, b }]),
            ..Joined::DECLARATION
        };
        terminal_connection_mistake(&system, 0)
            .map(|m| m.as_str().to_string())
            .unwrap_or_default()
    };
    assert_eq!(error(port("a", "flange"), port("link", "a"), &[]), "");
    assert!(error(port("a", "flange"), port("link", "both"), &[])
        .ends_with("terminals of different kinds, `org.mechfmu.translational` and `other`"));
    assert!(error(port("a", "flange"), port("link", "c"), &[])
        .ends_with("`link.c` is no terminal of a mechanism (an FMU file's terminals are not known: connect its variables)"));
    assert!(
        error(port("q", "flange"), port("link", "a"), &[]).ends_with("there is no component `q`")
    );
    assert!(
        error(port("a", "flange"), port("b", "flange"), &[]).ends_with(
            "member `s` joins an output to an output: a member joins an output to an input"
        )
    );
    assert!(error(port("a", "speed"), port("link", "a"), &[])
        .ends_with("member `s` joins unlike units, `m/s` and `m`"));
    let also = [Connection {
        from: port("b", "x"),
        to: port("link", "x_a"),
    }];
    assert!(error(port("a", "flange"), port("link", "a"), &also)
        .ends_with("input `link.x_a` is fed by `b.x` and `a.x`: an input takes one output"));
}
