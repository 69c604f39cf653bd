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
    };
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
