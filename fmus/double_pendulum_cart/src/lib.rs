//! `DoublePendulumCart`: a double pendulum on a driven cart, declared from its energies.
//!
//! A cart of mass `M` rides a horizontal track at position `x`, pushed by a force `F` and
//! slowed by a viscous drag `c ẋ`. From a pin on the cart hangs a massless rod of length `l1`
//! carrying a point mass `m1`; from `m1` hangs a second massless rod of length `l2` carrying
//! a point mass `m2`. Both angles `φ1`, `φ2` are measured from the downward vertical,
//! counter-clockwise (a positive `φ` swings the mass towards `+I`):
//!
//! ```text
//! p1 = (x + l1 sin φ1, -l1 cos φ1)        p2 = p1 + (l2 sin φ2, -l2 cos φ2)
//! T  = ½ M ẋ² + ½ m1 |ṗ1|² + ½ m2 |ṗ2|²    V = g (m1 p1y + m2 p2y)     Q = (F - c ẋ, 0, 0)
//! ```
//!
//! That is the whole model: the runtime forms Lagrange's equations from `T`, `V` and `Q`
//! ([`mechfmu::lagrange`], derivatives exact by dual numbers) and solves them. Written out
//! (for the reader and the checks; the code does not use them), with `Δ = φ1 - φ2`,
//! `m12 = m1 + m2`:
//!
//! ```text
//! (M + m12) ẍ + m12 l1 cos φ1 φ̈1 + m2 l2 cos φ2 φ̈2 = F - c ẋ + m12 l1 φ̇1² sin φ1 + m2 l2 φ̇2² sin φ2
//! m12 l1 cos φ1 ẍ + m12 l1² φ̈1 + m2 l1 l2 cos Δ φ̈2  = -m12 g l1 sin φ1 - m2 l1 l2 φ̇2² sin Δ
//! m2 l2 cos φ2 ẍ + m2 l1 l2 cos Δ φ̈1 + m2 l2² φ̈2     = -m2 g l2 sin φ2 + m2 l1 l2 φ̇1² sin Δ
//! ```
//!
//! The mass matrix `∂²T/∂q̇²` is `Jᵀ diag(M, m1, m1, m2, m2) J`, `J` the Jacobian of the
//! bodies' velocities in `(ẋ, φ̇1, φ̇2)`: `J` has full rank whenever `l1, l2 > 0` (the cart's
//! velocity gives `ẋ`, then `ṗ1 - ẋ I = l1 φ̇1 (cos φ1, sin φ1)` gives `φ̇1`, and `ṗ2 - ṗ1`
//! gives `φ̇2`), so with positive masses the matrix is positive definite at every state and
//! the accelerations exist everywhere.
//!
//! The independent check is Newton's law for the three bodies separately, the rod
//! tensions `T1`, `T2` as unknowns (the cart `M ẍ = F - c ẋ + T1 sin φ1`, `m1 p̈1 = -T1 e1 +
//! T2 e2 - m1 g J`, `m2 p̈2 = -T2 e2 - m2 g J` with `e_i = (sin φi, -cos φi)`), solved as
//! one linear system: `tests/double_pendulum_cart.rs` here, `tests/python/refs/
//! double_pendulum_cart.py` and `refs/derive/double_pendulum_cart.py` (sympy) in the Python
//! suite.

#![forbid(unsafe_code)]

use mechfmu::lagrange::{Coordinate, Lagrangian};
use mechfmu::model::{lit, sin_cos, Experiment, Mechanism, Scalar, Variable};

