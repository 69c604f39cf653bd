//! The Oscillator declared from its energies: the mass's kinetic energy, the spring's
//! potential, and the force and the damper as generalized forces.

use mechfmu::lagrange::{Coordinate, Lagrangian};
use mechfmu::model::{lit, sin, Scalar};
use mechfmu_energies::{twin, twin_tests};
use oscillator::{Oscillator, OscillatorValues};

twin!(EnergyOscillator of Oscillator, evaluate(v) {
    Self::lagrange(v);
});

impl Lagrangian<1> for EnergyOscillator {
    const COORDINATES: [Coordinate; 1] = [Coordinate::free("x")];

    #[inline(always)]
    fn kinetic_energy<S: Scalar>(v: &OscillatorValues<S>) -> S {
        lit::<S>(0.5) * v.m * v.x_dot * v.x_dot
    }

    #[inline(always)]
    fn potential_energy<S: Scalar>(v: &OscillatorValues<S>) -> S {
        lit::<S>(0.5) * v.k * v.x * v.x
    }

    /// The input, the harmonic force and the damper.
    fn generalized_forces<S: Scalar>(v: &OscillatorValues<S>) -> [S; 1] {
        [v.F + v.F0 * sin(v.omega * v.time) - v.c * v.x_dot]
    }
}

// A forced, damped oscillation.
twin_tests!(EnergyOscillator of Oscillator in "oscillator",
    seed: 0x05c1_11a7,
    trajectories: [("F0", 1.5), ("omega", 2.5), ("F", -0.3), ("c", 0.1)],
    to: 10.0, by: 0.01,
);
