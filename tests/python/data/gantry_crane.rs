//! `GantryCrane`: the tutorial's mechanism declared from its energies (docs/tutorial.md,
//! "7. Declare a mechanism from its energies"), in a crate made by
//! `mechfmu new GantryCrane --energies`.

#![forbid(unsafe_code)]

use mechfmu::lagrange::{Coordinate, Lagrangian};
use mechfmu::model::{cos, lit, sin_cos, Experiment, Mechanism, Scalar, Variable};

mechfmu::mechanism! {
    /// A gantry crane: a trolley on a rail, moved by its drive, and a payload hanging from it
    /// on a cable that a winch hoists, swinging at angle phi from the downward vertical and
    /// pushed horizontally by the wind.
    pub struct GantryCrane / GantryCraneValues {
        /// Mass of the trolley
        M: Variable::parameter("kg", 500.0).positive(),
        /// Mass of the payload
        m: Variable::parameter("kg", 1000.0).positive(),
        /// Gravitational acceleration
        g: Variable::parameter("m/s2", 9.81),
        /// Acceleration of the trolley, prescribed by its drive
        x_ddot: Variable::input("m/s2", 0.0),
        /// Acceleration of the cable's length, prescribed by the winch (negative: hoisting up)
        l_ddot: Variable::input("m/s2", 0.0),
        /// Horizontal force of the wind on the payload
        F_wind: Variable::input("N", 0.0),
        /// Position of the trolley along the rail
        x: Variable::state("m", 0.0, "x_dot"),
        /// Velocity of the trolley
        x_dot: Variable::state("m/s", 0.0, "x_ddot"),
        /// Length of the cable
        l: Variable::state("m", 5.0, "l_dot"),
        /// Rate of change of the cable's length
        l_dot: Variable::state("m/s", 0.0, "l_ddot"),
        /// Angle of the cable from the downward vertical, counter-clockwise
        phi: Variable::state("rad", 0.0, "phi_dot"),
        /// Angular velocity of the cable
        phi_dot: Variable::state("rad/s", 0.0, "phi_ddot"),
        /// Angular acceleration of the cable
        phi_ddot: Variable::output("rad/s2"),
        /// Force the trolley's drive exerts on it along the rail
        F_trolley: Variable::output("N"),
        /// Force the winch exerts to lengthen the cable (minus the cable's tension)
        F_hoist: Variable::output("N"),
        /// Tension of the cable
        T_cable: Variable::output("N"),
    }
}

impl Lagrangian<3> for GantryCrane {
    const COORDINATES: [Coordinate; 3] = [
        Coordinate::driven("x", "F_trolley"),
        Coordinate::driven("l", "F_hoist"),
        Coordinate::free("phi"),
    ];

    /// The trolley at `ẋ`; the payload at `r = (x + l sin φ, -l cos φ)`, so
    /// `ṙ = (ẋ + l̇ sin φ + l φ̇ cos φ, -l̇ cos φ + l φ̇ sin φ)`.
    #[inline(always)]
    fn kinetic_energy<S: Scalar>(v: &GantryCraneValues<S>) -> S {
        let (sin, cos) = sin_cos(v.phi);
        let r_dot_x = v.x_dot + v.l_dot * sin + v.l * v.phi_dot * cos;
        let r_dot_y = -v.l_dot * cos + v.l * v.phi_dot * sin;
        let half = lit::<S>(0.5);
        half * v.M * v.x_dot * v.x_dot + half * v.m * (r_dot_x * r_dot_x + r_dot_y * r_dot_y)
    }

    /// Gravity on the payload, at height `-l cos φ` below the trolley.
    #[inline(always)]
    fn potential_energy<S: Scalar>(v: &GantryCraneValues<S>) -> S {
        -v.m * v.g * v.l * cos(v.phi)
    }

    /// The wind `F_wind (1, 0)` at the payload: `Q_i = F · ∂r/∂q_i`, with `∂r/∂x = (1, 0)`,
    /// `∂r/∂l = (sin φ, -cos φ)` and `∂r/∂φ = (l cos φ, l sin φ)`.
    fn generalized_forces<S: Scalar>(v: &GantryCraneValues<S>) -> [S; 3] {
        let (sin, cos) = sin_cos(v.phi);
        [v.F_wind, v.F_wind * sin, v.F_wind * v.l * cos]
    }
}

impl Mechanism for GantryCrane {
    const EXPERIMENT: Experiment = Experiment::until(10.0).step(0.01).tolerance(1e-8);

    const NOTES: &'static str = "
        Declared from its energies, with the trolley's position `x` and the cable's length `l`
        driven (their accelerations are inputs) and the swing `φ` free. The payload is at
        `r = (x + l sin φ, -l cos φ)`:

            T = ½ M ẋ² + ½ m ((ẋ + l̇ sin φ + l φ̇ cos φ)² + (l φ̇ sin φ - l̇ cos φ)²)
            V = -m g l cos φ
            Q_x = F_wind        Q_l = F_wind sin φ        Q_φ = F_wind l cos φ

        Lagrange's equation of `φ` gives the swing, those of `x` and `l` the forces the drives
        exert, `F_trolley` and `F_hoist`; the cable's tension is `T_cable = -F_hoist`.
    ";

    fn evaluate<S: Scalar>(v: &mut GantryCraneValues<S>) {
        Self::lagrange(v);
    }

    fn outputs<S: Scalar>(v: &mut GantryCraneValues<S>) {
        v.T_cable = -v.F_hoist;
    }

    fn diagnose(v: &GantryCraneValues<f64>) -> Option<String> {
        Self::mass_matrix_problem(v)
    }
}

mechfmu::export_fmu!(GantryCrane);
