//! The mechanism declaration API: what a mechanism author writes.
//!
//! A mechanism is declared once with the [`mechanism!`](crate::mechanism) macro (its
//! variables) and the [`Mechanism`] trait (its equations). The modelDescription, value
//! references, GUID, FMI functions and documentation are all generated from these two.

mod arrays;
mod layout;
mod scalar;
mod values;
mod variable;

pub use arrays::{check_arrays, element_name, Array, Shaped, Shapes};
pub use layout::{check_declaration, check_event_indicators, event_indicator_references, Layout};
#[doc(hidden)]
pub use layout::{
    count_selected, derivative_references, derivatives_among_states, selected_references, Selection,
};
pub use scalar::{cos, lit, sin, sin_cos, Scalar};
#[doc(hidden)]
pub use values::{copy_one_by_one, get_one_by_one, Fields};
pub use variable::{Causality, Initial, SetPhase, Variability, Variable};

/// The FMU's `DefaultExperiment`, and the tolerance used when the importer gives none.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Experiment {
    pub start: f64,
    pub stop: f64,
    pub step: f64,
    pub tolerance: f64,
}

/// What a mechanism's [`Mechanism::monitor`] says about the current state.
#[derive(Clone, Debug, PartialEq)]
pub enum Monitor {
    /// The model holds.
    Valid,
    /// The model holds only approximately (e.g. a slack cable): logged as a warning once
    /// per episode, i.e. when the condition starts.
    Warning(String),
    /// The model no longer holds (e.g. a trolley at the pivot): the step ends with
    /// `fmi2Discard` at the last valid time.
    Invalid(String),
}

/// The variables of a mechanism. Implemented by the [`mechanism!`](crate::mechanism) macro;
/// do not implement it by hand.
pub trait Declaration: Send + Sync + 'static {
    /// The model identifier (the FMU's file names).
    const NAME: &'static str;
    /// One paragraph describing the mechanism.
    const DESCRIPTION: &'static str;
    /// Every variable, in value-reference order (value reference = index).
    const VARIABLES: &'static [Variable];

    /// One value per variable plus the time, as named fields, generic over the scalar so the
    /// same equations run on `f64` and on dual numbers.
    type Values<S: Scalar>: ValueSet<S>;

    /// The continuous states, as the solver sees them: `[f64; number of states]`.
    type State: crate::solver::StateVector;
    /// The value references of the states, in declaration order ([`Layout::states`]).
    const STATES: &'static [usize];
    /// The value references of the states' derivatives ([`Layout::derivatives`]).
    const DERIVATIVES: &'static [usize];
    /// For each state's derivative, the position in the state vector of the state it is
    /// (`x' = v` with `v` a state), or `None` when `evaluate` computes it.
    const DERIVATIVES_AMONG_STATES: &'static [Option<usize>];
    /// The value references of the continuous variables (which a step must leave finite).
    const CONTINUOUS: &'static [usize];
    /// The continuous variables but the states and their derivatives: what a step still
    /// checks after the solver accepted its end point, where the solver has checked those.
    const CONTINUOUS_UNCHECKED: &'static [usize];
    /// The value references of the inputs, in declaration order ([`Layout::inputs`]).
    const INPUTS: &'static [usize];

    /// Values that are all zero.
    fn zeros<S: Scalar>() -> Self::Values<S>;

    /// The values with every field converted by `f` (e.g. `f64` to a dual number).
    fn map_values<A: Scalar, B: Scalar>(
        values: &Self::Values<A>,
        f: impl Fn(A) -> B,
    ) -> Self::Values<B>;
}

/// Access to a mechanism's values by value reference.
pub trait ValueSet<S: Scalar>: Fields<S> + Clone + Send + 'static {
    /// Value reference `vr`'s value, or `None` when `vr` is not a variable. O(1).
    #[inline(always)]
    fn get(&self, vr: usize) -> Option<S> {
        values::get(self, vr)
    }
    /// Sets value reference `vr`; false when `vr` is not a variable.
    #[inline(always)]
    fn set(&mut self, vr: usize, value: S) -> bool {
        values::set(self, vr, value)
    }
    fn time(&self) -> S;
    fn set_time(&mut self, t: S);
}

/// The equations of a mechanism.
///
/// `evaluate` is generic over the scalar type: it runs on `f64` for simulation and on dual
/// numbers for exact directional derivatives, so it must only use the operations of
/// [`Scalar`] (arithmetic, `sin`, `sqrt`, ... and [`lit`] for constants).
pub trait Mechanism: Declaration {
    /// The `DefaultExperiment` of the FMU.
    const EXPERIMENT: Experiment;

