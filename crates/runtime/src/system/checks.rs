//! The checks of a system declaration that run at compile time (`system!` runs each at the
//! line it is about), in words that name what is wrong: a component, connection, parameter
//! set or value. They know a mechanism's variables from its declaration; an FMU file's are
//! checked by the `mechfmu` command, which reads them.

use super::{joined_members, member_connection, terminal_of, Connection, Port, SystemDeclaration};
use crate::model::units::{base_units, BaseUnit};
use crate::model::{
    closest_name, edit_distance, str_eq, variable_position, Causality, ConstMessage, SetPhase,
    Variable,
};

/// What is wrong with component `index`: another component has its name, or
/// its FMU file is not named `*.fmu`.
pub const fn component_mistake(system: &SystemDeclaration, index: usize) -> Option<ConstMessage> {
    let component = &system.components[index];
    let mut m = ConstMessage::new();
    m.push("system!: component ").quoted(component.name);
    let mut same = 0;
    let mut i = 0;
    while i < system.components.len() {
        if str_eq(system.components[i].name, component.name) {
            same += 1;
        }
        i += 1;
    }
    if same > 1 {
        m.push(" is declared twice: give each component its own name");
        return Some(m);
    }
    if let super::Source::Fmu { path } = component.source {
        if !ends_with(path, ".fmu") {
            m.push(": ")
                .quoted(path)
                .push(" is not an FMU file (`*.fmu`)");
            return Some(m);
        }
    }
    None
}

/// What is wrong with connection `index`: an end that names no component or no variable of
/// it, a start that is not an output or an end that is not an input, unlike units, or an
/// input that another connection feeds too.
pub const fn connection_mistake(system: &SystemDeclaration, index: usize) -> Option<ConstMessage> {
    let connection = &system.connections[index];
    let mut m = ConstMessage::new();
    m.push("system!: connection ");
    port_text(&mut m, connection.from);
    m.push(" => ");
    port_text(&mut m, connection.to);
    m.push(": ");
    let from = match resolve(system, connection.from, &mut m) {
        Ok(from) => from,
        Err(()) => return Some(m),
    };
    let to = match resolve(system, connection.to, &mut m) {
        Ok(to) => to,
        Err(()) => return Some(m),
    };
    if let Some(from) = from {
        if !matches!(from.causality, Causality::Output) {
            quoted_port(&mut m, connection.from)
                .push(" is ")
                .push(article(from.causality))
                .push(from.causality.as_str())
                .push(", not an output: a connection runs from an output to an input");
            return Some(m);
        }
    }
    if let Some(to) = to {
        if !matches!(to.causality, Causality::Input) {
            quoted_port(&mut m, connection.to)
                .push(" is ")
                .push(article(to.causality))
                .push(to.causality.as_str())
                .push(", not an input: a connection runs from an output to an input");
            return Some(m);
        }
    }
    if let (Some(from), Some(to)) = (from, to) {
        if !units_alike(from.unit, to.unit) {
            m.push("it joins unlike units: ");
            quoted_port(&mut m, connection.from)
                .push(" is in ")
                .quoted(from.unit)
                .push(", ");
            quoted_port(&mut m, connection.to)
                .push(" in ")
                .quoted(to.unit);
            return Some(m);
        }
    }
    if fed_twice(system, connection.to, &mut m) {
        return Some(m);
    }
    None
}

/// Whether more than one connection (a terminal's members among them) feeds `input`: then
/// `m` names them all.
const fn fed_twice(system: &SystemDeclaration, input: Port, m: &mut ConstMessage) -> bool {
    let feeding = feeders(system, input, None);
    if feeding <= 1 {
        return false;
    }
    m.push("input ");
    quoted_port(m, input).push(" is fed by ");
    feeders(system, input, Some(m));
    m.push(": an input takes one output");
    true
}

/// How many connections feed `input`; each one's start written to `m` when given.
const fn feeders(
    system: &SystemDeclaration,
    input: Port,
    mut m: Option<&mut ConstMessage>,
) -> usize {
    let mut count = 0;
    let mut i = 0;
    while i < system.connections.len() {
        count = listed(system.connections[i], input, count, &mut m);
        i += 1;
    }
    let mut j = 0;
    while j < system.terminal_connections.len() {
        let joined = &system.terminal_connections[j];
        let mut k = 0;
        while k < joined_members(system, joined) {
            if let Some(c) = member_connection(system, joined, k) {
                count = listed(c, input, count, &mut m);
            }
            k += 1;
        }
        j += 1;
    }
    count
}

