//! Arrays and names the FMI 3.0 writer refuses, each an error naming the problem.

use super::*;

/// A mechanism of two parameters of one unit, one of another, and two states, with the
/// arrays and event indicators given.
macro_rules! pair {
    ($name:ident / $values:ident, $arrays:expr, $indicators:expr) => {
        crate::mechanism! {
            /// A test of refused arrays.
            pub struct $name / $values {
                /// p_1
                p_1: Variable::parameter("m", 1.0),
                /// p_2
                p_2: Variable::parameter("m", 2.0),
                /// q
                q: Variable::parameter("kg", 1.0),
                /// s_1
                s_1: Variable::state("m", 0.0, "d_1"),
                /// s_2
                s_2: Variable::state("m", 0.0, "d_2"),
                /// d_1
                d_1: Variable::output("m/s"),
                /// d_2
                d_2: Variable::output("m/s"),
            }
        }
        impl Mechanism for $name {
            const EXPERIMENT: Experiment = EXPERIMENT;
            const ARRAYS: &'static [Array] = $arrays;
            const EVENT_INDICATORS: &'static [&'static str] = $indicators;
            fn evaluate<S: Scalar>(v: &mut $values<S>) {
                v.d_1 = -v.s_1;
                v.d_2 = -v.s_2;
            }
        }
    };
}

const PS: Array = Array::new("P", "", &[2], &["p_1", "p_2"]);
const SS: Array = Array::new("S", "", &[2], &["s_1", "s_2"]);
const DS: Array = Array::new("D", "", &[2], &["d_1", "d_2"]);

pair!(Good / GoodValues, &[PS, SS, DS], &[]);
pair!(
    Twice / TwiceValues,
    &[PS, Array::new("Q", "", &[1], &["p_2"])],
    &[]
);
pair!(Scalars / ScalarsValues, &[SS], &[]);
pair!(
    Mixed / MixedValues,
    &[Array::new("P", "", &[2], &["p_1", "q"])],
    &[]
);
pair!(Indicator / IndicatorValues, &[SS, DS], &["s_1"]);
pair!(
    Typed / TypedValues,
    &[Array::new("Mass", "", &[1], &["q"])],
    &[]
);
pair!(
    Timed / TimedValues,
    &[Array::new("time", "", &[1], &["q"])],
    &[]
);

#[test]
fn good_arrays_are_written() {
    let xml = model_description::<Good>().unwrap();
    let elements = variables(&xml);
    assert_eq!(float64(&elements, "D").get("derivative"), Some("3"));
    // The description of an array is optional.
    assert_eq!(float64(&elements, "P").get("description"), None);
}

#[test]
fn refused_arrays_are_errors_naming_the_problem() {
    let cases = [
        (
            model_description::<Twice>(),
            "`p_2` is an element of two arrays",
        ),
        (
            model_description::<Scalars>(),
            "the derivatives of `S` are not shaped as it is",
        ),
        (
            model_description::<Mixed>(),
            "`q` differs from `p_1` in unit",
        ),
        (
            model_description::<Indicator>(),
            "event indicator `s_1` is an element of array `S`",
        ),
        (
            model_description::<Typed>(),
            "variable `Mass` has the name of the type of unit \"kg\"",
        ),
        (
            model_description::<Timed>(),
            "two variables of FMI 3.0 are named `time`",
        ),
    ];
    for (result, expected) in cases {
        let err = result.expect_err(expected);
        assert!(err.contains(expected), "{err}");
    }
    // Every error names the model.
    assert!(model_description::<Twice>()
        .unwrap_err()
        .starts_with("Twice: "));
}
