use quick_xml::events::Event;
use quick_xml::{Reader, XmlVersion};

use super::*;
use crate::model::{Declaration, Experiment, Scalar};

crate::mechanism! {
    /// A payload swinging under a trolley whose acceleration is prescribed:
    ///     a test mechanism   with   an input state derivative.
    pub struct Swing / SwingValues {
        /// Payload mass
        m: Variable::parameter("kg", 2.0).positive(),
        /// Cable length
        l: Variable::parameter("m", 1.5).positive(),
        /// Gravity
        g: Variable::parameter("m/s2", 9.81),
        /// Rotary damping of the pivot
        c: Variable::tunable("N.m.s/rad", 0.0).min(0.0),
        /// Trolley acceleration
        x_ddot: Variable::input("m/s2", 0.0),
        /// Trolley position
        x: Variable::state("m", 0.0, "x_dot"),
        /// Trolley velocity
        x_dot: Variable::state("m/s", 0.0, "x_ddot"),
        /// Cable angle from the vertical
        phi: Variable::state("rad", 0.2, "phi_dot"),
        /// Cable angular velocity
        phi_dot: Variable::state("rad/s", 0.0, "phi_ddot"),
        /// Cable angular acceleration
        phi_ddot: Variable::output("rad/s2"),
        /// Cable tension
        T: Variable::output("N"),
        /// Tension over weight
        load_factor: Variable::output("1"),
        /// Small-angle natural frequency sqrt(g/l)
        omega_0: Variable::calculated("rad/s"),
    }
}

impl Mechanism for Swing {
    const EXPERIMENT: Experiment = Experiment {
        start: 0.0,
        stop: 20.0,
        step: 0.01,
        tolerance: 1e-8,
    };

    fn calculate(v: &mut SwingValues<f64>) -> Result<(), String> {
        v.omega_0 = (v.g / v.l).sqrt();
        Ok(())
    }

    fn evaluate<S: Scalar>(v: &mut SwingValues<S>) {
        let (s, c) = (v.phi.sin(), v.phi.cos());
        v.phi_ddot = -(v.g * s + v.x_ddot * c) / v.l - v.c * v.phi_dot / (v.m * v.l * v.l);
        v.T = v.m * (v.g * c + v.l * v.phi_dot * v.phi_dot - v.x_ddot * s);
        v.load_factor = v.T / (v.m * v.g);
    }
}

/// An element (start or empty tag) read back: name and attributes.
#[derive(Debug)]
pub(super) struct Element {
    pub(super) name: String,
    pub(super) attributes: Vec<(String, String)>,
}

impl Element {
    pub(super) fn get(&self, key: &str) -> Option<&str> {
        self.attributes
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| v.as_str())
    }
}

/// Parses the XML back with quick-xml's reader (all well-formedness checks on), checking
/// that every tag is closed; returns the elements in document order with their depth.
pub(super) fn parse_back(xml: &str) -> Vec<(usize, Element)> {
    let mut reader = Reader::from_str(xml);
    reader.config_mut().trim_text(true);
    reader.config_mut().enable_all_checks(true);
    let mut stack: Vec<String> = Vec::new();
    let mut elements = Vec::new();
    let mut declaration = false;
    loop {
        let event = reader.read_event().expect("well-formed XML");
        let (start, empty) = match &event {
            Event::Start(e) => (Some(e.clone()), false),
            Event::Empty(e) => (Some(e.clone()), true),
            Event::End(e) => {
                let name = e.name().into_inner().to_string();
                assert_eq!(stack.pop().as_deref(), Some(name.as_str()));
                (None, false)
            }
            Event::Decl(_) => {
                declaration = true;
                (None, false)
            }
            Event::Eof => break,
            // Annotations' text (FMI 3.0's arrays name their FMI 2.0 scalars).
            Event::Text(_) => (None, false),
            other => panic!("unexpected event {other:?}"),
        };
        if let Some(e) = start {
            let name = e.name().into_inner().to_string();
            let attributes = e
                .attributes()
                .map(|a| {
                    let a = a.expect("well-formed attribute, not duplicated");
                    (
                        a.key.into_inner().to_string(),
                        a.normalized_value(XmlVersion::Explicit1_0)
                            .unwrap()
                            .into_owned(),
                    )
                })
                .collect();
            elements.push((
                stack.len(),
                Element {
                    name: name.clone(),
                    attributes,
                },
            ));
            if !empty {
                stack.push(name);
            }
        }
    }
    assert!(declaration, "no XML declaration");
    assert!(stack.is_empty(), "unclosed {stack:?}");
    assert_eq!(elements.iter().filter(|(d, _)| *d == 0).count(), 1);
    elements
}

/// Swing's XML declaring no optional capability (the tests of the full set use
/// `model_description_for` with `CAPABILITIES` explicitly).
fn swing() -> String {
    model_description_for::<Swing>(&Capabilities::NONE).unwrap()
}