/// `count`, plus one when `c` feeds `input` (its start then written to `m`, after a comma).
const fn listed(
    c: Connection,
    input: Port,
    count: usize,
    m: &mut Option<&mut ConstMessage>,
) -> usize {
    if !same_port(c.to, input) {
        return count;
    }
    if let Some(m) = m {
        if count > 0 {
            m.push(" and ");
        }
        quoted_port(m, c.from);
    }
    count + 1
}

/// What is wrong with terminal connection `index`: an end that is no terminal of a
/// mechanism, terminals of different kinds or members, a member pair that is not an output
/// and an input of alike units, or an input another connection feeds too.
pub const fn terminal_connection_mistake(
    system: &SystemDeclaration,
    index: usize,
) -> Option<ConstMessage> {
    let joined = &system.terminal_connections[index];
    let mut m = ConstMessage::new();
    m.push("system!: terminals ");
    port_text(&mut m, joined.a);
    m.push(" <=> ");
    port_text(&mut m, joined.b);
    m.push(": ");
    let ends = [joined.a, joined.b];
    let mut e = 0;
    while e < 2 {
        if terminal_of(system, ends[e]).is_none() {
            if component_position(system, ends[e].component).is_none() {
                m.push("there is no component ").quoted(ends[e].component);
            } else {
                quoted_port(&mut m, ends[e])
                    .push(" is no terminal of a mechanism (an FMU file's terminals are not known: connect its variables)");
            }
            return Some(m);
        }
        e += 1;
    }
    let (Some((ta, va)), Some((tb, vb))) =
        (terminal_of(system, joined.a), terminal_of(system, joined.b))
    else {
        return None;
    };
    if !str_eq(ta.kind, tb.kind) {
        m.push("terminals of different kinds, ")
            .quoted(ta.kind)
            .push(" and ")
            .quoted(tb.kind);
        return Some(m);
    }
    let sides = [(ta, joined.b), (tb, joined.a)];
    let others = [tb, ta];
    let mut s = 0;
    while s < 2 {
        let (terminal, other_end) = sides[s];
        let mut k = 0;
        while k < terminal.members.len() {
            if others[s].variable_of(terminal.members[k].0).is_none() {
                m.push("member ")
                    .quoted(terminal.members[k].0)
                    .push(" has no match in ");
                quoted_port(&mut m, other_end);
                return Some(m);
            }
            k += 1;
        }
        s += 1;
    }
    let mut k = 0;
    while k < ta.members.len() {
        let member = ta.members[k].0;
        let (a, b) = (ta.members[k].1, tb.variable_of(member));
        let Some(b) = b else { return None };
        let (Some(ia), Some(ib)) = (variable_position(va, a), variable_position(vb, b)) else {
            return None;
        };
        let Some(c) = member_connection(system, joined, k) else {
            m.push("member ")
                .quoted(member)
                .push(" joins ")
                .push(article(va[ia].causality))
                .push(va[ia].causality.as_str())
                .push(" to ")
                .push(article(vb[ib].causality))
                .push(vb[ib].causality.as_str())
                .push(": a member joins an output to an input");
            return Some(m);
        };
        if !units_alike(va[ia].unit, vb[ib].unit) {
            m.push("member ")
                .quoted(member)
                .push(" joins unlike units, ")
                .quoted(va[ia].unit)
                .push(" and ")
                .quoted(vb[ib].unit);
            return Some(m);
        }
        if fed_twice(system, c.to, &mut m) {
            return Some(m);
        }
        k += 1;
    }
    None
}

/// `system!`'s check of the terminal connection `a <=> b`: panics with its mistake.
#[doc(hidden)]
pub const fn check_terminal_connection(system: &SystemDeclaration, a: Port, b: Port) {
    let mut i = 0;
    while i < system.terminal_connections.len() {
        let c = &system.terminal_connections[i];
        if same_port(c.a, a) && same_port(c.b, b) {
            if let Some(m) = terminal_connection_mistake(system, i) {
                panic!("{}", m.as_str());
            }
            return;
        }
        i += 1;
    }
}

