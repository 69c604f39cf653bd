//! The PendulumCart through its FMI functions: its right-hand side against Newton–Euler
//! written here body by body, energy, normal force and linearized frequencies.

use mechfmu::fmi2::ffi::*;
use mechfmu_testkit::harness::Harness;
use mechfmu_testkit::rng::Rng;
use pendulum_cart::PendulumCart;

type Fmu = Harness<PendulumCart>;

mechfmu_testkit::golden_tests!(PendulumCart);

const NAMES: [&str; 12] = [
    "M",
    "m",
    "l",
    "k",
    "c1",
    "c2",
    "g",
    "F",
    "x",
    "x_dot",
    "theta",
    "theta_dot",
];

/// At random parameters, inputs and states, the FMU's accelerations, F_N and E satisfy
/// Newton's law on the cart, Newton's law and Euler's equation (about C) on the rod, and the
/// energy computed from the bodies' velocities and heights. Nothing here reuses the
/// Lagrange form the FMU implements: the reaction (F1, F2) of the rod on the cart is
/// computed from the rod's Newton's law and must then satisfy the two remaining equations.
#[test]
fn right_hand_side_satisfies_newton_euler_body_by_body() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    for _ in 0..200 {
        let v = [
            rng.uniform(0.1, 5.0),    // M
            rng.uniform(0.05, 3.0),   // m
            rng.uniform(0.05, 1.5),   // l
            rng.uniform(0.0, 50.0),   // k
            rng.uniform(0.0, 2.0),    // c1
            rng.uniform(0.0, 0.5),    // c2
            rng.uniform(0.0, 20.0),   // g
            rng.uniform(-10.0, 10.0), // F
            rng.uniform(-1.0, 1.0),   // x
            rng.uniform(-3.0, 3.0),   // x_dot
            rng.uniform(-7.0, 7.0),   // theta
            rng.uniform(-10.0, 10.0), // theta_dot
        ];
        let [mc, m, l, k, c1, c2, g, f, x, xd, th, thd] = v;
        let start: Vec<(&str, f64)> = NAMES.iter().copied().zip(v).collect();
        let mut fmu = Fmu::new();
        fmu.initialize(None, 0.0, &start).unwrap();
        let (xdd, thdd, f_n, e) = (
            fmu.get("x_ddot"),
            fmu.get("theta_ddot"),
            fmu.get("F_N"),
            fmu.get("E"),
        );

        let (s, c) = th.sin_cos();
        let i_c = m * (4.0 * l) * (4.0 * l) / 12.0; // thin rod about its centre
                                                    // C = A + l (sin θ, -cos θ); its acceleration by differentiating twice.
        let a_c = [
            xdd + l * (thdd * c - thd * thd * s),
            l * (thdd * s + thd * thd * c),
        ];
        // Rod: m a_C = F I - (F1, F2) - m g J  =>  the force of the rod on the cart.
        let (f1, f2) = (f - m * a_c[0], -m * g - m * a_c[1]);
        // Cart, horizontally: M ẍ = F1 - k x - c1 ẋ.
        let cart = mc * xdd - (f1 - k * x - c1 * xd);
        // Rod, Euler about C: moments of F at D = C + 2l e, of -(F1, F2) at A = C - l e, and
        // of the damper couple.
        let (cd, ca) = ([2.0 * l * s, -2.0 * l * c], [-l * s, l * c]);
        let moment = (cd[0] * 0.0 - cd[1] * f) + (ca[0] * -f2 - ca[1] * -f1) - c2 * thd;
        let euler = i_c * thdd - moment;
        // Cart, vertically: F_N + F2 - M g = 0.
        let normal = mc * g - f2;
        let force_scale =
            (mc + m) * (g + xdd.abs()) + f.abs() + k * x.abs() + c1 * xd.abs() + m * l * thd * thd;
        assert!(
            cart.abs() <= 1e-13 * force_scale,
            "cart: residual {cart:e} at {start:?}"
        );
        assert!(
            euler.abs() <= 1e-13 * force_scale * l,
            "rod: residual {euler:e} at {start:?}"
        );
        assert!(
            (f_n - normal).abs() <= 1e-13 * force_scale,
            "F_N {f_n} != {normal} at {start:?}"
        );

        let v_c = [xd + l * thd * c, l * thd * s];
        let energy = 0.5 * mc * xd * xd
            + 0.5 * m * (v_c[0] * v_c[0] + v_c[1] * v_c[1])
            + 0.5 * i_c * thd * thd
            + 0.5 * k * x * x
            + m * g * (-l * c);
        let e_scale =
            0.5 * (mc + m) * xd * xd + 2.0 * m * l * l * thd * thd + 0.5 * k * x * x + m * g * l;
        assert!(
            (e - energy).abs() <= 1e-14 * e_scale,
            "E {e} != {energy} at {start:?}"
        );
    }
}

