use super::*;
use crate::model::{Array, Declaration, Experiment, Scalar};
use crate::xml::tests::{find, names, parse_in_schema_order, Element};

const EXPERIMENT: Experiment = Experiment::until(10.0).step(0.01).tolerance(1e-6);

crate::mechanism! {
    /// A mass driven by F0 sin(w t) and an input force, against viscous damping.
    pub struct Drive / DriveValues {
        /// Mass
        m: Variable::parameter("kg", 1.0).positive(),
        /// Damping
        c: Variable::tunable("N.s/m", 0.1).min(0.0),
        /// Drive amplitude
        F0: Variable::parameter("N", 1.0),
        /// Drive frequency
        w: Variable::parameter("rad/s", 2.0),
        /// Input force
        u: Variable::input("N", 0.0),
        /// Position
        x: Variable::state("m", 0.5, "v"),
        /// Velocity
        v: Variable::state("m/s", 0.0, "a"),
        /// Acceleration
        a: Variable::output("m/s2"),
        /// Momentum
        p: Variable::output("kg.m/s"),
        /// Half the drive frequency
        half_w: Variable::calculated("rad/s"),
    }
}

impl Mechanism for Drive {
    const EXPERIMENT: Experiment = EXPERIMENT;
    const MONITORED: bool = true;
    const EVENT_INDICATORS: &'static [&'static str] = &["x"];
    fn calculate(v: &mut DriveValues<f64>) -> Result<(), String> {
        v.half_w = v.w / 2.0;
        Ok(())
    }
    fn evaluate<S: Scalar>(v: &mut DriveValues<S>) {
        v.a = (v.F0 * (v.w * v.time).sin() + v.u - v.c * v.v) / v.m;
        v.p = v.m * v.v;
    }
}

// Drive's FMI 3.0 value references, its variables' 1-based places: m 1, c 2, F0 3, w 4, u 5,
// x 6, v 7, a 8, p 9, half_w 10; time, listed last, 0.

crate::mechanism! {
    /// Two masses on springs, with a symmetric mass matrix.
    pub struct Plate / PlateValues {
        /// Mass matrix, first diagonal element
        m_11: Variable::parameter("kg", 2.0).positive(),
        /// Mass matrix, off the diagonal
        m_12: Variable::parameter("kg", 0.5),
        /// Mass matrix, second diagonal element
        m_22: Variable::parameter("kg", 3.0).positive(),
        /// Stiffness
        k: Variable::tunable("N/m", 4.0).min(0.0),
        /// First force
        f_1: Variable::input("N", 0.0),
        /// Second force
        f_2: Variable::input("N", 1.0),
        /// First position
        x_1: Variable::state("m", 0.1, "v_1"),
        /// Second position
        x_2: Variable::state("m", 0.2, "v_2"),
        /// First velocity
        v_1: Variable::state("m/s", 0.0, "a_1"),
        /// Second velocity
        v_2: Variable::state("m/s", 0.0, "a_2"),
        /// First acceleration
        a_1: Variable::output("m/s2"),
        /// Second acceleration
        a_2: Variable::output("m/s2"),
        /// Energy
        E: Variable::output("J"),
        /// Determinant of the mass matrix
        det: Variable::calculated("kg2").fixed(),
    }
}

impl Mechanism for Plate {
    const EXPERIMENT: Experiment = EXPERIMENT;
    const ARRAYS: &'static [Array] = &[
        Array::new(
            "M",
            "Mass matrix",
            &[2, 2],
            &["m_11", "m_12", "m_12", "m_22"],
        ),
        Array::new("f", "Forces", &[2], &["f_1", "f_2"]),
        Array::new("x", "Positions", &[2], &["x_1", "x_2"]),
        Array::new("v", "Velocities", &[2], &["v_1", "v_2"]),
        Array::new("a", "Accelerations", &[2], &["a_1", "a_2"]),
    ];
    fn calculate(v: &mut PlateValues<f64>) -> Result<(), String> {
        v.det = v.m_11 * v.m_22 - v.m_12 * v.m_12;
        (v.det > 0.0)
            .then_some(())
            .ok_or("the mass matrix is not positive definite".into())
    }
    fn evaluate<S: Scalar>(v: &mut PlateValues<S>) {
        let (r_1, r_2) = (v.f_1 - v.k * v.x_1, v.f_2 - v.k * v.x_2);
        let det = v.m_11 * v.m_22 - v.m_12 * v.m_12;
        v.a_1 = (v.m_22 * r_1 - v.m_12 * r_2) / det;
        v.a_2 = (v.m_11 * r_2 - v.m_12 * r_1) / det;
    }
    fn outputs<S: Scalar>(v: &mut PlateValues<S>) {
        let kinetic =
            v.m_11 * v.v_1 * v.v_1 + (v.m_12 + v.m_12) * v.v_1 * v.v_2 + v.m_22 * v.v_2 * v.v_2;
        v.E = (kinetic + v.k * (v.x_1 * v.x_1 + v.x_2 * v.x_2)) / (S::one() + S::one());
    }
}

