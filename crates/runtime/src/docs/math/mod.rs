//! The equations of the notes as MathML Core, which current browsers render without web
//! fonts. A dotted variable becomes its letter with the dot over it (`<mover>`, an
//! over-script: as an accent, Chromium without a math font draws the dots inside the
//! letter, where they vanish), so the dot cannot collide with a superscript, as a combining
//! dot does in many monospace fonts (`θ̇² x` shown as `θ² x`).
//!
//! [`block`] renders an indented block of the notes: one `<math display="block">` per group
//! of lines between blank lines, the lines of a group aligned on their first relation (or
//! each on its own when one has none), several equations on one line kept apart by the wide
//! space the notes put between them, a matrix written as rows in square brackets as a
//! matrix. [`inline`] renders an inline `code` span that [`is_math`]. Both keep the plain
//! text in `alttext`; whatever they cannot read gives `None`, so the caller shows the plain
//! text instead of anything garbled.

mod lex;
mod tree;

use super::escape;
use tree::Node;

/// Whether an inline `code` span is an equation or a symbol rather than a plain identifier
/// (`x_ddot`, `fmi2Warning`) or a command (`mechfmu validate`): a Greek letter, a dot of a
/// time derivative, a superscript or a mathematical sign in it, an operator between spaces,
/// a sign before a term (`-g Z`), a function's parentheses (`diag(k, m)`), or symbols side
/// by side (`m l`).
pub fn is_math(code: &str) -> bool {
    const SIGNS: &str = "\u{307}\u{308}²³¹⁰⁴⁵⁶⁷⁸⁹⁻ᵀ₀₁₂₃₄₅₆₇₈₉≤≥≈≠→·×⊗∫∂½";
    let greek = |c: char| ('\u{391}'..='\u{3c9}').contains(&c);
    let sign = |c: char| c == '-' || c == '+';
    let term = |c: char| c.is_alphanumeric() || c == '(';
    let mut chars = code.chars();
    let signed = chars.next().is_some_and(sign) && chars.next().is_some_and(term);
    let symbols_side_by_side = code.contains(' ')
        && lex::tokens(code).is_some_and(|tokens| {
            tokens.iter().all(|token| match token {
                lex::Token::Name { text, .. } => {
                    text.chars().count() == 1 || tree::is_symbol_name(text)
                }
                _ => true,
            })
        });
    code.chars()
        .any(|c| SIGNS.contains(c) || greek(c) || lex::dotted_letter(c).is_some())
        || [" = ", " + ", " - ", " < ", " > ", " / "]
            .iter()
            .any(|op| code.contains(op))
        || lex::FUNCTIONS
            .iter()
            .any(|f| code.contains(&format!("{f}(")))
        || signed
        || symbols_side_by_side
}

/// An inline equation: `<math>` with the plain text in `alttext`.
pub fn inline(code: &str) -> Option<String> {
    let nodes = line(code)?;
    let mut out = format!("<math alttext=\"{}\">", alt_text(code.trim()));
    tree::emit(&nodes, &mut out);
    out.push_str("</math>");
    Some(out)
}

/// The equations of an indented block of the notes: one `<math display="block">` per group
/// of lines between blank lines, each with its plain text in `alttext`.
pub fn block(text: &str) -> Option<String> {
    let mut out = String::new();
    for group in groups(text) {
        out.push_str(&display(&group)?);
        out.push('\n');
    }
    Some(out)
}

/// The groups of non-blank lines, without trailing spaces.
fn groups(text: &str) -> Vec<Vec<&str>> {
    let mut groups = vec![Vec::new()];
    for l in text.lines().map(str::trim_end) {
        match groups.last_mut() {
            Some(group) if !l.is_empty() => group.push(l),
            Some(group) if group.is_empty() => {}
            _ => groups.push(Vec::new()),
        }
    }
    groups.retain(|g| !g.is_empty());
    groups
}

/// One group of lines as a display: a matrix equation, one line, or aligned lines.
fn display(lines: &[&str]) -> Option<String> {
    let plain: Vec<&str> = lines.iter().map(|l| l.trim()).collect();
    let mut out = format!(
        "<math display=\"block\" alttext=\"{}\">",
        alt_text(&plain.join("\n"))
    );
    if let Some(nodes) = matrix_equation(lines) {
        tree::emit(&nodes, &mut out);
    } else if let [one] = lines {
        tree::emit(&line(one)?, &mut out);
    } else {
        out.push_str(&aligned(lines)?);
    }
    out.push_str("</math>");
    Some(out)
}

