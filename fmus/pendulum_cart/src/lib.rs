//! `PendulumCart`: a cart on a spring carrying a swinging rod (MIT 2.003 quiz 2 review,
//! section 5 "Example: Pendulum Cart").
//!
//! The cart (mass `M`) rides on the ground, tied to a wall by a spring `k` and a dashpot
//! `c1`; `x` is the position of the pin `A` from the spring's unstretched position. A thin rod
//! (mass `m`, length `4l`) hangs from `A`, a distance `l` from its centre of mass `C`, so
//! `I_C = m (4l)²/12 = 4/3 m l²` and `I_A = I_C + m l² = 7/3 m l²`; the pin has a rotary
//! damper `c2`. `θ` is the rod's angle from the downward vertical, counter-clockwise, so with
//! `e = (sin θ, -cos θ)` along the rod: `r_C = x I + l e`, `r_D = x I + 3l e`. A horizontal
//! force `F I` acts at the rod's far end `D`.
//!
//! Equations of motion, by Lagrange (the notes' variational route), re-derived:
//!
//! ```text
//! T = ½ (M+m) ẋ² + m l ẋ θ̇ cos θ + 7/6 m l² θ̇²        V = ½ k x² - m g l cos θ
//! Ξ_x = F - c1 ẋ                                       (virtual work of F at D: F δx_D,
//! Ξ_θ = 3 F l cos θ - c2 θ̇                              δx_D = δx + 3 l cos θ δθ)
//!
//! (M+m) ẍ + m l cos θ θ̈ = F - c1 ẋ - k x + m l θ̇² sin θ
//! m l cos θ ẍ + 7/3 m l² θ̈ = 3 F l cos θ - c2 θ̇ - m g l sin θ
//! ```
//!
//! and by Newton–Euler (the notes' direct route), as the independent check: with `(F1, F2)`
//! the force of the rod on the cart at `A`, the cart gives `M ẍ = F1 - k x - c1 ẋ`, the rod
//! `m a_C = (F - F1, -F2 - m g)` with `a_C = (ẍ + l θ̈ cos θ - l θ̇² sin θ, l θ̈ sin θ + l θ̇² cos θ)`,
//! and Euler about `C`: `4/3 m l² θ̈ = 2 l F cos θ + l (F1 cos θ + F2 sin θ) - c2 θ̇`.
//! Eliminating `F1`, `F2` gives the two equations above (done by hand and by sympy in
//! `tests/python/refs/derive/pendulum_cart.py`; the tests evaluate both routes at random
//! states against this right-hand side). The notes reach the same equations, though their Euler step writes
//! `r_C × v_A = -ẋ l cos θ K`, whose sign is wrong (it is `+ẋ l cos θ K`); the final line
//! is right.
//!
//! Normal force: the notes print `F_N = (M+m) g - m l (θ̈ sin θ + θ̇² cos θ)`, which has the
//! wrong sign. Vertical Newton on the rod gives `F2 = -m g - m a_Cy`, and on the cart
//! `F_N + F2 - M g = 0`, so `F_N = (M+m) g + m l (θ̈ sin θ + θ̇² cos θ)`: at the bottom of a
//! swing the rod's centripetal acceleration points up and the cart is pressed down harder.

#![forbid(unsafe_code)]

use mechfmu::model::{lit, sin_cos, Experiment, Mechanism, Scalar, Variable};
use mechfmu::nalgebra::Matrix2;