    /// Notes for the FMU's documentation (`documentation/index.html`): the equations as
    /// implemented and where, and why, they depart from the source they come from. A small
    /// Markdown subset: paragraphs, `## headings`, `- ` lists, code blocks (fenced, or
    /// indented by four spaces: use them for equations) and inline `code`.
    const NOTES: &'static str = "";

    /// Computes the calculated parameters from the parameters, and rejects parameter values
    /// that the declared bounds cannot express (e.g. an inertia tensor that is not positive
    /// definite). Called at initialization and whenever a tunable parameter changes; the
    /// declared bounds (`positive`, `min`, `max`) are checked before it is called.
    fn calculate(_values: &mut Self::Values<f64>) -> Result<(), String> {
        Ok(())
    }

    /// Computes every state derivative from the states, inputs, parameters, calculated
    /// parameters and time, and every output that is not left to [`Mechanism::outputs`]
    /// (outputs that a derivative or [`Mechanism::monitor`] needs, or that come for free).
    ///
    /// It must be a function of those alone (not of the outputs it wrote last time) and
    /// write only derivatives and outputs: the runtime reuses an evaluation at the same
    /// point instead of repeating it (the solver's last stage is the next step's first).
    /// It runs at every stage of the solver (6 or 12 times per solver step): keep here only
    /// what the derivatives (and the monitor) need.
    fn evaluate<S: Scalar>(values: &mut Self::Values<S>);

    /// Computes the outputs that no derivative depends on (e.g. energies, momenta, positions
    /// in ground axes), from the states, inputs, parameters, calculated parameters, time and
    /// whatever [`Mechanism::evaluate`] wrote at the same point. The default computes
    /// nothing: then `evaluate` computes everything.
    ///
    /// The runtime calls it right after `evaluate` wherever the values become visible
    /// (communication points, `fmi2GetReal` after a `fmi2SetReal`, initialization, a
    /// restored or rolled-back state, directional and output derivatives, the dependency
    /// detection of the modelDescription), never at the solver's stages. So:
    /// * it must write only outputs (or local variables) that `evaluate` does not read and
    ///   that no derivative and no [`Mechanism::monitor`] reads;
    /// * like `evaluate`, it must be a function of the point alone, generic over the scalar
    ///   (it also runs on dual numbers, for exact derivatives of these outputs).
    ///
    /// Moving an output here changes neither its value (the same operations on the same
    /// numbers) nor the modelDescription; it only stops it being computed at every stage.
    fn outputs<S: Scalar>(_values: &mut Self::Values<S>) {}

    /// Whether [`Mechanism::project`] does anything (saves an evaluation per step).
    const PROJECTED: bool = false;

    /// Projects the states back onto the manifold they must stay on (e.g. a unit
    /// quaternion), at the end of every communication step. It must not change the physical
    /// state, only remove the integration's drift off the manifold.
    fn project(_values: &mut Self::Values<f64>) {}

    /// Whether [`Mechanism::monitor`] has anything to say (saves evaluating it).
    const MONITORED: bool = false;

    /// Checks the model's validity at every accepted solver step (values evaluated there by
    /// [`Mechanism::evaluate`] alone: it must not read what [`Mechanism::outputs`] writes).
    /// In Model Exchange, where the importer's solver takes the steps, it is asked at every
    /// `fmi2CompletedIntegratorStep` and at every event: `Warning` is logged once per
    /// episode, `Invalid` ends the simulation (`terminateSimulation`, with the message).
    fn monitor(_values: &Self::Values<f64>) -> Monitor {
        Monitor::Valid
    }

    /// The event indicators of Model Exchange, by variable name: continuous variables
    /// (states, or variables [`Mechanism::evaluate`] computes) whose sign changes where
    /// [`Mechanism::monitor`]'s verdict changes, e.g. `x` for a trolley that must stay on
    /// its side of the pivot (`x > 0`) and `T` for a cable that must pull (`T ≥ 0`). The
    /// importer's solver locates each change of sign and stops there, so the monitor is
    /// asked at the very time a limit is crossed rather than at the end of the step that
    /// crossed it. A name that is not a continuous variable does not compile.
    const EVENT_INDICATORS: &'static [&'static str] = &[];

    /// Declared scalars grouped into the arrays the physics has (an inertia tensor, a
    /// quaternion): FMI 3.0 shows each as one array variable, FMI 2.0 keeps the scalars.
    /// An array of states needs the array of their derivatives, in the same order. See
    /// [`Array`].
    const ARRAYS: &'static [Array] = &[];
}

/// A complete evaluation at the point the values hold: [`Mechanism::evaluate`] (the
/// derivatives) then [`Mechanism::outputs`] (the outputs no derivative needs). The one
/// place that knows the order; the solver's stages call `evaluate` alone.
#[inline]
pub fn evaluate_all<M: Mechanism, S: Scalar>(values: &mut M::Values<S>) {
    M::evaluate(values);
    M::outputs(values);
}