mechfmu::mechanism! {
    /// A cart of mass M on a horizontal track, pushed by a force F against a viscous drag
    /// c x_dot, carrying a double pendulum: a massless rod l1 to a point mass m1, a massless
    /// rod l2 from m1 to a point mass m2, both angles from the downward vertical. The
    /// accelerations are Lagrange's equations of T = 1/2 M x_dot^2 + 1/2 m1 |v1|^2 + 1/2 m2
    /// |v2|^2, V = g (m1 y1 + m2 y2) and Q = (F - c x_dot, 0, 0).
    pub struct DoublePendulumCart / DoublePendulumCartValues {
        /// Mass of the cart
        M: Variable::parameter("kg", 1.0).positive(),
        /// First point mass, at the end of the upper rod
        m1: Variable::parameter("kg", 0.5).positive(),
        /// Second point mass, at the end of the lower rod
        m2: Variable::parameter("kg", 0.5).positive(),
        /// Length of the upper rod, from the pin on the cart to m1
        l1: Variable::parameter("m", 0.5).positive(),
        /// Length of the lower rod, from m1 to m2
        l2: Variable::parameter("m", 0.5).positive(),
        /// Acceleration of gravity
        g: Variable::parameter("m/s2", 9.81).min(0.0),
        /// Viscous drag coefficient of the track on the cart
        c: Variable::tunable("N.s/m", 0.0).min(0.0),
        /// Horizontal force pushing the cart
        F: Variable::input("N", 0.0),
        /// Position of the cart (of the pin) along the track
        x: Variable::state("m", 0.0, "x_dot"),
        /// Velocity of the cart
        x_dot: Variable::state("m/s", 0.0, "x_ddot"),
        /// Angle of the upper rod from the downward vertical, counter-clockwise
        phi1: Variable::state("rad", 1.0, "phi1_dot"),
        /// Angular velocity of the upper rod
        phi1_dot: Variable::state("rad/s", 0.0, "phi1_ddot"),
        /// Angle of the lower rod from the downward vertical, counter-clockwise
        phi2: Variable::state("rad", 0.5, "phi2_dot"),
        /// Angular velocity of the lower rod
        phi2_dot: Variable::state("rad/s", 0.0, "phi2_ddot"),
        /// Acceleration of the cart
        x_ddot: Variable::output("m/s2"),
        /// Angular acceleration of the upper rod
        phi1_ddot: Variable::output("rad/s2"),
        /// Angular acceleration of the lower rod
        phi2_ddot: Variable::output("rad/s2"),
        /// Horizontal position of m2 in the ground frame
        tip_x: Variable::output("m"),
        /// Vertical position of m2 in the ground frame (from the track's height)
        tip_y: Variable::output("m"),
        /// Mechanical energy T + V (heights measured from the track)
        E: Variable::output("J"),
        /// Horizontal momentum of the cart and both masses
        p_x: Variable::output("N.s"),
    }
}

impl Lagrangian<3> for DoublePendulumCart {
    const COORDINATES: [Coordinate; 3] = [
        Coordinate::free("x"),
        Coordinate::free("phi1"),
        Coordinate::free("phi2"),
    ];

    /// The cart at `ẋ`; `m1` and `m2` at the velocities of `p1` and `p2`.
    // Inlined, the work on the parameters' zero derivatives folds away: a step costs 2.3-2.6
    // times these equations written by hand, against 5.8-7.0 not inlined.
    #[inline(always)]
    fn kinetic_energy<S: Scalar>(v: &DoublePendulumCartValues<S>) -> S {
        let [v1, v2] = velocities(v);
        let half = lit::<S>(0.5);
        half * v.M * v.x_dot * v.x_dot
            + half * v.m1 * (v1[0] * v1[0] + v1[1] * v1[1])
            + half * v.m2 * (v2[0] * v2[0] + v2[1] * v2[1])
    }

    /// Gravity on both masses, heights from the track.
    // Inlined for the same reason.
    #[inline(always)]
    fn potential_energy<S: Scalar>(v: &DoublePendulumCartValues<S>) -> S {
        let [p1, p2] = positions(v);
        v.g * (v.m1 * p1[1] + v.m2 * p2[1])
    }

    /// `F` and the drag act on the cart along `I`, whose virtual displacement is `δx`.
    fn generalized_forces<S: Scalar>(v: &DoublePendulumCartValues<S>) -> [S; 3] {
        [v.F - v.c * v.x_dot, S::zero(), S::zero()]
    }
}

/// `p1` and `p2` in the ground frame.
#[inline(always)]
fn positions<S: Scalar>(v: &DoublePendulumCartValues<S>) -> [[S; 2]; 2] {
    let (sin1, cos1) = sin_cos(v.phi1);
    let (sin2, cos2) = sin_cos(v.phi2);
    let p1 = [v.x + v.l1 * sin1, -v.l1 * cos1];
    [p1, [p1[0] + v.l2 * sin2, p1[1] - v.l2 * cos2]]
}

/// `ṗ1` and `ṗ2`: the positions differentiated by hand.
#[inline(always)]
fn velocities<S: Scalar>(v: &DoublePendulumCartValues<S>) -> [[S; 2]; 2] {
    let (sin1, cos1) = sin_cos(v.phi1);
    let (sin2, cos2) = sin_cos(v.phi2);
    let (w1, w2) = (v.l1 * v.phi1_dot, v.l2 * v.phi2_dot);
    let v1 = [v.x_dot + w1 * cos1, w1 * sin1];
    [v1, [v1[0] + w2 * cos2, v1[1] + w2 * sin2]]
}