pub(super) fn find<'a>(elements: &'a [(usize, Element)], name: &str) -> Vec<&'a Element> {
    elements
        .iter()
        .filter(|(_, e)| e.name == name)
        .map(|(_, e)| e)
        .collect()
}

#[test]
fn well_formed_and_in_schema_order() {
    let xml = swing();
    assert!(xml.starts_with("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<fmiModelDescription"));
    assert!(xml.ends_with("</fmiModelDescription>\n"));
    let elements = parse_back(&xml);
    let top: Vec<&str> = elements
        .iter()
        .filter(|(d, _)| *d == 1)
        .map(|(_, e)| e.name.as_str())
        .collect();
    assert_eq!(
        top,
        [
            "ModelExchange",
            "CoSimulation",
            "UnitDefinitions",
            "TypeDefinitions",
            "LogCategories",
            "DefaultExperiment",
            "ModelVariables",
            "ModelStructure"
        ]
    );
    let root = &elements[0].1;
    assert_eq!(root.name, "fmiModelDescription");
    assert_eq!(root.get("fmiVersion"), Some("2.0"));
    assert_eq!(root.get("modelName"), Some("Swing"));
    assert_eq!(
        root.get("guid"),
        Some(crate::contract::guid::<Swing>().as_str())
    );
    assert_eq!(
        root.get("description"),
        Some(
            "A payload swinging under a trolley whose acceleration is prescribed: \
             a test mechanism with an input state derivative."
        )
    );
    assert_eq!(
        root.get("generationTool"),
        Some(concat!("mechfmu ", env!("CARGO_PKG_VERSION")))
    );
    assert_eq!(root.get("generationDateAndTime"), None);
    assert_eq!(
        find(&elements, "ScalarVariable").len(),
        Swing::VARIABLES.len()
    );
}

#[test]
fn deterministic() {
    assert_eq!(swing(), swing());
    assert_eq!(
        model_description::<Swing>(),
        model_description_for::<Swing>(&CAPABILITIES)
    );
    assert_eq!(model_description::<Swing>(), model_description::<Swing>());
}

#[test]
fn capabilities_none_is_written_as_specified() {
    let xml = swing();
    // Swing has no monitor and no projection: nothing to do at a completed step.
    assert!(xml.contains(
        "<ModelExchange modelIdentifier=\"Swing\" needsExecutionTool=\"false\" \
         completedIntegratorStepNotNeeded=\"true\" canBeInstantiatedOnlyOncePerProcess=\"false\" \
         canNotUseMemoryManagementFunctions=\"true\" canGetAndSetFMUstate=\"false\" \
         canSerializeFMUstate=\"false\" providesDirectionalDerivative=\"false\"/>"
    ));
    assert!(xml.contains(
        "<CoSimulation modelIdentifier=\"Swing\" needsExecutionTool=\"false\" \
         canHandleVariableCommunicationStepSize=\"true\" canInterpolateInputs=\"false\" \
         maxOutputDerivativeOrder=\"0\" canRunAsynchronuously=\"false\" \
         canBeInstantiatedOnlyOncePerProcess=\"false\" canNotUseMemoryManagementFunctions=\"true\" \
         canGetAndSetFMUstate=\"false\" canSerializeFMUstate=\"false\" \
         providesDirectionalDerivative=\"false\"/>"
    ));
    assert!(xml.contains(
        "<DefaultExperiment startTime=\"0.0\" stopTime=\"20.0\" tolerance=\"1e-8\" stepSize=\"0.01\"/>"
    ));
}

#[test]
fn units_types_and_display_units() {
    let xml = swing();
    // Every unit once, in order of first use, with its base-unit exponents.
    let elements = parse_back(&xml);
    let units: Vec<&str> = find(&elements, "Unit")
        .iter()
        .map(|u| u.get("name").unwrap())
        .collect();
    assert_eq!(
        units,
        [
            "kg",
            "m",
            "m/s2",
            "N.m.s/rad",
            "m/s",
            "rad",
            "rad/s",
            "rad/s2",
            "N",
            "1"
        ]
    );
    assert!(xml.contains(
        "    <Unit name=\"N.m.s/rad\">\n      <BaseUnit kg=\"1\" m=\"2\" s=\"-1\" rad=\"-1\"/>\n    </Unit>"
    ));
    assert!(xml.contains("    <Unit name=\"1\">\n      <BaseUnit/>\n    </Unit>"));
    assert!(xml.contains(
        "    <Unit name=\"rad/s\">\n      <BaseUnit s=\"-1\" rad=\"1\"/>\n      \
         <DisplayUnit name=\"deg/s\" factor=\"57.29577951308232\"/>\n    </Unit>"
    ));
    assert!(xml.contains(
        "<SimpleType name=\"AngularAcceleration\">\n      \
         <Real quantity=\"AngularAcceleration\" unit=\"rad/s2\" displayUnit=\"deg/s2\"/>"
    ));
    assert!(xml.contains("<SimpleType name=\"Dimensionless\">\n      <Real unit=\"1\"/>"));
    // A variable refers to its type; angles show in degrees.
    assert!(xml.contains(
        "<ScalarVariable name=\"phi\" valueReference=\"7\" description=\"Cable angle from the vertical\" \
         causality=\"output\" variability=\"continuous\" initial=\"exact\">\n      \
         <Real declaredType=\"Angle\" start=\"0.2\" displayUnit=\"deg\"/>"
    ));
    assert!(xml.contains("<Real declaredType=\"Mass\" start=\"2.0\" min=\"0.0\"/>"));
}