mechfmu::mechanism! {
    /// A cart on a spring k and dashpot c1, carrying a rod of mass m and length 4 l pinned a
    /// distance l from its centre of mass, with rotary damping c2 and a horizontal force F at
    /// the rod's far end. (M+m) x_ddot + c1 x_dot + k x + m l (theta_ddot cos(theta) -
    /// theta_dot^2 sin(theta)) = F; m l x_ddot cos(theta) + 7/3 m l^2 theta_ddot + c2 theta_dot
    /// + m g l sin(theta) = 3 F l cos(theta).
    pub struct PendulumCart / PendulumCartValues {
        /// Mass of the cart
        M: Variable::parameter("kg", 1.0).positive(),
        /// Mass of the rod
        m: Variable::parameter("kg", 0.5).positive(),
        /// Distance from the pin A to the rod's centre of mass (the rod is 4 l long)
        l: Variable::parameter("m", 0.25).positive(),
        /// Stiffness of the spring from the wall to the cart (0 allowed)
        k: Variable::tunable("N/m", 10.0).min(0.0),
        /// Damping coefficient of the dashpot from the wall to the cart
        c1: Variable::tunable("N.s/m", 0.0).min(0.0),
        /// Rotary damping coefficient at the pin
        c2: Variable::tunable("N.m.s/rad", 0.0).min(0.0),
        /// Acceleration of gravity
        g: Variable::parameter("m/s2", 9.81).min(0.0),
        /// Horizontal force at the rod's far end D (3 l below the pin when the rod hangs)
        F: Variable::input("N", 0.0),
        /// Position of the cart (of the pin A) from the spring's unstretched position
        x: Variable::state("m", 0.0, "x_dot"),
        /// Velocity of the cart
        x_dot: Variable::state("m/s", 0.0, "x_ddot"),
        /// Angle of the rod from the downward vertical, counter-clockwise
        theta: Variable::state("rad", 0.3, "theta_dot"),
        /// Angular velocity of the rod
        theta_dot: Variable::state("rad/s", 0.0, "theta_ddot"),
        /// Acceleration of the cart
        x_ddot: Variable::output("m/s2"),
        /// Angular acceleration of the rod
        theta_ddot: Variable::output("rad/s2"),
        /// Normal force of the ground on the cart (upward)
        F_N: Variable::output("N"),
        /// Mechanical energy: kinetic + spring + gravity (heights measured from the pin A)
        E: Variable::output("J"),
        /// Lower natural frequency of the motion linearized about x = 0, theta = 0
        omega_n1: Variable::calculated("rad/s"),
        /// Higher natural frequency of the motion linearized about x = 0, theta = 0
        omega_n2: Variable::calculated("rad/s"),
    }
}

impl Mechanism for PendulumCart {
    const EXPERIMENT: Experiment = Experiment::until(10.0).step(0.01).tolerance(1e-6);

    const NOTES: &'static str = "
        Cart `M` on a spring `k` and dashpot `c1`; thin rod `m`, length `4l`, pinned at `A` a
        distance `l` from its centre of mass (`I_A = 7/3 m l²`), rotary damper `c2`; horizontal
        force `F` at the rod's far end `D`, `3l` below `A`; `θ` from the downward vertical.
        By Lagrange, with `T = ½ (M+m) ẋ² + m l ẋ θ̇ cos θ + 7/6 m l² θ̇²`,
        `V = ½ k x² - m g l cos θ` and the virtual work of `F` at `D`:

            (M+m) ẍ + c1 ẋ + k x + m l (θ̈ cos θ - θ̇² sin θ) = F
            m l ẍ cos θ + 7/3 m l² θ̈ + c2 θ̇ + m g l sin θ    = 3 F l cos θ
            F_N = (M+m) g + m l (θ̈ sin θ + θ̇² cos θ)
            E   = ½ (M+m) ẋ² + m l ẋ θ̇ cos θ + 7/6 m l² θ̇² + ½ k x² - m g l cos θ

        Checked against Newton–Euler (rod and cart separately, the pin force eliminated) and
        the energy balance `dE/dt = F (ẋ + 3 l θ̇ cos θ) - c1 ẋ² - c2 θ̇²`. `omega_n1`,
        `omega_n2` are the frequencies of the motion linearized about `x = 0, θ = 0`: mass
        matrix `[[M+m, m l], [m l, 7/3 m l²]]`, stiffness `diag(k, m g l)`.

