//! An equation's tokens as a tree (brackets, square roots, superscripts on what they
//! follow), and the tree as MathML Core: `<mi>`, `<mn>`, `<mo>`, `<mover>` for the dots of
//! a time derivative, `<msub>`, `<msup>`, `<msubsup>`, `<msqrt>`, `<mtable>` for a matrix.

use super::lex::{Token, FUNCTIONS};
use crate::docs::escape;
use std::fmt::Write as _;

/// One piece of an equation.
#[derive(Clone, Debug, PartialEq)]
pub(super) enum Node {
    Name {
        text: String,
        dots: u8,
        subscript: Option<String>,
    },
    Number(String),
    /// `prefix`: a sign or an integral before its operand (`-g`, `= -(…)`, `(0, -k3)`).
    Operator {
        symbol: char,
        prefix: bool,
    },
    Fenced {
        open: char,
        close: char,
        inner: Vec<Node>,
    },
    Sqrt(Vec<Node>),
    Superscript {
        base: Box<Node>,
        script: String,
    },
    /// Rows of cells, in square brackets.
    Matrix(Vec<Vec<Vec<Node>>>),
    /// Words beside or between equations: `so`, `parallel axis theorem`.
    Text(String),
    /// The wide space between two equations written on one line.
    Gap,
}

/// Words that join equations (`F = T sin s so T = …`): text, not names.
const CONNECTIVES: &[&str] = &[
    "so", "while", "and", "or", "with", "where", "when", "if", "for",
];

/// Greek letters spelled out, as the variable names spell them (`tau`, `omega_n`).
const GREEK: &[(&str, &str)] = &[
    ("alpha", "α"),
    ("beta", "β"),
    ("gamma", "γ"),
    ("delta", "δ"),
    ("epsilon", "ε"),
    ("zeta", "ζ"),
    ("eta", "η"),
    ("theta", "θ"),
    ("kappa", "κ"),
    ("lambda", "λ"),
    ("mu", "μ"),
    ("nu", "ν"),
    ("xi", "ξ"),
    ("pi", "π"),
    ("rho", "ρ"),
    ("sigma", "σ"),
    ("tau", "τ"),
    ("phi", "φ"),
    ("chi", "χ"),
    ("psi", "ψ"),
    ("omega", "ω"),
    ("Gamma", "Γ"),
    ("Delta", "Δ"),
    ("Theta", "Θ"),
    ("Lambda", "Λ"),
    ("Pi", "Π"),
    ("Sigma", "Σ"),
    ("Phi", "Φ"),
    ("Psi", "Ψ"),
    ("Omega", "Ω"),
];

/// A thin space (TeX's `\,`): between a function's name and what is around it.
const THIN_SPACE: &str = "<mspace width=\"0.1667em\"/>";
/// Around a word between equations.
const WORD_SPACE: &str = "<mspace width=\"0.5em\"/>";

/// The tree of `tokens`, or `None` when brackets do not match, a superscript has nothing
/// to sit on or `sqrt` has no parenthesis.
pub(super) fn parse(tokens: &[Token]) -> Option<Vec<Node>> {
    Parser { tokens, next: 0 }.sequence(None)
}

struct Parser<'a> {
    tokens: &'a [Token],
    next: usize,
}

impl Parser<'_> {
    /// Nodes up to `closer` (consumed), or to the end when there is none.
    fn sequence(&mut self, closer: Option<char>) -> Option<Vec<Node>> {
        let mut nodes: Vec<Node> = Vec::new();
        loop {
            let Some(token) = self.tokens.get(self.next) else {
                return closer.is_none().then_some(nodes);
            };
            self.next += 1;
            match token {
                Token::Close(c) => return (closer == Some(*c)).then_some(nodes),
                Token::Operator('|') if closer == Some('|') => return Some(nodes),
                Token::Operator('|') => {
                    let inner = self.sequence(Some('|'))?;
                    nodes.push(Node::Fenced {
                        open: '|',
                        close: '|',
                        inner,
                    });
                }
                Token::Open(open) => {
                    let close = closing(*open);
                    let inner = self.sequence(Some(close))?;
                    nodes.push(Node::Fenced {
                        open: *open,
                        close,
                        inner,
                    });
                }
                Token::Name { text, .. } if text == "sqrt" => {
                    if self.tokens.get(self.next) != Some(&Token::Open('(')) {
                        return None;
                    }
                    self.next += 1;
                    nodes.push(Node::Sqrt(self.sequence(Some(')'))?));
                }
                Token::Name {
                    text,
                    dots,
                    subscript,
                } => nodes.push(Node::Name {
                    text: text.clone(),
                    dots: *dots,
                    subscript: subscript.clone(),
                }),
                Token::Number(n) => nodes.push(Node::Number(n.clone())),
                Token::Operator(symbol) => {
                    let after_operand = !matches!(nodes.last(), None | Some(Node::Operator { .. }));
                    nodes.push(Node::Operator {
                        symbol: *symbol,
                        prefix: !after_operand && "+-−∫".contains(*symbol),
                    });
                }
                Token::Superscript(script) => {
                    let base = nodes.pop().filter(|base| {
                        !matches!(base, Node::Operator { .. } | Node::Superscript { .. })
                    })?;
                    nodes.push(Node::Superscript {
                        base: Box::new(base),
                        script: script.clone(),
                    });
                }
            }
        }
    }
}

fn closing(open: char) -> char {
    match open {
        '(' => ')',
        '[' => ']',
        _ => '}',
    }
}

