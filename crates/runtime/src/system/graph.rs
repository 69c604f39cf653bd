//! Loops of direct feedthrough: an output that depends, through connections and through
//! components whose outputs follow their inputs at once, on itself. Such a system has no
//! order in which its components can be evaluated, so it is refused, with the loop named
//! variable by variable.

use std::collections::BTreeMap;

/// A variable of a component, `(component, variable)`.
pub type PortName<'a> = (&'a str, &'a str);

/// An output of a component and the inputs of that component it depends on directly (an
/// FMU's `<ModelStructure>`: the dependencies of an output that are inputs).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Feedthrough<'a> {
    pub component: &'a str,
    pub output: &'a str,
    pub inputs: Vec<&'a str>,
}

/// The first loop of direct feedthrough, as the message that names it
/// (`a.F => b.u, which b.y follows at once; b.y => a.u, ...`), or `None` when the system has
/// none. `connections` run from an output to an input.
pub fn feedthrough_cycle(
    connections: &[(PortName<'_>, PortName<'_>)],
    feedthrough: &[Feedthrough<'_>],
) -> Option<String> {
    // From an input: the outputs of its component that follow it at once. From an output:
    // the inputs it feeds.
    let mut next: BTreeMap<PortName<'_>, Vec<PortName<'_>>> = BTreeMap::new();
    for f in feedthrough {
        for input in &f.inputs {
            next.entry((f.component, *input))
                .or_default()
                .push((f.component, f.output));
        }
    }
    for (from, to) in connections {
        next.entry(*from).or_default().push(*to);
    }
    let mut finished: Vec<PortName<'_>> = Vec::new();
    for (start, _) in connections {
        let mut path = Vec::new();
        if let Some(cycle) = search(*start, &next, &mut path, &mut finished) {
            return Some(describe(&cycle, connections));
        }
    }
    None
}

/// Depth-first search from `port`: the loop found, starting and ending at one port.
fn search<'a>(
    port: PortName<'a>,
    next: &BTreeMap<PortName<'a>, Vec<PortName<'a>>>,
    path: &mut Vec<PortName<'a>>,
    finished: &mut Vec<PortName<'a>>,
) -> Option<Vec<PortName<'a>>> {
    if let Some(at) = path.iter().position(|p| *p == port) {
        let mut cycle = path[at..].to_vec();
        cycle.push(port);
        return Some(cycle);
    }
    if finished.contains(&port) {
        return None;
    }
    path.push(port);
    for following in next.get(&port).into_iter().flatten() {
        if let Some(cycle) = search(*following, next, path, finished) {
            return Some(cycle);
        }
    }
    path.pop();
    finished.push(port);
    None
}

/// `a loop of direct feedthrough: a.y => b.u; b.y follows b.u at once; b.y => a.u; a.y
/// follows a.u at once`, from the loop's ports in order (the first one again at the end).
fn describe(cycle: &[PortName<'_>], connections: &[(PortName<'_>, PortName<'_>)]) -> String {
    let name = |(c, v): PortName<'_>| format!("`{c}.{v}`");
    let steps: Vec<String> = cycle
        .windows(2)
        .map(|pair| {
            if connections.contains(&(pair[0], pair[1])) {
                format!("{} => {}", name(pair[0]), name(pair[1]))
            } else {
                format!("{} follows {} at once", name(pair[1]), name(pair[0]))
            }
        })
        .collect();
    format!(
        "a loop of direct feedthrough, which no order of evaluation resolves: {} (break it \
         with a component whose output does not follow its input at once, one with a state)",
        steps.join("; ")
    )
}
