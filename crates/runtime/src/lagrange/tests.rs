//! Lagrange's equations from energies against equations written by hand for the same
//! mechanisms, the jets' derivatives against num-dual's hyper-dual numbers, and the errors.

use super::{Coordinate, Jet, Lagrangian};
use crate::model::{
    lit, sin_cos, Declaration, Experiment, Layout, Mechanism, Scalar, SetPhase, Variable,
};
use crate::simulation::Simulation;
use nalgebra::Const;
use num_dual::{Derivative, Dual64, HyperDualVec, HyperHyperDual64};

/// A function of two velocities, two coordinates and the time using every operation a jet
/// implements: `(v1, v2, q1, q2, t)`.
fn every_operation<S: nalgebra::RealField + Copy>([v1, v2, q1, q2, t]: [S; 5]) -> S {
    let lit = |x: f64| -> S { nalgebra::convert(x) };
    let (s, c) = (q1 * v2 + t).sin_cos();
    let a = (v1 * v1 + q2 * q2 + lit(1.0)).sqrt() * s;
    let b = (q2 * v1).exp() / (lit(2.0) + c) - (v2 * v2 + lit(0.5)).ln();
    let d = q1.atan2(v1 + lit(3.0)) * v2.powi(3) + (q2 * t).tanh() * v1.hypot(q1);
    let e = (q1 * lit(0.3)).tan() * (v2 * q2).sinh() - (v1 * lit(0.2)).atan();
    a * b + d - e * v2 / (q1 * q1 + lit(2.0))
}

/// The other functions a jet implements, on arguments inside their domains: inverse and
/// hyperbolic functions, logarithms, powers (integer, constant, by a jet), a division by a
/// constant, `abs` of a negative value, `atan2` with `|y| > |x|`.
fn every_other_operation<S: nalgebra::RealField + Copy>([v1, v2, q1, q2, t]: [S; 5]) -> S {
    let lit = |x: f64| -> S { nalgebra::convert(x) };
    let small = (q1 * v2 * lit(0.1)).sin() * lit(0.5); // in (-0.5, 0.5)
    let above_one = v1 * v1 + q2 * q2 + lit(1.5);
    let a = small.asin() * v1 + small.acos() * q2 + small.atanh() * t + above_one.acosh();
    let b = (q1 * v2).cosh() / lit(3.0) + (v1 * q2).asinh() + above_one.ln_1p() * v2.exp2();
    let c = (q2 * lit(0.3)).exp_m1() * above_one.cbrt() + above_one.log(lit(3.0)) * v1.log2();
    let d = above_one.log10() * q1.powi(0) + v2.powi(1) * q1.powi(2) + v1.powi(-1) + q2.powi(4);
    let e = (-above_one).abs() * (v2 * q1 + lit(3.0)).powf(lit(2.5))
        + above_one.powf(q1 * v2)
        + above_one.recip();
    let f = (v1 * lit(7.0)).atan2(q1 * lit(0.1) + lit(0.2));
    a * b + c * d - e * f
}

/// Seeds of the five arguments as jets, and the reference's: ε1 on the velocities, ε2 on all
/// five (the full Hessian rows of the velocities).
fn seeded(x: [f64; 5]) -> ([Jet<2>; 5], [Reference; 5]) {
    let [v1, v2, q1, q2, t] = x;
    let jets = [
        Jet::velocity(0, v1),
        Jet::velocity(1, v2),
        Jet::coordinate(0, q1, v1),
        Jet::coordinate(1, q2, v2),
        Jet::time(t),
    ];
    let reference = std::array::from_fn(|i| {
        let e1 = (i < 2).then(|| Derivative::derivative_generic(Const::<2>, Const::<1>, i));
        HyperDualVec::new(
            x[i],
            e1.unwrap_or(Derivative::none()),
            Derivative::derivative_generic(Const::<1>, Const::<5>, i),
            Derivative::none(),
        )
    });
    (jets, reference)
}

type Reference = HyperDualVec<f64, Const<2>, Const<5>>;

