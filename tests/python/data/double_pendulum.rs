//! `DoublePendulum`: two point masses on massless rods, the first hinged at a fixed pivot,
//! the second at the first mass (the tutorial's example of a user's own mechanism).
//!
//! Lagrangian with θ1, θ2 from the downward vertical, Δ = θ1 − θ2:
//! T = ½(m1+m2) l1² θ̇1² + ½ m2 l2² θ̇2² + m2 l1 l2 θ̇1 θ̇2 cos Δ,
//! V = −(m1+m2) g l1 cos θ1 − m2 g l2 cos θ2.

#![forbid(unsafe_code)]

use mechfmu::nalgebra::{Matrix2, Vector2};
use mechfmu::model::{lit, Experiment, Mechanism, Scalar, Variable};

mechfmu::mechanism! {
    /// A double pendulum: two point masses on massless rods, in a vertical plane.
    pub struct DoublePendulum / DoublePendulumValues {
        /// Mass of the first bob
        m1: Variable::parameter("kg", 1.0).positive(),
        /// Mass of the second bob
        m2: Variable::parameter("kg", 1.0).positive(),
        /// Length of the first rod
        l1: Variable::parameter("m", 1.0).positive(),
        /// Length of the second rod
        l2: Variable::parameter("m", 1.0).positive(),
        /// Gravitational acceleration
        g: Variable::parameter("m/s2", 9.81),
        /// Angle of the first rod from the downward vertical
        theta1: Variable::state("rad", 2.0, "theta1_dot"),
        /// Angle of the second rod from the downward vertical
        theta2: Variable::state("rad", 1.0, "theta2_dot"),
        /// Angular velocity of the first rod
        theta1_dot: Variable::state("rad/s", 0.0, "theta1_ddot"),
        /// Angular velocity of the second rod
        theta2_dot: Variable::state("rad/s", 0.0, "theta2_ddot"),
        /// Angular acceleration of the first rod
        theta1_ddot: Variable::output("rad/s2"),
        /// Angular acceleration of the second rod
        theta2_ddot: Variable::output("rad/s2"),
        /// Mechanical energy T + V
        E: Variable::output("J"),
    }
}

impl Mechanism for DoublePendulum {
    const EXPERIMENT: Experiment = Experiment::until(10.0).step(0.01).tolerance(1e-8);

    fn evaluate<S: Scalar>(v: &mut DoublePendulumValues<S>) {
        let half = lit::<S>(0.5);
        let (s, c) = ((v.theta1 - v.theta2).sin(), (v.theta1 - v.theta2).cos());
        // Lagrange: M(q) q̈ = f(q, q̇), solved as a 2×2 system.
        let mass = Matrix2::new(
            (v.m1 + v.m2) * v.l1 * v.l1,
            v.m2 * v.l1 * v.l2 * c,
            v.m2 * v.l1 * v.l2 * c,
            v.m2 * v.l2 * v.l2,
        );
        let force = Vector2::new(
            -v.m2 * v.l1 * v.l2 * s * v.theta2_dot * v.theta2_dot - (v.m1 + v.m2) * v.g * v.l1 * v.theta1.sin(),
            v.m2 * v.l1 * v.l2 * s * v.theta1_dot * v.theta1_dot - v.m2 * v.g * v.l2 * v.theta2.sin(),
        );
        let acc = mass.lu().solve(&force).unwrap_or_else(|| Vector2::new(S::zero(), S::zero()));
        v.theta1_ddot = acc[0];
        v.theta2_ddot = acc[1];
        let kinetic = half * (v.m1 + v.m2) * v.l1 * v.l1 * v.theta1_dot * v.theta1_dot
            + half * v.m2 * v.l2 * v.l2 * v.theta2_dot * v.theta2_dot
            + v.m2 * v.l1 * v.l2 * v.theta1_dot * v.theta2_dot * c;
        let potential = -(v.m1 + v.m2) * v.g * v.l1 * v.theta1.cos() - v.m2 * v.g * v.l2 * v.theta2.cos();
        v.E = kinetic + potential;
    }
}

mechfmu::export_fmu!(DoublePendulum);
