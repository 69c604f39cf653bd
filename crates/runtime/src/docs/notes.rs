//! A small Markdown subset for [`Mechanism::NOTES`](crate::model::Mechanism::NOTES) and
//! descriptions: paragraphs (separated by a blank line), `## headings`, `- ` list items,
//! code blocks fenced with three backticks, equations (lines indented by four spaces) and
//! inline `code`, *emphasis* and **strong**. Equations, and inline code that reads as
//! mathematics, become MathML ([`math`](super::math)); what it cannot read stays plain text
//! (`<pre>`, `<code>`). Everything else is text, HTML-escaped.

use super::{escape, math};

/// HTML of `text`.
pub fn render(text: &str) -> String {
    let mut out = String::new();
    let mut para: Vec<&str> = Vec::new();
    let mut list: Vec<String> = Vec::new();
    let mut code: Option<Vec<&str>> = None; // inside a fenced block
    let mut indented: Vec<&str> = Vec::new();

    fn flush_para(out: &mut String, para: &mut Vec<&str>) {
        if !para.is_empty() {
            out.push_str("<p>");
            out.push_str(&inline(&para.join(" ")));
            out.push_str("</p>\n");
            para.clear();
        }
    }
    fn flush_list(out: &mut String, list: &mut Vec<String>) {
        if !list.is_empty() {
            out.push_str("<ul>\n");
            for item in list.iter() {
                out.push_str("<li>");
                out.push_str(&inline(item));
                out.push_str("</li>\n");
            }
            out.push_str("</ul>\n");
            list.clear();
        }
    }
    fn flush_code(out: &mut String, lines: &[&str]) {
        out.push_str("<pre>");
        out.push_str(&escape(lines.join("\n").trim_end()));
        out.push_str("</pre>\n");
    }
    fn flush_equations(out: &mut String, lines: &[&str]) {
        match math::block(&lines.join("\n")) {
            Some(mathml) => out.push_str(&mathml),
            None => flush_code(out, lines),
        }
    }

    let text = dedent(text);
    for line in text.lines() {
        if let Some(block) = code.as_mut() {
            if line.trim_start().starts_with("```") {
                flush_code(&mut out, block);
                code = None;
            } else {
                block.push(line);
            }
            continue;
        }
        if line.starts_with("    ") && para.is_empty() && list.is_empty() {
            indented.push(&line[4..]);
            continue;
        }
        if !indented.is_empty() {
            if line.trim().is_empty() {
                indented.push("");
                continue;
            }
            flush_equations(&mut out, &indented);
            indented.clear();
        }
        let t = line.trim();
        if t.starts_with("```") {
            flush_para(&mut out, &mut para);
            flush_list(&mut out, &mut list);
            code = Some(Vec::new());
        } else if t.is_empty() {
            flush_para(&mut out, &mut para);
            flush_list(&mut out, &mut list);
        } else if let Some(h) = t.strip_prefix("## ").or_else(|| t.strip_prefix("### ")) {
            flush_para(&mut out, &mut para);
            flush_list(&mut out, &mut list);
            out.push_str("<h3>");
            out.push_str(&inline(h));
            out.push_str("</h3>\n");
        } else if let Some(item) = t.strip_prefix("- ").or_else(|| t.strip_prefix("* ")) {
            flush_para(&mut out, &mut para);
            list.push(item.to_string());
        } else if !list.is_empty() && line.starts_with(' ') {
            // continuation of a list item
            let last = list.last_mut().expect("non-empty");
            last.push(' ');
            last.push_str(t);
        } else {
            flush_list(&mut out, &mut list);
            para.push(t);
        }
    }
    if let Some(block) = code {
        flush_code(&mut out, &block);
    }
    if !indented.is_empty() {
        flush_equations(&mut out, &indented);
    }
    flush_para(&mut out, &mut para);
    flush_list(&mut out, &mut list);
    out
}

/// Removes the indentation common to all non-blank lines (notes written inside an indented
/// Rust string literal).
pub(super) fn dedent(text: &str) -> String {
    let indent = text
        .lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| l.len() - l.trim_start().len())
        .min()
        .unwrap_or(0);
    text.lines()
        .map(|l| {
            if l.len() >= indent {
                &l[indent..]
            } else {
                l.trim_start()
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// Inline markup: `code` (an equation as MathML), **strong**, *emphasis*.
fn inline(text: &str) -> String {
    let mut out = String::new();
    let mut rest = text;
    while !rest.is_empty() {
        if let Some(after) = rest.strip_prefix('`') {
            if let Some(end) = after.find('`') {
                out.push_str(&code_span(&after[..end]));
                rest = &after[end + 1..];
                continue;
            }
        }
        if let Some(after) = rest.strip_prefix("**") {
            if let Some(end) = after.find("**") {
                out.push_str("<strong>");
                out.push_str(&inline(&after[..end]));
                out.push_str("</strong>");
                rest = &after[end + 2..];
                continue;
            }
        }
        if let Some(after) = rest.strip_prefix('*') {
            if let Some(end) = after.find('*') {
                if end > 0 && !after.starts_with(' ') {
                    out.push_str("<em>");
                    out.push_str(&inline(&after[..end]));
                    out.push_str("</em>");
                    rest = &after[end + 1..];
                    continue;
                }
            }
        }
        let c = rest.chars().next().expect("non-empty");
        out.push_str(&escape(&c.to_string()));
        rest = &rest[c.len_utf8()..];
    }
    out
}

/// An inline `code` span: inline MathML when it reads as mathematics, else `<code>`.
fn code_span(code: &str) -> String {
    math::is_math(code)
        .then(|| math::inline(code))
        .flatten()
        .unwrap_or_else(|| format!("<code>{}</code>", escape(code)))
}