/// A test function, on jets and on the reference.
type Both = (fn([Jet<2>; 5]) -> Jet<2>, fn([Reference; 5]) -> Reference);

#[test]
fn jets_carry_the_second_derivatives_of_a_hyper_dual_vector() {
    let functions: [(&str, Both); 2] = [
        ("every_operation", (every_operation, every_operation)),
        (
            "every_other_operation",
            (every_other_operation, every_other_operation),
        ),
    ];
    for (name, (on_jets, on_reference)) in functions {
        for k in 0..50 {
            let x = [0.3, -0.7, 1.1, 0.4, 0.9].map(|x: f64| x + 0.05 * k as f64);
            let (jets, reference) = seeded(x);
            check_jet(
                on_jets(jets),
                on_reference(reference),
                x,
                &format!("{name} at {k}"),
            );
        }
    }
}

/// The jet's parts against the hyper-dual vector's derivatives at `x`.
fn check_jet(jet: Jet<2>, reference: Reference, x: [f64; 5], at: &str) {
    let [v1, v2, ..] = x;
    let hessian = reference.eps1eps2.unwrap_generic(Const::<2>, Const::<5>);
    let gradient = reference.eps2.unwrap_generic(Const::<1>, Const::<5>);
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-13 * (1.0 + b.abs());
    assert!(
        close(jet.re, reference.re),
        "{at}: {} / {}",
        jet.re,
        reference.re
    );
    for i in 0..2 {
        assert!(close(jet.v[i], gradient[i]), "∂/∂v{i} at {at}");
        assert!(close(jet.q[i], gradient[2 + i]), "∂/∂q{i} at {at}");
        for j in i..2 {
            assert!(close(jet.vv[i][j], hessian[(i, j)]), "vv{i}{j} at {at}");
        }
        // Along the path: the coordinates at the velocities, the time at 1.
        let along = hessian[(i, 2)] * v1 + hessian[(i, 3)] * v2 + hessian[(i, 4)];
        assert!(close(jet.vp[i], along), "vp{i} at {at}");
    }
    let along = gradient[2] * v1 + gradient[3] * v2 + gradient[4];
    assert!(close(jet.p, along), "p at {at}");
}

#[test]
fn a_negative_base_to_a_constant_integer_power_is_its_power() {
    use nalgebra::ComplexField;
    let (jets, _) = seeded([0.3, -0.7, 1.1, 0.4, 0.9]);
    let x = jets[1] * jets[2] - jets[4]; // negative
    assert!(x.re < 0.0);
    let (by_powf, by_powi) = (x.powf(Jet::constant(3.0)), x.powi(3));
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-14 * (1.0 + b.abs());
    assert!(close(by_powf.re, by_powi.re));
    for i in 0..2 {
        assert!(close(by_powf.v[i], by_powi.v[i]) && close(by_powf.q[i], by_powi.q[i]));
        assert!(close(by_powf.vv[i][1], by_powi.vv[i][1]) && close(by_powf.vp[i], by_powi.vp[i]));
    }
}

#[test]
fn a_jet_is_exactly_zero_along_what_it_does_not_depend_on() {
    use nalgebra::ComplexField;
    // sqrt at 0 has an infinite derivative along v0; along v1 and q0 the product depends on
    // nothing, and its derivatives there are 0, not ∞ · 0.
    let root = Jet::<2>::velocity(0, 0.0).sqrt();
    let y = root * Jet::<2>::coordinate(1, 2.0, 3.0);
    assert_eq!((y.v[0], y.vp[0]), (f64::INFINITY, f64::INFINITY));
    assert_eq!(y.vv[0][0], f64::NEG_INFINITY);
    assert_eq!(
        (y.v[1], y.q[0], y.vv[0][1], y.vv[1][1], y.vp[1]),
        (0.0, 0.0, 0.0, 0.0, 0.0)
    );
    assert_eq!((y.q[1], y.p), (0.0, 0.0));
}

