use super::*;
use crate::model::{Experiment, MovingCase, Scalar, Variable};

crate::mechanism! {
    /// A mass on a spring: m x'' + k x = 0.
    pub struct Spring / SpringValues {
        /// Mass
        m: Variable::parameter("kg", 1.0).positive(),
        /// Stiffness
        k: Variable::tunable("N/m", 4.0).min(0.0),
        /// Push
        F: Variable::input("N", 0.0),
        /// Position
        x: Variable::state("m", 1.0, "v"),
        /// Velocity
        v: Variable::state("m/s", 0.0, "a"),
        /// Acceleration <a & b>
        a: Variable::output("m/s2"),
    }
}

impl Mechanism for Spring {
    const EXPERIMENT: Experiment = Experiment::until(2.0).step(0.01).tolerance(1e-8);
    const NOTES: &'static str = "
        The equation of motion:

            m x'' + k x = F

        - no damping;
        - `F` is held over a step.

        ## Departures
        None, *really*.
    ";
    fn evaluate<S: Scalar>(v: &mut SpringValues<S>) {
        v.a = (v.F - v.k * v.x) / v.m;
    }
}

#[test]
fn default_experiment_records_every_output_at_every_communication_point() {
    let run = default_experiment::<Spring>().unwrap();
    assert_eq!(run.time.len(), 201);
    assert_eq!(run.stopped, None);
    let names: Vec<&str> = run.signals.iter().map(|(v, _)| v.name).collect();
    assert_eq!(names, ["x", "v"], "the states, not the other outputs");
    let x = &run.signals[0].1;
    assert!((x[200] - (2.0f64 * 2.0).cos()).abs() < 1e-6, "{}", x[200]);
}

/// The text `write` gives, after checking that it gives the same twice and that it
/// contains every one of `needles`.
pub(super) fn complete_and_deterministic(
    write: fn() -> Result<String, String>,
    needles: &[&str],
) -> String {
    let text = write().unwrap();
    assert_eq!(text, write().unwrap());
    for needle in needles {
        assert!(text.contains(needle), "missing {needle:?} in\n{text}");
    }
    text
}

#[test]
fn documentation_is_complete_and_deterministic() {
    let guid = crate::contract::guid::<Spring>();
    let needles = [
        "<h1>Spring</h1>",
        "<svg",
        "</svg>",
        "<math display=\"block\" alttext=\"m x'' + k x = F\"><mi>m</mi><msup><mi>x</mi><mo>″</mo></msup><mo>+</mo>",
        "<li>no damping;</li>",
        "<li><code>F</code> is held over a step.</li>",
        "<h3>Departures</h3>",
        "<em>really</em>",
        "Acceleration &lt;a &amp; b&gt;",
        "<td><code>k</code></td><td class=\"num\">1</td><td>parameter</td><td>tunable</td><td>exact</td><td>N/m</td><td class=\"num\">4</td><td class=\"num\">0</td>",
        "<td class=\"num\">&gt; 0</td>",
        "canSerializeFMUstate",
        "unit: m/s<",
        &guid,
    ];
    let html = complete_and_deterministic(documentation::<Spring>, &needles);
    // the input has no `initial`
    assert!(html.contains(
        "<td><code>F</code></td><td class=\"num\">2</td><td>input</td><td>continuous</td><td></td>"
    ));
}

#[test]
fn write_documentation_follows_the_buffer_protocol() {
    let len =
        unsafe { crate::export::write_text(documentation::<Spring>, std::ptr::null_mut(), 0) };
    let mut buf = vec![0xffu8; len + 1];
    assert_eq!(
        unsafe { crate::export::write_text(documentation::<Spring>, buf.as_mut_ptr(), buf.len()) },
        len
    );
    assert_eq!(buf[len], 0);
    assert_eq!(
        std::str::from_utf8(&buf[..len]).unwrap(),
        documentation::<Spring>().unwrap()
    );
    // too small: nothing written, the length still reported
    let mut small = vec![0xffu8; 8];
    assert_eq!(
        unsafe {
            crate::export::write_text(documentation::<Spring>, small.as_mut_ptr(), small.len())
        },
        len
    );
    assert!(small.iter().all(|&b| b == 0xff));
}

#[test]
fn the_fmi3_page_shows_fmi3s_variables_calls_and_token() {
    let html = super::documentation_fmi3::<Spring>().unwrap();
    assert_eq!(html, super::documentation_fmi3::<Spring>().unwrap());
    assert!(html.contains("<title>Spring: FMI 3.0 FMU</title>"));
    let token = crate::contract::instantiation_token::<Spring>();
    assert!(html.contains(&format!("instantiation token <code>{token}</code>")));
    // The independent variable first, with value reference 0.
    assert!(html.contains("<tr><td><code>time</code></td><td class=\"num\">0</td>"));
    assert!(
        html.contains("fmi3CompletedIntegratorStep")
            || html.contains("needsCompletedIntegratorStep")
    );
    assert!(html.contains("<code>x86_64-linux/Spring.so</code>"));
    assert!(html.contains("<code>x86_64-windows/Spring.dll</code>"));
    assert!(
        !html.contains("fmi2"),
        "an FMI 2.0 name on the FMI 3.0 page"
    );
}

crate::mechanism! {
    /// A pendulum: l φ'' = -g sin φ.
    pub struct Pendulum / PendulumValues {
        /// Length
        l: Variable::parameter("m", 1.0).positive(),
        /// Gravitational acceleration
        g: Variable::parameter("m/s2", 9.81),
        /// Angle from the downward vertical
        phi: Variable::state("rad", 0.0, "phi_dot"),
        /// Angular velocity
        phi_dot: Variable::state("rad/s", 0.0, "phi_ddot"),
        /// Angular acceleration
        phi_ddot: Variable::output("rad/s2"),
    }
}

