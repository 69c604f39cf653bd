use super::*;
use quick_xml::events::Event;
use quick_xml::Reader;

/// `θ̇` as MathML: the letter with its dot as an accent.
const THETA_DOT: &str = "<mover><mi>θ</mi><mo>˙</mo></mover>";
const THIN: &str = "<mspace width=\"0.1667em\"/>";

/// The MathML between `<math …>` and `</math>`.
fn body(math: &str) -> &str {
    let start = math.find('>').expect("an opening tag") + 1;
    let end = math.rfind("</math>").expect("a closing tag");
    &math[start..end]
}

/// Reads `xml` to the end with quick-xml's checks on: tags balanced, attributes and
/// character references well-formed.
fn assert_well_formed(xml: &str) {
    let mut reader = Reader::from_str(xml);
    reader.config_mut().enable_all_checks(true);
    let mut depth = 0i32;
    loop {
        match reader.read_event() {
            Ok(Event::Start(e)) => {
                for attribute in e.attributes() {
                    let attribute = attribute.unwrap_or_else(|err| panic!("{err} in {xml}"));
                    attribute
                        .normalized_value(quick_xml::XmlVersion::Implicit1_0)
                        .unwrap_or_else(|err| panic!("{err} in {xml}"));
                }
                depth += 1;
            }
            Ok(Event::End(_)) => depth -= 1,
            Ok(Event::GeneralRef(r)) => {
                // a character reference, or one of XML's own five entities
                let known = if r.is_char_ref() {
                    matches!(r.resolve_char_ref(), Ok(Some(_)))
                } else {
                    matches!(&*r.into_inner(), "lt" | "gt" | "amp" | "quot" | "apos")
                };
                assert!(known, "an unknown reference in {xml}");
            }
            Ok(Event::Eof) => break,
            Ok(_) => {}
            Err(err) => panic!("{err} in {xml}"),
        }
    }
    assert_eq!(depth, 0, "{xml}");
}

#[test]
fn a_dotted_variable_is_its_letter_with_an_accent_and_its_square_a_superscript_apart() {
    let math = inline("θ̇² x").unwrap();
    assert_eq!(
        math,
        format!("<math alttext=\"θ̇² x\"><msup>{THETA_DOT}<mn>2</mn></msup><mi>x</mi></math>")
    );
    // precomposed letters (ẋ, ẍ) and the second derivative's two dots
    assert_eq!(
        body(&inline("ẍ + φ̈").unwrap()),
        "<mover><mi>x</mi><mo>¨</mo></mover><mo>+</mo>\
         <mover><mi>φ</mi><mo>¨</mo></mover>"
    );
    // a dotted, subscripted, squared variable: ẋ1²
    assert_eq!(
        body(&inline("½ m1 ẋ1²").unwrap()),
        "<mn>½</mn><msub><mi>m</mi><mn>1</mn></msub>\
         <msubsup><mover><mi>x</mi><mo>˙</mo></mover><mn>1</mn><mn>2</mn></msubsup>"
    );
}

#[test]
fn names_numbers_operators_subscripts_and_functions() {
    assert_eq!(
        body(&inline("l φ̈ = -g sin φ").unwrap()),
        format!(
            "<mi>l</mi><mover><mi>φ</mi><mo>¨</mo></mover><mo>=</mo>\
             <mo form=\"prefix\">−</mo><mi>g</mi>{THIN}<mi>sin</mi><mo>&#x2061;</mo>{THIN}<mi>φ</mi>"
        )
    );
    assert_eq!(
        body(&inline("i_A = (cos θ, sin θ)").unwrap()),
        format!(
            "<msub><mi>i</mi><mi>A</mi></msub><mo>=</mo><mrow><mo>(</mo>\
             <mi>cos</mi><mo>&#x2061;</mo>{THIN}<mi>θ</mi><mo>,</mo>\
             <mi>sin</mi><mo>&#x2061;</mo>{THIN}<mi>θ</mi><mo>)</mo></mrow>"
        )
    );
    // spelled Greek names, inequalities, escaping
    assert_eq!(
        body(&inline("omega_n < tau ≤ 2.5").unwrap()),
        "<msub><mi>ω</mi><mi>n</mi></msub><mo>&lt;</mo><mi>τ</mi><mo>≤</mo><mn>2.5</mn>"
    );
    // a squared function, the transpose, an inverse, primes
    assert_eq!(
        body(&inline("m sin² s Rᵀ I_B⁻¹ x''").unwrap()),
        format!(
            "<mi>m</mi>{THIN}<msup><mi>sin</mi><mn>2</mn></msup><mo>&#x2061;</mo>{THIN}<mi>s</mi>\
             <msup><mi>R</mi><mi>T</mi></msup>\
             <msubsup><mi>I</mi><mi>B</mi><mrow><mo>−</mo><mn>1</mn></mrow></msubsup>\
             <msup><mi>x</mi><mo>″</mo></msup>"
        )
    );
}

#[test]
fn square_roots_and_superscripts_on_brackets() {
    assert_eq!(
        body(&inline("sqrt(F² + (τ/x)²)").unwrap()),
        "<msqrt><msup><mi>F</mi><mn>2</mn></msup><mo>+</mo>\
         <msup><mrow><mo>(</mo><mi>τ</mi><mo>/</mo><mi>x</mi><mo>)</mo></mrow><mn>2</mn></msup></msqrt>"
    );
    assert_eq!(
        body(&inline("(|q|² - 1)").unwrap()),
        "<mrow><mo>(</mo><msup><mrow><mo>|</mo><mi>q</mi><mo>|</mo></mrow><mn>2</mn></msup>\
         <mo>−</mo><mn>1</mn><mo>)</mo></mrow>"
    );
}

