//! A case that moves, for the documentation of a mechanism whose default experiment stands
//! still: an equilibrium plots as flat lines, which shows nothing of the mechanism.

use super::const_text::{str_eq, ConstMessage};
use super::{Causality, Experiment, Initial, Variable};

/// What a mechanism's documentation plots when its default experiment stands still
/// ([`Mechanism::MOVING_CASE`](super::Mechanism::MOVING_CASE)): the values that differ
/// from the declared defaults, run on the same simulation, start time, communication step
/// and tolerance as the default experiment, and the sentences the page says about it.
///
/// ```
/// use mechfmu::model::{sin, Experiment, Mechanism, MovingCase, Scalar, Variable};
///
/// mechfmu::mechanism! {
///     /// A pendulum: l phi'' = -g sin(phi).
///     pub struct Pendulum / PendulumValues {
///         /// Length
///         l: Variable::parameter("m", 1.0).positive(),
///         /// Angle from the downward vertical
///         phi: Variable::state("rad", 0.0, "phi_dot"),
///         /// Angular velocity
///         phi_dot: Variable::state("rad/s", 0.0, "phi_ddot"),
///         /// Angular acceleration
///         phi_ddot: Variable::output("rad/s2"),
///     }
/// }
///
/// impl Mechanism for Pendulum {
///     const EXPERIMENT: Experiment =
///         Experiment::until(10.0).step(0.01).tolerance(1e-6);
///     const MOVING_CASE: Option<MovingCase> = Some(MovingCase {
///         name: "swing",
///         at_rest: "the pendulum hangs at rest",
///         shows: "the pendulum released from rest at 30° from the vertical",
///         values: &[("phi", 0.5235987755982988)],
///         stop: None,
///     });
///     fn evaluate<S: Scalar>(v: &mut PendulumValues<S>) {
///         v.phi_ddot = -mechfmu::model::lit::<S>(9.81) * sin(v.phi) / v.l;
///     }
/// }
///
/// mechfmu::export_fmu!(Pendulum);
/// # fn main() {}
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MovingCase {
    /// A short name: the reference case's (`validation/cases.py`) when it is one.
    pub name: &'static str,
    /// Why the default experiment stands still, a clause the page completes: "In the
    /// default experiment {at_rest}; this is an equilibrium, so every state keeps its start
    /// value."
    pub at_rest: &'static str,
    /// What the case shows, a clause: "The plot below shows the case `{name}`: {shows}."
    pub shows: &'static str,
    /// Start values, parameters and constant inputs that differ from the declared ones, by
    /// variable name: only what an importer may set before initialization.
    pub values: &'static [(&'static str, f64)],
    /// Where the case stops when the default experiment's stop time would run past what it
    /// shows (a motion that runs away); `None`: the default experiment's.
    pub stop: Option<f64>,
}

