//! The Crane declared from its energies: the payload's kinetic and potential energies with
//! the trolley's `x` and the boom's `θ` driven. Lagrange's equations give the swing, and the
//! generalized forces the drives exert, `F` along the boom and `tau` about `O`, from the
//! energies alone.

mod crane_outputs;

use crane::{Crane, CraneValues};
use mechfmu::lagrange::{Coordinate, Lagrangian};
use mechfmu::model::{lit, sin_cos, Scalar};
use mechfmu_energies::{twin, twin_tests};

twin!(EnergyCrane of Crane, evaluate(v) {
    Self::lagrange(v);
    crane_outputs::tension_and_power!(v);
});

impl Lagrangian<3> for EnergyCrane {
    const COORDINATES: [Coordinate; 3] = [
        Coordinate::driven("x", "F"),
        Coordinate::driven("theta", "tau"),
        Coordinate::free("phi"),
    ];

    /// The payload at `x (cos θ, sin θ) + l (sin φ, -cos φ)`, differentiated by hand.
    #[inline(always)]
    fn kinetic_energy<S: Scalar>(v: &CraneValues<S>) -> S {
        let (sin_th, cos_th) = sin_cos(v.theta);
        let (sin_phi, cos_phi) = sin_cos(v.phi);
        let vel_x = v.x_dot * cos_th - v.x * v.theta_dot * sin_th + v.l * v.phi_dot * cos_phi;
        let vel_y = v.x_dot * sin_th + v.x * v.theta_dot * cos_th + v.l * v.phi_dot * sin_phi;
        lit::<S>(0.5) * v.m * (vel_x * vel_x + vel_y * vel_y)
    }

    #[inline(always)]
    fn potential_energy<S: Scalar>(v: &CraneValues<S>) -> S {
        let (sin_th, _) = sin_cos(v.theta);
        let (_, cos_phi) = sin_cos(v.phi);
        v.m * v.g * (v.x * sin_th - v.l * cos_phi)
    }
}

// The swing with the trolley and the boom driven.
twin_tests!(EnergyCrane of Crane in "crane",
    seed: 0xc4ae,
    trajectories: [("phi", 1.0), ("x_ddot", 0.2), ("theta_ddot", -0.01), ("theta_dot", 0.1)],
    to: 5.0, by: 0.01,
);