// Plate's FMI 3.0 value references, its variables' 1-based places: M 1 (m_11, m_12, m_22),
// k 2, f 3 (f_1, f_2), x 4 (x_1, x_2), v 5 (v_1, v_2), a 6 (a_1, a_2), E 7, det 8; time, listed last, 0.

fn variables(xml: &str) -> Vec<(usize, Element)> {
    let elements = parse_in_schema_order(xml);
    assert_eq!(elements[0].1.name, "fmiModelDescription");
    elements
}

/// The `<Float64>` named `name`.
fn float64<'a>(elements: &'a [(usize, Element)], name: &str) -> &'a Element {
    find(elements, "Float64")
        .into_iter()
        .find(|e| e.get("name") == Some(name))
        .unwrap_or_else(|| panic!("no variable {name}"))
}

#[test]
fn well_formed_and_in_schema_order() {
    let xml = model_description::<Drive>().unwrap();
    let elements = variables(&xml);
    let root = &elements[0].1;
    let token = crate::contract::instantiation_token::<Drive>();
    assert_eq!(root.get("fmiVersion"), Some("3.0"));
    assert_eq!(root.get("modelName"), Some("Drive"));
    assert_eq!(root.get("instantiationToken"), Some(token.as_str()));
    assert_ne!(token, crate::contract::guid::<Drive>());
    assert_eq!(root.get("guid"), None);
    assert_eq!(root.get("variableNamingConvention"), Some("structured"));
    assert_eq!(
        root.get("description"),
        Some("A mass driven by F0 sin(w t) and an input force, against viscous damping.")
    );
    // Every declared scalar, and the time.
    assert_eq!(find(&elements, "Float64").len(), Drive::VARIABLES.len() + 1);
    assert!(xml.contains("<Category name=\"logStatusWarning\" description=\"Messages of calls that return fmi3Warning\"/>"));
    assert!(!xml.contains("fmi2"));
}

#[test]
fn deterministic() {
    assert_eq!(model_description::<Plate>(), model_description::<Plate>());
    assert_eq!(model_description::<Drive>(), model_description::<Drive>());
}

#[test]
fn capability_flags_are_spelled_and_ordered_as_the_schema_has_them() {
    let drive = model_description::<Drive>().unwrap();
    // Drive has a monitor and an event indicator.
    assert!(drive.contains(
        "<ModelExchange modelIdentifier=\"Drive\" canGetAndSetFMUState=\"true\" \
         canSerializeFMUState=\"true\" providesDirectionalDerivatives=\"true\" \
         providesAdjointDerivatives=\"true\" needsCompletedIntegratorStep=\"true\"/>"
    ));
    assert!(drive.contains(
        "<CoSimulation modelIdentifier=\"Drive\" canGetAndSetFMUState=\"true\" \
         canSerializeFMUState=\"true\" providesDirectionalDerivatives=\"true\" \
         providesAdjointDerivatives=\"true\" canHandleVariableCommunicationStepSize=\"true\" \
         maxOutputDerivativeOrder=\"1\" providesIntermediateUpdate=\"false\" \
         mightReturnEarlyFromDoStep=\"true\" canReturnEarlyAfterIntermediateUpdate=\"false\" \
         hasEventMode=\"true\"/>"
    ));
    let plate = model_description::<Plate>().unwrap();
    assert!(plate.contains("needsCompletedIntegratorStep=\"false\"/>"));
    assert!(plate.contains("mightReturnEarlyFromDoStep=\"false\""));
    assert!(!plate.contains("<EventIndicator"));
    assert!(drive.contains(
        "    <EventIndicator valueReference=\"6\" dependencies=\"6\" dependenciesKind=\"constant\"/>\n  \
         </ModelStructure>"
    ));
}

#[test]
fn time_comes_last_with_value_reference_0() {
    for xml in [model_description::<Drive>(), model_description::<Plate>()] {
        let xml = xml.unwrap();
        let elements = variables(&xml);
        let last = *find(&elements, "Float64").last().unwrap();
        assert_eq!(last.get("name"), Some("time"));
        assert_eq!(last.get("causality"), Some("independent"));
        assert_eq!(last.get("variability"), Some("continuous"));
        assert_eq!((last.get("start"), last.get("initial")), (None, None));
    }
    let plate = model_description::<Plate>().unwrap();
    assert!(plate.contains(
        "<Float64 name=\"time\" valueReference=\"0\" description=\"Simulation time\" \
         causality=\"independent\" variability=\"continuous\"/>"
    ));
}