/// Lines as the rows of a table: aligned on their first relation when every line has one
/// (`l φ̈ = …` over `T = …`), else each line left-aligned.
fn aligned(lines: &[&str]) -> Option<String> {
    let rows: Vec<Vec<Node>> = lines.iter().map(|l| line(l)).collect::<Option<_>>()?;
    let relations: Option<Vec<usize>> = rows
        .iter()
        .map(|row| row.iter().position(is_relation))
        .collect();
    let mut out = String::from("<mtable class=\"equations\">");
    for (k, row) in rows.iter().enumerate() {
        out.push_str("<mtr>");
        if let Some(at) = relations.as_ref().map(|r| r[k]) {
            out.push_str("<mtd class=\"lhs\" columnalign=\"right\">");
            tree::emit(&row[..at], &mut out);
            out.push_str("</mtd><mtd class=\"relation\">");
            tree::emit(&row[at..=at], &mut out);
            out.push_str("</mtd><mtd class=\"rhs\" columnalign=\"left\">");
            tree::emit(&row[at + 1..], &mut out);
        } else {
            out.push_str("<mtd class=\"rhs\" columnalign=\"left\">");
            tree::emit(row, &mut out);
        }
        out.push_str("</mtd></mtr>");
    }
    out.push_str("</mtable>");
    Some(out)
}

/// `M = [ a  0 ]` over rows `[ 0  b ]`: the left-hand side and the rows, whose cells are
/// apart by wide spaces. `None` when the lines are not written so.
fn matrix_equation(lines: &[&str]) -> Option<Vec<Node>> {
    let (first, rest) = lines.split_first()?;
    if rest.is_empty() {
        return None;
    }
    let (lhs, first_row) = first.split_at(first.find('[')?);
    let rows: Vec<&str> = std::iter::once(first_row)
        .chain(rest.iter().copied())
        .map(|row| row.trim().strip_prefix('[')?.strip_suffix(']'))
        .collect::<Option<_>>()?;
    let cells: Vec<Vec<Vec<Node>>> = rows
        .iter()
        .map(|row| wide_split(row).into_iter().map(expression).collect())
        .collect::<Option<_>>()?;
    if cells.iter().any(|row| row.len() != cells[0].len()) {
        return None;
    }
    let mut nodes = expression(lhs)?;
    nodes.push(Node::Matrix(cells));
    Some(nodes)
}

/// One line: its equations apart by wide spaces, the words beside them as text.
fn line(text: &str) -> Option<Vec<Node>> {
    let mut nodes = Vec::new();
    for (k, piece) in equations(text).iter().enumerate() {
        if k > 0 {
            nodes.push(Node::Gap);
        }
        if is_annotation(piece) {
            nodes.push(Node::Text(piece.clone()));
        } else {
            nodes.extend(expression(piece)?);
        }
    }
    Some(nodes)
}

fn expression(text: &str) -> Option<Vec<Node>> {
    tree::parse(&lex::tokens(text)?)
}

/// The equations of a line: its pieces apart by two spaces or more, a piece joined again
/// to the one before when the spaces only align an operator (`T   = m …`).
fn equations(text: &str) -> Vec<String> {
    const OPERATORS: &str = "=+-−<>≤≥≈≠→·×⊗/";
    let mut pieces: Vec<String> = Vec::new();
    for piece in wide_split(text) {
        match pieces.last_mut() {
            Some(before)
                if piece.starts_with(|c| OPERATORS.contains(c))
                    || before.ends_with(|c| OPERATORS.contains(c) || "([,".contains(c)) =>
            {
                before.push(' ');
                before.push_str(piece);
            }
            _ => pieces.push(piece.to_string()),
        }
    }
    pieces
}

/// The pieces of a line apart by two spaces or more.
fn wide_split(text: &str) -> Vec<&str> {
    text.split("  ")
        .map(str::trim)
        .filter(|p| !p.is_empty())
        .collect()
}

/// Words beside an equation (`parallel axis theorem`, `Euler's equations about B`): letters
/// only, with a word that is no function's or Greek letter's name.
fn is_annotation(piece: &str) -> bool {
    piece
        .chars()
        .all(|c| c.is_alphabetic() || c == ' ' || c == '\'')
        && piece
            .split_whitespace()
            .any(|word| word.chars().count() > 1 && !tree::is_symbol_name(word))
}

fn is_relation(node: &Node) -> bool {
    matches!(node, Node::Operator { symbol, prefix: false } if "=<>≤≥≈≠".contains(*symbol))
}

/// Plain text for an attribute: escaped, line breaks kept as character references.
fn alt_text(text: &str) -> String {
    escape(text).replace('\n', "&#10;")
}

#[cfg(test)]
mod tests;
