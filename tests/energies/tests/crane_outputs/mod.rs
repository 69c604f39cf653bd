//! What the crane twins compute after Lagrange's equations, as the hand-written crates do:
//! the cable's pull, which the monitor reads, and the drives' power, the rate of the work.
//! Neither comes from the energies; both read the accelerations they gave.

/// `tension_and_power!(v)` on a crane's values (`Crane`'s or `CraneDynamics`').
macro_rules! tension_and_power {
    ($v:ident) => {{
        use crane_kinematics::{cable_tension, normal_acceleration, radial_acceleration};
        use mechfmu::model::sin_cos;
        let (sin_s, cos_s) = sin_cos($v.theta - $v.phi);
        let (_, cos_phi) = sin_cos($v.phi);
        let a_radial = radial_acceleration($v.x, $v.theta_dot, $v.x_ddot);
        let a_normal = normal_acceleration($v.x, $v.x_dot, $v.theta_dot, $v.theta_ddot);
        let a_trolley = (a_radial, a_normal);
        $v.T = cable_tension(
            $v.m,
            $v.l,
            $v.g,
            a_trolley,
            (sin_s, cos_s),
            $v.phi_dot,
            cos_phi,
        );
        $v.P_drives = $v.F * $v.x_dot + $v.tau * $v.theta_dot;
    }};
}

pub(crate) use tension_and_power;