#[test]
fn derivative_attribute_points_at_the_state() {
    let elements = parse_back(&swing());
    let variables = find(&elements, "ScalarVariable");
    let reals = find(&elements, "Real");
    // Reals of the SimpleTypes come first.
    let reals = &reals[reals.len() - variables.len()..];
    let derivative = |name: &str| {
        let i = variables
            .iter()
            .position(|v| v.get("name") == Some(name))
            .unwrap();
        reals[i].get("derivative")
    };
    // ScalarVariable indices: x 6, x_dot 7, phi 8, phi_dot 9.
    assert_eq!(derivative("x_dot"), Some("6"));
    assert_eq!(derivative("x_ddot"), Some("7")); // an input
    assert_eq!(derivative("phi_dot"), Some("8"));
    assert_eq!(derivative("phi_ddot"), Some("9"));
    assert_eq!(derivative("x"), None);
    assert_eq!(derivative("T"), None);
}

#[test]
fn model_exchange_has_its_derivatives_whatever_the_capabilities() {
    // Model Exchange needs `<Derivatives>` and the states among the knowns (FMI 2.0.5,
    // section 2.2.8), with or without directional derivatives.
    let none = swing();
    let all = model_description_for::<Swing>(&Capabilities {
        provides_directional_derivative: true,
        ..Capabilities::NONE
    })
    .unwrap();
    let structure = |xml: &str| xml[xml.find("<ModelStructure>").unwrap()..].to_string();
    assert!(none.contains("<Derivatives>"));
    assert_eq!(structure(&none), structure(&all));
}

#[test]
fn model_structure_with_directional_derivatives() {
    let capabilities = Capabilities {
        provides_directional_derivative: true,
        ..Capabilities::NONE
    };
    let xml = model_description_for::<Swing>(&capabilities).unwrap();
    parse_back(&xml);
    assert!(xml.contains("providesDirectionalDerivative=\"true\""));
    // States as knowns; Derivatives in state order: x_dot, x_ddot (the input), phi_dot,
    // phi_ddot.
    assert!(
        xml.contains("<Unknown index=\"6\" dependencies=\"6\" dependenciesKind=\"dependent\"/>")
    );
    assert!(xml.contains(
        "    <Derivatives>\n      \
         <Unknown index=\"7\" dependencies=\"7\" dependenciesKind=\"dependent\"/>\n      \
         <Unknown index=\"5\" dependencies=\"5\" dependenciesKind=\"dependent\"/>\n      \
         <Unknown index=\"9\" dependencies=\"9\" dependenciesKind=\"dependent\"/>\n      \
         <Unknown index=\"10\" dependencies=\"5 8 9\" \
         dependenciesKind=\"dependent dependent dependent\"/>\n    \
         </Derivatives>"
    ));
    assert!(xml.contains(
        "<Unknown index=\"11\" dependencies=\"5 8 9\" \
         dependenciesKind=\"dependent dependent dependent\"/>"
    ));
}

#[test]
fn an_unknown_unit_is_an_error_naming_it() {
    // `mechanism!` rejects it at compile time; a declaration made by hand meets it here
    let odd = [Variable::parameter("furlong", 1.0).named("d", "Distance")];
    let experiment = Swing::EXPERIMENT;
    let Err(err) = super::shared::check_declaration("Odd", &odd, experiment) else {
        panic!("a declaration with the unit \"furlong\" was accepted");
    };
    assert!(
        err.contains("Odd") && err.contains("`d`") && err.contains("\"furlong\""),
        "{err}"
    );
}

#[test]
fn numbers() {
    assert_eq!(real(20.0), "20.0");
    assert_eq!(real(0.01), "0.01");
    assert_eq!(real(1e-8), "1e-8");
    assert_eq!(real(-0.0), "0.0");
    assert_eq!(real(9.81), "9.81");
    assert_eq!(real(180.0 / std::f64::consts::PI), "57.29577951308232");
    for x in [0.1, 1.0 / 3.0, 6.02214076e23, 1e-300, -2.5] {
        assert_eq!(real(x).parse::<f64>(), Ok(x));
    }
}

#[test]
fn descriptions_are_one_line() {
    assert_eq!(one_line("  a\n   b  c \n"), "a b c");
    assert_eq!(one_line(""), "");
}