/// What is wrong with parameter set `index`: another set has its name.
pub const fn set_mistake(system: &SystemDeclaration, index: usize) -> Option<ConstMessage> {
    let name = system.parameter_sets[index].name;
    let mut i = 0;
    while i < system.parameter_sets.len() {
        if i != index && str_eq(system.parameter_sets[i].name, name) {
            let mut m = ConstMessage::new();
            m.push("system!: parameter set ")
                .quoted(name)
                .push(" is declared twice: give each set its own name");
            return Some(m);
        }
        i += 1;
    }
    None
}

/// What is wrong with value `index` of parameter set `set`: it names no component or no
/// variable of it, a variable an importer cannot set before initialization (a calculated
/// parameter, an output the model computes), a value outside the variable's bounds, or a
/// variable the set gives another value too.
pub const fn binding_mistake(
    system: &SystemDeclaration,
    set: usize,
    index: usize,
) -> Option<ConstMessage> {
    let parameter_set = &system.parameter_sets[set];
    let binding = &parameter_set.values[index];
    let mut m = ConstMessage::new();
    m.push("system!: parameter set ")
        .quoted(parameter_set.name)
        .push(": ");
    let variable = match resolve(system, binding.port, &mut m) {
        Ok(variable) => variable,
        Err(()) => return Some(m),
    };
    let mut i = 0;
    while i < parameter_set.values.len() {
        if i != index && same_port(parameter_set.values[i].port, binding.port) {
            quoted_port(&mut m, binding.port).push(" is given a value twice");
            return Some(m);
        }
        i += 1;
    }
    if !binding.value.is_finite() {
        quoted_port(&mut m, binding.port).push(" is given a value that is not a finite number");
        return Some(m);
    }
    let Some(v) = variable else {
        return None;
    };
    if !v.settable(SetPhase::Instantiated) {
        quoted_port(&mut m, binding.port)
            .push(" is ")
            .push(article(v.causality))
            .push(v.causality.as_str())
            .push(" the model computes: a parameter set gives parameters, inputs and the start values of states");
        return Some(m);
    }
    let bound = match (v.min, v.max) {
        (Some(min), _) if v.positive && binding.value <= min => Some("not > 0, as it must be"),
        (Some(min), _) if binding.value < min => Some("below the variable's minimum"),
        (_, Some(max)) if binding.value > max => Some("above the variable's maximum"),
        _ => None,
    };
    if let Some(bound) = bound {
        quoted_port(&mut m, binding.port)
            .push(" is given a value ")
            .push(bound);
        return Some(m);
    }
    None
}

/// The variable `port` names, `None` for a variable of an FMU file (not known here); an
/// error (written to `m`) when the component or the mechanism's variable does not exist.
const fn resolve(
    system: &SystemDeclaration,
    port: Port,
    m: &mut ConstMessage,
) -> Result<Option<&'static Variable>, ()> {
    let Some(c) = component_position(system, port.component) else {
        m.push("there is no component ").quoted(port.component);
        if let Some(close) = closest_component(system, port.component) {
            m.push(" (did you mean ").quoted(close).push("?)");
        }
        return Err(());
    };
    let component = &system.components[c];
    let (model, variables) = match component.source {
        super::Source::Mechanism {
            model, variables, ..
        } => (model, variables),
        super::Source::Fmu { .. } => return Ok(None),
    };
    match variable_position(variables, port.variable) {
        Some(v) => Ok(Some(&variables[v])),
        None => {
            m.push("component ")
                .quoted(port.component)
                .push(" (")
                .push(model)
                .push(") has no variable ")
                .quoted(port.variable);
            if let Some(close) = closest_name(variables, port.variable) {
                m.push(" (did you mean ").quoted(close).push("?)");
            }
            Err(())
        }
    }
}

/// The position of the component called `name`.
pub(super) const fn component_position(system: &SystemDeclaration, name: &str) -> Option<usize> {
    let mut i = 0;
    while i < system.components.len() {
        if str_eq(system.components[i].name, name) {
            return Some(i);
        }
        i += 1;
    }
    None
}