#[test]
fn equations_on_one_line_stay_apart_and_words_between_them_are_text() {
    let math =
        block("F = T sin s        τ = x T cos s        so T = sqrt(F² + (τ/x)²) while T ≥ 0")
            .unwrap();
    assert_eq!(math.matches("<math display=\"block\"").count(), 1);
    assert_eq!(math.matches("<mspace width=\"2em\"/>").count(), 2);
    assert!(math.contains("<mtext>so</mtext>"), "{math}");
    assert!(math.contains("<mtext>while</mtext>"), "{math}");
    assert!(math.contains("alttext=\"F = T sin s        τ = x T cos s        so T"));
    // words beside an equation
    let math = block("q̇ = ½ q ⊗ (0, ω)        orientation").unwrap();
    assert!(math.ends_with("<mspace width=\"2em\"/><mtext>orientation</mtext></math>\n"));
}

#[test]
fn lines_align_on_their_relation_and_spaces_that_align_stay_in_the_equation() {
    let math = block("l φ̈ = -g sin φ\nT   = m g").unwrap();
    assert!(math.contains("<mtable class=\"equations\">"), "{math}");
    assert_eq!(
        math.matches("<mtd class=\"relation\"><mo>=</mo></mtd>")
            .count(),
        2
    );
    assert!(math.contains("<mtd class=\"lhs\" columnalign=\"right\"><mi>T</mi></mtd>"));
    assert!(!math.contains("2em"), "alignment spaces are no gap: {math}");
    assert!(math.contains("alttext=\"l φ̈ = -g sin φ&#10;T   = m g\""));
    // a line without a relation: every line left-aligned on its own
    let math = block("a = b\nc + d").unwrap();
    assert!(!math.contains("relation"));
    assert_eq!(math.matches("<mtd class=\"rhs\"").count(), 2);
}

#[test]
fn a_matrix_written_in_rows_is_a_matrix_and_blank_lines_part_displays() {
    let text = "M = [ μ            0   ]\n    [ 0   -m l x sin s ]\n\nf = [ F ]\n    [ τ ]";
    let math = block(text).unwrap();
    assert_eq!(math.matches("<math display=\"block\"").count(), 2);
    assert!(math.contains(
        "<mi>M</mi><mo>=</mo><mrow><mo>[</mo><mtable><mtr><mtd><mi>μ</mi></mtd><mtd><mn>0</mn></mtd></mtr>\
         <mtr><mtd><mn>0</mn></mtd><mtd><mo form=\"prefix\">−</mo><mi>m</mi>"
    ), "{math}");
    // rows of different lengths are no matrix, and no equation either
    assert_eq!(block("M = [ a   b ]\n    [ c ]"), None);
}

#[test]
fn what_it_cannot_read_gives_none_never_garbled_output() {
    for text in [
        "x = (a + b",
        "x = a)",
        "² x",
        "x = sqrt y",
        "a & b",
        "y = {x]",
        "x = +²",
    ] {
        assert_eq!(block(text), None, "{text:?}");
        assert_eq!(inline(text), None, "{text:?}");
    }
}

#[test]
fn plain_identifiers_are_code_and_equations_math() {
    for code in [
        "x_ddot",
        "fmi2Warning",
        "E_payload",
        "x(t)",
        "4l",
        "xy",
        "I",
        "+",
        "--release",
        "mechfmu validate",
    ] {
        assert!(!is_math(code), "{code}");
    }
    for code in [
        "φ",
        "T < 0",
        "x ≤ 0",
        "θ(t)",
        "c = 0",
        "ẍ - θ̇² x",
        "omega_n = sqrt(k/m)",
        "I_B⁻¹",
        "-g Z",
        "diag(k, m g l)",
        "m l",
        "-d/dt E_pot",
    ] {
        assert!(is_math(code), "{code}");
    }
}

/// The notes of every mechanism of the repository (`fmus/*/src/lib.rs`), as written.
fn every_mechanisms_notes() -> Vec<(String, String)> {
    let fmus = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fmus");
    let mut notes = Vec::new();
    for entry in std::fs::read_dir(&fmus).expect("the fmus directory") {
        let source = entry.expect("an entry").path().join("src/lib.rs");
        let Ok(text) = std::fs::read_to_string(&source) else {
            continue;
        };
        const START: &str = "const NOTES: &'static str = \"";
        if let Some(at) = text.find(START) {
            let rest = &text[at + START.len()..];
            let end = rest.find("\";").expect("the end of the notes");
            notes.push((source.display().to_string(), rest[..end].to_string()));
        }
    }
    notes.sort();
    notes
}

#[test]
fn every_equation_of_every_mechanisms_notes_converts_to_well_formed_mathml() {
    let notes = every_mechanisms_notes();
    assert!(notes.len() >= 6, "{notes:?}");
    for (source, text) in &notes {
        let html = crate::docs::notes::render(text);
        assert!(
            !html.contains("<pre>"),
            "{source}: an equation fell back:\n{html}"
        );
        assert!(html.contains("<math display=\"block\""), "{source}");
        assert_eq!(html, crate::docs::notes::render(text), "deterministic");
        // every inline span that reads as mathematics converts
        for (k, span) in text.split('`').enumerate() {
            if k % 2 == 1 && is_math(span) {
                let math = inline(span).unwrap_or_else(|| panic!("{source}: `{span}`"));
                assert_well_formed(&math);
            }
        }
        let mut at = 0;
        while let Some(start) = html[at..].find("<math") {
            let end = html[at + start..].find("</math>").expect("closed") + "</math>".len();
            assert_well_formed(&html[at + start..at + start + end]);
            at += start + end;
        }
    }
}
