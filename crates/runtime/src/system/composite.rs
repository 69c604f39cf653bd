//! A system as one mechanism, worked out at compile time from its declaration: its variables
//! (every component's, named `component.variable`, an input fed by a connection turned into a
//! local variable that the connection computes, the `default` parameter set as start values)
//! and the order its equations are evaluated in ([`Step`]).
//!
//! The order: a component's equations run once the values its connected inputs come from are
//! known. A state or a parameter is known before any equation runs; any other output is known
//! once its component's equations have run. So the two shipped systems evaluate the
//! stateless element first (its inputs are the bodies' states), then the bodies (their inputs
//! are its outputs). When no such order exists (a component's output that does not follow its
//! inputs at once feeding, through others, its own inputs), every component is evaluated once
//! per component, in the order declared: each round makes one more link of every chain of
//! connections exact, and no chain is longer than the components (a chain that closes on
//! itself is a loop of direct feedthrough, refused at the declaration).

use super::checks::component_position;
use super::{member_connection, Connection, Port, Source, SystemDeclaration, DEFAULT_SET};
use crate::model::{str_eq, variable_position, Causality, Initial, Variability, Variable};

/// One thing the system's evaluation does, in order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Step {
    /// The value of `from` into `to` (the system's value references): a connection.
    Copy { from: usize, to: usize },
    /// Component `component`'s equations, and its outputs too when `outputs` (an output of
    /// it feeds another component's input).
    Evaluate { component: usize, outputs: bool },
}

/// The variables of component `k` (none for an FMU file's: such a system has no FMU).
const fn variables_of(system: &SystemDeclaration, k: usize) -> &'static [Variable] {
    match system.components[k].source {
        Source::Mechanism { variables, .. } => variables,
        Source::Fmu { .. } => &[],
    }
}

/// Whether every component is a mechanism (a system with an FMU file among its components
/// cannot be compiled into one FMU).
pub const fn all_mechanisms(system: &SystemDeclaration) -> bool {
    let mut k = 0;
    while k < system.components.len() {
        if let Source::Fmu { .. } = system.components[k].source {
            return false;
        }
        k += 1;
    }
    true
}

/// The number of variables: every component's.
pub const fn variable_count(system: &SystemDeclaration) -> usize {
    offset(system, system.components.len())
}

/// The value reference of component `k`'s first variable.
const fn offset(system: &SystemDeclaration, k: usize) -> usize {
    let (mut i, mut n) = (0, 0);
    while i < k {
        n += variables_of(system, i).len();
        i += 1;
    }
    n
}

/// The system's value reference of `port` (`component.variable`).
pub const fn reference(system: &SystemDeclaration, port: Port) -> Option<usize> {
    let Some(k) = component_position(system, port.component) else {
        return None;
    };
    match variable_position(variables_of(system, k), port.variable) {
        Some(j) => Some(offset(system, k) + j),
        None => None,
    }
}

/// The number of connections: those declared, then each terminal connection's members.
pub const fn connection_count(system: &SystemDeclaration) -> usize {
    let (mut t, mut n) = (0, system.connections.len());
    while t < system.terminal_connections.len() {
        n += super::joined_members(system, &system.terminal_connections[t]);
        t += 1;
    }
    n
}

/// Connection `i`, counted as [`connection_count`] counts them.
const fn connection(system: &SystemDeclaration, i: usize) -> Option<Connection> {
    if i < system.connections.len() {
        return Some(system.connections[i]);
    }
    let (mut i, mut t) = (i - system.connections.len(), 0);
    while t < system.terminal_connections.len() {
        let joined = &system.terminal_connections[t];
        let n = super::joined_members(system, joined);
        if i < n {
            return member_connection(system, joined, i);
        }
        i -= n;
        t += 1;
    }
    None
}

/// The number of bytes of every variable's name, `component.variable`.
pub const fn names_len(system: &SystemDeclaration) -> usize {
    name_start(system, system.components.len(), 0)
}

/// Where the name of component `k`'s variable `j` starts among the names.
const fn name_start(system: &SystemDeclaration, k: usize, j: usize) -> usize {
    let (mut c, mut n) = (0, 0);
    while c <= k && c < system.components.len() {
        let variables = variables_of(system, c);
        let last = if c == k { j } else { variables.len() };
        let mut v = 0;
        while v < last {
            n += system.components[c].name.len() + 1 + variables[v].name.len();
            v += 1;
        }
        c += 1;
    }
    n
}

