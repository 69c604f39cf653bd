//! `CraneController`: the stateless control law that positions `CraneDynamics`' trolley and
//! boom: the static drive loads as feed-forward, proportional–derivative feedback on the
//! trolley's position and the boom's angle, and sway damping from the payload's swing.
//!
//! `F = (m + m_trolley) g sin θ + kp_x (x_ref - x) - kd_x ẋ + k_sway φ̇`,
//! `tau = (m + m_trolley) g x cos θ + kp_theta (theta_ref - θ) - kd_theta θ̇`

#![forbid(unsafe_code)]

use mechfmu::model::{sin_cos, Experiment, Mechanism, Scalar, Terminal, Variable};

mechfmu::mechanism! {
    /// The control law of a luffing crane's drives: feed-forward of the static loads, PD
    /// feedback towards x_ref and theta_ref, and sway damping from phi_dot, at once from its
    /// inputs (no state).
    pub struct CraneController / CraneControllerValues {
        /// Trolley position to reach, along the boom
        x_ref: Variable::tunable("m", 12.0),
        /// Boom angle to reach, from the horizontal
        theta_ref: Variable::tunable("rad", 0.6),
        /// Proportional gain on the trolley position
        kp_x: Variable::tunable("N/m", 1200.0),
        /// Derivative gain on the trolley velocity
        kd_x: Variable::tunable("N.s/m", 1700.0),
        /// Proportional gain on the boom angle
        kp_theta: Variable::tunable("N.m/rad", 125000.0),
        /// Derivative gain on the boom's angular velocity
        kd_theta: Variable::tunable("N.m.s/rad", 175000.0),
        /// Sway damping gain on the payload's angular velocity
        k_sway: Variable::tunable("N.s/rad", 3000.0),
        /// Payload mass, as the crane's
        m: Variable::parameter("kg", 1000.0).positive(),
        /// Trolley mass, as the crane's
        m_trolley: Variable::parameter("kg", 200.0).positive(),
        /// Gravitational acceleration
        g: Variable::parameter("m/s2", 9.81),
        /// Trolley position along the boom, measured
        x: Variable::input("m", 10.0),
        /// Trolley velocity along the boom, measured
        x_dot: Variable::input("m/s", 0.0),
        /// Boom angle from the horizontal, measured
        theta: Variable::input("rad", 0.5),
        /// Boom angular velocity, measured
        theta_dot: Variable::input("rad/s", 0.0),
        /// Payload angular velocity, measured
        phi_dot: Variable::input("rad/s", 0.0),
        /// Trolley drive force
        F: Variable::output("N"),
        /// Boom drive torque
        tau: Variable::output("N.m"),
    }
}

impl Mechanism for CraneController {
    const EXPERIMENT: Experiment = Experiment::until(1.0).step(0.01).tolerance(1e-6);

    // CraneDynamics' terminals, the other way round
    const TERMINALS: &'static [Terminal] = &[
        Terminal::new(
            "drives",
            "org.mechfmu.crane.drives",
            "The drive force on the trolley and the torque on the boom",
            &[("F", "F"), ("tau", "tau")],
        ),
        Terminal::new(
            "motion",
            "org.mechfmu.crane.motion",
            "What the controller measures: the trolley's and the boom's positions and speeds, the payload's swing rate",
            &[
                ("x", "x"),
                ("x_dot", "x_dot"),
                ("theta", "theta"),
                ("theta_dot", "theta_dot"),
                ("phi_dot", "phi_dot"),
            ],
        ),
    ];

    const NOTES: &'static str = "
        A controller for `CraneDynamics`, to be connected to it: it reads the crane's trolley
        position `x`, boom angle `θ` and their velocities, and the payload's angular velocity
        `φ̇`, and writes the crane's drive force and torque:

            F   = (m + m_trolley) g sin θ   + kp_x (x_ref - x) - kd_x ẋ + k_sway φ̇
            tau = (m + m_trolley) g x cos θ + kp_theta (theta_ref - θ) - kd_theta θ̇

        The first terms are `CraneDynamics`' static drive loads (the payload hanging still
        under the trolley), so the crane holds still at the reference; the others are
        proportional–derivative feedback towards `x_ref` and `theta_ref`, and a damping of the
        payload's swing through the trolley. `m`, `m_trolley` and `g` are the crane's.

        It has no state, and both outputs depend directly on the inputs (direct
        feedthrough). The references `mechfmu validate` runs are these formulas, at random
        inputs.
    ";

    // No state, so no derivative: the drives, at once from the inputs.
    fn evaluate<S: Scalar>(v: &mut CraneControllerValues<S>) {
        let weight = (v.m + v.m_trolley) * v.g;
        let (sin, cos) = sin_cos(v.theta);
        v.F = weight * sin + v.kp_x * (v.x_ref - v.x) - v.kd_x * v.x_dot + v.k_sway * v.phi_dot;
        v.tau =
            weight * v.x * cos + v.kp_theta * (v.theta_ref - v.theta) - v.kd_theta * v.theta_dot;
    }
}

// The FMU's functions; none when the crate is compiled into a system's FMU.
#[cfg(not(feature = "component"))]
mechfmu::export_fmu!(CraneController);