#[test]
fn energy_is_constant_without_damping_and_force() {
    for (theta, theta_dot, x) in [(0.3, 0.0, 0.0), (2.5, 0.0, 0.1), (0.0, 9.0, -0.2)] {
        let mut fmu = Fmu::new();
        let start = [("theta", theta), ("theta_dot", theta_dot), ("x", x)];
        fmu.initialize(Some(1e-8), 0.0, &start).unwrap();
        let e0 = fmu.get("E");
        // Energy above the equilibrium (x = 0, θ = 0, at rest), the scale of the motion.
        let scale = e0 + 0.5 * 0.25 * 9.81;
        let mut worst = 0.0f64;
        for n in 1..=200 {
            fmu.step_to(0.1 * n as f64, 0.01).unwrap();
            worst = worst.max((fmu.get("E") - e0).abs());
        }
        assert!(
            worst <= 1e-7 * scale,
            "start {start:?}: drift {worst:e} of {scale}"
        );
    }
}

#[test]
fn normal_force_at_the_bottom_exceeds_the_weight() {
    // At θ = 0 the θ̈ term drops out: F_N = (M+m) g + m l θ̇² exactly; the notes' sign would
    // give less than the weight.
    let mut fmu = Fmu::new();
    fmu.initialize(
        None,
        0.0,
        &[("theta", 0.0), ("theta_dot", 4.0), ("x", 0.05)],
    )
    .unwrap();
    let weight = 1.5 * 9.81;
    let f_n = fmu.get("F_N");
    assert!(
        (f_n - (weight + 0.5 * 0.25 * 16.0)).abs() < 1e-13,
        "F_N = {f_n}"
    );
    assert!(f_n > weight);
}

/// The notes' form of det(K - ω² M) = 0 for M = [[M+m, m l], [m l, 7/3 m l²]],
/// K = diag(k, m g l): a ω⁴ - b ω² + c = 0.
fn closed_form(mc: f64, m: f64, l: f64, k: f64, g: f64) -> [f64; 2] {
    let a = (mc + m) * 7.0 / 3.0 * m * l * l - (m * l).powi(2);
    let b = k * 7.0 / 3.0 * m * l * l + (mc + m) * m * g * l;
    let c = k * m * g * l;
    let sqrt_d = (b * b - 4.0 * a * c).sqrt();
    [
        (2.0 * c / (b + sqrt_d)).sqrt(),
        ((b + sqrt_d) / (2.0 * a)).sqrt(),
    ]
}

#[test]
fn linearized_frequencies_match_the_closed_form() {
    for (mc, m, l, k, g) in [
        (1.0, 0.5, 0.25, 10.0, 9.81),
        (3.0, 0.2, 1.0, 1.0, 9.81),
        (0.4, 2.0, 0.1, 100.0, 1.6),
        (1.0, 0.5, 0.25, 0.0, 9.81),
    ] {
        let mut fmu = Fmu::new();
        fmu.initialize(
            None,
            0.0,
            &[("M", mc), ("m", m), ("l", l), ("k", k), ("g", g)],
        )
        .unwrap();
        let want = closed_form(mc, m, l, k, g);
        let got = [fmu.get("omega_n1"), fmu.get("omega_n2")];
        for i in 0..2 {
            assert!(
                (got[i] - want[i]).abs() <= 1e-13 * want[1],
                "{got:?} != {want:?}"
            );
        }
        if k == 0.0 {
            assert_eq!(got[0], 0.0, "a free cart has a zero frequency");
        }
    }
    // k is tunable: the frequencies follow it.
    let mut fmu = Fmu::new();
    fmu.initialize(None, 0.0, &[]).unwrap();
    assert_eq!(fmu.set("k", 40.0), fmi2OK);
    let want = closed_form(1.0, 0.5, 0.25, 40.0, 9.81);
    assert!((fmu.get("omega_n2") - want[1]).abs() <= 1e-13 * want[1]);
}

#[test]
fn invalid_parameters_are_rejected_at_initialization() {
    for (name, value) in [
        ("M", 0.0),
        ("m", -0.5),
        ("l", 0.0),
        ("k", -1.0),
        ("c2", -0.1),
        ("g", -9.81),
    ] {
        mechfmu_testkit::harness::assert_rejected_at_initialization::<PendulumCart>(name, value);
    }
}

/// Reset, FMU state, serialization, derivatives and threads: the checks every FMU passes.
#[test]
fn conforms() {
    mechfmu_testkit::conformance::check::<PendulumCart>();
}
