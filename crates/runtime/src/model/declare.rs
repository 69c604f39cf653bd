//! [`mechanism!`](crate::mechanism): a declaration's variables, as a unit struct, a struct of
//! named values and the compile-time lists the solver and the FMI layers index with. Each
//! mistake in a declaration is one compile error at its variable's line
//! ([`check_variable`](super::check_variable); names declared twice by
//! `mechfmu_macros::unique_variables`).

/// Declares a mechanism's variables: a unit struct implementing [`Declaration`](crate::model::Declaration) and a
/// generic struct of named values for the equations.
///
/// Each field is one variable; its name is the variable name, its doc comment the
/// description, its value a [`Variable`](crate::model::Variable) constructor. Value references follow the order of
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
///     const EXPERIMENT: Experiment = Experiment::until(1.0).step(0.01).tolerance(1e-8);
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
        $crate::__unique_variables! {
            ($crate::__mechanism_expand)
            { $(#[doc = $doc])* $vis struct $name / $values }
            [ $( ($var) { $(#[doc = $vdoc])* $var : $decl } )* ]
        }
    };
}

/// What [`mechanism!`] expands to, once its variables' names are known to be unique.
#[doc(hidden)]
#[macro_export]
macro_rules! __mechanism_expand {
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
            // Each variable's check carries that variable's span: a mistake is reported
            // once, at its line, in words that name it.
            use $crate::model::declaration_error as __mechfmu_declaration_error;
            use $crate::__source_text as __mechfmu_source_text;
            $(
                $crate::__at_span! {
                    ($var)
                    const _: () = if let ::core::option::Option::Some(error) =
                        __mechfmu_declaration_error(
                            VARIABLES,
                            __mechfmu_position(VARIABLES, ::core::stringify!($var)),
                            __mechfmu_source_text!($decl),
                        )
                    {
                        ::core::panic!("{}", error.as_str());
                    };
                }
            )*
            const fn __mechfmu_position(variables: &[$crate::model::Variable], name: &str) -> usize {
                let mut i = 0;
                while !$crate::model::str_eq(variables[i].name, name) {
                    i += 1;
                }
                i
            }
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
                $crate::__declared_references!(VARIABLES);

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

/// The value references a [`Declaration`](crate::model::Declaration) lists, worked out from its
/// variables at compile time (`VARIABLES`, with `N_STATES`, `N_CONTINUOUS`,
/// `N_CONTINUOUS_UNCHECKED` and `N_INPUTS` counted from them in the same scope): the items of
/// the impl that `mechanism!` and `system!` write alike.
#[doc(hidden)]
#[macro_export]
macro_rules! __declared_references {
    ($variables:ident) => {
        const STATES: &'static [usize] = &$crate::model::selected_references::<N_STATES>(
            $variables,
            $crate::model::Selection::States,
        );
        const DERIVATIVES: &'static [usize] =
            &$crate::model::derivative_references::<N_STATES>($variables);
        const DERIVATIVES_AMONG_STATES: &'static [Option<usize>] =
            &$crate::model::derivatives_among_states::<N_STATES>($variables);
        const CONTINUOUS: &'static [usize] = &$crate::model::selected_references::<N_CONTINUOUS>(
            $variables,
            $crate::model::Selection::Continuous,
        );
        const CONTINUOUS_UNCHECKED: &'static [usize] =
            &$crate::model::selected_references::<N_CONTINUOUS_UNCHECKED>(
                $variables,
                $crate::model::Selection::ContinuousUnchecked,
            );
        const INPUTS: &'static [usize] = &$crate::model::selected_references::<N_INPUTS>(
            $variables,
            $crate::model::Selection::Inputs,
        );
    };
}

#[cfg(test)]
mod tests {
    use crate::model::{Declaration, ValueSet, Variable};

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
    fn a_field_names_its_variable() {
        use crate::model::variable_of;
        assert_eq!(variable_of::<Probe>(|v| &v.a).name, "a");
        assert_eq!(variable_of::<Probe>(|v| &v.c).name, "c");
        let time = std::panic::catch_unwind(|| variable_of::<Probe>(|v| &v.time));
        assert!(time.is_err(), "the time is no variable");
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
        let layout = crate::model::Layout::new(Driven::VARIABLES).unwrap();
        assert_eq!(Driven::INPUTS, layout.inputs);
        assert_eq!(Driven::STATES, layout.states);
    }
}