/// A variable's value reference is its 1-based place in the document (`time`, listed last,
/// is 0), so an importer that takes `derivative` for a 1-based place, as FMI 2.0 has it,
/// finds the state.
#[test]
fn value_references_are_places_in_the_document() {
    for xml in [model_description::<Drive>(), model_description::<Plate>()] {
        let xml = xml.unwrap();
        let elements = variables(&xml);
        let floats = find(&elements, "Float64");
        let references: Vec<usize> = (floats.iter())
            .map(|e| e.get("valueReference").unwrap().parse().unwrap())
            .collect();
        let mut places: Vec<usize> = (1..floats.len()).collect();
        places.push(0);
        assert_eq!(references, places);
        // Each state comes before its derivative, at the place its reference names.
        for (at, e) in floats.iter().enumerate() {
            if let Some(state) = e.get("derivative") {
                let state: usize = state.parse().unwrap();
                assert!(state <= at, "{e:?}");
                let named = floats[state - 1].get("valueReference");
                assert_eq!(named, Some(state.to_string().as_str()));
            }
        }
    }
}

#[test]
fn arrays_have_dimensions_and_a_start_value_per_element() {
    let xml = model_description::<Plate>().unwrap();
    // The symmetric matrix: m_12 at two places; no min (the off-diagonal element has none).
    assert!(xml.contains(
        "    <Float64 name=\"M\" valueReference=\"1\" description=\"Mass matrix\" \
         causality=\"parameter\" variability=\"fixed\" declaredType=\"Mass\" initial=\"exact\" \
         unit=\"kg\" start=\"2.0 0.5 0.5 3.0\">\n      \
         <Annotations>\n        \
         <Annotation type=\"org.mechfmu.scalars\">m_11 m_12 m_12 m_22</Annotation>\n      \
         </Annotations>\n      \
         <Dimension start=\"2\"/>\n      <Dimension start=\"2\"/>\n    </Float64>"
    ));
    assert!(xml.contains(
        "    <Float64 name=\"f\" valueReference=\"3\" description=\"Forces\" causality=\"input\" \
         variability=\"continuous\" declaredType=\"Force\" unit=\"N\" start=\"0.0 1.0\">\n      \
         <Annotations>\n        \
         <Annotation type=\"org.mechfmu.scalars\">f_1 f_2</Annotation>\n      \
         </Annotations>\n      \
         <Dimension start=\"2\"/>\n    </Float64>"
    ));
    // A scalar keeps its bound; a unit without a quantity has no type.
    assert!(xml.contains(
        "<Float64 name=\"k\" valueReference=\"2\" description=\"Stiffness\" \
         causality=\"parameter\" variability=\"tunable\" declaredType=\"TranslationalSpringConstant\" \
         initial=\"exact\" unit=\"N/m\" min=\"0.0\" start=\"4.0\"/>"
    ));
    assert!(xml.contains(
        "<Float64 name=\"det\" valueReference=\"8\" description=\"Determinant of the mass matrix\" \
         causality=\"calculatedParameter\" variability=\"fixed\" initial=\"calculated\" unit=\"kg2\"/>"
    ));
    let elements = variables(&xml);
    assert_eq!(
        names(&elements, "Float64Type").join(" "),
        "Mass TranslationalSpringConstant Force Length Velocity Acceleration Energy"
    );
    // Calculated arrays and outputs have no start.
    assert_eq!(float64(&elements, "a").get("start"), None);
    assert_eq!(find(&elements, "Dimension").len(), 2 + 4);
}

#[test]
fn derivatives_point_at_their_states() {
    let plate = model_description::<Plate>().unwrap();
    let elements = variables(&plate);
    let derivative = |name: &str| float64(&elements, name).get("derivative");
    assert_eq!(derivative("x"), None);
    assert_eq!(derivative("v"), Some("4"));
    assert_eq!(derivative("a"), Some("5"));
    let drive = model_description::<Drive>().unwrap();
    let elements = variables(&drive);
    let derivative = |name: &str| float64(&elements, name).get("derivative");
    assert_eq!(derivative("v"), Some("6"));
    assert_eq!(derivative("a"), Some("7"));
    // Angles' rates show in degrees.
    assert_eq!(float64(&elements, "w").get("displayUnit"), Some("deg/s"));
    assert!(drive.contains(
        "<Float64Type name=\"AngularVelocity\" quantity=\"AngularVelocity\" unit=\"rad/s\" \
         displayUnit=\"deg/s\"/>"
    ));
}

/// `<tag valueReference=".." dependencies=".." dependenciesKind=".."/>`.
fn unknown(tag: &str, vr: usize, dependencies: &[(usize, DependencyKind)]) -> String {
    let references: Vec<String> = dependencies.iter().map(|(k, _)| k.to_string()).collect();
    let kinds: Vec<&str> = dependencies.iter().map(|(_, kind)| kind.as_str()).collect();
    format!(
        "<{tag} valueReference=\"{vr}\" dependencies=\"{}\" dependenciesKind=\"{}\"/>",
        references.join(" "),
        kinds.join(" ")
    )
}

