//! Equations that give no derivative at the start: one never set fails the initialization,
//! naming it (a user's mechanism that forgets one compiles, so the runtime checks), and one
//! that is no number says at which states.

use mechfmu::model::{Experiment, Mechanism, Scalar, Variable};
use mechfmu_testkit::harness::{Harness, ONE_SECOND};

mechfmu::mechanism! {
    /// A pendulum whose `evaluate` forgets the angular acceleration.
    pub struct Forgetful / ForgetfulValues {
        /// Gravity over length
        g_over_l: Variable::parameter("1/s2", 9.81),
        /// Angle
        theta: Variable::state("rad", 0.8, "theta_dot"),
        /// Angular velocity
        theta_dot: Variable::state("rad/s", 0.0, "theta_ddot"),
        /// Angular acceleration, never set
        theta_ddot: Variable::local("rad/s2"),
        /// Height factor
        h: Variable::output("1"),
    }
}

impl Mechanism for Forgetful {
    const EXPERIMENT: Experiment = ONE_SECOND;
    fn evaluate<S: Scalar>(v: &mut ForgetfulValues<S>) {
        v.h = S::one() - v.theta.cos();
    }
}

mechfmu::mechanism! {
    /// The same pendulum, its acceleration set.
    pub struct Pendulum / PendulumValues {
        /// Gravity over length
        g_over_l: Variable::parameter("1/s2", 9.81),
        /// Angle
        theta: Variable::state("rad", 0.8, "theta_dot"),
        /// Angular velocity
        theta_dot: Variable::state("rad/s", 0.0, "theta_ddot"),
        /// Angular acceleration
        theta_ddot: Variable::local("rad/s2"),
    }
}

impl Mechanism for Pendulum {
    const EXPERIMENT: Experiment = ONE_SECOND;
    fn evaluate<S: Scalar>(v: &mut PendulumValues<S>) {
        v.theta_ddot = -v.g_over_l * v.theta.sin();
    }
}

#[test]
fn a_derivative_never_set_fails_the_initialization_naming_it() {
    let mut fmu = Harness::<Forgetful>::new();
    assert!(fmu.initialize(None, 0.0, &[]).is_err());
    assert!(
        fmu.logged(
            "the equations never set `theta_ddot`, the derivative of `theta_dot`: `evaluate` must compute the derivative of every state"
        ),
        "{:?}",
        fmu.messages()
    );
}

#[test]
fn a_derivative_set_passes_and_swings() {
    let mut fmu = Harness::<Pendulum>::new();
    fmu.initialize(None, 0.0, &[]).unwrap();
    fmu.step_to(0.5, 0.1).unwrap();
    assert!(fmu.get("theta") < 0.8 && fmu.get("theta_dot") < 0.0);
}

mechfmu::mechanism! {
    /// x' = 1 / x: no number at x = 0.
    pub struct Inverse / InverseValues {
        /// Position
        x: Variable::state("m", 0.0, "x_dot"),
        /// Velocity
        x_dot: Variable::output("m/s"),
    }
}

impl Mechanism for Inverse {
    const EXPERIMENT: Experiment = ONE_SECOND;
    fn evaluate<S: Scalar>(v: &mut InverseValues<S>) {
        v.x_dot = S::one() / v.x;
    }
}

/// Equations that give no number at the start say where: the states' values.
#[test]
fn no_number_at_the_start_names_the_states() {
    let mut fmu = Harness::<Inverse>::new();
    assert!(fmu.initialize(None, 0.0, &[]).is_err());
    assert!(
        fmu.logged(
            "`x_dot` evaluates to inf at t = 0 with these parameters and inputs, where x = 0"
        ),
        "{:?}",
        fmu.messages()
    );
}
