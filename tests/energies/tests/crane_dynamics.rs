//! The CraneDynamics declared from its energies: the boom's, the trolley's and the payload's
//! kinetic and potential energies, with the drives' force and torque as generalized forces.

mod crane_outputs;

use crane_dynamics::{CraneDynamics, CraneDynamicsValues};
use mechfmu::lagrange::{Coordinate, Lagrangian};
use mechfmu::model::{lit, sin_cos, Scalar};
use mechfmu_energies::{twin, twin_tests};

twin!(EnergyCraneDynamics of CraneDynamics, evaluate(v) {
    Self::lagrange(v);
    crane_outputs::tension_and_power!(v);
});

impl Lagrangian<3> for EnergyCraneDynamics {
    const COORDINATES: [Coordinate; 3] = [
        Coordinate::free("x"),
        Coordinate::free("theta"),
        Coordinate::free("phi"),
    ];

    /// The boom turning about `O`, the trolley at `x (cos θ, sin θ)`, the payload `l` below it
    /// along `(sin φ, -cos φ)`.
    #[inline(always)]
    fn kinetic_energy<S: Scalar>(v: &CraneDynamicsValues<S>) -> S {
        let half = lit::<S>(0.5);
        let (sin_th, cos_th) = sin_cos(v.theta);
        let (sin_phi, cos_phi) = sin_cos(v.phi);
        let trolley_x = v.x_dot * cos_th - v.x * v.theta_dot * sin_th;
        let trolley_y = v.x_dot * sin_th + v.x * v.theta_dot * cos_th;
        let payload_x = trolley_x + v.l * v.phi_dot * cos_phi;
        let payload_y = trolley_y + v.l * v.phi_dot * sin_phi;
        half * v.J_boom * v.theta_dot * v.theta_dot
            + half * v.m_trolley * (trolley_x * trolley_x + trolley_y * trolley_y)
            + half * v.m * (payload_x * payload_x + payload_y * payload_y)
    }

    #[inline(always)]
    fn potential_energy<S: Scalar>(v: &CraneDynamicsValues<S>) -> S {
        let (sin_th, _) = sin_cos(v.theta);
        let (_, cos_phi) = sin_cos(v.phi);
        let trolley_y = v.x * sin_th;
        v.g * (v.m_trolley * trolley_y + v.m * (trolley_y - v.l * cos_phi))
    }

    /// The drive's force along the boom does work on `x`, the boom's torque on `θ`.
    fn generalized_forces<S: Scalar>(v: &CraneDynamicsValues<S>) -> [S; 3] {
        [v.F, v.tau, S::zero()]
    }
}

// The swing with the drives' force and torque applied.
twin_tests!(EnergyCraneDynamics of CraneDynamics in "crane_dynamics",
    seed: 0xd1_ca,
    trajectories: [("phi", 0.8), ("F", 9000.0), ("tau", 90000.0), ("x_dot", 0.3)],
    to: 5.0, by: 0.01,
);
