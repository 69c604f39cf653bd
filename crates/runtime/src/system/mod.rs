//! Systems of mechanisms: components (mechanisms of the workspace, or FMU files), connections
//! from an output to an input, named parameter sets and a default experiment, declared once
//! with [`system!`](crate::system) and checked at compile time where the declaration can
//! tell (the components' and variables' names, a connection's ends and units, an input
//! connected twice, a parameter set's values). What needs the components' model descriptions
//! (an FMU file's variables, the direct feedthrough that can close a loop) is checked by the
//! `mechfmu` command when it builds the system, with [`feedthrough_cycle`] and the same
//! messages.
//!
//! A system whose components are all mechanisms is also one mechanism (`system!` implements
//! [`Mechanism`] for it: [`composite`] lays out its variables and the order of its equations,
//! [`values`] its values, [`equations`] runs them), which
//! [`export_fmu!`](crate::export_fmu) exports as one FMU.

mod checks;
#[doc(hidden)]
pub mod composite;
mod declare;
#[doc(hidden)]
pub mod equations;
mod graph;
mod json;
#[doc(hidden)]
pub mod values;

pub use checks::{
    binding_mistake, component_mistake, connection_mistake, set_mistake,
    terminal_connection_mistake, units_alike,
};
#[doc(hidden)]
pub use checks::{
    check_binding, check_component, check_connection, check_set, check_terminal_connection,
};
pub use graph::{feedthrough_cycle, Feedthrough, PortName};
pub use json::declaration_json;
pub use values::{Components, SystemValues};

use crate::model::{Causality, Experiment, Mechanism, Terminal, Variable};

/// A system: implemented by [`system!`](crate::system); do not implement it by hand.
pub trait System: Send + Sync + 'static {
    /// What the system is made of.
    const DECLARATION: SystemDeclaration;
}

/// The whole declaration of a system, as [`system!`](crate::system) writes it down.
#[derive(Clone, Copy, Debug)]
pub struct SystemDeclaration {
    pub name: &'static str,
    pub description: &'static str,
    pub components: &'static [Component],
    pub connections: &'static [Connection],
    /// Terminals joined member by member (each member one more connection).
    pub terminal_connections: &'static [TerminalConnection],
    /// Every set is the `default` set (when declared) with its own values over it.
    pub parameter_sets: &'static [ParameterSet],
    pub experiment: Experiment,
}

/// One component of a system, by the name the system gives it.
#[derive(Clone, Copy, Debug)]
pub struct Component {
    pub name: &'static str,
    pub description: &'static str,
    pub source: Source,
}

/// What a component is.
#[derive(Clone, Copy, Debug)]
pub enum Source {
    /// A mechanism: its FMU is the one `mechfmu build` makes of it.
    Mechanism {
        model: &'static str,
        variables: &'static [Variable],
        terminals: &'static [Terminal],
    },
    /// An FMU file, by its path from the system crate's folder; its variables are known
    /// when its model description is read.
    Fmu { path: &'static str },
}

impl Source {
    /// The mechanism `M`.
    pub const fn mechanism<M: Mechanism>() -> Source {
        Source::Mechanism {
            model: M::NAME,
            variables: M::VARIABLES,
            terminals: M::TERMINALS,
        }
    }

    /// The FMU at `path`.
    pub const fn fmu(path: &'static str) -> Source {
        Source::Fmu { path }
    }

    /// The variables, when the declaration knows them (a mechanism's).
    pub const fn variables(&self) -> Option<&'static [Variable]> {
        match *self {
            Source::Mechanism { variables, .. } => Some(variables),
            Source::Fmu { .. } => None,
        }
    }
}

/// A variable of a component: `component.variable`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Port {
    pub component: &'static str,
    pub variable: &'static str,
}

/// An output feeding an input.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Connection {
    pub from: Port,
    pub to: Port,
}

/// Two terminals joined: each member of one to the member of the same name of the other,
/// from the one that is an output to the one that is an input.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct TerminalConnection {
    /// `component.terminal`.
    pub a: Port,
    pub b: Port,
}

/// A named set of values for the components' parameters and start values.
#[derive(Clone, Copy, Debug)]
pub struct ParameterSet {
    pub name: &'static str,
    pub description: &'static str,
    pub values: &'static [Binding],
}

/// One value of a parameter set.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Binding {
    pub port: Port,
    pub value: f64,
}

