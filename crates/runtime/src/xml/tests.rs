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
    const EXPERIMENT: Experiment = Experiment::until(20.0).step(0.01).tolerance(1e-8);

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

/// The `name` attribute of each `<element>`.
pub(super) fn names<'a>(elements: &'a [(usize, Element)], element: &str) -> Vec<&'a str> {
    find(elements, element)
        .into_iter()
        .map(|e| e.get("name").unwrap())
        .collect()
}

/// The elements of a model description of either standard, checked to be one document
/// whose top-level elements come in the order both schemas give them.
pub(super) fn parse_in_schema_order(xml: &str) -> Vec<(usize, Element)> {
    assert!(xml.starts_with("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<fmiModelDescription"));
    assert!(xml.ends_with("</fmiModelDescription>\n"));
    let elements = parse_back(xml);
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
    elements
}

#[test]
fn well_formed_and_in_schema_order() {
    let xml = swing();
    let elements = parse_in_schema_order(&xml);
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
    assert_eq!(
        names(&elements, "Unit").join(" "),
        "kg m m/s2 N.m.s/rad m/s rad rad/s rad/s2 N 1"
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
    // A variable refers to its type, and carries its unit too; angles show in degrees.
    assert!(xml.contains(
        "<ScalarVariable name=\"phi\" valueReference=\"7\" description=\"Cable angle from the vertical\" \
         causality=\"output\" variability=\"continuous\" initial=\"exact\">\n      \
         <Real declaredType=\"Angle\" unit=\"rad\" displayUnit=\"deg\" start=\"0.2\"/>"
    ));
    assert!(xml.contains("<Real declaredType=\"Mass\" unit=\"kg\" min=\"0.0\" start=\"2.0\"/>"));
}

/// Importers that read `unit` on `<Real>` only (OMSimulator) see every variable's unit:
/// each `<Real>` of a variable has its type's unit and display unit (FMI 2.0.5 section
/// 2.2.7: the attributes of section 2.2.3 on the variable itself).
#[test]
fn every_real_has_the_unit_and_display_unit_of_its_type() {
    let elements = parse_back(&swing());
    let mut types = std::collections::HashMap::new();
    let mut current = None;
    let mut reals = 0;
    for (_, e) in &elements {
        match e.name.as_str() {
            "SimpleType" => current = e.get("name"),
            "ScalarVariable" => current = None,
            "Real" if current.is_some() => {
                types.insert(current.unwrap(), (e.get("unit"), e.get("displayUnit")));
            }
            "Real" => {
                reals += 1;
                let declared = e.get("declaredType").expect("every Real has a type");
                assert_eq!(
                    (e.get("unit"), e.get("displayUnit")),
                    types[declared],
                    "{e:?}"
                );
                assert!(e.get("unit").is_some(), "{e:?}");
            }
            _ => {}
        }
    }
    assert_eq!(reals, Swing::VARIABLES.len());
}

/// The `ScalarVariable`s and their `<Real>`s, in the same order (the `<Real>`s of the
/// `SimpleType`s come first, and are left out).
fn variables_and_their_reals(elements: &[(usize, Element)]) -> (Vec<&Element>, Vec<&Element>) {
    let variables = find(elements, "ScalarVariable");
    let mut reals = find(elements, "Real");
    reals.drain(..reals.len() - variables.len());
    (variables, reals)
}

#[test]
fn derivative_attribute_points_at_the_state() {
    let elements = parse_back(&swing());
    let (variables, reals) = variables_and_their_reals(&elements);
    let derivative = |name: &str| {
        let i = variables
            .iter()
            .position(|v| v.get("name") == Some(name))
            .unwrap();
        reals[i].get("derivative")
    };
    // ScalarVariable indices: x 5, x_dot 6, x_ddot 7 (an input declared before both, written
    // after them), phi 8, phi_dot 9.
    assert_eq!(derivative("x_dot"), Some("5"));
    assert_eq!(derivative("x_ddot"), Some("6"));
    assert_eq!(derivative("phi_dot"), Some("8"));
    assert_eq!(derivative("phi_ddot"), Some("9"));
    assert_eq!(derivative("x"), None);
    assert_eq!(derivative("T"), None);
}

/// Every `derivative` points back, to a `ScalarVariable` written before it, and every
/// variable keeps its value reference (the declaration's order).
#[test]
fn states_come_before_their_derivatives_with_their_value_references() {
    let elements = parse_back(&swing());
    let (variables, reals) = variables_and_their_reals(&elements);
    for (i, real) in reals.iter().enumerate() {
        if let Some(state) = real.get("derivative") {
            let state: usize = state.parse().unwrap();
            assert!(state <= i, "{:?} points at {state}", variables[i]);
        }
    }
    for (vr, declared) in Swing::VARIABLES.iter().enumerate() {
        let written = variables
            .iter()
            .find(|v| v.get("name") == Some(declared.name))
            .unwrap();
        assert_eq!(written.get("valueReference"), Some(vr.to_string().as_str()));
    }
    let names: Vec<&str> = variables.iter().map(|v| v.get("name").unwrap()).collect();
    assert_eq!(
        names[..9],
        ["m", "l", "g", "c", "x", "x_dot", "x_ddot", "phi", "phi_dot"]
    );
}

#[test]
fn the_order_puts_each_chain_of_states_before_its_derivative() {
    // 0 is the derivative of 2, 2 of 3; 1 of 4; 5 stands alone.
    let state_of = |i: usize| match i {
        0 => Some(2),
        2 => Some(3),
        1 => Some(4),
        _ => None,
    };
    assert_eq!(
        crate::model::states_before_derivatives(6, state_of),
        [3, 2, 0, 4, 1, 5]
    );
    // Declared in order already: unchanged.
    let state_of = |i: usize| (i % 2 == 1).then(|| i - 1);
    assert_eq!(
        crate::model::states_before_derivatives(4, state_of),
        [0, 1, 2, 3]
    );
    // A circle (no declaration has one) still writes each variable once.
    let mut circle = crate::model::states_before_derivatives(3, |i| Some((i + 1) % 3));
    circle.sort_unstable();
    assert_eq!(circle, [0, 1, 2]);
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
    // States as knowns (an output that is a state: itself, by a factor 1); Derivatives in
    // state order: x_dot, x_ddot (the input), phi_dot, phi_ddot, whose factor of phi_dot is
    // the tunable damping's -c/(m l^2).
    assert!(xml.contains("<Unknown index=\"5\" dependencies=\"5\" dependenciesKind=\"constant\"/>"));
    assert!(xml.contains(
        "    <Derivatives>\n      \
         <Unknown index=\"6\" dependencies=\"6\" dependenciesKind=\"constant\"/>\n      \
         <Unknown index=\"7\" dependencies=\"7\" dependenciesKind=\"constant\"/>\n      \
         <Unknown index=\"9\" dependencies=\"9\" dependenciesKind=\"constant\"/>\n      \
         <Unknown index=\"10\" dependencies=\"7 8 9\" \
         dependenciesKind=\"dependent dependent tunable\"/>\n    \
         </Derivatives>"
    ));
    assert!(xml.contains(
        "<Unknown index=\"11\" dependencies=\"7 8 9\" \
         dependenciesKind=\"dependent dependent dependent\"/>"
    ));
    // Initial unknowns by index; in Initialization Mode the parameters are knowns too.
    assert!(xml.contains(
        "    <InitialUnknowns>\n      \
         <Unknown index=\"10\" dependencies=\"1 2 3 4 7 8 9\" \
         dependenciesKind=\"dependent dependent dependent dependent dependent dependent dependent\"/>"
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
