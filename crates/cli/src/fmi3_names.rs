//! The names of the FMI 2.0 scalars in an FMU's FMI 3.0 version: an array variable's
//! elements are the scalars its annotation `org.mechfmu.scalars` lists (row-major), named
//! `array[i,j]` (1-based) there. `mechfmu build` renames the columns of the reference files
//! it packages into an FMI 3.0 FMU with it.

use mechfmu::model::element_name;
use mechfmu::xml::fmi3::SCALARS_ANNOTATION;
use quick_xml::events::Event;
use quick_xml::{Reader, XmlVersion};

/// For every scalar that is an array element in FMI 3.0: (its FMI 2.0 name, its FMI 3.0
/// element name), from the FMI 3.0 model description `xml`. A scalar at several places (a
/// symmetric matrix) is named by its first.
pub fn element_names(xml: &str) -> Result<Vec<(String, String)>, String> {
    let mut reader = Reader::from_str(xml);
    let mut names: Vec<(String, String)> = Vec::new();
    // The array being read: its name, dimensions and scalars.
    let mut array: Option<(String, Vec<usize>, Vec<String>)> = None;
    let mut in_scalars = false;
    loop {
        let event = reader
            .read_event()
            .map_err(|e| format!("the FMI 3.0 model description does not parse: {e}"))?;
        match event {
            Event::Start(e) if e.name().into_inner() == "Float64" => {
                let name = attribute(&e, "name")?.unwrap_or_default();
                array = Some((name, Vec::new(), Vec::new()));
            }
            Event::Start(e) if e.name().into_inner() == "Annotation" => {
                in_scalars = attribute(&e, "type")?.as_deref() == Some(SCALARS_ANNOTATION);
            }
            Event::Text(t) if in_scalars => {
                let text = t.xml_content(XmlVersion::Explicit1_0);
                if let Some((_, _, scalars)) = array.as_mut() {
                    scalars.extend(text.split_whitespace().map(str::to_string));
                }
            }
            Event::End(e) if e.name().into_inner() == "Annotation" => in_scalars = false,
            Event::Empty(e) if e.name().into_inner() == "Dimension" => {
                let start = attribute(&e, "start")?.unwrap_or_default();
                let n = start
                    .parse()
                    .map_err(|_| format!("a <Dimension start=\"{start}\"> is not a size"))?;
                if let Some((_, dimensions, _)) = array.as_mut() {
                    dimensions.push(n);
                }
            }
            Event::End(e) if e.name().into_inner() == "Float64" => {
                if let Some((name, dimensions, scalars)) = array.take() {
                    for (k, scalar) in scalars.into_iter().enumerate() {
                        if !names.iter().any(|(s, _)| *s == scalar) {
                            names.push((scalar, element_name(&name, &dimensions, k)));
                        }
                    }
                }
            }
            Event::Eof => break,
            _ => {}
        }
    }
    Ok(names)
}

fn attribute(e: &quick_xml::events::BytesStart, key: &str) -> Result<Option<String>, String> {
    for a in e.attributes() {
        let a = a.map_err(|e| format!("bad attribute: {e}"))?;
        if a.key.into_inner() == key {
            let value = a
                .normalized_value(XmlVersion::Explicit1_0)
                .map_err(|e| format!("bad attribute value: {e}"))?;
            return Ok(Some(value.into_owned()));
        }
    }
    Ok(None)
}

/// `csv` with the quoted column names of its first line renamed by `names`.
pub fn rename_columns(csv: &[u8], names: &[(String, String)]) -> Vec<u8> {
    let text = String::from_utf8_lossy(csv);
    let (header, rest) = text.split_once('\n').unwrap_or((&text, ""));
    let renamed: Vec<String> = header
        .trim_end_matches('\r')
        .split(',')
        .map(|column| {
            let bare = column.trim().trim_matches('"');
            match names.iter().find(|(scalar, _)| scalar == bare) {
                Some((_, element)) => format!("\"{element}\""),
                None => column.to_string(),
            }
        })
        .collect();
    let mut out = renamed.join(",");
    out.push('\n');
    out.push_str(rest);
    out.into_bytes()
}

#[cfg(test)]
mod tests {
    use super::*;

    const XML: &str = r#"<fmiModelDescription><ModelVariables>
<Float64 name="time" valueReference="3"/>
<Float64 name="I" valueReference="0"><Annotations><Annotation type="org.mechfmu.scalars">a b b c</Annotation></Annotations><Dimension start="2"/><Dimension start="2"/></Float64>
<Float64 name="g" valueReference="2"/>
</ModelVariables></fmiModelDescription>"#;

    #[test]
    fn elements_are_named_row_major_and_a_repeated_scalar_by_its_first_place() {
        let names = element_names(XML).unwrap();
        let expected = [("a", "I[1,1]"), ("b", "I[1,2]"), ("c", "I[2,2]")];
        assert_eq!(names, expected.map(|(s, e)| (s.to_string(), e.to_string())));
    }

    #[test]
    fn only_the_header_is_renamed() {
        let names = element_names(XML).unwrap();
        let csv = b"\"time\",\"a\",\"g\",\"c\"\n0,1,2,3\n";
        assert_eq!(
            String::from_utf8(rename_columns(csv, &names)).unwrap(),
            "\"time\",\"I[1,1]\",\"g\",\"I[2,2]\"\n0,1,2,3\n"
        );
    }
}
