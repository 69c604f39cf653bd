//! The PendulumCart declared from its energies: the cart's and the rod's kinetic energies
//! from their velocities, the spring's and gravity's potential, and the virtual work of the
//! force at the rod's end and of the dampers.

use mechfmu::lagrange::{Coordinate, Lagrangian};
use mechfmu::model::{lit, sin_cos, Scalar};
use mechfmu_energies::{twin, twin_tests};
use pendulum_cart::{PendulumCart, PendulumCartValues};

twin!(EnergyCart of PendulumCart, evaluate(v) {
    Self::lagrange(v);
});

impl Lagrangian<2> for EnergyCart {
    const COORDINATES: [Coordinate; 2] = [Coordinate::free("x"), Coordinate::free("theta")];

    /// The cart at ẋ; the rod's centre C at `x I + l (sin θ, -cos θ)`, turning at θ̇ with
    /// `I_C = m (4l)²/12`.
    #[inline(always)]
    fn kinetic_energy<S: Scalar>(v: &PendulumCartValues<S>) -> S {
        let (sin, cos) = sin_cos(v.theta);
        let half = lit::<S>(0.5);
        let (vc_x, vc_y) = (v.x_dot + v.l * v.theta_dot * cos, v.l * v.theta_dot * sin);
        let i_c = lit::<S>(16.0 / 12.0) * v.m * v.l * v.l;
        half * v.M * v.x_dot * v.x_dot
            + half * v.m * (vc_x * vc_x + vc_y * vc_y)
            + half * i_c * v.theta_dot * v.theta_dot
    }

    #[inline(always)]
    fn potential_energy<S: Scalar>(v: &PendulumCartValues<S>) -> S {
        let (_, cos) = sin_cos(v.theta);
        lit::<S>(0.5) * v.k * v.x * v.x - v.m * v.g * v.l * cos
    }

    /// `F` at D, `x + 3 l sin θ` along I: `δx_D = δx + 3 l cos θ δθ`; the dampers.
    fn generalized_forces<S: Scalar>(v: &PendulumCartValues<S>) -> [S; 2] {
        let (_, cos) = sin_cos(v.theta);
        [
            v.F - v.c1 * v.x_dot,
            lit::<S>(3.0) * v.F * v.l * cos - v.c2 * v.theta_dot,
        ]
    }
}

// The cart and the rod forced and damped.
twin_tests!(EnergyCart of PendulumCart in "pendulum_cart",
    seed: 0x5eed_ca27,
    trajectories: [("F", 2.0), ("c1", 0.3), ("c2", 0.05), ("theta", 1.2), ("x_dot", -0.4)],
    to: 5.0, by: 0.01,
);