impl Mechanism for DoublePendulumCart {
    const EXPERIMENT: Experiment = Experiment::until(10.0).step(0.01).tolerance(1e-9);

    const NOTES: &'static str = "
        Cart `M` on a horizontal track, pushed by `F`, slowed by a viscous drag `c ẋ`; a
        massless rod `l1` from a pin on the cart to a point mass `m1`, a massless rod `l2`
        from `m1` to a point mass `m2`; `φ1`, `φ2` from the downward vertical,
        counter-clockwise. Declared from its energies alone:

            p1 = (x + l1 sin φ1, -l1 cos φ1)      p2 = p1 + (l2 sin φ2, -l2 cos φ2)
            T  = ½ M ẋ² + ½ m1 |ṗ1|² + ½ m2 |ṗ2|²
            V  = g (m1 p1y + m2 p2y)              Q = (F - c ẋ, 0, 0)

        The accelerations are Lagrange's equations of `T`, `V` and `Q`, formed with exact
        derivatives and solved at every evaluation; no equation of motion is written by
        hand. Written out, with `Δ = φ1 - φ2` and `m12 = m1 + m2`:

            (M+m12) ẍ + m12 l1 cos φ1 φ̈1 + m2 l2 cos φ2 φ̈2 = F - c ẋ + m12 l1 φ̇1² sin φ1 + m2 l2 φ̇2² sin φ2
            m12 l1 cos φ1 ẍ + m12 l1² φ̈1 + m2 l1 l2 cos Δ φ̈2 = -m12 g l1 sin φ1 - m2 l1 l2 φ̇2² sin Δ
            m2 l2 cos φ2 ẍ + m2 l1 l2 cos Δ φ̈1 + m2 l2² φ̈2    = -m2 g l2 sin φ2 + m2 l1 l2 φ̇1² sin Δ

        The mass matrix is positive definite at every state for positive masses and
        lengths. Outputs: the position of `m2` (`tip_x`, `tip_y`), `E = T + V` and the
        horizontal momentum `p_x = M ẋ + m1 ṗ1x + m2 ṗ2x`. Checked against Newton's law for
        the cart, `m1` and `m2` separately (the rod tensions as unknowns), and the balances
        `dE/dt = F ẋ - c ẋ²`, `dp_x/dt = F - c ẋ`: with `F = 0` and `c = 0`, `E` and `p_x`
        are constant.

        ## Parameters and tolerance
        - The drag `c` is tunable, as the PendulumCart's dampers: changing it moves nothing
          and stores no energy. Masses, lengths and `g` are fixed: a length changed
          mid-run would move the bodies, a mass would change the momentum, at once.
        - The DefaultExperiment's tolerance is 1e-9. From `φ1 = 1`, `φ2 = 0.5` at rest the
          motion is regular (a perturbation grows less than 10-fold against each signal's
          range in 10 s), but a double pendulum turns chaotic at larger swings, where any
          error is amplified. At 1e-9 the FMU follows the reference (Newton's law per body,
          DOP853 at 1e-12) to 6e-10 of each signal's range over the 10 s, ten times the
          reference's own error (5e-11); at 1e-6 it would be 2e-6.
    ";

    fn evaluate<S: Scalar>(v: &mut DoublePendulumCartValues<S>) {
        Self::lagrange(v);
    }

    fn diagnose(v: &DoublePendulumCartValues<f64>) -> Option<String> {
        Self::mass_matrix_problem(v)
    }

    /// What no derivative needs: where `m2` is, the energy and the horizontal momentum.
    fn outputs<S: Scalar>(v: &mut DoublePendulumCartValues<S>) {
        let [_, p2] = positions(v);
        v.tip_x = p2[0];
        v.tip_y = p2[1];
        v.E = Self::kinetic_energy(v) + Self::potential_energy(v);
        let [v1, v2] = velocities(v);
        v.p_x = v.M * v.x_dot + v.m1 * v1[0] + v.m2 * v2[0];
    }
}

// The FMU's functions; none when the crate is compiled into a system's FMU.
#[cfg(not(feature = "component"))]
mechfmu::export_fmu!(DoublePendulumCart);