#[test]
fn a_remainder_carries_the_derivatives_of_its_dividend() {
    let (jets, _) = seeded([0.3, -0.7, 1.1, 0.4, 0.9]);
    let x = jets[0] * jets[2] + jets[4];
    let r = x % Jet::constant(0.25);
    assert_eq!(r.re, x.re % 0.25);
    assert_eq!((r.v, r.q, r.p, r.vv, r.vp), (x.v, x.q, x.p, x.vv, x.vp));
}

#[test]
fn sines_of_hyper_hyper_duals_are_num_duals_to_rounding() {
    for k in -20..20 {
        let x = HyperHyperDual64::new(0.3 * k as f64, 0.7, -1.1, 0.4, 0.2, -0.3, 0.9, 0.5);
        let (s, c) = sin_cos(x);
        let (s_ref, c_ref) = nalgebra::ComplexField::sin_cos(x);
        let parts = |y: HyperHyperDual64| {
            [
                y.re,
                y.eps1,
                y.eps2,
                y.eps3,
                y.eps1eps2,
                y.eps1eps3,
                y.eps2eps3,
                y.eps1eps2eps3,
            ]
        };
        for (a, b) in parts(s)
            .into_iter()
            .chain(parts(c))
            .zip(parts(s_ref).into_iter().chain(parts(c_ref)))
        {
            assert!((a - b).abs() <= 1e-15 * (1.0 + b.abs()), "{a} / {b}");
        }
    }
}

/// A test mechanism whose equations are its Lagrangian's, its failures diagnosed by its
/// mass matrix.
macro_rules! lagrangian_mechanism {
    ($name:ident / $values:ident, $experiment:expr) => {
        impl Mechanism for $name {
            const EXPERIMENT: Experiment = $experiment;
            fn evaluate<S: Scalar>(v: &mut $values<S>) {
                Self::lagrange(v);
            }
            fn diagnose(v: &$values<f64>) -> Option<String> {
                Self::mass_matrix_problem(v)
            }
        }
    };
}

crate::mechanism! {
    /// A pendulum hanging from a support moved horizontally by a drive and shaken vertically
    /// by a prescribed motion `A sin(ω t)`: a driven coordinate, a free one and a kinetic
    /// energy that depends on the time.
    pub struct Shaken / ShakenValues {
        /// Bob mass
        m: Variable::parameter("kg", 2.0).positive(),
        /// Support mass
        M: Variable::parameter("kg", 3.0).positive(),
        /// Rod length
        l: Variable::parameter("m", 0.8).positive(),
        /// Gravity
        g: Variable::parameter("m/s2", 9.81),
        /// Amplitude of the vertical shaking
        A: Variable::parameter("m", 0.05),
        /// Its angular frequency
        w: Variable::parameter("rad/s", 7.0),
        /// Support acceleration, prescribed
        a: Variable::input("m/s2", 0.0),
        /// Support position
        x: Variable::state("m", 0.0, "x_dot"),
        /// Support velocity
        x_dot: Variable::state("m/s", 0.0, "a"),
        /// Angle from the downward vertical
        phi: Variable::state("rad", 0.4, "phi_dot"),
        /// Angular velocity
        phi_dot: Variable::state("rad/s", 0.0, "phi_ddot"),
        /// Angular acceleration
        phi_ddot: Variable::output("rad/s2"),
        /// Horizontal force of the drive on the support
        F: Variable::output("N"),
    }
}

impl Lagrangian<2> for Shaken {
    const COORDINATES: [Coordinate; 2] = [Coordinate::driven("x", "F"), Coordinate::free("phi")];

    /// The support at `(x, A sin ωt)`, the bob `l` from it along `(sin φ, -cos φ)`.
    fn kinetic_energy<S: Scalar>(v: &ShakenValues<S>) -> S {
        let (sin, cos) = sin_cos(v.phi);
        let shake = v.A * v.w * sin_cos(v.w * v.time).1;
        let bob_x = v.x_dot + v.l * v.phi_dot * cos;
        let bob_y = shake + v.l * v.phi_dot * sin;
        let half = lit::<S>(0.5);
        half * v.M * (v.x_dot * v.x_dot + shake * shake)
            + half * v.m * (bob_x * bob_x + bob_y * bob_y)
    }

