//! `terminalsAndIcons/terminalsAndIcons.xml` of the FMI 3.0 FMU (FMI 3.0 §2.4.9): each
//! terminal of the mechanism ([`Mechanism::TERMINALS`]), its members matched by name
//! (`plug`), each a signal.

use super::shared::{finish, write_each, writer};
use crate::model::Mechanism;

/// The file, or `None` for a mechanism without terminals (its FMU has none).
pub fn terminals_and_icons<M: Mechanism>() -> Result<Option<String>, String> {
    if M::TERMINALS.is_empty() {
        return Ok(None);
    }
    let written = writer().and_then(|mut w| {
        w.create_element("fmiTerminalsAndIcons")
            .with_attribute(("fmiVersion", "3.0"))
            .write_inner_content(|w| {
                write_each(w, "Terminals", M::TERMINALS, |w, terminal| {
                    let mut attributes = vec![
                        ("name", terminal.name),
                        ("matchingRule", "plug"),
                        ("terminalKind", terminal.kind),
                    ];
                    if !terminal.description.is_empty() {
                        attributes.push(("description", terminal.description));
                    }
                    w.create_element("Terminal")
                        .with_attributes(attributes)
                        .write_inner_content(|w| {
                            for (member, variable) in terminal.members {
                                w.create_element("TerminalMemberVariable")
                                    .with_attributes([
                                        ("variableName", *variable),
                                        ("memberName", *member),
                                        ("variableKind", "signal"),
                                    ])
                                    .write_empty()?;
                            }
                            Ok(())
                        })?;
                    Ok(())
                })
            })?;
        Ok(w.into_inner())
    });
    finish("terminalsAndIcons.xml", written).map(Some)
}