        ## Departures from the notes
        - Normal force: the notes print `F_N = (M+m) g - m l (θ̈ sin θ + θ̇² cos θ)`. Vertical
          Newton on the rod and on the cart gives a `+`: at the bottom of a swing the rod's
          centripetal acceleration points up and the cart is pressed down harder.
        - The notes' Euler step writes `r_C × v_A = -ẋ l cos θ K`; it is `+ẋ l cos θ K`. Their
          final equations of motion are right and are the ones above.
    ";

    fn calculate(v: &mut PendulumCartValues<f64>) -> Result<(), String> {
        // Linearized about x = 0, θ = 0 (cos θ → 1, sin θ → θ, θ̇² θ dropped): the mass matrix
        // at θ = 0 and the stiffness diag(k, m g l).
        let ml = v.m * v.l;
        let mass = Matrix2::new(v.M + v.m, ml, ml, 7.0 / 3.0 * ml * v.l);
        let stiffness = Matrix2::new(v.k, 0.0, 0.0, ml * v.g);
        let [first, second] = mechfmu::modal::undamped_modes(&mass, &stiffness)?;
        v.omega_n1 = first.omega;
        v.omega_n2 = second.omega;
        Ok(())
    }

    fn evaluate<S: Scalar>(v: &mut PendulumCartValues<S>) {
        let (sin, cos) = sin_cos(v.theta);
        let ml = v.m * v.l;
        let i_a = lit::<S>(7.0 / 3.0) * ml * v.l;

        // Lagrange's equations as  [[M+m, m l cos θ], [m l cos θ, I_A]] (ẍ, θ̈) = (f_x, f_θ).
        let (a11, a12, a22) = (v.M + v.m, ml * cos, i_a);
        let f_x = v.F - v.c1 * v.x_dot - v.k * v.x + ml * v.theta_dot * v.theta_dot * sin;
        let f_theta = lit::<S>(3.0) * v.F * v.l * cos - v.c2 * v.theta_dot - ml * v.g * sin;
        // det = m l² (7/3 M + m (7/3 - cos² θ)) > 0 for positive masses and length: the
        // mass matrix is never singular, so Cramer's rule is safe at every state. One
        // division (the reciprocal of det) instead of two: it needs only cos θ, so it runs
        // while the numerators, which wait for the forces, are formed.
        let inv_det = (a11 * a22 - a12 * a12).recip();
        v.x_ddot = (a22 * f_x - a12 * f_theta) * inv_det;
        v.theta_ddot = (a11 * f_theta - a12 * f_x) * inv_det;
    }

    /// What no derivative needs: the normal force and the energy, from the accelerations
    /// `evaluate` computed.
    fn outputs<S: Scalar>(v: &mut PendulumCartValues<S>) {
        let (sin, cos) = sin_cos(v.theta);
        let ml = v.m * v.l;
        let i_a = lit::<S>(7.0 / 3.0) * ml * v.l;

        // Newton's law on the rod, vertically: -F2 - m g = m a_Cy with
        // a_Cy = l (θ̈ sin θ + θ̇² cos θ); on the cart: F_N + F2 - M g = 0 (it does not move
        // vertically). The notes print the m l (...) term with a minus sign: wrong.
        v.F_N = (v.M + v.m) * v.g + ml * (v.theta_ddot * sin + v.theta_dot * v.theta_dot * cos);

        let half = lit::<S>(0.5);
        v.E = half * (v.M + v.m) * v.x_dot * v.x_dot
            + ml * v.x_dot * v.theta_dot * cos
            + half * i_a * v.theta_dot * v.theta_dot
            + half * v.k * v.x * v.x
            - ml * v.g * cos;
    }
}

// The FMU's functions; none when the crate is compiled into a system's FMU.
#[cfg(not(feature = "component"))]
mechfmu::export_fmu!(PendulumCart);
