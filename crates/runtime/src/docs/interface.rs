//! The interface page of a mechanism: Markdown, for the repository (`docs/mechanisms/`),
//! where `documentation/index.html` is for the FMU. The same declaration, the same table
//! (value references, causality, variability, the `initial` an importer sees, units, start
//! values, bounds; FMI 3.0's arrays) and the same notes, without the plot and the
//! capabilities.

use super::notes::dedent;
use super::num;
use super::tables::{shown_initial, shown_min};
use crate::model::{Mechanism, Shapes, Variable};
use std::fmt::Write as _;

/// The interface of mechanism `M` as a Markdown page: its description, default experiment,
/// variables and equations ([`Mechanism::NOTES`]). Deterministic: the same declaration gives
/// the same bytes, whichever build renders it.
pub fn interface<M: Mechanism>() -> Result<String, String> {
    let e = M::EXPERIMENT;
    let mut md = String::new();
    let _ = write!(
        md,
        "<!-- Generated from the declaration of {name} by `mechfmu docs`: do not edit. -->\n\n\
         # {name}\n\n",
        name = M::NAME
    );
    let description = dedent(M::DESCRIPTION);
    if !description.trim().is_empty() {
        md.push_str(description.trim());
        md.push_str("\n\n");
    }

    md.push_str("## Default experiment\n\n");
    let _ = write!(
        md,
        "| start | stop | communication step | relative tolerance |\n\
         |---:|---:|---:|---:|\n\
         | {} s | {} s | {} s | {} |\n\n",
        num(e.start),
        num(e.stop),
        num(e.step),
        num(e.tolerance)
    );

    md.push_str("## Variables\n\n");
    md.push_str(&variable_table(M::VARIABLES));
    md.push_str(&fmi3_arrays::<M>()?);

    md.push_str("\n## Equations and notes\n\n");
    if M::NOTES.trim().is_empty() {
        md.push_str("*The mechanism declares no notes.*\n");
    } else {
        md.push_str(&notes(M::NOTES));
    }
    md.push_str("\n## Events\n\n");
    md.push_str(&super::events::<M>());
    Ok(md)
}

/// What differs in the FMI 3.0 FMU: the value references (the independent `time` first,
/// then each variable's place in its model description), and the arrays that replace the
/// scalars they group.
fn fmi3_arrays<M: Mechanism>() -> Result<String, String> {
    let shapes = Shapes::new(M::VARIABLES, M::ARRAYS)?;
    let references: Vec<String> = (shapes.variables.iter())
        .map(|s| format!("`{}` {}", s.name, s.reference))
        .collect();
    let mut md = format!(
        "\nIn the FMI 3.0 FMU, the variables are numbered in the order its model description \
         lists them (each state before its derivative): {}; `time`, the independent variable \
         listed last, has value reference {}.",
        references.join(", "),
        Shapes::TIME_REFERENCE
    );
    let arrays: Vec<_> = shapes.variables.iter().filter(|s| s.is_array()).collect();
    if arrays.is_empty() {
        md.push('\n');
        return Ok(md);
    }
    md.push_str(
        " These arrays replace the scalars they group (row-major):\n\n\
         | array | value ref. | dimensions | elements | description |\n\
         |---|---:|---|---|---|\n",
    );
    for shaped in arrays {
        let dimensions: Vec<String> = shaped.dimensions.iter().map(usize::to_string).collect();
        let elements: Vec<String> = (shaped.elements.iter())
            .map(|&e| format!("`{}`", M::VARIABLES[e].name))
            .collect();
        let _ = writeln!(
            md,
            "| `{}` | {} | {} | {} | {} |",
            shaped.name,
            shaped.reference,
            dimensions.join(" × "),
            elements.join(" "),
            shaped.description
        );
    }
    Ok(md)
}

