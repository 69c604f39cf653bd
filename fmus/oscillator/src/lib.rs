//! `Oscillator`: a single degree of freedom with lumped mass, spring and damper, driven by a
//! force input and a harmonic force (MIT 2.003 final review, sections 3 and 4).
//!
//! `m ẍ + c ẋ + k x = F + F0 sin(ω t)`

#![forbid(unsafe_code)]

use mechfmu::model::{sin, Experiment, Mechanism, Scalar, Terminal, Variable, TRANSLATIONAL};

mechfmu::mechanism! {
    /// A mass on a spring and a damper, driven by an input force F and a harmonic force
    /// F0 sin(omega t): m x_ddot + c x_dot + k x = F + F0 sin(omega t).
    pub struct Oscillator / OscillatorValues {
        /// Mass
        m: Variable::parameter("kg", 1.0).positive(),
        /// Damping coefficient
        c: Variable::tunable("N.s/m", 0.4).min(0.0),
        /// Spring stiffness
        k: Variable::tunable("N/m", 4.0).min(0.0),
        /// Amplitude of the harmonic force F0 sin(omega t)
        F0: Variable::tunable("N", 0.0),
        /// Angular frequency of the harmonic force
        omega: Variable::tunable("rad/s", 1.0),
        /// External force on the mass
        F: Variable::input("N", 0.0),
        /// Position of the mass
        x: Variable::state("m", 1.0, "x_dot"),
        /// Velocity of the mass
        x_dot: Variable::state("m/s", 0.0, "x_ddot"),
        /// Acceleration of the mass
        x_ddot: Variable::output("m/s2"),
        /// Undamped natural frequency sqrt(k/m)
        omega_n: Variable::calculated("rad/s"),
        /// Damping ratio c / (2 sqrt(m k))
        zeta: Variable::calculated("1"),
    }
}

impl Mechanism for Oscillator {
    const EXPERIMENT: Experiment = Experiment::until(20.0).step(0.01).tolerance(1e-6);

    const TERMINALS: &'static [Terminal] = &[Terminal::new(
        "flange",
        TRANSLATIONAL,
        "The mass: its position and velocity, and the force on it",
        &[("s", "x"), ("v", "x_dot"), ("f", "F")],
    )];

    const NOTES: &'static str = "
        Newton's second law on the mass (MIT 2.003 final review, sections 3 and 4):

            m ẍ + c ẋ + k x = F + F0 sin(ω t)

        with the calculated parameters `omega_n = sqrt(k/m)` and `zeta = c / (2 sqrt(m k))`
        (`zeta` is reported as infinite when `k = 0`: a free mass).

        The notes' closed forms are the references `mechfmu validate` runs: the free response
        for `ζ > 1`, `ζ = 1`, `0 < ζ < 1` and `ζ = 0`, the step response to a constant `F`, and
        the complete response to `F0 sin(ω t)`, whose steady part has amplitude
        `X = F0 / sqrt((k - m ω²)² + (c ω)²)` and phase `ψ = -atan2(c ω, k - m ω²)`.

        ## Departures from the notes
        None in the equation. The FMU adds the input force `F` (held over a communication
        step, or following its derivatives when the importer sets them) beside the notes'
        harmonic forcing.
    ";

    fn calculate(v: &mut OscillatorValues<f64>) -> Result<(), String> {
        v.omega_n = (v.k / v.m).sqrt();
        // k = 0 leaves a free mass: no natural frequency, and ζ is infinite (overdamped
        // when c > 0); report it as such rather than as NaN.
        v.zeta = if v.k > 0.0 {
            v.c / (2.0 * (v.m * v.k).sqrt())
        } else {
            f64::INFINITY
        };
        Ok(())
    }

    fn evaluate<S: Scalar>(v: &mut OscillatorValues<S>) {
        // F0 is a parameter, never a dual number's variable, so F0 = 0 drops the term
        // exactly, derivatives included: the free response costs no sine.
        let harmonic = if v.F0 == S::zero() {
            S::zero()
        } else {
            v.F0 * sin(v.omega * v.time)
        };
        let forcing = v.F + harmonic;
        v.x_ddot = (forcing - v.c * v.x_dot - v.k * v.x) / v.m;
    }
}

// The FMU's functions; none when the crate is compiled into a system's FMU.
#[cfg(not(feature = "component"))]
mechfmu::export_fmu!(Oscillator);