    fn potential_energy<S: Scalar>(v: &ShakenValues<S>) -> S {
        let height = v.A * sin_cos(v.w * v.time).0;
        v.g * ((v.M + v.m) * height - v.m * v.l * sin_cos(v.phi).1)
    }
}

lagrangian_mechanism!(
    Shaken / ShakenValues,
    Experiment::until(1.0).step(0.01).tolerance(1e-8)
);

/// Newton's law on the bob in the support's accelerating frame, and on the support.
fn shaken_by_hand(v: &ShakenValues<f64>) -> (f64, f64) {
    let (sin, cos) = v.phi.sin_cos();
    let vertical = -v.A * v.w * v.w * (v.w * v.time).sin();
    let phi_ddot = -((v.g + vertical) * sin + v.a * cos) / v.l;
    let bob_x = v.a + v.l * (phi_ddot * cos - v.phi_dot * v.phi_dot * sin);
    (phi_ddot, v.M * v.a + v.m * bob_x)
}

#[test]
fn a_driven_coordinate_and_a_time_dependent_energy_give_newtons_law() {
    let mut v = ShakenValues::<f64> {
        m: 2.0,
        M: 3.0,
        l: 0.8,
        g: 9.81,
        A: 0.05,
        w: 7.0,
        ..Default::default()
    };
    for k in 0..200 {
        let k = k as f64;
        (v.time, v.a, v.phi, v.phi_dot, v.x_dot) = (
            0.013 * k,
            (0.7 * k).sin(),
            0.05 * k - 3.0,
            (0.3 * k).cos(),
            0.1,
        );
        Shaken::evaluate(&mut v);
        let (phi_ddot, force) = shaken_by_hand(&v);
        assert!(
            (v.phi_ddot - phi_ddot).abs() <= 1e-13 * (1.0 + phi_ddot.abs()),
            "{k}: {} / {phi_ddot}",
            v.phi_ddot
        );
        assert!(
            (v.F - force).abs() <= 1e-13 * (1.0 + force.abs()),
            "{k}: {} / {force}",
            v.F
        );

        // The derivative along φ, by the third-order path, against the hand's by a dual number.
        let mut dual = Shaken::map_values(&v, Dual64::from_re);
        dual.phi = Dual64::new(v.phi, 1.0);
        Shaken::evaluate(&mut dual);
        let (sin, cos) = v.phi.sin_cos();
        let vertical = -v.A * v.w * v.w * (v.w * v.time).sin();
        let d_phi_ddot = -((v.g + vertical) * cos - v.a * sin) / v.l;
        assert!((dual.phi_ddot.re - v.phi_ddot).abs() <= 1e-14 * (1.0 + v.phi_ddot.abs()));
        assert!(
            (dual.phi_ddot.eps - d_phi_ddot).abs() <= 1e-13 * (1.0 + d_phi_ddot.abs()),
            "{k}"
        );

        // Along the time (the shaking moves with it) and along φ̇ (the drive's force has a
        // centripetal term).
        let mut dual = Shaken::map_values(&v, Dual64::from_re);
        dual.time = Dual64::new(v.time, 1.0);
        dual.phi_dot = Dual64::new(v.phi_dot, 0.5);
        Shaken::evaluate(&mut dual);
        let d_phi_ddot = v.A * v.w.powi(3) * (v.w * v.time).cos() * sin / v.l;
        let d_force = 0.5 * (-2.0 * v.m * v.l * v.phi_dot * sin) + v.m * v.l * cos * d_phi_ddot;
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * (1.0 + b.abs());
        assert!(
            close(dual.phi_ddot.eps, d_phi_ddot),
            "{k}: {} / {d_phi_ddot}",
            dual.phi_ddot.eps
        );
        assert!(
            close(dual.F.eps, d_force),
            "{k}: {} / {d_force}",
            dual.F.eps
        );
    }
}

