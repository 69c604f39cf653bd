use super::*;
use crate::model::{Experiment, Scalar};

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
    const EXPERIMENT: Experiment = Experiment {
        start: 0.0,
        stop: 2.0,
        step: 0.01,
        tolerance: 1e-8,
    };
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

#[test]
fn documentation_is_complete_and_deterministic() {
    let html = documentation::<Spring>().unwrap();
    assert_eq!(html, documentation::<Spring>().unwrap());
    for needle in [
        "<h1>Spring</h1>",
        "<svg",
        "</svg>",
        "<pre>m x'' + k x = F</pre>",
        "<li>no damping;</li>",
        "<li><code>F</code> is held over a step.</li>",
        "<h3>Departures</h3>",
        "<em>really</em>",
        "Acceleration &lt;a &amp; b&gt;",
        "<td><code>k</code></td><td class=\"num\">1</td><td>parameter</td><td>tunable</td><td>exact</td><td>N/m</td><td class=\"num\">4</td><td class=\"num\">0</td>",
        "<td class=\"num\">&gt; 0</td>",
        "canSerializeFMUstate",
        "unit: m/s<",
        &crate::contract::guid::<Spring>(),
    ] {
        assert!(html.contains(needle), "missing {needle:?} in\n{html}");
    }
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
    // The independent variable first, with the value reference after the last variable's.
    let time = format!(
        "<tr><td><code>time</code></td><td class=\"num\">{}</td>",
        <Spring as crate::model::Declaration>::VARIABLES.len()
    );
    assert!(html.contains(&time));
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
