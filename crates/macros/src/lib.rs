//! Compile-time support for [`mechanism!`](../mechfmu/macro.mechanism.html): each mistake in
//! a declaration is reported once, at the line of the variable it is about.
//!
//! - [`at_span!`]: the declaration checks of `mechanism!` run as constant evaluation, and
//!   rustc reports a failed constant at the span of the expression that computes it, which,
//!   written by a `macro_rules!` macro, is the whole invocation. `at_span!` gives the tokens
//!   of a check the span of the variable it checks.
//! - [`unique_variables!`]: a name declared twice would be a struct field declared twice,
//!   which rustc reports three times, at the invocation. `unique_variables!` reports it once,
//!   at the second declaration, and expands the declaration without it.
//! - [`source_text!`]: a declaration as its author would write it, for the messages.

use proc_macro::{Delimiter, Group, Punct, Spacing, Span, TokenStream, TokenTree};

/// `at_span!((MARKER) TOKENS...)` emits `TOKENS` with every token's span set to the span of
/// `MARKER` (one token tree, e.g. a variable's name or its declaration).
///
/// Only the span changes, so paths whose meaning depends on their span (`$crate`, names
/// local to a macro) must not be among `TOKENS`: bring them in first with a `use`.
#[proc_macro]
pub fn at_span(input: TokenStream) -> TokenStream {
    let mut tokens = input.into_iter();
    let span = match tokens.next() {
        Some(TokenTree::Group(marker)) => marker
            .stream()
            .into_iter()
            .next()
            .map_or(marker.span(), |t| t.span()),
        _ => return error(Span::call_site(), "at_span!: expected `(MARKER) TOKENS...`"),
    };
    respan(tokens.collect(), span)
}

fn respan(stream: TokenStream, span: Span) -> TokenStream {
    stream
        .into_iter()
        .map(|token| match token {
            TokenTree::Group(group) => {
                let mut inner = Group::new(group.delimiter(), respan(group.stream(), span));
                inner.set_span(span);
                TokenTree::Group(inner)
            }
            mut other => {
                other.set_span(span);
                other
            }
        })
        .collect()
}

/// `unique_variables!((CALLBACK) { HEADER } [ (NAME) { VARIABLE } ... ])` expands to
/// `CALLBACK! { HEADER { VARIABLE, ... } }` with each NAME's first VARIABLE only, and a
/// `compile_error!` at each later NAME.
#[proc_macro]
pub fn unique_variables(input: TokenStream) -> TokenStream {
    let groups: Vec<Group> = input
        .into_iter()
        .filter_map(|token| match token {
            TokenTree::Group(group) => Some(group),
            _ => None,
        })
        .collect();
    let [callback, header, variables] = groups.as_slice() else {
        return error(
            Span::call_site(),
            "unique_variables!: expected `(CALLBACK) { HEADER } [ (NAME) { VARIABLE } ... ]`",
        );
    };
    let mut seen: Vec<String> = Vec::new();
    let mut variables_kept = TokenStream::new();
    let mut errors = TokenStream::new();
    let mut pairs = variables.stream().into_iter();
    while let (Some(TokenTree::Group(name)), Some(TokenTree::Group(variable))) =
        (pairs.next(), pairs.next())
    {
        let Some(ident) = name.stream().into_iter().next() else {
            continue;
        };
        let text = ident.to_string();
        if seen.contains(&text) {
            errors.extend(error(
                ident.span(),
                &format!("mechanism!: variable `{text}` is declared twice: give each variable its own name"),
            ));
            continue;
        }
        seen.push(text);
        variables_kept.extend(variable.stream());
        variables_kept.extend([TokenTree::Punct(Punct::new(',', Spacing::Alone))]);
    }
    let mut body = header.stream();
    body.extend([TokenTree::Group(Group::new(
        Delimiter::Brace,
        variables_kept,
    ))]);
    let mut out: TokenStream = callback.stream();
    out.extend([
        TokenTree::Punct(Punct::new('!', Spacing::Alone)),
        TokenTree::Group(Group::new(Delimiter::Brace, body)),
    ]);
    out.extend(errors);
    out
}

/// `compile_error!(message)` at `span`.
fn error(span: Span, message: &str) -> TokenStream {
    let tokens: TokenStream = format!("::core::compile_error!({message:?});")
        .parse()
        .expect("a valid token stream");
    respan(tokens, span)
}

/// `source_text!(TOKENS)`: `TOKENS` as a string literal, printed as people write Rust
/// (`Variable::parameter("kg", -1.0).positive()`, not `stringify!`'s
/// `Variable :: parameter("kg", - 1.0).positive()`).
#[proc_macro]
pub fn source_text(input: TokenStream) -> TokenStream {
    let mut text = String::new();
    print_compact(input, &mut text);
    TokenTree::Literal(proc_macro::Literal::string(&text)).into()
}

/// Tokens without spaces but after a comma and between two words.
fn print_compact(stream: TokenStream, out: &mut String) {
    let mut previous_was_word = false;
    for token in stream {
        match &token {
            TokenTree::Group(group) => {
                let (open, close) = match group.delimiter() {
                    Delimiter::Parenthesis => ("(", ")"),
                    Delimiter::Bracket => ("[", "]"),
                    Delimiter::Brace => ("{ ", " }"),
                    Delimiter::None => ("", ""),
                };
                out.push_str(open);
                print_compact(group.stream(), out);
                out.push_str(close);
                previous_was_word = group.delimiter() == Delimiter::None;
            }
            TokenTree::Punct(punct) => {
                out.push(punct.as_char());
                if punct.as_char() == ',' {
                    out.push(' ');
                }
                previous_was_word = false;
            }
            TokenTree::Ident(_) | TokenTree::Literal(_) => {
                if previous_was_word {
                    out.push(' ');
                }
                out.push_str(&token.to_string());
                previous_was_word = true;
            }
        }
    }
}