/// Declares a mechanism's variables: a unit struct implementing [`Declaration`] and a
/// generic struct of named values for the equations.
///
/// Each field is one variable; its name is the variable name, its doc comment the
/// description, its value a [`Variable`] constructor. Value references follow the order of
/// declaration. A duplicate name does not compile.
///
/// ```
/// use mechfmu::model::{Experiment, Mechanism, Scalar, Variable};
///
/// mechfmu::mechanism! {
///     /// A mass falling under gravity.
///     pub struct Fall / FallValues {
///         /// Gravity
///         g: Variable::parameter("m/s2", 9.81),
///         /// Height
///         h: Variable::state("m", 10.0, "v"),
///         /// Vertical velocity
///         v: Variable::state("m/s", 0.0, "a"),
///         /// Vertical acceleration
///         a: Variable::output("m/s2"),
///     }
/// }
///
/// impl Mechanism for Fall {
///     const EXPERIMENT: Experiment = Experiment { start: 0.0, stop: 1.0, step: 0.01, tolerance: 1e-8 };
///     fn evaluate<S: Scalar>(v: &mut FallValues<S>) {
///         v.a = -v.g;
///     }
/// }
/// ```
///
/// Mistakes in a declaration do not compile. A duplicate variable:
///
/// ```compile_fail
/// use mechfmu::model::Variable;
/// mechfmu::mechanism! {
///     /// Twice x.
///     pub struct Twice / TwiceValues {
///         /// x
///         x: Variable::parameter("m", 1.0),
///         /// x again
///         x: Variable::parameter("m", 2.0),
///     }
/// }
/// ```
///
/// A state whose derivative names no variable:
///
/// ```compile_fail
/// use mechfmu::model::Variable;
/// mechfmu::mechanism! {
///     /// A state without its rate.
///     pub struct Lost / LostValues {
///         /// Position
///         x: Variable::state("m", 1.0, "x_dot"),
///     }
/// }
/// ```
///
/// A start value outside its bounds:
///
/// ```compile_fail
/// use mechfmu::model::Variable;
/// mechfmu::mechanism! {
///     /// A negative mass.
///     pub struct Negative / NegativeValues {
///         /// Mass
///         m: Variable::parameter("kg", -1.0).positive(),
///     }
/// }
/// ```
#[macro_export]
macro_rules! mechanism {
    (
        $(#[doc = $doc:literal])*
        $vis:vis struct $name:ident / $values:ident {
            $(
                $(#[doc = $vdoc:literal])*
                $var:ident : $decl:expr
            ),* $(,)?
        }
    ) => {
        $(#[doc = $doc])*
        #[derive(Clone, Copy, Debug, Default)]
        $vis struct $name;

        #[doc = concat!("The values of every variable of [`", stringify!($name), "`], and the time.")]
        #[derive(Clone, Copy, Debug, Default, PartialEq)]
        #[allow(non_snake_case)]
        // repr(C): the time, then the variables in value-reference order, without padding
        // (all fields have the same type), so value reference `vr` is element `vr + 1`
        // (`model::Fields`).
        #[repr(C)]
        $vis struct $values<S> {
            /// Simulation time (s).
            pub time: S,
            $( $(#[doc = $vdoc])* pub $var: S, )*
        }

        const _: () = {
            /// The time plus one value per variable.
            const LEN: usize = 1 + <[&str]>::len(&[$(stringify!($var)),*]);

            // SAFETY: `$values` is the repr(C) struct declared above: the time and one field
            // per variable, every one of type S (`_fields_are_scalars` would not compile
            // otherwise), LEN in all.
            unsafe impl<S: $crate::model::Scalar> $crate::model::Fields<S> for $values<S> {
                const LEN: usize = LEN;
            }
            #[allow(dead_code)]
            fn _fields_are_scalars<S: $crate::model::Scalar>(v: $values<S>) -> [S; LEN] {
                [v.time $(, v.$var)*]
            }

            impl<S: $crate::model::Scalar> $crate::model::ValueSet<S> for $values<S> {
                #[inline]
                fn time(&self) -> S { self.time }
                #[inline]
                fn set_time(&mut self, t: S) { self.time = t; }
            }

            const VARIABLES: &[$crate::model::Variable] = &[
                $( $crate::model::Variable::named($decl, stringify!($var), concat!("" $(, $vdoc)*)), )*
            ];
            const _: () = $crate::model::check_declaration(VARIABLES);
            const N_STATES: usize =
                $crate::model::count_selected(VARIABLES, $crate::model::Selection::States);
            const N_CONTINUOUS: usize =
                $crate::model::count_selected(VARIABLES, $crate::model::Selection::Continuous);
            const N_INPUTS: usize =
                $crate::model::count_selected(VARIABLES, $crate::model::Selection::Inputs);
            const N_CONTINUOUS_UNCHECKED: usize = $crate::model::count_selected(
                VARIABLES,
                $crate::model::Selection::ContinuousUnchecked,
            );

            impl $crate::model::Declaration for $name {
                const NAME: &'static str = stringify!($name);
                const DESCRIPTION: &'static str = concat!("" $(, $doc)*);
                const VARIABLES: &'static [$crate::model::Variable] = VARIABLES;
                type Values<S: $crate::model::Scalar> = $values<S>;
                type State = [f64; N_STATES];
                const STATES: &'static [usize] = &$crate::model::selected_references::<N_STATES>(
                    VARIABLES,
                    $crate::model::Selection::States,
                );
                const DERIVATIVES: &'static [usize] =
                    &$crate::model::derivative_references::<N_STATES>(VARIABLES);
                const DERIVATIVES_AMONG_STATES: &'static [Option<usize>] =
                    &$crate::model::derivatives_among_states::<N_STATES>(VARIABLES);
                const CONTINUOUS: &'static [usize] = &$crate::model::selected_references::<
                    N_CONTINUOUS,
                >(
                    VARIABLES,
                    $crate::model::Selection::Continuous,
                );
                const CONTINUOUS_UNCHECKED: &'static [usize] =
                    &$crate::model::selected_references::<N_CONTINUOUS_UNCHECKED>(
                        VARIABLES,
                        $crate::model::Selection::ContinuousUnchecked,
                    );
                const INPUTS: &'static [usize] = &$crate::model::selected_references::<N_INPUTS>(
                    VARIABLES,
                    $crate::model::Selection::Inputs,
                );

                fn zeros<S: $crate::model::Scalar>() -> $values<S> {
                    $values { time: S::zero(), $( $var: S::zero(), )* }
                }

                fn map_values<A: $crate::model::Scalar, B: $crate::model::Scalar>(
                    v: &$values<A>,
                    f: impl Fn(A) -> B,
                ) -> $values<B> {
                    $values { time: f(v.time), $( $var: f(v.$var), )* }
                }
            }
        };
    };
}

#[cfg(test)]
mod tests {
    use super::{Declaration, ValueSet, Variable};

    crate::mechanism! {
        /// Three variables of each kind that matters to `ValueSet`.
        pub struct Probe / ProbeValues {
            /// a
            a: Variable::parameter("m", 1.0),
            /// b
            b: Variable::state("m", 2.0, "c"),
            /// c
            c: Variable::output("m/s"),
        }
    }

    #[test]
    fn value_references_index_the_fields() {
        let mut v = ProbeValues::<f64> {
            time: 0.5,
            a: 1.0,
            b: 2.0,
            c: 3.0,
        };
        assert_eq!(Probe::VARIABLES.len(), 3);
        assert_eq!(
            (0..4).map(|vr| v.get(vr)).collect::<Vec<_>>(),
            [Some(1.0), Some(2.0), Some(3.0), None]
        );
        assert_eq!(v.get(usize::MAX), None);
        assert!(v.set(1, 20.0));
        assert!(!v.set(3, 9.0));
        assert!(!v.set(usize::MAX, 9.0));
        assert_eq!((v.time, v.a, v.b, v.c), (0.5, 1.0, 20.0, 3.0));
        v.set_time(7.0);
        assert_eq!(v.time(), 7.0);
    }

    #[test]
    fn compile_time_references_follow_the_declaration() {
        assert_eq!(Probe::STATES, [1]);
        assert_eq!(Probe::DERIVATIVES, [2]);
        assert_eq!(Probe::DERIVATIVES_AMONG_STATES, [None]);
        // The parameter `a` is fixed; the state and the output are continuous.
        assert_eq!(Probe::CONTINUOUS, [1, 2]);
        // Both are the solver's: the state and its derivative.
        assert_eq!(Probe::CONTINUOUS_UNCHECKED, [] as [usize; 0]);
        assert_eq!(Probe::INPUTS, [] as [usize; 0]);
    }

    crate::mechanism! {
        /// Inputs between other variables.
        pub struct Driven / DrivenValues {
            /// k
            k: Variable::parameter("1", 1.0),
            /// u
            u: Variable::input("1", 0.0),
            /// x
            x: Variable::state("1", 0.0, "x_dot"),
            /// w
            w: Variable::input("1", 0.0),
            /// x_dot
            x_dot: Variable::output("1"),
        }
    }

    #[test]
    fn compile_time_inputs_are_the_layouts() {
        assert_eq!(Driven::INPUTS, [1, 3]);
        let layout = super::Layout::new(Driven::VARIABLES).unwrap();
        assert_eq!(Driven::INPUTS, layout.inputs);
        assert_eq!(Driven::STATES, layout.states);
    }
}
