//! [`system!`](crate::system): a system's components, connections, parameter sets and
//! default experiment, as a unit struct implementing [`System`](super::System). Each mistake
//! is a compile error at the line it is about ([`super::checks`]).

/// Declares a system of mechanisms: a unit struct implementing
/// [`System`](crate::system::System).
///
/// - `components`: each a name (the system's: `a`, `spring`) and what it is, a mechanism's
///   type, or `fmu("path/to/Model.fmu")` for an FMU file (its path from the crate's folder);
///   a doc comment describes it.
/// - `connections`: `from.output => to.input`, each input fed by one output at most.
/// - `terminals` (optional): `a.terminal <=> b.terminal`, two mechanisms' terminals
///   ([`Mechanism::TERMINALS`](crate::model::Mechanism::TERMINALS)) of one kind joined member
///   by member, each member from the side where it is an output to the side where it is an
///   input.
/// - `parameter_sets` (optional): named sets of values for parameters, inputs and the start
///   values of states, `component.variable = value`. The set called `default` is the one an
///   importer applies when none is chosen; every other set is the default set with its own
///   values over it.
/// - `experiment`: the system's default experiment (its step is the communication step).
///
/// ```
/// use mechfmu::model::{Experiment, Mechanism, Scalar, Variable};
///
/// mechfmu::mechanism! {
///     /// A gain.
///     pub struct Gain / GainValues {
///         /// Gain
///         k: Variable::tunable("1", 2.0),
///         /// Input
///         u: Variable::input("m", 0.0),
///         /// Output
///         y: Variable::output("m"),
///     }
/// }
/// impl Mechanism for Gain {
///     const EXPERIMENT: Experiment = Experiment::until(1.0);
///     fn evaluate<S: Scalar>(v: &mut GainValues<S>) {
///         v.y = v.k * v.u;
///     }
/// }
///
/// mechfmu::system! {
///     /// Two gains in a row.
///     pub struct Chain {
///         components {
///             /// The first gain
///             first: Gain,
///             /// The second gain
///             second: Gain,
///         }
///         connections {
///             first.y => second.u,
///         }
///         parameter_sets {
///             /// Both gains 3
///             default { first.k = 3.0, second.k = 3.0 }
///             /// The second gain 1
///             once { second.k = 1.0 }
///         }
///         experiment: Experiment::until(1.0).step(0.1),
///     }
/// }
///
/// use mechfmu::system::System;
/// let once = Chain::DECLARATION.resolved_set("once").unwrap();
/// assert_eq!(once.iter().map(|b| b.value).collect::<Vec<_>>(), [3.0, 1.0]);
/// ```
///
/// A connection between unlike units does not compile:
///
/// ```compile_fail
/// use mechfmu::model::{Experiment, Mechanism, Scalar, Variable};
/// mechfmu::mechanism! {
///     /// A speed from a position.
///     pub struct Odd / OddValues {
///         /// Position
///         x: Variable::input("m", 0.0),
///         /// Speed
///         v: Variable::output("m/s"),
///     }
/// }
/// impl Mechanism for Odd {
///     const EXPERIMENT: Experiment = Experiment::until(1.0);
///     fn evaluate<S: Scalar>(v: &mut OddValues<S>) {
///         v.v = v.x;
///     }
/// }
/// mechfmu::system! {
///     /// A speed fed into a position.
///     pub struct Unlike {
///         components { a: Odd, b: Odd }
///         connections { a.v => b.x }
///         experiment: Experiment::until(1.0),
///     }
/// }
/// ```
#[macro_export]
macro_rules! system {
    (
        $(#[doc = $doc:literal])*
        $vis:vis struct $name:ident {
            components {
                $(
                    $(#[doc = $cdoc:literal])*
                    $component:ident : $($source:ident)::+ $(($path:literal))?
                ),* $(,)?
            }
            connections {
                $( $from:ident . $output:ident => $to:ident . $input:ident ),* $(,)?
            }
            $(
                terminals {
                    $( $a:ident . $a_terminal:ident <=> $b:ident . $b_terminal:ident ),* $(,)?
                }
            )?
            $(
                parameter_sets {
                    $(
                        $(#[doc = $sdoc:literal])*
                        $set:ident {
                            $( $bound:ident . $variable:ident = $value:expr ),* $(,)?
                        }
                    )*
                }
            )?
            experiment: $experiment:expr $(,)?
        }
    ) => {
        $(#[doc = $doc])*
        #[derive(Clone, Copy, Debug, Default)]
        $vis struct $name;

        const _: () = {
            const DECLARATION: $crate::system::SystemDeclaration =
                $crate::system::SystemDeclaration {
                    name: ::core::stringify!($name),
                    description: ::core::concat!("" $(, $doc)*),
                    components: &[$(
                        $crate::system::Component {
                            name: ::core::stringify!($component),
                            description: ::core::concat!("" $(, $cdoc)*),
                            source: $crate::__system_source!($($source)::+ $(($path))?),
                        },
                    )*],
                    connections: &[$(
                        $crate::system::Connection {
                            from: $crate::system::Port {
                                component: ::core::stringify!($from),
                                variable: ::core::stringify!($output),
                            },
                            to: $crate::system::Port {
                                component: ::core::stringify!($to),
                                variable: ::core::stringify!($input),
                            },
                        },
                    )*],
                    terminal_connections: &[$($(
                        $crate::system::TerminalConnection {
                            a: $crate::system::Port {
                                component: ::core::stringify!($a),
                                variable: ::core::stringify!($a_terminal),
                            },
                            b: $crate::system::Port {
                                component: ::core::stringify!($b),
                                variable: ::core::stringify!($b_terminal),
                            },
                        },
                    )*)?],
                    parameter_sets: &[$($(
                        $crate::system::ParameterSet {
                            name: ::core::stringify!($set),
                            description: ::core::concat!("" $(, $sdoc)*),
                            values: &[$(
                                $crate::system::Binding {
                                    port: $crate::system::Port {
                                        component: ::core::stringify!($bound),
                                        variable: ::core::stringify!($variable),
                                    },
                                    value: $value,
                                },
                            )*],
                        },
                    )*)?],
                    experiment: $experiment,
                };

            impl $crate::system::System for $name {
                const DECLARATION: $crate::system::SystemDeclaration = DECLARATION;
            }

            // Each check carries the span of what it checks: a mistake is reported at its line.
            #[allow(unused_imports)]
            use $crate::system::{
                check_binding as __mechfmu_check_binding,
                check_component as __mechfmu_check_component,
                check_connection as __mechfmu_check_connection,
                check_set as __mechfmu_check_set,
                check_terminal_connection as __mechfmu_check_terminal_connection,
            };
            use $crate::system::Port as __MechfmuPort;
            $(
                $crate::__at_span! {
                    ($component)
                    const _: () = __mechfmu_check_component(&DECLARATION, ::core::stringify!($component));
                }
            )*
            $(
                $crate::__at_span! {
                    ($from)
                    const _: () = __mechfmu_check_connection(
                        &DECLARATION,
                        __MechfmuPort { component: ::core::stringify!($from), variable: ::core::stringify!($output) },
                        __MechfmuPort { component: ::core::stringify!($to), variable: ::core::stringify!($input) },
                    );
                }
            )*
            $($(
                $crate::__at_span! {
                    ($a)
                    const _: () = __mechfmu_check_terminal_connection(
                        &DECLARATION,
                        __MechfmuPort { component: ::core::stringify!($a), variable: ::core::stringify!($a_terminal) },
                        __MechfmuPort { component: ::core::stringify!($b), variable: ::core::stringify!($b_terminal) },
                    );
                }
            )*)?
            $($(
                $crate::__at_span! {
                    ($set)
                    const _: () = __mechfmu_check_set(&DECLARATION, ::core::stringify!($set));
                }
                $(
                    $crate::__at_span! {
                        ($bound)
                        const _: () = __mechfmu_check_binding(
                            &DECLARATION,
                            ::core::stringify!($set),
                            __MechfmuPort { component: ::core::stringify!($bound), variable: ::core::stringify!($variable) },
                        );
                    }
                )*
            )*)?
        };

        $crate::__system_mechanism! {
            $name
            notes: ::core::concat!(
                "A system of mechanisms compiled into one FMU: its components' equations, \
                 evaluated in an order in which every connected input is known when its \
                 component's equations run, integrated together by one solver (no \
                 co-simulation, so no coupling error). Each variable is a component's, \
                 named `component.variable`; an input that a connection feeds is a local \
                 variable holding the connected output's value.\n\n## Components\n\n"
                $(, "- `", ::core::stringify!($component), "`: ",
                    ::core::stringify!($($source)::+ $(($path))?) $(, " ", $cdoc)*, "\n")*
                , "\n## Connections\n\n"
                $(, "- `", ::core::stringify!($from), ".", ::core::stringify!($output), "` \u{2192} `",
                    ::core::stringify!($to), ".", ::core::stringify!($input), "`\n")*
                $($(, "- terminal `", ::core::stringify!($a), ".", ::core::stringify!($a_terminal),
                    "` \u{2194} `", ::core::stringify!($b), ".", ::core::stringify!($b_terminal),
                    "`, member by member\n")*)?
                $($(
                    , "\n## Parameter set `", ::core::stringify!($set), "`\n\n"
                    $(, $sdoc)*, "\n\n"
                    $(, "- `", ::core::stringify!($bound), ".", ::core::stringify!($variable), " = ",
                        ::core::stringify!($value), "`\n")*
                )*)?
            );
            [] $( $component : $($source)::+ $(($path))? ),*
        }
    };
}

/// A system's [`Declaration`](crate::model::Declaration) and
/// [`Mechanism`](crate::model::Mechanism), when every component is a mechanism: the system as
/// one mechanism ([`composite`](super::composite)), which
/// [`export_fmu!`](crate::export_fmu) exports as an FMU. Nothing when a component
/// is an FMU file.
#[doc(hidden)]
#[macro_export]
macro_rules! __system_mechanism {
    // an FMU file among the components: the system is an SSP only
    ($name:ident notes: $notes:expr; [$($done:tt)*] $component:ident : fmu ($path:literal) $(, $($rest:tt)*)?) => {};
    ($name:ident notes: $notes:expr; [$($done:tt)*] $component:ident : $($source:ident)::+ $(, $($rest:tt)*)?) => {
        $crate::__system_mechanism! { $name notes: $notes; [$($done)* ($($source)::+)] $($($rest)*)? }
    };
    ($name:ident notes: $notes:expr; [$(($($mechanism:tt)*))*]) => {
        const _: () = {
            use $crate::model::{count_selected, Selection, Variable};
            use $crate::system::composite;

            type Components = $crate::__system_list!($(($($mechanism)*))*);
            const SYSTEM: &$crate::system::SystemDeclaration =
                &<$name as $crate::system::System>::DECLARATION;
            const N: usize = composite::variable_count(SYSTEM);
            const NAMES_LEN: usize = composite::names_len(SYSTEM);
            const NAMES: [u8; NAMES_LEN] = composite::names::<NAMES_LEN>(SYSTEM);
            const ALL_VARIABLES: [Variable; N] = composite::variables::<N>(SYSTEM, &NAMES);
            const VARIABLES: &[Variable] = &ALL_VARIABLES;
            const _: () = assert!(
                <Components as $crate::system::Components>::VARIABLES == N,
                "the components' values and the declaration disagree"
            );
            const PLAN_LEN: usize = composite::plan_len(SYSTEM);
            const PLAN: [composite::Step; PLAN_LEN] = composite::plan::<PLAN_LEN>(SYSTEM);
            const _: () = assert!(
                PLAN_LEN <= $crate::system::equations::MAX_PLAN,
                "a system compiled into one FMU evaluates at most 256 steps (its components and the connections into them)"
            );
            const EVENT_LISTS: &[&[&str]] =
                &[$(<$($mechanism)* as $crate::model::Mechanism>::EVENT_INDICATORS),*];
            const N_EVENTS: usize = composite::event_indicator_count(EVENT_LISTS);
            const EVENTS: [&str; N_EVENTS] =
                composite::event_indicators::<N_EVENTS>(SYSTEM, EVENT_LISTS, VARIABLES);
            const N_STATES: usize = count_selected(VARIABLES, Selection::States);
            const N_CONTINUOUS: usize = count_selected(VARIABLES, Selection::Continuous);
            const N_INPUTS: usize = count_selected(VARIABLES, Selection::Inputs);
            const N_CONTINUOUS_UNCHECKED: usize =
                count_selected(VARIABLES, Selection::ContinuousUnchecked);

            impl $crate::model::Declaration for $name {
                const NAME: &'static str = SYSTEM.name;
                const DESCRIPTION: &'static str = SYSTEM.description;
                const VARIABLES: &'static [Variable] = VARIABLES;
                type Values<S: $crate::model::Scalar> = $crate::system::SystemValues<S, Components>;
                type State = [f64; N_STATES];
                $crate::__declared_references!(VARIABLES);

                fn zeros<S: $crate::model::Scalar>() -> Self::Values<S> {
                    $crate::system::values::zeros()
                }

                fn map_values<A: $crate::model::Scalar, B: $crate::model::Scalar>(
                    values: &Self::Values<A>,
                    f: impl Fn(A) -> B,
                ) -> Self::Values<B> {
                    $crate::system::values::map_values(values, f)
                }
            }

            impl $crate::model::Mechanism for $name {
                const EXPERIMENT: $crate::model::Experiment = SYSTEM.experiment;
                const NOTES: &'static str = $notes;
                const PROJECTED: bool = <Components as $crate::system::Components>::PROJECTED;
                const MONITORED: bool = <Components as $crate::system::Components>::MONITORED;
                const EVENT_INDICATORS: &'static [&'static str] = &EVENTS;

                fn calculate(values: &mut Self::Values<f64>) -> Result<(), String> {
                    $crate::system::equations::calculate(values, SYSTEM)
                }

                #[inline(always)]
                fn evaluate<S: $crate::model::Scalar>(values: &mut Self::Values<S>) {
                    $crate::__system_steps!(values, PLAN);
                }

                #[inline]
                fn outputs<S: $crate::model::Scalar>(values: &mut Self::Values<S>) {
                    $crate::system::equations::outputs(values, &PLAN)
                }

                fn diagnose(values: &Self::Values<f64>) -> Option<String> {
                    $crate::system::equations::diagnose(values, SYSTEM)
                }

                fn project(values: &mut Self::Values<f64>) {
                    $crate::system::equations::project(values, SYSTEM)
                }

                fn monitor(values: &Self::Values<f64>) -> $crate::model::Monitor {
                    $crate::system::equations::monitor(values, SYSTEM)
                }
            }
        };
    };
}

/// Each step of a system's plan, each with its index a constant (see
/// [`run_step`](crate::system::equations::run_step)); the steps past the plan's end are
/// none.
#[doc(hidden)]
#[macro_export]
macro_rules! __system_steps {
    ($values:ident, $plan:ident) => {
        $crate::__system_steps!($values, $plan;
            0 1 2 3 4 5 6 7 8 9 10 11 12 13 14 15
            16 17 18 19 20 21 22 23 24 25 26 27 28 29 30 31
            32 33 34 35 36 37 38 39 40 41 42 43 44 45 46 47
            48 49 50 51 52 53 54 55 56 57 58 59 60 61 62 63
            64 65 66 67 68 69 70 71 72 73 74 75 76 77 78 79
            80 81 82 83 84 85 86 87 88 89 90 91 92 93 94 95
            96 97 98 99 100 101 102 103 104 105 106 107 108 109 110 111
            112 113 114 115 116 117 118 119 120 121 122 123 124 125 126 127
            128 129 130 131 132 133 134 135 136 137 138 139 140 141 142 143
            144 145 146 147 148 149 150 151 152 153 154 155 156 157 158 159
            160 161 162 163 164 165 166 167 168 169 170 171 172 173 174 175
            176 177 178 179 180 181 182 183 184 185 186 187 188 189 190 191
            192 193 194 195 196 197 198 199 200 201 202 203 204 205 206 207
            208 209 210 211 212 213 214 215 216 217 218 219 220 221 222 223
            224 225 226 227 228 229 230 231 232 233 234 235 236 237 238 239
            240 241 242 243 244 245 246 247 248 249 250 251 252 253 254 255
        );
    };
    ($values:ident, $plan:ident; $($i:literal)*) => {
        $(
            if let ::core::option::Option::Some(step) = $plan.get($i) {
                $crate::system::equations::run_step($values, *step);
            }
        )*
    };
}

/// The components of a system as a list in types, `(A, (B, ()))`, from `(A) (B)`.
#[doc(hidden)]
#[macro_export]
macro_rules! __system_list {
    () => { () };
    (($($head:tt)*) $($rest:tt)*) => { ($($head)*, $crate::__system_list!($($rest)*)) };
}

/// What a component of [`system!`] is: `fmu("path")` or a mechanism's type.
#[doc(hidden)]
#[macro_export]
macro_rules! __system_source {
    (fmu ($path:literal)) => {
        $crate::system::Source::fmu($path)
    };
    ($($mechanism:ident)::+) => {
        $crate::system::Source::mechanism::<$($mechanism)::+>()
    };
}
