//! What the lab is measuring, on stderr: one line rewritten in place on a terminal, a line
//! each elsewhere.

use std::io::IsTerminal;

/// Says what is being measured now.
pub fn show(message: &str) {
    if std::io::stderr().is_terminal() {
        eprint!("\r\x1b[2K{message} ...");
    } else {
        eprintln!("{message} ...");
    }
}

/// Clears the line [`show`] wrote on a terminal (before other output).
pub fn clear() {
    if std::io::stderr().is_terminal() {
        eprint!("\r\x1b[2K");
    }
}