/// The variables in value-reference order, one table row each.
fn variable_table(variables: &[Variable]) -> String {
    let mut md = String::from(
        "| name | value ref. | causality | variability | initial | unit | start | min | max | description |\n\
         |---|---:|---|---|---|---|---:|---:|---:|---|\n",
    );
    for (vr, v) in variables.iter().enumerate() {
        let opt = |x: Option<f64>| x.map(num).unwrap_or_default();
        let mut description = cell(v.description());
        if let Some(d) = v.derivative {
            let _ = write!(description, " (its derivative: `{d}`)");
        }
        let _ = writeln!(
            md,
            "| `{}` | {vr} | {} | {} | {} | {} | {} | {} | {} | {} |",
            v.name,
            v.causality.as_str(),
            v.variability.as_str(),
            shown_initial(v),
            cell(v.unit),
            opt(v.start),
            shown_min(v, ">"),
            opt(v.max),
            description.trim(),
        );
    }
    md
}

/// Text for a table cell: on one line, with what Markdown would read as HTML, a cell
/// boundary or emphasis escaped.
fn cell(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for (i, word) in text.split_whitespace().enumerate() {
        if i > 0 {
            out.push(' ');
        }
        for c in word.chars() {
            match c {
                '<' => out.push_str("&lt;"),
                '&' => out.push_str("&amp;"),
                '\\' | '|' | '*' => {
                    out.push('\\');
                    out.push(c);
                }
                _ => out.push(c),
            }
        }
    }
    out
}

/// The notes, already Markdown: unindented (they sit in an indented Rust string), headings
/// one level down (they belong under "Equations and notes"), code blocks untouched.
fn notes(text: &str) -> String {
    let text = dedent(text);
    let mut md = String::new();
    let mut fenced = false;
    for line in text.trim_matches('\n').lines() {
        let line = line.trim_end();
        if line.trim_start().starts_with("```") {
            fenced = !fenced;
        } else if !fenced && line.starts_with('#') {
            md.push('#');
        }
        md.push_str(line);
        md.push('\n');
    }
    md
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::docs::tests::{complete_and_deterministic, Spring};

    #[test]
    fn interface_is_complete_and_deterministic() {
        let needles = [
            "# Spring\n\nA mass on a spring: m x'' + k x = 0.\n\n## Default experiment\n",
            "| 0 s | 2 s | 0.01 s | 1e-8 |",
            "| `m` | 0 | parameter | fixed | exact | kg | 1 | > 0 |  | Mass |",
            "| `k` | 1 | parameter | tunable | exact | N/m | 4 | 0 |  | Stiffness |",
            // the input has no `initial`
            "| `F` | 2 | input | continuous |  | N | 0 |  |  | Push |",
            "| `x` | 3 | output | continuous | exact | m | 1 |  |  | Position (its derivative: `v`) |",
            "| `a` | 5 | output | continuous | calculated | m/s2 |  |  |  | Acceleration &lt;a &amp; b> |",
            "## Equations and notes\n\nThe equation of motion:\n\n    m x'' + k x = F\n\n- no damping;\n",
            "\n### Departures\nNone, *really*.\n",
        ];
        let md = complete_and_deterministic(interface::<Spring>, &needles);
        assert!(
            md.ends_with("*really*.\n\n## Events\n\nNone: no event indicators, no limits, nothing to do at `fmi2CompletedIntegratorStep` (`completedIntegratorStepNotNeeded`).\n"),
            "{md}"
        );
        assert!(!md.contains("\n\n\n"), "{md}");
    }

    #[test]
    fn cells_stay_in_their_column() {
        assert_eq!(cell(" a |  b\n c * d \\ "), "a \\| b c \\* d \\\\");
        assert_eq!(cell("<a & b> > 0"), "&lt;a &amp; b> > 0");
    }

    #[test]
    fn headings_go_down_a_level_outside_code() {
        let md = notes("\n    ## A\n    text\n    ```\n    # not a heading\n    ```\n");
        assert_eq!(md, "### A\ntext\n```\n# not a heading\n```\n");
    }

    #[test]
    fn write_interface_follows_the_buffer_protocol() {
        let len =
            unsafe { crate::export::write_text(interface::<Spring>, std::ptr::null_mut(), 0) };
        let mut buf = vec![0xffu8; len + 1];
        assert_eq!(
            unsafe { crate::export::write_text(interface::<Spring>, buf.as_mut_ptr(), buf.len()) },
            len
        );
        assert_eq!(
            std::str::from_utf8(&buf[..len]).unwrap(),
            interface::<Spring>().unwrap()
        );
    }
}