/// The MathML of a sequence of nodes (without the `<math>` around it).
pub(super) fn emit(nodes: &[Node], out: &mut String) {
    for (k, node) in nodes.iter().enumerate() {
        let (previous, next) = (k.checked_sub(1).map(|j| &nodes[j]), nodes.get(k + 1));
        let function = is_function(node);
        let words = is_connective(node);
        if (function && previous.is_some_and(is_operand))
            || (words && !matches!(previous, None | Some(Node::Gap)))
        {
            out.push_str(if words { WORD_SPACE } else { THIN_SPACE });
        }
        emit_node(node, out);
        if function {
            // Function application (U+2061), then a thin space unless parentheses follow.
            out.push_str("<mo>&#x2061;</mo>");
            if !matches!(next, Some(Node::Fenced { .. }) | None) {
                out.push_str(THIN_SPACE);
            }
        }
        if words && !matches!(next, None | Some(Node::Gap)) {
            out.push_str(WORD_SPACE);
        }
    }
}

fn emit_node(node: &Node, out: &mut String) {
    match node {
        Node::Name {
            text,
            dots,
            subscript,
        } => match subscript {
            _ if is_connective(node) => {
                let _ = write!(out, "<mtext>{}</mtext>", escape(text));
            }
            None => dotted(text, *dots, out),
            Some(subscript) => {
                out.push_str("<msub>");
                dotted(text, *dots, out);
                script(subscript, out);
                out.push_str("</msub>");
            }
        },
        Node::Number(n) => {
            let _ = write!(out, "<mn>{n}</mn>");
        }
        Node::Operator { symbol, prefix } => {
            let symbol = if *symbol == '-' { '−' } else { *symbol };
            let form = if *prefix { " form=\"prefix\"" } else { "" };
            let _ = write!(out, "<mo{form}>{}</mo>", escape(&symbol.to_string()));
        }
        Node::Fenced { open, close, inner } => {
            let _ = write!(out, "<mrow><mo>{open}</mo>");
            emit(inner, out);
            let _ = write!(out, "<mo>{close}</mo></mrow>");
        }
        Node::Sqrt(inner) => {
            out.push_str("<msqrt>");
            emit(inner, out);
            out.push_str("</msqrt>");
        }
        Node::Superscript { base, script: sup } => match base.as_ref() {
            Node::Name {
                text,
                dots,
                subscript: Some(sub),
            } => {
                out.push_str("<msubsup>");
                dotted(text, *dots, out);
                script(sub, out);
                script(sup, out);
                out.push_str("</msubsup>");
            }
            base => {
                out.push_str("<msup>");
                emit_node(base, out);
                script(sup, out);
                out.push_str("</msup>");
            }
        },
        Node::Matrix(rows) => {
            out.push_str("<mrow><mo>[</mo><mtable>");
            for row in rows {
                out.push_str("<mtr>");
                for cell in row {
                    out.push_str("<mtd>");
                    emit(cell, out);
                    out.push_str("</mtd>");
                }
                out.push_str("</mtr>");
            }
            out.push_str("</mtable><mo>]</mo></mrow>");
        }
        Node::Text(text) => {
            let _ = write!(out, "<mtext>{}</mtext>", escape(text));
        }
        Node::Gap => out.push_str("<mspace width=\"2em\"/>"),
    }
}

/// A letter or a name, with the dots of its time derivatives over it as an accent (U+02D9
/// DOT ABOVE, U+00A8 DIAERESIS: the spacing characters MathML renderers stack as accents).
fn dotted(text: &str, dots: u8, out: &mut String) {
    let name = greek(text).map_or_else(|| escape(text), String::from);
    match dots {
        0 => {
            let _ = write!(out, "<mi>{name}</mi>");
        }
        _ => {
            let dot = if dots == 1 { '˙' } else { '¨' };
            // an over-script, not `accent="true"`: Chromium places an accent from the
            // text font inside the letter, where the dots disappear
            let _ = write!(out, "<mover><mi>{name}</mi><mo>{dot}</mo></mover>");
        }
    }
}

/// A subscript or superscript: a number, a sign and a number (`−1`), a prime or a name.
fn script(text: &str, out: &mut String) {
    let is_number = |s: &str| !s.is_empty() && s.chars().all(|c| c.is_ascii_digit());
    if is_number(text) {
        let _ = write!(out, "<mn>{text}</mn>");
    } else if let Some(n) = text.strip_prefix('−').filter(|n| is_number(n)) {
        let _ = write!(out, "<mrow><mo>−</mo><mn>{n}</mn></mrow>");
    } else if matches!(text, "′" | "″" | "‴") {
        let _ = write!(out, "<mo>{text}</mo>");
    } else {
        dotted(text, 0, out);
    }
}

fn greek(text: &str) -> Option<&'static str> {
    GREEK
        .iter()
        .find(|(name, _)| *name == text)
        .map(|(_, letter)| *letter)
}

/// A word that names a function or a Greek letter: a symbol, not prose.
pub(super) fn is_symbol_name(word: &str) -> bool {
    FUNCTIONS.contains(&word) || greek(word).is_some()
}

/// A word that joins equations (`so`, `while`): text, with a space either side.
fn is_connective(node: &Node) -> bool {
    matches!(node, Node::Name { text, subscript: None, .. } if CONNECTIVES.contains(&text.as_str()))
}

/// A function's name (`sin`, `sin²`), which takes a thin space around it.
fn is_function(node: &Node) -> bool {
    match node {
        Node::Name {
            text,
            subscript: None,
            ..
        } => FUNCTIONS.contains(&text.as_str()),
        Node::Superscript { base, .. } => is_function(base),
        _ => false,
    }
}

/// Something a function's name after it is set apart from (not an operator, not words).
fn is_operand(node: &Node) -> bool {
    match node {
        Node::Name { .. } => !is_connective(node),
        Node::Operator { .. } | Node::Text(_) | Node::Gap => false,
        _ => true,
    }
}
