//! The Oscillator declared from its energies: the mass's kinetic energy, the spring's
//! potential, and the force and the damper as generalized forces.

use mechfmu::lagrange::{Coordinate, Lagrangian};
use mechfmu::model::{lit, sin, Scalar};
use mechfmu_energies::{agreement, reference_case, same_trajectories, twin};
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

#[test]
fn accelerations_agree_at_random_points() {
    let found = agreement::<Oscillator, EnergyOscillator>(1000, 0x05c1_11a7);
    println!("{found:?}");
    assert!(found.worst_value <= 1e-12, "{found:?}");
    assert!(found.worst_derivative <= 1e-12, "{found:?}");
}

#[test]
fn reference_case_agrees() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fmus/oscillator");
    let (hand, twin) = reference_case::<Oscillator, EnergyOscillator>(&dir);
    println!("reference: hand {hand:e}, twin {twin:e}");
    assert!(twin <= hand + 1e-9, "hand {hand:e}, twin {twin:e}");
}

#[test]
fn forced_trajectories_agree() {
    let start = [("F0", 1.5), ("omega", 2.5), ("F", -0.3), ("c", 0.1)];
    let worst = same_trajectories::<Oscillator, EnergyOscillator>(&start, 10.0, 0.01);
    println!("trajectories: {worst:e}");
    assert!(worst <= 1e-9, "{worst:e}");
}

/// What `mechfmu bench --energies` counts the instructions of (see `mechfmu_energies::probe`).
#[test]
#[ignore]
fn probe() {
    mechfmu_energies::probe::<Oscillator, EnergyOscillator>();
}
