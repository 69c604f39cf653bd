//! A system as one mechanism: its variables, its order of evaluation, its equations.

use super::composite::{self, Step};
use super::tests::{Body, Link};
use super::System;
use crate::model::{Causality, Declaration, Experiment, Mechanism, Scalar, ValueSet, Variable};

crate::system! {
    /// Two masses on a spring, the spring declared last.
    pub struct Pair {
        components {
            /// One mass
            left: Body,
            /// The other
            right: Body,
            /// Between them
            spring: Link,
        }
        connections {
            left.x => spring.x_a,
            right.x => spring.x_b,
            spring.F_a => left.F,
            spring.F_b => right.F,
        }
        parameter_sets {
            /// Apart
            default { right.x = 3.0, spring.k = 2.0 }
        }
        experiment: Experiment::until(1.0),
    }
}

#[test]
fn variables_are_the_components_named_component_dot_variable() {
    let names: Vec<&str> = Pair::VARIABLES.iter().map(|v| v.name).collect();
    assert_eq!(
        names,
        [
            "left.m",
            "left.F",
            "left.x",
            "left.v",
            "left.a",
            "left.w",
            "right.m",
            "right.F",
            "right.x",
            "right.v",
            "right.a",
            "right.w",
            "spring.k",
            "spring.x_a",
            "spring.x_b",
            "spring.F_a",
            "spring.F_b"
        ]
    );
    let variable = |name: &str| Pair::VARIABLES.iter().find(|v| v.name == name).unwrap();
    // a state's derivative is named as the system names it
    assert_eq!(variable("right.x").derivative, Some("right.v"));
    // the default set gives the start values
    assert_eq!(variable("right.x").start, Some(3.0));
    assert_eq!(variable("spring.k").start, Some(2.0));
    assert_eq!(variable("left.x").start, Some(1.0));
    // a connected input is the system's to compute
    for connected in ["left.F", "spring.x_a"] {
        let v = variable(connected);
        assert_eq!(
            (v.causality, v.start),
            (Causality::Local, None),
            "{connected}"
        );
    }
    assert_eq!(Pair::INPUTS, [] as [usize; 0]);
    assert_eq!(Pair::STATES, [2, 3, 8, 9]);
    assert_eq!(Pair::DERIVATIVES, [3, 4, 9, 10]);
}

#[test]
fn the_spring_is_evaluated_before_the_masses_it_pushes() {
    const P: usize = composite::plan_len(&Pair::DECLARATION);
    let plan = composite::plan::<P>(&Pair::DECLARATION);
    assert_eq!(
        plan,
        [
            Step::Copy { from: 2, to: 13 },
            Step::Copy { from: 8, to: 14 },
            Step::Evaluate {
                component: 2,
                outputs: true
            },
            Step::Copy { from: 15, to: 1 },
            Step::Evaluate {
                component: 0,
                outputs: false
            },
            Step::Copy { from: 16, to: 7 },
            Step::Evaluate {
                component: 1,
                outputs: false
            },
        ]
    );
}

#[test]
fn the_equations_are_the_components_through_their_connections() {
    let mut v = Pair::zeros::<f64>();
    for (vr, variable) in Pair::VARIABLES.iter().enumerate() {
        if let Some(start) = variable.start {
            v.set(vr, start);
        }
    }
    v.set_time(0.25);
    Pair::evaluate(&mut v);
    let get = |name: &str| {
        let vr = Pair::VARIABLES.iter().position(|v| v.name == name).unwrap();
        v.get(vr).unwrap()
    };
    // spring: 2 (3 - 1) = 4 N on the left mass, -4 N on the right one
    assert_eq!((get("left.a"), get("right.a")), (4.0, -4.0));
    assert_eq!(
        v.components.head.time, 0.25,
        "each component has the system's time"
    );
    assert_eq!(v.components.tail.tail.head.time, 0.25);
}

crate::mechanism! {
    /// A first-order lag whose output is twice its state, computed (not a state).
    pub struct Lag / LagValues {
        /// Input
        u: Variable::input("1", 0.0),
        /// State
        x: Variable::state("1", 1.0, "x_dot"),
        /// Rate
        x_dot: Variable::local("1/s"),
        /// Output
        y: Variable::output("1"),
    }
}

impl Mechanism for Lag {
    const EXPERIMENT: Experiment = Experiment::until(1.0);
    fn evaluate<S: Scalar>(v: &mut LagValues<S>) {
        v.x_dot = v.u - v.x;
        v.y = v.x + v.x;
    }
}

crate::system! {
    /// Two lags, each fed by the other's output.
    pub struct Ring {
        components {
            /// One
            one: Lag,
            /// Two
            two: Lag,
        }
        connections {
            one.y => two.u,
            two.y => one.u,
        }
        parameter_sets {
            /// Unlike states
            default { two.x = 5.0 }
        }
        experiment: Experiment::until(1.0),
    }
}

/// No component can go first (each one's input is the other's computed output, though no
/// output follows its input at once): every component is evaluated once per component, and
/// the derivatives come out exact.
#[test]
fn without_an_order_each_round_makes_one_more_link_exact() {
    const P: usize = composite::plan_len(&Ring::DECLARATION);
    assert_eq!(P, 2 * (1 + 1 + 1 + 1));
    let mut v = Ring::zeros::<f64>();
    for (vr, variable) in Ring::VARIABLES.iter().enumerate() {
        if let Some(start) = variable.start {
            v.set(vr, start);
        }
    }
    Ring::evaluate(&mut v);
    let get = |name: &str| {
        let vr = Ring::VARIABLES.iter().position(|v| v.name == name).unwrap();
        v.get(vr).unwrap()
    };
    // one.u = 2 · 5, two.u = 2 · 1
    assert_eq!(
        (get("one.x_dot"), get("two.x_dot")),
        (10.0 - 1.0, 2.0 - 5.0)
    );
}
