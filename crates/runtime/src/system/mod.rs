//! Systems of mechanisms: components (mechanisms of the workspace, or FMU files), connections
//! from an output to an input, named parameter sets and a default experiment, declared once
//! with [`system!`](crate::system) and checked at compile time where the declaration can
//! tell (the components' and variables' names, a connection's ends and units, an input
//! connected twice, a parameter set's values). What needs the components' model descriptions
//! (an FMU file's variables, the direct feedthrough that can close a loop) is checked by the
//! `mechfmu` command when it builds the system, with [`feedthrough_cycle`] and the same
//! messages.

mod checks;
mod declare;
mod graph;
mod json;

pub use checks::{
    binding_mistake, component_mistake, connection_mistake, set_mistake, units_alike,
};
#[doc(hidden)]
pub use checks::{check_binding, check_component, check_connection, check_set};
pub use graph::{feedthrough_cycle, Feedthrough, PortName};
pub use json::declaration_json;

use crate::model::{Declaration, Experiment, Variable};

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
    },
    /// An FMU file, by its path from the system crate's folder; its variables are known
    /// when its model description is read.
    Fmu { path: &'static str },
}

impl Source {
    /// The mechanism `M`.
    pub const fn mechanism<M: Declaration>() -> Source {
        Source::Mechanism {
            model: M::NAME,
            variables: M::VARIABLES,
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

#[cfg(test)]
mod tests;