/// The name of the parameter set the others start from, and that an importer applies when
/// none is chosen.
pub const DEFAULT_SET: &str = "default";

impl SystemDeclaration {
    /// The component called `name`.
    pub fn component(&self, name: &str) -> Option<&Component> {
        self.components.iter().find(|c| c.name == name)
    }

    /// The values of the parameter set `name` as applied: the `default` set's, then the
    /// set's own over them, in the order first declared. `None` for an unknown set; the
    /// `default` set is known even when not declared (then it is empty).
    pub fn resolved_set(&self, name: &str) -> Option<Vec<Binding>> {
        let find = |n: &str| self.parameter_sets.iter().find(|s| s.name == n);
        let own = find(name);
        if own.is_none() && name != DEFAULT_SET {
            return None;
        }
        let mut values: Vec<Binding> = Vec::new();
        for set in [find(DEFAULT_SET), own].into_iter().flatten() {
            for binding in set.values {
                match values.iter_mut().find(|b| b.port == binding.port) {
                    Some(existing) => existing.value = binding.value,
                    None => values.push(*binding),
                }
            }
        }
        Some(values)
    }

    /// Every connection: those declared, then each terminal connection's, member by member
    /// (a terminal connection whose terminals are not known, or do not match, gives none:
    /// `system!` refuses it at compile time).
    pub fn all_connections(&self) -> Vec<Connection> {
        let mut all = self.connections.to_vec();
        for joined in self.terminal_connections {
            all.extend(
                (0..joined_members(self, joined))
                    .filter_map(|k| member_connection(self, joined, k)),
            );
        }
        all
    }

    /// The names of the parameter sets, `default` first (also when not declared).
    pub fn set_names(&self) -> Vec<&'static str> {
        let mut names = vec![DEFAULT_SET];
        names.extend(
            self.parameter_sets
                .iter()
                .map(|s| s.name)
                .filter(|n| *n != DEFAULT_SET),
        );
        names
    }
}

/// How many members the terminals of `joined` have (0 when either is not known).
pub(crate) const fn joined_members(
    system: &SystemDeclaration,
    joined: &TerminalConnection,
) -> usize {
    match terminal_of(system, joined.a) {
        Some((terminal, _)) => terminal.members.len(),
        None => 0,
    }
}

/// The connection member `k` of `joined` makes, from its output to its input (`None` where
/// the terminals do not match).
pub(crate) const fn member_connection(
    system: &SystemDeclaration,
    joined: &TerminalConnection,
    k: usize,
) -> Option<Connection> {
    let (Some((ta, va)), Some((tb, vb))) =
        (terminal_of(system, joined.a), terminal_of(system, joined.b))
    else {
        return None;
    };
    if k >= ta.members.len() {
        return None;
    }
    let (member, variable_a) = ta.members[k];
    let Some(variable_b) = tb.variable_of(member) else {
        return None;
    };
    let (Some(a), Some(b)) = (
        crate::model::variable_position(va, variable_a),
        crate::model::variable_position(vb, variable_b),
    ) else {
        return None;
    };
    let port_a = Port {
        component: joined.a.component,
        variable: variable_a,
    };
    let port_b = Port {
        component: joined.b.component,
        variable: variable_b,
    };
    match (va[a].causality, vb[b].causality) {
        (Causality::Output, Causality::Input) => Some(Connection {
            from: port_a,
            to: port_b,
        }),
        (Causality::Input, Causality::Output) => Some(Connection {
            from: port_b,
            to: port_a,
        }),
        _ => None,
    }
}

/// The terminal `port` names (`component.terminal`) and its component's variables.
pub(crate) const fn terminal_of(
    system: &SystemDeclaration,
    port: Port,
) -> Option<(Terminal, &'static [Variable])> {
    let mut i = 0;
    while i < system.components.len() {
        let component = &system.components[i];
        if crate::model::str_eq(component.name, port.component) {
            return match component.source {
                Source::Mechanism {
                    variables,
                    terminals,
                    ..
                } => match crate::model::terminal_named(terminals, port.variable) {
                    Some(terminal) => Some((terminal, variables)),
                    None => None,
                },
                Source::Fmu { .. } => None,
            };
        }
        i += 1;
    }
    None
}

#[cfg(test)]
mod tests;

#[cfg(test)]
mod composite_tests;