/// Every variable's name, `component.variable`, one after the other (`L` is [`names_len`]).
pub const fn names<const L: usize>(system: &SystemDeclaration) -> [u8; L] {
    let mut out = [0u8; L];
    let (mut k, mut at) = (0, 0);
    while k < system.components.len() {
        let component = system.components[k].name.as_bytes();
        let variables = variables_of(system, k);
        let mut j = 0;
        while j < variables.len() {
            at = copy(&mut out, at, component);
            out[at] = b'.';
            at = copy(&mut out, at + 1, variables[j].name.as_bytes());
            j += 1;
        }
        k += 1;
    }
    out
}

/// `from` into `out` at `at`; where it ends.
const fn copy<const L: usize>(out: &mut [u8; L], at: usize, from: &[u8]) -> usize {
    let mut i = 0;
    while i < from.len() {
        out[at + i] = from[i];
        i += 1;
    }
    at + from.len()
}

/// The name of component `k`'s variable `j` among `names` (what [`names`] wrote).
const fn name_of(
    names: &'static [u8],
    system: &SystemDeclaration,
    k: usize,
    j: usize,
) -> &'static str {
    let len = system.components[k].name.len() + 1 + variables_of(system, k)[j].name.len();
    let (_, rest) = names.split_at(name_start(system, k, j));
    let (name, _) = rest.split_at(len);
    match core::str::from_utf8(name) {
        Ok(name) => name,
        Err(_) => panic!("a variable's name is not UTF-8"),
    }
}

/// Whether component `k`'s variable `j` is an input that a connection feeds.
const fn connected_input(system: &SystemDeclaration, k: usize, j: usize) -> bool {
    let name = variables_of(system, k)[j].name;
    let mut i = 0;
    while i < connection_count(system) {
        if let Some(c) = connection(system, i) {
            if str_eq(c.to.component, system.components[k].name) && str_eq(c.to.variable, name) {
                return true;
            }
        }
        i += 1;
    }
    false
}

/// The `default` parameter set's value for component `k`'s variable `j`, if it has one.
const fn default_value(system: &SystemDeclaration, k: usize, j: usize) -> Option<f64> {
    let name = variables_of(system, k)[j].name;
    let mut s = 0;
    while s < system.parameter_sets.len() {
        let set = &system.parameter_sets[s];
        if str_eq(set.name, DEFAULT_SET) {
            let mut b = 0;
            while b < set.values.len() {
                let port = set.values[b].port;
                if str_eq(port.component, system.components[k].name) && str_eq(port.variable, name)
                {
                    return Some(set.values[b].value);
                }
                b += 1;
            }
        }
        s += 1;
    }
    None
}

/// The system's variables (`N` is [`variable_count`]), named from `names` (what [`names`]
/// wrote): each component's, in the order declared, an input a connection feeds turned into
/// a local variable (the connection computes it), the `default` set's values as start values.
pub const fn variables<const N: usize>(
    system: &SystemDeclaration,
    names: &'static [u8],
) -> [Variable; N] {
    let mut out = [Variable::local("1"); N];
    let mut k = 0;
    while k < system.components.len() {
        let variables = variables_of(system, k);
        let mut j = 0;
        while j < variables.len() {
            let mut v = variables[j];
            v.name = name_of(names, system, k, j);
            if let Some(derivative) = v.derivative {
                v.derivative = match variable_position(variables, derivative) {
                    Some(d) => Some(name_of(names, system, k, d)),
                    None => panic!("a state's derivative is not a variable of its mechanism"),
                };
            }
            if connected_input(system, k, j) {
                v.causality = Causality::Local;
                v.variability = Variability::Continuous;
                v.initial = Some(Initial::Calculated);
                v.start = None;
            } else if let Some(value) = default_value(system, k, j) {
                v.start = Some(value);
            }
            out[offset(system, k) + j] = v;
            j += 1;
        }
        k += 1;
    }
    out
}

/// Whether the value of `port` is known before any equation runs: a state's, or a value
/// that does not change during a step (a parameter).
const fn known_before_evaluation(system: &SystemDeclaration, port: Port) -> bool {
    let Some(k) = component_position(system, port.component) else {
        return false;
    };
    let variables = variables_of(system, k);
    match variable_position(variables, port.variable) {
        Some(j) => {
            let v = &variables[j];
            v.derivative.is_some() || !matches!(v.variability, Variability::Continuous)
        }
        None => false,
    }
}

/// Whether an output of component `k` that only its equations compute feeds another
/// component: then its outputs are computed with its derivatives.
const fn feeds_others(system: &SystemDeclaration, k: usize) -> bool {
    let mut i = 0;
    while i < connection_count(system) {
        if let Some(c) = connection(system, i) {
            if str_eq(c.from.component, system.components[k].name)
                && !known_before_evaluation(system, c.from)
            {
                return true;
            }
        }
        i += 1;
    }
    false
}

