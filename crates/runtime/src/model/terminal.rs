//! Terminals: the variables that make up one port of a mechanism (a mass's position, velocity
//! and the force on it), declared so that a system connects the port as one and an FMI 3.0
//! importer reads them from `terminalsAndIcons/terminalsAndIcons.xml` (FMI 3.0 §2.4.9).

use super::checks::position;
use super::const_text::{str_eq, ConstMessage};
use super::Variable;

/// A port on a line: a point's position `s` and velocity `v`, and the force `f` along the
/// line (on the point, or that the point exerts).
pub const TRANSLATIONAL: &str = "org.mechfmu.translational";

/// One port of a mechanism: named members, each a variable. Two terminals connect member by
/// member (FMI 3.0's matching rule `plug`: members of one name join), each member joining an
/// output to an input.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Terminal {
    pub name: &'static str,
    /// What kind of port it is (FMI 3.0's `terminalKind`): only terminals of one kind connect.
    pub kind: &'static str,
    pub description: &'static str,
    /// `(member, variable)`.
    pub members: &'static [(&'static str, &'static str)],
}

impl Terminal {
    pub const fn new(
        name: &'static str,
        kind: &'static str,
        description: &'static str,
        members: &'static [(&'static str, &'static str)],
    ) -> Self {
        Terminal {
            name,
            kind,
            description,
            members,
        }
    }

    /// The variable of member `member`.
    pub const fn variable_of(&self, member: &str) -> Option<&'static str> {
        let mut i = 0;
        while i < self.members.len() {
            if str_eq(self.members[i].0, member) {
                return Some(self.members[i].1);
            }
            i += 1;
        }
        None
    }
}

/// The terminal of `terminals` called `name`.
pub const fn terminal_named(terminals: &[Terminal], name: &str) -> Option<Terminal> {
    let mut i = 0;
    while i < terminals.len() {
        if str_eq(terminals[i].name, name) {
            return Some(terminals[i]);
        }
        i += 1;
    }
    None
}

/// Compile-time check of a mechanism's terminals, run by `export_fmu!`: each has a name of its
/// own and members of names of their own, each naming a declared variable once.
pub const fn check_terminals(variables: &[Variable], terminals: &[Terminal]) {
    let mut t = 0;
    while t < terminals.len() {
        let terminal = &terminals[t];
        let mut m = ConstMessage::new();
        m.push("Mechanism::TERMINALS: terminal ")
            .quoted(terminal.name);
        let mut other = 0;
        while other < t {
            if str_eq(terminals[other].name, terminal.name) {
                m.push(" is declared twice");
                panic!("{}", m.as_str());
            }
            other += 1;
        }
        if terminal.members.is_empty() {
            m.push(" has no member");
            panic!("{}", m.as_str());
        }
        let mut k = 0;
        while k < terminal.members.len() {
            let (member, variable) = terminal.members[k];
            if position(variables, variable).is_none() {
                m.push(": member ")
                    .quoted(member)
                    .push(" names ")
                    .quoted(variable)
                    .push(", which is no declared variable");
                panic!("{}", m.as_str());
            }
            let mut j = 0;
            while j < k {
                if str_eq(terminal.members[j].0, member) {
                    m.push(": member ")
                        .quoted(member)
                        .push(" is declared twice");
                    panic!("{}", m.as_str());
                }
                j += 1;
            }
            k += 1;
        }
        t += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const VARIABLES: &[Variable] = &[
        Variable::input("N", 0.0).named("F", ""),
        Variable::state("m", 0.0, "v").named("x", ""),
        Variable::state("m/s", 0.0, "a").named("v", ""),
        Variable::output("m/s2").named("a", ""),
    ];

    fn mistake(terminals: &[Terminal]) -> String {
        std::panic::catch_unwind(|| check_terminals(VARIABLES, terminals))
            .err()
            .and_then(|e| e.downcast_ref::<String>().cloned())
            .unwrap_or_default()
    }

    #[test]
    fn a_terminal_names_its_members_variables_once() {
        const RIGHT: &[Terminal] = &[Terminal::new(
            "flange",
            TRANSLATIONAL,
            "",
            &[("s", "x"), ("f", "F")],
        )];
        assert_eq!(mistake(RIGHT), "");
        assert_eq!(RIGHT[0].variable_of("f"), Some("F"));
        assert_eq!(terminal_named(RIGHT, "flange"), Some(RIGHT[0]));
        assert_eq!(
            mistake(&[Terminal::new("flange", TRANSLATIONAL, "", &[("s", "y")])]),
            "Mechanism::TERMINALS: terminal `flange`: member `s` names `y`, which is no declared variable"
        );
        assert!(mistake(&[Terminal::new(
            "flange",
            TRANSLATIONAL,
            "",
            &[("s", "x"), ("s", "v")]
        )])
        .ends_with("member `s` is declared twice"));
        assert!(mistake(&[
            Terminal::new("t", TRANSLATIONAL, "", &[("s", "x")]),
            Terminal::new("t", TRANSLATIONAL, "", &[("s", "v")])
        ])
        .ends_with("terminal `t` is declared twice"));
        assert!(mistake(&[Terminal::new("t", TRANSLATIONAL, "", &[])]).ends_with("has no member"));
    }
}