crate::mechanism! {
    /// Two carts, the second of which the kinetic energy forgets.
    pub struct Forgotten / ForgottenValues {
        /// Mass
        m: Variable::parameter("kg", 1.0).positive(),
        /// First cart
        x: Variable::state("m", 0.0, "x_dot"),
        /// Its velocity
        x_dot: Variable::state("m/s", 0.0, "x_ddot"),
        /// Second cart
        y: Variable::state("m", 0.0, "y_dot"),
        /// Its velocity
        y_dot: Variable::state("m/s", 0.0, "y_ddot"),
        /// First acceleration
        x_ddot: Variable::output("m/s2"),
        /// Second acceleration
        y_ddot: Variable::output("m/s2"),
    }
}

impl Lagrangian<2> for Forgotten {
    const COORDINATES: [Coordinate; 2] = [Coordinate::free("x"), Coordinate::free("y")];
    fn kinetic_energy<S: Scalar>(v: &ForgottenValues<S>) -> S {
        lit::<S>(0.5) * v.m * v.x_dot * v.x_dot
    }
    fn potential_energy<S: Scalar>(v: &ForgottenValues<S>) -> S {
        v.x * v.y
    }
}

lagrangian_mechanism!(
    Forgotten / ForgottenValues,
    Experiment::until(1.0).step(0.1).tolerance(1e-6)
);

#[test]
fn a_kinetic_energy_without_a_velocity_is_refused_at_initialization_naming_it() {
    let mut sim = Simulation::<Forgotten>::new(Layout::new(Forgotten::VARIABLES).unwrap());
    sim.setup(None, 0.0).unwrap();
    sim.set_real(&[1], &[0.5], SetPhase::Initialization)
        .unwrap();
    let message = sim.update().unwrap_err();
    assert!(message.contains("does not depend on `y_dot`"), "{message}");
    assert!(message.contains("x = 0.5"), "names the point: {message}");
    assert!(message.contains("`x_ddot` evaluates to NaN"), "{message}");
}

crate::mechanism! {
    /// A cart whose second coordinate loses its inertia where the first turns negative.
    pub struct Collapsing / CollapsingValues {
        /// Mass
        m: Variable::parameter("kg", 1.0).positive(),
        /// First coordinate
        x: Variable::state("m", 0.05, "x_dot"),
        /// Its velocity
        x_dot: Variable::state("m/s", -1.0, "x_ddot"),
        /// Second coordinate
        y: Variable::state("m", 0.0, "y_dot"),
        /// Its velocity
        y_dot: Variable::state("m/s", 0.0, "y_ddot"),
        /// First acceleration
        x_ddot: Variable::output("m/s2"),
        /// Second acceleration
        y_ddot: Variable::output("m/s2"),
    }
}

impl Lagrangian<2> for Collapsing {
    const COORDINATES: [Coordinate; 2] = [Coordinate::free("x"), Coordinate::free("y")];
    fn kinetic_energy<S: Scalar>(v: &CollapsingValues<S>) -> S {
        let inertia = nalgebra::RealField::max(v.x, S::zero());
        lit::<S>(0.5) * v.m * (v.x_dot * v.x_dot + inertia * v.y_dot * v.y_dot)
    }
    fn potential_energy<S: Scalar>(_: &CollapsingValues<S>) -> S {
        S::zero()
    }
}

lagrangian_mechanism!(
    Collapsing / CollapsingValues,
    Experiment::until(1.0).step(0.1).tolerance(1e-6)
);

#[test]
fn a_step_into_a_singular_mass_matrix_stops_and_says_why() {
    let mut sim = Simulation::<Collapsing>::new(Layout::new(Collapsing::VARIABLES).unwrap());
    sim.setup(None, 0.0).unwrap();
    sim.update().unwrap();
    let failure = sim.step(0.0, 0.1).unwrap_err();
    let crate::simulation::StepFailure::Stopped { time, message, .. } = failure else {
        panic!("{failure:?}")
    };
    assert!(time < 0.05 + 1e-9, "stopped at {time}, past x = 0");
    assert!(message.contains("does not depend on `y_dot`"), "{message}");
}
