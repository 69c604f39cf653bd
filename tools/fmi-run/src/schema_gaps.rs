//! What a legal model description may carry and the `fmi` crate's schema refuses: the gaps
//! this importer works around, so that the crate's limits are not taken for the FMU's faults.
//!
//! fmi-schema 0.8 reads the model description strictly (unknown attributes are errors) and
//! lacks:
//!
//! * on any element, XML's own attributes: namespace declarations (`xmlns`, `xmlns:xsi`, ...)
//!   and the XML Schema instance attributes (`xsi:noNamespaceSchemaLocation`, ...), which
//!   many exporters write on `<fmiModelDescription>` (`unknown field "xmlns:xsi"`). They are
//!   XML's, not FMI's: no FMI element or attribute lives in a namespace;
//! * on FMI 2.0's `<ScalarVariable>`, `canHandleMultipleSetPerTimeInstant` (FMI 2.0.5
//!   section 2.2.7; only Model Exchange inputs use it, and this runner sets each input once
//!   per communication point);
//! * on FMI 3.0's `<Float32>` and `<Float64>` variables, the attributes of their physical
//!   meaning (`quantity`, `unit`, `displayUnit`, `relativeQuantity`, `unbounded`, `nominal`:
//!   FMI 3.0 section 2.4.7.4; its `<Float64Type>` has them), so that every FMU whose
//!   variables carry a unit (every mechfmu FMU does) is refused with `unknown field "unit"
//!   in element "FmiFloat64"`.
//!
//! Nothing of a run depends on any of them, so [`readable_archive`] removes exactly these
//! attributes of exactly these elements from the archive's `modelDescription.xml` before the
//! crate imports it; everything else (the archive, the rest of the XML, the binary) goes to
//! the crate as it is, and is read as strictly as ever.

use std::io::{Cursor, Read, Write};

/// The attributes of FMI 3.0's `<Float32>` and `<Float64>` variables the crate's schema lacks.
pub(crate) const FLOAT_UNIT_ATTRIBUTES: [&str; 6] = [
    "quantity",
    "unit",
    "displayUnit",
    "relativeQuantity",
    "unbounded",
    "nominal",
];

/// Whether the crate is given the model description without the attribute `attribute` of
/// the element `element`.
fn removed(element: &str, attribute: &str) -> bool {
    attribute == "xmlns"
        || attribute.starts_with("xmlns:")
        || attribute.starts_with("xsi:")
        || (matches!(element, "Float64" | "Float32") && FLOAT_UNIT_ATTRIBUTES.contains(&attribute))
        || (element == "ScalarVariable" && attribute == "canHandleMultipleSetPerTimeInstant")
}

/// `xml` without the attributes [`removed`] names (comments, processing instructions,
/// CDATA, end tags and text are copied as they are).
pub(crate) fn strip(xml: &str) -> String {
    let mut out = String::with_capacity(xml.len());
    let mut rest = xml;
    while let Some(at) = rest.find('<') {
        out.push_str(&rest[..at]);
        rest = &rest[at..];
        let end = match ["<!--", "<![CDATA[", "<?"]
            .iter()
            .zip(["-->", "]]>", "?>"])
            .find(|(open, _)| rest.starts_with(**open))
        {
            Some((_, close)) => rest.find(close).map_or(rest.len(), |e| e + close.len()),
            None => tag_end(rest),
        };
        let tag = &rest[..end];
        if tag.starts_with("<!") || tag.starts_with("<?") || tag.starts_with("</") {
            out.push_str(tag);
        } else {
            let name_end = tag[1..]
                .find(|c: char| c.is_whitespace() || c == '>' || c == '/')
                .map_or(tag.len(), |e| e + 1);
            out.push_str(&kept_attributes(tag, name_end));
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

/// The start tag `tag` (its name ending at `name_end`) without the [`removed`] attributes.
fn kept_attributes(tag: &str, name_end: usize) -> String {
    let element = &tag[1..name_end];
    let mut out = tag[..name_end].to_string();
    let mut s = &tag[name_end..];
    loop {
        let trimmed = s.trim_start();
        let space = &s[..s.len() - trimmed.len()];
        let Some(eq) = trimmed.find('=') else {
            out.push_str(s); // "/>" or ">"
            break;
        };
        let attribute = trimmed[..eq].trim();
        let value = trimmed[eq + 1..].trim_start();
        let Some(q) = value.chars().next().filter(|c| *c == '"' || *c == '\'') else {
            out.push_str(s);
            break;
        };
        let close = value[1..].find(q).map_or(value.len(), |e| e + 2);
        let whole = trimmed.len() - value.len() + close;
        if !removed(element, attribute) {
            out.push_str(space);
            out.push_str(&trimmed[..whole]);
        }
        s = &trimmed[whole..];
    }
    out
}

/// The FMU archive `bytes` with its `modelDescription.xml` passed through [`strip`].
pub(crate) fn readable_archive(bytes: &[u8]) -> Result<Vec<u8>, String> {
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

/// The crate's import of the FMU at `path` (FMI 2.0's or 3.0's, as `Imp` is), its model
/// description without what [`removed`] names.
pub(crate) fn import<Imp: fmi::traits::FmiImport>(path: &std::path::Path) -> Result<Imp, String> {
    let cannot = |e: &dyn std::fmt::Display| format!("cannot import {}: {e}", path.display());
    let bytes = std::fs::read(path).map_err(|e| cannot(&e))?;
    let archive = readable_archive(&bytes).map_err(|e| cannot(&e))?;
    fmi::import::new(Cursor::new(archive)).map_err(|e| cannot(&e))
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

    #[test]
    fn strips_xml_namespace_attributes_and_fmi2_multiple_set() {
        let xml = r#"<?xml version="1.0" encoding="UTF-8"?>
<!-- the FMU's "description" > here -->
<fmiModelDescription xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance" fmiVersion="2.0"
  xsi:noNamespaceSchemaLocation="fmiModelDescription.xsd" xmlns="urn:x" modelName="M">
  <ScalarVariable name="u" valueReference="0" canHandleMultipleSetPerTimeInstant="false"><Real start="0"/></ScalarVariable>
  <Real unit="m" canHandleMultipleSetPerTimeInstant="true"/><![CDATA[ <a xmlns="x"> ]]>
</fmiModelDescription>"#;
        let want = r#"<?xml version="1.0" encoding="UTF-8"?>
<!-- the FMU's "description" > here -->
<fmiModelDescription fmiVersion="2.0" modelName="M">
  <ScalarVariable name="u" valueReference="0"><Real start="0"/></ScalarVariable>
  <Real unit="m" canHandleMultipleSetPerTimeInstant="true"/><![CDATA[ <a xmlns="x"> ]]>
</fmiModelDescription>"#;
        assert_eq!(strip(xml), want);
    }
}