const SWING: MovingCase = MovingCase {
    name: "swing",
    at_rest: "the pendulum hangs at rest",
    shows: "the pendulum released from rest at 0.5 rad",
    values: &[("phi", 0.5), ("l", 2.0)],
    stop: None,
};

impl Mechanism for Pendulum {
    const EXPERIMENT: Experiment = Experiment::until(5.0).step(0.01).tolerance(1e-8);
    const MOVING_CASE: Option<MovingCase> = Some(SWING);
    fn evaluate<S: Scalar>(v: &mut PendulumValues<S>) {
        v.phi_ddot = -v.g * crate::model::sin(v.phi) / v.l;
    }
}

crate::mechanism! {
    /// A free mass at rest: m x'' = F.
    pub struct Rest / RestValues {
        /// Push
        F: Variable::input("N", 0.0),
        /// Position
        x: Variable::state("m", 0.0, "v"),
        /// Velocity
        v: Variable::state("m/s", 0.0, "a"),
        /// Acceleration
        a: Variable::output("m/s2"),
    }
}

impl Mechanism for Rest {
    const EXPERIMENT: Experiment = Experiment::until(1.0).step(0.1).tolerance(1e-8);
    fn evaluate<S: Scalar>(v: &mut RestValues<S>) {
        v.a = v.F;
    }
}

/// The `points` of every polyline of a page's plot.
fn polylines(html: &str) -> Vec<Vec<(f64, f64)>> {
    html.split("<polyline ")
        .skip(1)
        .map(|line| {
            let points = line.split("points=\"").nth(1).expect("points");
            points[..points.find('"').expect("closed")]
                .split(' ')
                .map(|p| {
                    let (x, y) = p.split_once(',').expect("x,y");
                    (x.parse().expect("x"), y.parse().expect("y"))
                })
                .collect()
        })
        .collect()
}

#[test]
fn a_default_experiment_at_an_equilibrium_stands_still_to_the_last_bit() {
    assert!(default_experiment::<Pendulum>().unwrap().stands_still());
    assert!(default_experiment::<Rest>().unwrap().stands_still());
    assert!(!default_experiment::<Spring>().unwrap().stands_still());
    // one bit off is motion
    let mut run = default_experiment::<Pendulum>().unwrap();
    let last = run.signals[0].1.last_mut().unwrap();
    *last = f64::from_bits(last.to_bits() + 1);
    assert!(!run.stands_still());
}

#[test]
fn the_moving_case_runs_on_the_simulation_with_its_values() {
    let run = moving_case::<Pendulum>(&SWING).unwrap();
    assert!(!run.stands_still());
    let phi = &run.signals[0].1;
    assert_eq!(phi[0], 0.5);
    // it swings from 0.5 rad to -0.5 rad (between communication points) and back
    let lowest = phi.iter().copied().fold(f64::INFINITY, f64::min);
    assert!((lowest + 0.5).abs() < 1e-4, "{lowest}");
    // a misspelled name is an error, not a silent default
    let misspelled = MovingCase {
        values: &[("ph", 0.5)],
        ..SWING
    };
    let error = moving_case::<Pendulum>(&misspelled).unwrap_err();
    assert!(error.contains("`ph` names no variable"), "{error}");
    // its own stop time
    let short = MovingCase {
        stop: Some(1.0),
        ..SWING
    };
    let run = moving_case::<Pendulum>(&short).unwrap();
    assert_eq!((run.time.len(), run.time.last()), (101, Some(&1.0)));
    let sentence = super::experiment::why_the_case::<Pendulum>(&short);
    assert!(
        sentence.ends_with("<code>l</code> = 2 m and stops at 1 s."),
        "{sentence}"
    );
}

#[test]
fn a_page_whose_default_experiment_stands_still_says_why_and_plots_the_moving_case() {
    let html = documentation::<Pendulum>().unwrap();
    assert!(
        html.contains(
            "<p>In the default experiment the pendulum hangs at rest; this is an equilibrium, \
             so every state keeps its start value. The plot below shows the case \
             <code>swing</code> instead: the pendulum released from rest at 0.5 rad. It differs \
             from the default experiment in <code>phi</code> = 0.5 rad and <code>l</code> = 2 m \
             only."
        ),
        "{html}"
    );
    assert!(html.contains("aria-label=\"Outputs of the case swing\""));
    let lines = polylines(&html);
    assert_eq!(lines.len(), 2, "phi and phi_dot");
    for line in &lines {
        assert!(
            line.iter().any(|p| p.1 != line[0].1),
            "a flat line: {line:?}"
        );
    }
    assert_eq!(html, documentation::<Pendulum>().unwrap(), "deterministic");
}

#[test]
fn a_page_that_stands_still_without_a_moving_case_says_so() {
    let html = documentation::<Rest>().unwrap();
    assert!(html
        .contains("<p>In the default experiment nothing moves: every state keeps its start value"));
    assert!(html.contains("aria-label=\"Outputs of the default experiment\""));
    assert!(polylines(&html)
        .iter()
        .all(|line| line.iter().all(|p| p.1 == line[0].1)));
    // a page that moves says nothing of the kind
    let html = documentation::<Spring>().unwrap();
    assert!(!html.contains("In the default experiment"));
    assert!(html.contains("The curves are this FMU's own states"));
}