/// Compile-time check of a mechanism's moving case, run by `export_fmu!`: each value names
/// a declared variable that can be set before initialization (an input, a parameter, a
/// state's start value), once, with a finite value; the stop time, if any, is after the
/// start. A misspelled name does not compile:
///
/// ```compile_fail
/// use mechfmu::model::{Experiment, Mechanism, MovingCase, Scalar, Variable};
///
/// mechfmu::mechanism! {
///     /// A mass at rest, pushed by F.
///     pub struct Rest / RestValues {
///         /// Push
///         F: Variable::input("N", 0.0),
///         /// Position
///         x: Variable::state("m", 0.0, "v"),
///         /// Velocity
///         v: Variable::state("m/s", 0.0, "a"),
///         /// Acceleration
///         a: Variable::output("m/s2"),
///     }
/// }
///
/// impl Mechanism for Rest {
///     const EXPERIMENT: Experiment =
///         Experiment::until(1.0).step(0.1).tolerance(1e-6);
///     const MOVING_CASE: Option<MovingCase> = Some(MovingCase {
///         name: "pushed",
///         at_rest: "the mass rests",
///         shows: "the mass pushed",
///         values: &[("f", 1.0)], // the input is `F`
///         stop: None,
///     });
///     fn evaluate<S: Scalar>(v: &mut RestValues<S>) {
///         v.a = v.F;
///     }
/// }
///
/// mechfmu::export_fmu!(Rest);
/// # fn main() {}
/// ```
pub const fn check_moving_case(
    variables: &[Variable],
    experiment: Experiment,
    case: Option<MovingCase>,
) {
    let Some(case) = case else {
        return;
    };
    if let Some(stop) = case.stop {
        if !(stop.is_finite() && stop > experiment.start) {
            panic!("Mechanism::MOVING_CASE: the stop time is not after the start time");
        }
    }
    let values = case.values;
    let mut k = 0;
    while k < values.len() {
        let (name, value) = values[k];
        let mut m = ConstMessage::new();
        m.push("Mechanism::MOVING_CASE: ").quoted(name);
        let mut j = 0;
        while j < variables.len() && !str_eq(variables[j].name, name) {
            j += 1;
        }
        if j == variables.len() {
            m.push(" names no declared variable");
            panic!("{}", m.as_str());
        }
        if !settable_before_initialization(&variables[j]) {
            m.push(" is computed by the model: only inputs, parameters and states' start values can be given");
            panic!("{}", m.as_str());
        }
        if !value.is_finite() {
            m.push(" is given a value that is not a finite number");
            panic!("{}", m.as_str());
        }
        let mut i = 0;
        while i < k {
            if str_eq(values[i].0, name) {
                m.push(" is given twice");
                panic!("{}", m.as_str());
            }
            i += 1;
        }
        k += 1;
    }
}

/// What `fmi2SetReal` accepts before initialization (`Variable::settable` in the phases
/// before it), in a form the compiler can evaluate.
const fn settable_before_initialization(variable: &Variable) -> bool {
    matches!(variable.causality, Causality::Input)
        || matches!(variable.initial, Some(Initial::Exact | Initial::Approx))
}

#[cfg(test)]
mod tests {
    use super::*;

    const VARIABLES: &[Variable] = &[
        Variable::parameter("kg", 1.0).named("m", ""),
        Variable::input("N", 0.0).named("F", ""),
        Variable::state("m", 0.0, "v").named("x", ""),
        Variable::output("m/s").named("v", ""),
    ];

    const EXPERIMENT: Experiment = Experiment::until(1.0).step(0.1).tolerance(1e-6);

    fn case(values: &'static [(&'static str, f64)]) -> Option<MovingCase> {
        Some(MovingCase {
            name: "case",
            at_rest: "it rests",
            shows: "it moves",
            values,
            stop: None,
        })
    }

    fn refusal(case: Option<MovingCase>) -> String {
        let panic = std::panic::catch_unwind(|| check_moving_case(VARIABLES, EXPERIMENT, case))
            .expect_err("refused");
        panic
            .downcast_ref::<&str>()
            .map(|s| s.to_string())
            .or_else(|| panic.downcast_ref::<String>().cloned())
            .unwrap_or_default()
    }

    #[test]
    fn a_case_may_set_parameters_inputs_and_start_values() {
        check_moving_case(VARIABLES, EXPERIMENT, None);
        let values = case(&[("m", 2.0), ("F", 1.0), ("x", 0.5)]);
        check_moving_case(VARIABLES, EXPERIMENT, values);
        let stop = values.map(|c| MovingCase {
            stop: Some(0.5),
            ..c
        });
        check_moving_case(VARIABLES, EXPERIMENT, stop);
    }

    #[test]
    fn a_misspelled_computed_repeated_or_infinite_value_is_refused() {
        assert_eq!(
            refusal(case(&[("xx", 1.0)])),
            "Mechanism::MOVING_CASE: `xx` names no declared variable"
        );
        assert!(refusal(case(&[("v", 1.0)]))
            .starts_with("Mechanism::MOVING_CASE: `v` is computed by the model"));
        assert!(refusal(case(&[("x", 1.0), ("x", 2.0)])).ends_with("`x` is given twice"));
        assert!(refusal(case(&[("x", f64::NAN)]))
            .contains("`x` is given a value that is not a finite number"));
        let early = case(&[]).map(|c| MovingCase {
            stop: Some(0.0),
            ..c
        });
        assert!(refusal(early).contains("not after the start time"));
    }
}
