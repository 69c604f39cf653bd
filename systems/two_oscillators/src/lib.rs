//! `TwoOscillators`: the `TwoMassOscillator` cut into its parts, two `Oscillator`s joined by
//! a `SpringDamper`. With the `default` parameter set it is `TwoMassOscillator` at its
//! defaults (`m1 = a.m`, `k1 = a.k`, `c1 = a.c`, `m2 = b.m`, `k2 = b.k`, `c2 = b.c`,
//! `k3 = spring.k`, `c3 = spring.c`), which a co-simulation of it approaches as its
//! communication step shrinks.

#![forbid(unsafe_code)]

use mechfmu::model::Experiment;
use oscillator::Oscillator;
use spring_damper::SpringDamper;

mechfmu::system! {
    /// Two masses, each on its own spring and damper to the ground, joined by a third
    /// spring and damper: TwoMassOscillator as three connected FMUs.
    pub struct TwoOscillators {
        components {
            /// The first mass, on its spring to the ground
            a: Oscillator,
            /// The spring and damper between the masses
            spring: SpringDamper,
            /// The second mass, on its spring to the ground
            b: Oscillator,
        }
        connections {}
        // each mass's position and velocity to its end of the spring, the spring's force back
        terminals {
            a.flange <=> spring.a,
            b.flange <=> spring.b,
        }
        parameter_sets {
            /// TwoMassOscillator's defaults: unit masses and springs, no damping, the first
            /// mass displaced by 1 m
            default {
                a.m = 1.0, a.k = 1.0, a.c = 0.0,
                b.m = 1.0, b.k = 1.0, b.c = 0.0,
                spring.k = 1.0, spring.c = 0.0,
                a.x = 1.0, b.x = 0.0,
            }
            /// Unlike masses and springs, every spring damped
            damped {
                b.m = 2.0, b.k = 0.5, spring.k = 2.0,
                a.c = 0.1, b.c = 0.2, spring.c = 0.05,
            }
        }
        experiment: Experiment::until(30.0).step(0.01).tolerance(1e-6),
    }
}

// What the system is (its SSP); with the feature `fmu`, the system as one FMU: its
// components' equations integrated together.
#[cfg(not(feature = "fmu"))]
mechfmu::export_system!(TwoOscillators);
#[cfg(feature = "fmu")]
mechfmu::export_fmu!(TwoOscillators);