/// The order of evaluation, one component at a time, as a bit per component: `None` when
/// none exists (see the module's documentation).
const fn order(system: &SystemDeclaration) -> Option<[usize; 64]> {
    let n = system.components.len();
    assert!(
        n <= 64,
        "a system compiled into one FMU has at most 64 components"
    );
    let mut out = [0usize; 64];
    let mut done: u64 = 0;
    let mut placed = 0;
    while placed < n {
        // the first component whose connected inputs all come from known values
        let mut k = 0;
        let mut found = n;
        while k < n && found == n {
            if done & (1u64 << k) == 0 && inputs_known(system, k, done) {
                found = k;
            }
            k += 1;
        }
        if found == n {
            return None;
        }
        out[placed] = found;
        done |= 1u64 << found;
        placed += 1;
    }
    Some(out)
}

/// Whether every connected input of component `k` comes from a value known once the
/// components of `done` have been evaluated.
const fn inputs_known(system: &SystemDeclaration, k: usize, done: u64) -> bool {
    let mut i = 0;
    while i < connection_count(system) {
        if let Some(c) = connection(system, i) {
            if str_eq(c.to.component, system.components[k].name)
                && !known_before_evaluation(system, c.from)
            {
                match component_position(system, c.from.component) {
                    Some(source) if done & (1u64 << source) != 0 => {}
                    _ => return false,
                }
            }
        }
        i += 1;
    }
    true
}

/// The number of connections into component `k`.
const fn inputs_of(system: &SystemDeclaration, k: usize) -> usize {
    let (mut i, mut n) = (0, 0);
    while i < connection_count(system) {
        if let Some(c) = connection(system, i) {
            if str_eq(c.to.component, system.components[k].name) {
                n += 1;
            }
        }
        i += 1;
    }
    n
}

/// The number of [`Step`]s of the system's evaluation.
pub const fn plan_len(system: &SystemDeclaration) -> usize {
    let n = system.components.len();
    let rounds = match order(system) {
        Some(_) => 1,
        None => n,
    };
    let (mut k, mut steps) = (0, 0);
    while k < n {
        steps += inputs_of(system, k) + 1;
        k += 1;
    }
    steps * rounds
}

/// The system's evaluation (`P` is [`plan_len`]): for each component in order, the
/// connections into it, then its equations.
pub const fn plan<const P: usize>(system: &SystemDeclaration) -> [Step; P] {
    let n = system.components.len();
    let (order, rounds) = match order(system) {
        Some(order) => (order, 1),
        None => {
            let mut declared = [0usize; 64];
            let mut k = 0;
            while k < n {
                declared[k] = k;
                k += 1;
            }
            (declared, n)
        }
    };
    let mut out = [Step::Evaluate {
        component: 0,
        outputs: false,
    }; P];
    let (mut at, mut round) = (0, 0);
    while round < rounds {
        let mut position = 0;
        while position < n {
            let k = order[position];
            let mut i = 0;
            while i < connection_count(system) {
                if let Some(c) = connection(system, i) {
                    if str_eq(c.to.component, system.components[k].name) {
                        let (Some(from), Some(to)) =
                            (reference(system, c.from), reference(system, c.to))
                        else {
                            panic!("a connection names a variable no component has");
                        };
                        out[at] = Step::Copy { from, to };
                        at += 1;
                    }
                }
                i += 1;
            }
            out[at] = Step::Evaluate {
                component: k,
                outputs: feeds_others(system, k),
            };
            at += 1;
            position += 1;
        }
        round += 1;
    }
    out
}

/// The number of event indicators of the components (`lists`, one per component).
pub const fn event_indicator_count(lists: &[&[&str]]) -> usize {
    let (mut k, mut n) = (0, 0);
    while k < lists.len() {
        n += lists[k].len();
        k += 1;
    }
    n
}

/// The components' event indicators (`lists`, one per component, `E` in all) by the
/// system's names of their variables (`variables`, what [`variables`] made).
pub const fn event_indicators<const E: usize>(
    system: &SystemDeclaration,
    lists: &[&[&'static str]],
    variables: &'static [Variable],
) -> [&'static str; E] {
    let mut out = [""; E];
    let (mut k, mut at) = (0, 0);
    while k < lists.len() {
        let mut i = 0;
        while i < lists[k].len() {
            let port = Port {
                component: system.components[k].name,
                variable: lists[k][i],
            };
            out[at] = match reference(system, port) {
                Some(vr) => variables[vr].name,
                None => panic!("an event indicator is not a variable of its mechanism"),
            };
            at += 1;
            i += 1;
        }
        k += 1;
    }
    out
}
