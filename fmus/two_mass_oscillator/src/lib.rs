//! `TwoMassOscillator`: two masses coupled by springs and dampers, and their vibration modes
//! (MIT 2.003 final review, section 5 "Vibration Modes").
//!
//! Spring `k1` and damper `c1` tie mass 1 to a wall, `k2` and `c2` tie mass 2 to the other
//! wall, `k3` and `c3` join the masses. Newton's second law on each mass (the coupling spring
//! pulls mass 1 with `k3 (x2 - x1)` and mass 2 with `k3 (x1 - x2)`, likewise the damper):
//!
//! ```text
//! m1 ẍ1 + (c1+c3) ẋ1 - c3 ẋ2 + (k1+k3) x1 - k3 x2 = F1
//! m2 ẍ2 + (c2+c3) ẋ2 - c3 ẋ1 + (k2+k3) x2 - k3 x1 = F2
//! ```
//!
//! Checked by a route that does not reuse them: these are Lagrange's equations of
//! `T = ½ m1 ẋ1² + ½ m2 ẋ2²`, `V = ½ k1 x1² + ½ k2 x2² + ½ k3 (x1 - x2)²` with the
//! Rayleigh dissipation `D = ½ c1 ẋ1² + ½ c2 ẋ2² + ½ c3 (ẋ1 - ẋ2)²`, so the energy `E = T + V`
//! obeys `dE/dt = F1 ẋ1 + F2 ẋ2 - 2D` (tested). The notes print the undamped equations only;
//! they agree with these at `c = 0` and `F = 0`.
//!
//! The modes are the generalized eigenpairs of `K a = ω² M a` with `M = diag(m1, m2)` and
//! `K = [[k1+k3, -k3], [-k3, k2+k3]]`; the notes' closed form for `ω²` (the roots of
//! `det(K - ω² M) = 0`) is the independent check in the tests.

#![forbid(unsafe_code)]

use mechfmu::model::{Array, Experiment, Mechanism, Scalar, Variable};
use mechfmu::nalgebra::Matrix2;

mechfmu::mechanism! {
    /// Two masses on springs and dampers: k1, c1 from a wall to mass 1, k2, c2 from a wall to
    /// mass 2, k3, c3 between them, forces F1 and F2 on the masses. Gives the undamped natural
    /// frequencies and mode shapes. m1 x1_ddot + (c1+c3) x1_dot - c3 x2_dot + (k1+k3) x1 - k3 x2
    /// = F1, m2 x2_ddot + (c2+c3) x2_dot - c3 x1_dot + (k2+k3) x2 - k3 x1 = F2.
    pub struct TwoMassOscillator / TwoMassOscillatorValues {
        /// Mass 1
        m1: Variable::parameter("kg", 1.0).positive(),
        /// Mass 2
        m2: Variable::parameter("kg", 1.0).positive(),
        /// Stiffness of the spring from the wall to mass 1 (0 allowed)
        k1: Variable::tunable("N/m", 1.0).min(0.0),
        /// Stiffness of the spring from the wall to mass 2 (0 allowed)
        k2: Variable::tunable("N/m", 1.0).min(0.0),
        /// Stiffness of the spring between the masses
        k3: Variable::tunable("N/m", 1.0).min(0.0),
        /// Damping coefficient of the damper from the wall to mass 1
        c1: Variable::tunable("N.s/m", 0.0).min(0.0),
        /// Damping coefficient of the damper from the wall to mass 2
        c2: Variable::tunable("N.s/m", 0.0).min(0.0),
        /// Damping coefficient of the damper between the masses
        c3: Variable::tunable("N.s/m", 0.0).min(0.0),
        /// External force on mass 1
        F1: Variable::input("N", 0.0),
        /// External force on mass 2
        F2: Variable::input("N", 0.0),
        /// Position of mass 1 (from its rest position)
        x1: Variable::state("m", 1.0, "x1_dot"),
        /// Position of mass 2 (from its rest position)
        x2: Variable::state("m", 0.0, "x2_dot"),
        /// Velocity of mass 1
        x1_dot: Variable::state("m/s", 0.0, "x1_ddot"),
        /// Velocity of mass 2
        x2_dot: Variable::state("m/s", 0.0, "x2_ddot"),
        /// Acceleration of mass 1
        x1_ddot: Variable::output("m/s2"),
        /// Acceleration of mass 2
        x2_ddot: Variable::output("m/s2"),
        /// Mechanical energy: kinetic energy of the masses plus the energy stored in the springs
        E: Variable::output("J"),
        /// Lower undamped natural frequency
        omega_n1: Variable::calculated("rad/s"),
        /// Higher undamped natural frequency
        omega_n2: Variable::calculated("rad/s"),
        /// Mode 1 shape, x1 component (the component of largest magnitude is +1; on a tie, x1)
        mode1_x1: Variable::calculated("1"),
        /// Mode 1 shape, x2 component
        mode1_x2: Variable::calculated("1"),
        /// Mode 2 shape, x1 component (the component of largest magnitude is +1; on a tie, x1)
        mode2_x1: Variable::calculated("1"),
        /// Mode 2 shape, x2 component
        mode2_x2: Variable::calculated("1"),
        /// Mass matrix, element (1,1): m1
        M_11: Variable::calculated("kg").fixed(),
        /// Mass matrix, elements (1,2) and (2,1): 0
        M_12: Variable::calculated("kg").fixed(),
        /// Mass matrix, element (2,2): m2
        M_22: Variable::calculated("kg").fixed(),
        /// Stiffness matrix, element (1,1): k1 + k3
        K_11: Variable::calculated("N/m"),
        /// Stiffness matrix, elements (1,2) and (2,1): -k3
        K_12: Variable::calculated("N/m"),
        /// Stiffness matrix, element (2,2): k2 + k3
        K_22: Variable::calculated("N/m"),
        /// Damping matrix, element (1,1): c1 + c3
        C_11: Variable::calculated("N.s/m"),
        /// Damping matrix, elements (1,2) and (2,1): -c3
        C_12: Variable::calculated("N.s/m"),
        /// Damping matrix, element (2,2): c2 + c3
        C_22: Variable::calculated("N.s/m"),
    }
}

