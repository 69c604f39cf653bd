//! The TwoMassOscillator declared from its energies: both masses' kinetic energies, the
//! three springs' potential, and the forces and dampers as generalized forces.

use mechfmu::lagrange::{Coordinate, Lagrangian};
use mechfmu::model::{lit, Scalar};
use mechfmu_energies::{twin, twin_tests};
use two_mass_oscillator::{TwoMassOscillator, TwoMassOscillatorValues};

twin!(EnergyTwoMass of TwoMassOscillator, evaluate(v) {
    Self::lagrange(v);
});

impl Lagrangian<2> for EnergyTwoMass {
    const COORDINATES: [Coordinate; 2] = [Coordinate::free("x1"), Coordinate::free("x2")];

    #[inline(always)]
    fn kinetic_energy<S: Scalar>(v: &TwoMassOscillatorValues<S>) -> S {
        lit::<S>(0.5) * (v.m1 * v.x1_dot * v.x1_dot + v.m2 * v.x2_dot * v.x2_dot)
    }

    /// The wall springs k1, k2 and the coupling spring k3, stretched by x2 - x1.
    #[inline(always)]
    fn potential_energy<S: Scalar>(v: &TwoMassOscillatorValues<S>) -> S {
        let stretch = v.x2 - v.x1;
        lit::<S>(0.5) * (v.k1 * v.x1 * v.x1 + v.k2 * v.x2 * v.x2 + v.k3 * stretch * stretch)
    }

    /// The inputs, the wall dampers and the coupling damper's pull.
    fn generalized_forces<S: Scalar>(v: &TwoMassOscillatorValues<S>) -> [S; 2] {
        let coupling = v.c3 * (v.x2_dot - v.x1_dot);
        [
            v.F1 - v.c1 * v.x1_dot + coupling,
            v.F2 - v.c2 * v.x2_dot - coupling,
        ]
    }
}

// Both masses forced and damped.
twin_tests!(EnergyTwoMass of TwoMassOscillator in "two_mass_oscillator",
    seed: 0x2_0a55,
    trajectories: [("F1", 0.5), ("F2", -1.0), ("c1", 0.2), ("c3", 0.4), ("k3", 3.0)],
    to: 10.0, by: 0.01,
);