/// The component name nearest to a misspelled `name` (as [`closest_name`] for variables).
const fn closest_component(system: &SystemDeclaration, name: &str) -> Option<&'static str> {
    let limit = if name.len() / 3 > 1 {
        name.len() / 3
    } else {
        1
    };
    let mut best: Option<(&'static str, usize)> = None;
    let mut i = 0;
    while i < system.components.len() {
        let candidate = system.components[i].name;
        if let Some(d) = edit_distance(candidate, name) {
            let better = match best {
                Some((_, best_distance)) => d < best_distance,
                None => true,
            };
            if d <= limit && better {
                best = Some((candidate, d));
            }
        }
        i += 1;
    }
    match best {
        Some((close, _)) => Some(close),
        None => None,
    }
}

/// Whether two units are the same quantity (the same SI base-unit exponents): `N.m` and
/// `J` are alike, `m` and `m/s` are not. A unit that does not parse is alike only to itself.
pub const fn units_alike(a: &str, b: &str) -> bool {
    match (base_units(a), base_units(b)) {
        (Ok(a), Ok(b)) => same_base(a, b),
        _ => str_eq(a, b),
    }
}

const fn same_base(a: BaseUnit, b: BaseUnit) -> bool {
    a.kg == b.kg
        && a.m == b.m
        && a.s == b.s
        && a.a == b.a
        && a.k == b.k
        && a.mol == b.mol
        && a.cd == b.cd
        && a.rad == b.rad
}

const fn same_port(a: Port, b: Port) -> bool {
    str_eq(a.component, b.component) && str_eq(a.variable, b.variable)
}

const fn port_text(m: &mut ConstMessage, port: Port) -> &mut ConstMessage {
    m.push(port.component).push(".").push(port.variable)
}

const fn quoted_port(m: &mut ConstMessage, port: Port) -> &mut ConstMessage {
    m.push("`");
    port_text(m, port).push("`")
}

const fn article(causality: Causality) -> &'static str {
    match causality {
        Causality::Input | Causality::Output => "an ",
        _ => "a ",
    }
}

const fn ends_with(text: &str, suffix: &str) -> bool {
    let (text, suffix) = (text.as_bytes(), suffix.as_bytes());
    if text.len() < suffix.len() {
        return false;
    }
    let start = text.len() - suffix.len();
    let mut i = 0;
    while i < suffix.len() {
        if text[start + i] != suffix[i] {
            return false;
        }
        i += 1;
    }
    true
}

/// `system!`'s check of the component called `name`: panics with its mistake.
#[doc(hidden)]
pub const fn check_component(system: &SystemDeclaration, name: &str) {
    let mut i = 0;
    while i < system.components.len() {
        if str_eq(system.components[i].name, name) {
            if let Some(m) = component_mistake(system, i) {
                panic!("{}", m.as_str());
            }
            return;
        }
        i += 1;
    }
}

/// `system!`'s check of the connection `from => to`: panics with its mistake.
#[doc(hidden)]
pub const fn check_connection(system: &SystemDeclaration, from: Port, to: Port) {
    let mut i = 0;
    while i < system.connections.len() {
        let c = &system.connections[i];
        if same_port(c.from, from) && same_port(c.to, to) {
            if let Some(m) = connection_mistake(system, i) {
                panic!("{}", m.as_str());
            }
            return;
        }
        i += 1;
    }
}

/// `system!`'s check of the parameter set `set`: panics with its mistake.
#[doc(hidden)]
pub const fn check_set(system: &SystemDeclaration, set: &str) {
    if let Some(s) = set_position(system, set) {
        if let Some(m) = set_mistake(system, s) {
            panic!("{}", m.as_str());
        }
    }
}

/// `system!`'s check of the value of `port` in the parameter set `set`: panics with its
/// mistake.
#[doc(hidden)]
pub const fn check_binding(system: &SystemDeclaration, set: &str, port: Port) {
    let Some(s) = set_position(system, set) else {
        return;
    };
    let values = system.parameter_sets[s].values;
    let mut i = 0;
    while i < values.len() {
        if same_port(values[i].port, port) {
            if let Some(m) = binding_mistake(system, s, i) {
                panic!("{}", m.as_str());
            }
            return;
        }
        i += 1;
    }
}

const fn set_position(system: &SystemDeclaration, name: &str) -> Option<usize> {
    let mut i = 0;
    while i < system.parameter_sets.len() {
        if str_eq(system.parameter_sets[i].name, name) {
            return Some(i);
        }
        i += 1;
    }
    None
}