impl Mechanism for TwoMassOscillator {
    const EXPERIMENT: Experiment = Experiment::until(30.0).step(0.01).tolerance(1e-6);

    const NOTES: &'static str = "
        Newton's second law on each mass (MIT 2.003 final review, section 5); the coupling
        spring pulls mass 1 with `k3 (x2 - x1)` and mass 2 with `k3 (x1 - x2)`, likewise the
        coupling damper:

            m1 ẍ1 + (c1+c3) ẋ1 - c3 ẋ2 + (k1+k3) x1 - k3 x2 = F1
            m2 ẍ2 + (c2+c3) ẋ2 - c3 ẋ1 + (k2+k3) x2 - k3 x1 = F2

        These are Lagrange's equations of `T = ½ m1 ẋ1² + ½ m2 ẋ2²`,
        `V = ½ k1 x1² + ½ k2 x2² + ½ k3 (x1 - x2)²` with Rayleigh's dissipation
        `D = ½ c1 ẋ1² + ½ c2 ẋ2² + ½ c3 (ẋ1 - ẋ2)²`, so `E = T + V` obeys
        `dE/dt = F1 ẋ1 + F2 ẋ2 - 2 D`.

        The undamped modes are the generalized eigenpairs of `K a = ω² M a`,
        `M = diag(m1, m2)`, `K = [[k1+k3, -k3], [-k3, k2+k3]]`, frequencies ascending, each
        shape scaled so that its component of largest magnitude is +1 (on a tie, `x1`).

        ## Departures from the notes
        The notes print the undamped, unforced equations only; these agree with them at
        `c = 0`, `F = 0`. The dampers and forces are additions, checked by the energy balance
        above. The notes' closed form for `ω²` is used as the independent check of the
        eigen-solver.
    ";

    /// The matrices of `M ẍ + C ẋ + K x = F` and the modes as FMI 3.0 arrays (FMI 2.0 has
    /// their scalars).
    const ARRAYS: &'static [Array] = &[
        Array::new(
            "M",
            "Mass matrix",
            &[2, 2],
            &["M_11", "M_12", "M_12", "M_22"],
        ),
        Array::new(
            "K",
            "Stiffness matrix",
            &[2, 2],
            &["K_11", "K_12", "K_12", "K_22"],
        ),
        Array::new(
            "C",
            "Damping matrix",
            &[2, 2],
            &["C_11", "C_12", "C_12", "C_22"],
        ),
        Array::new(
            "modes",
            "Undamped mode shapes, column j is mode j (its component of largest magnitude is +1)",
            &[2, 2],
            &["mode1_x1", "mode2_x1", "mode1_x2", "mode2_x2"],
        ),
    ];

    fn calculate(v: &mut TwoMassOscillatorValues<f64>) -> Result<(), String> {
        (v.M_11, v.M_12, v.M_22) = (v.m1, 0.0, v.m2);
        (v.K_11, v.K_12, v.K_22) = (v.k1 + v.k3, -v.k3, v.k2 + v.k3);
        (v.C_11, v.C_12, v.C_22) = (v.c1 + v.c3, -v.c3, v.c2 + v.c3);
        let mass = Matrix2::new(v.M_11, v.M_12, v.M_12, v.M_22);
        let stiffness = Matrix2::new(v.K_11, v.K_12, v.K_12, v.K_22);
        let [first, second] = mechfmu::modal::undamped_modes(&mass, &stiffness)?;
        v.omega_n1 = first.omega;
        v.omega_n2 = second.omega;
        (v.mode1_x1, v.mode1_x2) = (first.shape[0], first.shape[1]);
        (v.mode2_x1, v.mode2_x2) = (second.shape[0], second.shape[1]);
        Ok(())
    }

    fn evaluate<S: Scalar>(v: &mut TwoMassOscillatorValues<S>) {
        // Force of the coupling spring and damper on mass 1 (mass 2 gets its opposite).
        let coupling = v.k3 * (v.x2 - v.x1) + v.c3 * (v.x2_dot - v.x1_dot);
        v.x1_ddot = (v.F1 - v.k1 * v.x1 - v.c1 * v.x1_dot + coupling) / v.m1;
        v.x2_ddot = (v.F2 - v.k2 * v.x2 - v.c2 * v.x2_dot - coupling) / v.m2;
    }

    /// The energy: no derivative needs it.
    fn outputs<S: Scalar>(v: &mut TwoMassOscillatorValues<S>) {
        let half = mechfmu::model::lit::<S>(0.5);
        let stretch = v.x1 - v.x2;
        v.E = half
            * (v.m1 * v.x1_dot * v.x1_dot
                + v.m2 * v.x2_dot * v.x2_dot
                + v.k1 * v.x1 * v.x1
                + v.k2 * v.x2 * v.x2
                + v.k3 * stretch * stretch);
    }
}

// The FMU's functions; none when the crate is compiled into a system's FMU.
#[cfg(not(feature = "component"))]
mechfmu::export_fmu!(TwoMassOscillator);
