//! The symbols a `.tbd` text stub (TAPI v4 YAML) says its library exports, read line by line:
//! every document's `exports:` and `reexports:` items (`- targets: [...]` then lists of
//! `symbols`, `weak-symbols`, `thread-local-symbols`, `objc-classes`, `objc-eh-types`,
//! `objc-ivars`), the lists `[ a, 'b', ... ]` possibly spanning lines.

use super::Arch;
use std::collections::BTreeSet;

/// The symbols a `.tbd` text stub (TAPI v4 YAML, as zig's libSystem.tbd) exports for `arch`
/// (targets `x86_64-macos` for X86_64; `arm64-macos` or `arm64e-macos` for Arm64), over all
/// its documents (zig's file has a document per re-exported sub-library), including
/// `symbols`, `weak-symbols`, `thread-local-symbols` lists, and `objc-classes` as
/// `_OBJC_CLASS_$_<name>` / `_OBJC_METACLASS_$_<name>` (and those of `reexports:`, which the
/// library exports as its own, `objc-eh-types` as `_OBJC_EHTYPE_$_<name>`, `objc-ivars` as
/// `_OBJC_IVAR_$_<name>`).
pub fn tbd_exports(tbd: &str, arch: Arch) -> BTreeSet<String> {
    let wanted: &[&str] = match arch {
        Arch::X86_64 => &["x86_64-macos"],
        Arch::Arm64 => &["arm64-macos", "arm64e-macos"],
    };
    let mut out = BTreeSet::new();
    let mut in_exports = false;
    let mut item = Item::default();
    for entry in entries(tbd) {
        match entry {
            Entry::Document => {
                item.flush(wanted, &mut out);
                in_exports = false;
            }
            Entry::Key {
                top,
                dash,
                key,
                value,
            } => {
                if top {
                    item.flush(wanted, &mut out);
                    in_exports = key == "exports" || key == "reexports";
                    continue;
                }
                if !in_exports {
                    continue;
                }
                if dash {
                    item.flush(wanted, &mut out);
                }
                let list = flow_list(&value);
                match key.as_str() {
                    "targets" => item.targets = list,
                    "symbols" | "weak-symbols" | "thread-local-symbols" => {
                        item.symbols.extend(list)
                    }
                    "objc-classes" => item.symbols.extend(list.iter().flat_map(|c| {
                        [
                            format!("_OBJC_CLASS_$_{c}"),
                            format!("_OBJC_METACLASS_$_{c}"),
                        ]
                    })),
                    "objc-eh-types" => item
                        .symbols
                        .extend(list.iter().map(|c| format!("_OBJC_EHTYPE_$_{c}"))),
                    "objc-ivars" => item
                        .symbols
                        .extend(list.iter().map(|c| format!("_OBJC_IVAR_$_{c}"))),
                    _ => {}
                }
            }
        }
    }
    item.flush(wanted, &mut out);
    out
}

/// One `- targets: [...]` item of an `exports:` list: its targets and symbols.
#[derive(Default)]
struct Item {
    targets: Vec<String>,
    symbols: Vec<String>,
}

impl Item {
    /// Adds the item's symbols to `out` if it is for one of the `wanted` targets, and empties it.
    fn flush(&mut self, wanted: &[&str], out: &mut BTreeSet<String>) {
        let item = std::mem::take(self);
        if item.targets.iter().any(|t| wanted.contains(&t.as_str())) {
            out.extend(item.symbols);
        }
    }
}

/// A line of a stub (with the lines its list continues on).
enum Entry {
    /// `---`: a document starts.
    Document,
    /// `key: value`: `top` when at the start of the line, `dash` when after `- `.
    Key {
        top: bool,
        dash: bool,
        key: String,
        value: String,
    },
}

/// The entries of a stub, in order.
fn entries(tbd: &str) -> Vec<Entry> {
    let mut out = Vec::new();
    let mut lines = tbd.lines();
    while let Some(line) = lines.next() {
        if line.starts_with("---") {
            out.push(Entry::Document);
            continue;
        }
        let text = line.trim_start();
        let (dash, rest) = match text.strip_prefix("- ") {
            Some(rest) => (true, rest.trim_start()),
            None => (false, text),
        };
        let top = !dash && text.len() == line.len();
        let text = rest;
        let Some((key, value)) = text.split_once(':') else {
            continue;
        };
        if key.is_empty()
            || key.starts_with('#')
            || !key
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_')
        {
            continue;
        }
        let mut value = value.trim().to_string();
        while value.starts_with('[') && !closed(&value) {
            let Some(next) = lines.next() else {
                break;
            };
            value.push(' ');
            value.push_str(next.trim());
        }
        out.push(Entry::Key {
            top,
            dash,
            key: key.to_string(),
            value,
        });
    }
    out
}

/// Whether the flow list `value` (starting with `[`) has its closing `]`, outside quotes.
fn closed(value: &str) -> bool {
    scan(value).1
}

/// The items of the flow list `value` (`[ a, 'b', "c" ]`), unquoted; none if not a list.
fn flow_list(value: &str) -> Vec<String> {
    if value.starts_with('[') {
        scan(value).0
    } else {
        Vec::new()
    }
}

/// The items of a flow list, and whether it ends: its `]` read, outside quotes. In single
/// quotes `''` is a quote; in double quotes a backslash escapes the next character.
fn scan(value: &str) -> (Vec<String>, bool) {
    let mut items = Vec::new();
    let mut item = String::new();
    let mut chars = value.chars().skip(1).peekable();
    let mut quote = None;
    let mut done = false;
    while let Some(c) = chars.next() {
        match (quote, c) {
            (Some('\''), '\'') if chars.peek() == Some(&'\'') => {
                chars.next();
                item.push('\'');
            }
            (Some('"'), '\\') => item.extend(chars.next()),
            (Some(q), c) if c == q => quote = None,
            (Some(_), c) => item.push(c),
            (None, '\'' | '"') => quote = Some(c),
            (None, ',' | ']') => {
                let name = item.trim();
                if !name.is_empty() {
                    items.push(name.to_string());
                }
                item.clear();
                if c == ']' {
                    done = true;
                    break;
                }
            }
            (None, c) => item.push(c),
        }
    }
    (items, done)
}
