//! The one gap of the `fmi` crate's FMI 3.0 schema this importer works around.
//!
//! fmi-schema 0.8 (and rust-fmi's main branch as of this writing) declares `<Float32>` and
//! `<Float64>` variables without the attributes FMI 3.0 gives them for their physical
//! meaning (`quantity`, `unit`, `displayUnit`, `relativeQuantity`, `unbounded`, `nominal`:
//! section 2.4.7.4 of the standard; its `<Float64Type>` has them), and reads the model
//! description strictly: an FMU whose variables carry a unit (every mechfmu FMU does, as FMI
//! 3.0 allows) is refused with `unknown field "unit" in element "FmiFloat64"`. Nothing of a
//! run depends on them, so [`without_unit_attributes`] removes exactly these attributes of
//! exactly these elements from the archive's `modelDescription.xml` before the crate imports
//! it; everything else (the archive, the rest of the XML, the binary) goes to the crate as
//! it is, and is read as strictly as ever.

use std::io::{Cursor, Read, Write};

/// The attributes of `<Float32>` and `<Float64>` variables the crate's schema lacks.
pub(crate) const UNREAD: [&str; 6] = [
    "quantity",
    "unit",
    "displayUnit",
    "relativeQuantity",
    "unbounded",
    "nominal",
];

/// `xml` without the [`UNREAD`] attributes of its `<Float32 ...>` and `<Float64 ...>` start
/// tags (not of `<Float64Type>` or any other element).
pub(crate) fn strip(xml: &str) -> String {
    let mut out = String::with_capacity(xml.len());
    let mut rest = xml;
    while let Some(at) = rest.find('<') {
        out.push_str(&rest[..at]);
        rest = &rest[at..];
        let name_end = rest[1..]
            .find(|c: char| c.is_whitespace() || c == '>' || c == '/')
            .map_or(rest.len(), |e| e + 1);
        let name = &rest[1..name_end];
        let end = tag_end(rest);
        if name == "Float64" || name == "Float32" {
            out.push_str(&name_and_kept_attributes(&rest[..end], name_end));
        } else {
            out.push_str(&rest[..end]);
        }
        rest = &rest[end..];
    }
    out.push_str(rest);
    out
}

/// The length of the tag starting `s` (up to and including its `>`, quotes respected).
fn tag_end(s: &str) -> usize {
    let mut quote = None;
    for (i, c) in s.char_indices().skip(1) {
        match (quote, c) {
            (None, '"' | '\'') => quote = Some(c),
            (Some(q), c) if c == q => quote = None,
            (None, '>') => return i + 1,
            _ => {}
        }
    }
    s.len()
}

/// The start tag `tag` (its name ending at `name_end`) without the [`UNREAD`] attributes.
fn name_and_kept_attributes(tag: &str, name_end: usize) -> String {
    let mut out = tag[..name_end].to_string();
    let mut s = &tag[name_end..];
    loop {
        let trimmed = s.trim_start();
        let space = &s[..s.len() - trimmed.len()];
        let Some(eq) = trimmed.find('=') else {
            out.push_str(s); // "/>" or ">"
            break;
        };
        let attr = trimmed[..eq].trim();
        let value = trimmed[eq + 1..].trim_start();
        let Some(q) = value.chars().next().filter(|c| *c == '"' || *c == '\'') else {
            out.push_str(s);
            break;
        };
        let close = value[1..].find(q).map_or(value.len(), |e| e + 2);
        let whole = trimmed.len() - value.len() + close;
        if !UNREAD.contains(&attr) {
            out.push_str(space);
            out.push_str(&trimmed[..whole]);
        }
        s = &trimmed[whole..];
    }
    out
}

/// The FMU archive `bytes` with its `modelDescription.xml` passed through [`strip`].
pub(crate) fn without_unit_attributes(bytes: &[u8]) -> Result<Vec<u8>, String> {
    let mut archive =
        zip::ZipArchive::new(Cursor::new(bytes)).map_err(|e| format!("not a zip archive: {e}"))?;
    let mut writer = zip::ZipWriter::new(Cursor::new(Vec::with_capacity(bytes.len())));
    // stored: the archive is read once, at once (compressing the binary again costs more)
    let options =
        zip::write::SimpleFileOptions::default().compression_method(zip::CompressionMethod::Stored);
    for i in 0..archive.len() {
        let mut file = archive
            .by_index(i)
            .map_err(|e| format!("cannot read entry {i} of the archive: {e}"))?;
        let name = file.name().to_string();
        if file.is_dir() {
            writer
                .add_directory(name.as_str(), options)
                .map_err(|e| format!("cannot copy {name}: {e}"))?;
            continue;
        }
        let mut data = Vec::with_capacity(file.size() as usize);
        file.read_to_end(&mut data)
            .map_err(|e| format!("cannot read {name}: {e}"))?;
        if name == "modelDescription.xml" {
            let xml = String::from_utf8(data)
                .map_err(|_| "modelDescription.xml is not UTF-8".to_string())?;
            data = strip(&xml).into_bytes();
        }
        writer
            .start_file(name.as_str(), options)
            .map_err(|e| format!("cannot copy {name}: {e}"))?;
        writer
            .write_all(&data)
            .map_err(|e| format!("cannot copy {name}: {e}"))?;
    }
    let out = writer
        .finish()
        .map_err(|e| format!("cannot write the archive: {e}"))?;
    Ok(out.into_inner())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strips_the_unit_attributes_of_float_variables_only() {
        let xml = r#"<Float64Type name="T" unit="m"/>
  <Float64 name="x" valueReference="1" unit="m" displayUnit="mm" description="a &gt; b = 'c'" start="1.0">
    <Dimension start="3"/>
  </Float64>
  <Float32 name='y' quantity='Q' valueReference='2'/><Float64name unit="m"/>"#;
        let want = r#"<Float64Type name="T" unit="m"/>
  <Float64 name="x" valueReference="1" description="a &gt; b = 'c'" start="1.0">
    <Dimension start="3"/>
  </Float64>
  <Float32 name='y' valueReference='2'/><Float64name unit="m"/>"#;
        assert_eq!(strip(xml), want);
        assert_eq!(strip("no tags"), "no tags");
    }
}