/// `knowns` each entering as `dependent`.
fn dependent(knowns: &[usize]) -> Vec<(usize, DependencyKind)> {
    knowns.iter().map(|&k| (k, Dependent)).collect()
}

use DependencyKind::{Constant, Dependent, Fixed, Tunable};

/// The elements of `<ModelStructure>`, one per line.
fn structure(xml: &str) -> Vec<String> {
    let start = xml.find("<ModelStructure>").unwrap();
    let end = xml.find("</ModelStructure>").unwrap();
    xml[start..end]
        .lines()
        .skip(1)
        .map(|l| l.trim().to_string())
        .filter(|l| !l.is_empty())
        .collect()
}

#[test]
fn model_structure_of_scalars_has_the_parameters_and_the_time_as_knowns() {
    let xml = model_description::<Drive>().unwrap();
    // a = (F0 sin(w t) + u - c v) / m: by 1/m (m fixed) in u, by -c/m (c tunable) in v;
    // nonlinear in the time and the parameters.
    let mut a = dependent(&[0, 1, 2, 3, 4]);
    a.extend([(5, Fixed), (7, Tunable)]);
    assert_eq!(
        structure(&xml),
        [
            unknown("Output", 6, &[(6, Constant)]),
            unknown("Output", 7, &[(7, Constant)]),
            unknown("Output", 8, &a),
            unknown("Output", 9, &[(1, Dependent), (7, Fixed)]),
            unknown("ContinuousStateDerivative", 7, &[(7, Constant)]),
            unknown("ContinuousStateDerivative", 8, &a),
            // In Initialization Mode the parameters are knowns: no factor is constant.
            unknown("InitialUnknown", 8, &dependent(&[0, 1, 2, 3, 4, 5, 7])),
            unknown("InitialUnknown", 9, &dependent(&[1, 7])),
            unknown("InitialUnknown", 10, &dependent(&[4])),
            unknown("EventIndicator", 6, &[(6, Constant)]),
        ]
    );
}

#[test]
fn model_structure_lists_an_array_once() {
    let xml = model_description::<Plate>().unwrap();
    // a = M^-1 (f - k x): by the fixed M^-1 in f, by -k M^-1 (k tunable) in x.
    let a = [(1, Dependent), (2, Dependent), (3, Fixed), (4, Tunable)];
    assert_eq!(
        structure(&xml),
        [
            unknown("Output", 4, &[(4, Constant)]),
            unknown("Output", 5, &[(5, Constant)]),
            unknown("Output", 6, &a),
            unknown("Output", 7, &dependent(&[1, 2, 4, 5])),
            unknown("ContinuousStateDerivative", 5, &[(5, Constant)]),
            unknown("ContinuousStateDerivative", 6, &a),
            unknown("InitialUnknown", 6, &dependent(&[1, 2, 3, 4])),
            unknown("InitialUnknown", 7, &dependent(&[1, 2, 4, 5])),
            unknown("InitialUnknown", 8, &dependent(&[1])),
        ]
    );
}

mod refused;

crate::mechanism! {
    /// x' = k sin(t) - x: a derivative that depends on every known of FMI 3.0.
    pub struct Decay / DecayValues {
        /// Drive
        k: Variable::parameter("m/s", 1.0),
        /// Position
        x: Variable::state("m", 1.0, "x_dot"),
        /// Its rate
        x_dot: Variable::local("m/s"),
        /// Twice the position
        y: Variable::output("m"),
    }
}

impl Mechanism for Decay {
    const EXPERIMENT: Experiment = EXPERIMENT;
    fn evaluate<S: Scalar>(v: &mut DecayValues<S>) {
        v.x_dot = v.k * v.time.sin() - v.x;
        v.y = v.x + v.x;
    }
}

#[test]
fn an_unknown_of_every_known_is_written_without_dependencies() {
    // Value references: time 0, k 1, x 2, x_dot 3, y 4. The derivative depends on the
    // time, k and x, all the knowns of its list: FMI 3.0 then omits the list, which keeps
    // the time's value reference 0 out of it. The outputs depend on x alone.
    let xml = model_description::<Decay>().unwrap();
    assert_eq!(
        structure(&xml),
        [
            unknown("Output", 2, &[(2, Constant)]),
            unknown("Output", 4, &[(2, Constant)]),
            "<ContinuousStateDerivative valueReference=\"3\"/>".to_string(),
            "<InitialUnknown valueReference=\"3\"/>".to_string(),
            unknown("InitialUnknown", 4, &[(2, Constant)]),
        ]
    );
}
