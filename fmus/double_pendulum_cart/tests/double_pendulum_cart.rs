//! The DoublePendulumCart through its FMI functions: its right-hand side, which the runtime
//! forms from the energies, against Newton's law written here for the cart, `m1` and `m2`
//! separately; the tip, energy and momentum from the bodies; the balances over a run.

use double_pendulum_cart::DoublePendulumCart;
use mechfmu::fmi2::ffi::*;
use mechfmu_testkit::harness::Harness;
use mechfmu_testkit::rng::Rng;

type Fmu = Harness<DoublePendulumCart>;

mechfmu_testkit::golden_tests!(DoublePendulumCart);

const NAMES: [&str; 14] = [
    "M", "m1", "m2", "l1", "l2", "g", "c", "F", "x", "x_dot", "phi1", "phi1_dot", "phi2",
    "phi2_dot",
];

/// Solves `a u = b` by Gaussian elimination with partial pivoting.
fn solve<const N: usize>(mut a: [[f64; N]; N], mut b: [f64; N]) -> [f64; N] {
    for k in 0..N {
        let pivot = (k..N)
            .max_by(|&i, &j| a[i][k].abs().total_cmp(&a[j][k].abs()))
            .unwrap();
        a.swap(k, pivot);
        b.swap(k, pivot);
        let (pivot_row, pivot_b) = (a[k], b[k]);
        for (row, bi) in a.iter_mut().zip(b.iter_mut()).skip(k + 1) {
            let f = row[k] / pivot_row[k];
            for (x, p) in row[k..].iter_mut().zip(&pivot_row[k..]) {
                *x -= f * p;
            }
            *bi -= f * pivot_b;
        }
    }
    let mut u = [0.0; N];
    for k in (0..N).rev() {
        let rest: f64 = (k + 1..N).map(|j| a[k][j] * u[j]).sum();
        u[k] = (b[k] - rest) / a[k][k];
    }
    u
}

/// Newton's law for the three bodies, the rod tensions `T1` (upper rod), `T2` (lower rod)
/// unknown beside the accelerations: `(ẍ, φ̈1, φ̈2, T1, T2)`. With `e_i = (sin φi, -cos φi)`
/// from the upper end of rod i to its mass, a rod in tension pulls its mass by `-T_i e_i`
/// and its upper end by `+T_i e_i`:
///
/// ```text
/// cart:  M ẍ          = F - c ẋ + T1 sin φ1                 (horizontally)
/// m1:    m1 p̈1        = -T1 e1 + T2 e2 - m1 g J
/// m2:    m2 p̈2        = -T2 e2 - m2 g J
/// p̈1 = ẍ I + l1 φ̈1 (cos φ1, sin φ1) - l1 φ̇1² e1'     e1' = (sin φ1, -cos φ1)
/// p̈2 = p̈1 + l2 φ̈2 (cos φ2, sin φ2) - l2 φ̇2² e2'
/// ```
///
/// the accelerations by differentiating the positions twice.
fn newton(v: [f64; 14]) -> [f64; 5] {
    let [mc, m1, m2, l1, l2, g, c, f, _x, xd, p1, w1, p2, w2] = v;
    let (s1, c1) = p1.sin_cos();
    let (s2, c2) = p2.sin_cos();
    // p̈1 = (ẍ + l1 c1 φ̈1 - l1 w1² s1, l1 s1 φ̈1 + l1 w1² c1), likewise for p̈2's extra part.
    let (cx1, cy1) = (-l1 * w1 * w1 * s1, l1 * w1 * w1 * c1);
    let (cx2, cy2) = (-l2 * w2 * w2 * s2, l2 * w2 * w2 * c2);
    let a = [
        // cart: M ẍ - T1 s1 = F - c ẋ
        [mc, 0.0, 0.0, -s1, 0.0],
        // m1, I: m1 (ẍ + l1 c1 φ̈1) + T1 s1 - T2 s2 = -m1 cx1
        [m1, m1 * l1 * c1, 0.0, s1, -s2],
        // m1, J: m1 l1 s1 φ̈1 - T1 c1 + T2 c2 = -m1 cy1 - m1 g
        [0.0, m1 * l1 * s1, 0.0, -c1, c2],
        // m2, I: m2 (ẍ + l1 c1 φ̈1 + l2 c2 φ̈2) + T2 s2 = -m2 (cx1 + cx2)
        [m2, m2 * l1 * c1, m2 * l2 * c2, 0.0, s2],
        // m2, J: m2 (l1 s1 φ̈1 + l2 s2 φ̈2) - T2 c2 = -m2 (cy1 + cy2) - m2 g
        [0.0, m2 * l1 * s1, m2 * l2 * s2, 0.0, -c2],
    ];
    let b = [
        f - c * xd,
        -m1 * cx1,
        -m1 * cy1 - m1 * g,
        -m2 * (cx1 + cx2),
        -m2 * (cy1 + cy2) - m2 * g,
    ];
    solve(a, b)
}

/// At random parameters, inputs and states, the FMU's accelerations (Lagrange's equations of
/// its energies) are Newton's, solved with the rod tensions; and its tip, energy and
/// momentum are those of the bodies' positions and velocities written here.
#[test]
fn right_hand_side_is_newtons_law_body_by_body() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let mut worst = [0.0f64; 3];
    for _ in 0..500 {
        let v = [
            rng.uniform(0.1, 5.0),    // M
            rng.uniform(0.05, 3.0),   // m1
            rng.uniform(0.05, 3.0),   // m2
            rng.uniform(0.05, 1.5),   // l1
            rng.uniform(0.05, 1.5),   // l2
            rng.uniform(0.0, 20.0),   // g
            rng.uniform(0.0, 2.0),    // c
            rng.uniform(-10.0, 10.0), // F
            rng.uniform(-1.0, 1.0),   // x
            rng.uniform(-3.0, 3.0),   // x_dot
            rng.uniform(-7.0, 7.0),   // phi1
            rng.uniform(-10.0, 10.0), // phi1_dot
            rng.uniform(-7.0, 7.0),   // phi2
            rng.uniform(-10.0, 10.0), // phi2_dot
        ];
        let [mc, m1, m2, l1, l2, g, _, _, x, xd, p1, w1, p2, w2] = v;
        let start: Vec<(&str, f64)> = NAMES.iter().copied().zip(v).collect();
        let mut fmu = Fmu::new();
        fmu.initialize(None, 0.0, &start).unwrap();
        let got = [
            fmu.get("x_ddot"),
            fmu.get("phi1_ddot"),
            fmu.get("phi2_ddot"),
        ];
        let want = newton(v);
        let scale = want[..3].iter().fold(1.0f64, |s, a| s.max(a.abs()));
        for i in 0..3 {
            let rel = (got[i] - want[i]).abs() / scale;
            worst[i] = worst[i].max(rel);
            assert!(
                rel <= 1e-12,
                "acceleration {i}: {} != Newton's {} at {start:?}",
                got[i],
                want[i]
            );
        }

        let (s1, c1) = p1.sin_cos();
        let (s2, c2) = p2.sin_cos();
        let tip = [x + l1 * s1 + l2 * s2, -l1 * c1 - l2 * c2];
        let v1 = [xd + l1 * w1 * c1, l1 * w1 * s1];
        let v2 = [v1[0] + l2 * w2 * c2, v1[1] + l2 * w2 * s2];
        let kinetic = 0.5 * mc * xd * xd
            + 0.5 * m1 * (v1[0] * v1[0] + v1[1] * v1[1])
            + 0.5 * m2 * (v2[0] * v2[0] + v2[1] * v2[1]);
        let potential = g * (m1 * (-l1 * c1) + m2 * tip[1]);
        let momentum = mc * xd + m1 * v1[0] + m2 * v2[0];
        let length = l1 + l2 + x.abs();
        assert!((fmu.get("tip_x") - tip[0]).abs() <= 1e-15 * length);
        assert!((fmu.get("tip_y") - tip[1]).abs() <= 1e-15 * length);
        let e_scale = kinetic + (m1 + m2) * g * (l1 + l2);
        assert!(
            (fmu.get("E") - (kinetic + potential)).abs() <= 1e-14 * e_scale,
            "E {} != {} at {start:?}",
            fmu.get("E"),
            kinetic + potential
        );
        let p_scale = mc * xd.abs() + (m1 + m2) * (v1[0].abs() + v2[0].abs()) + 1e-300;
        assert!((fmu.get("p_x") - momentum).abs() <= 1e-14 * p_scale);
    }
    println!(
        "worst |Lagrange - Newton| / scale: x_ddot {:.1e}, phi1_ddot {:.1e}, phi2_ddot {:.1e}",
        worst[0], worst[1], worst[2]
    );
}

/// Over `stop` seconds from `start`, the largest drift of `E` and of `p_x` from their start
/// values, each relative to `scale_of(E(0), p_x(0))`.
fn drifts(start: &[(&str, f64)], tolerance: f64, stop: f64) -> (f64, f64, f64, f64) {
    let mut fmu = Fmu::new();
    fmu.initialize(Some(tolerance), 0.0, start).unwrap();
    let (e0, p0) = (fmu.get("E"), fmu.get("p_x"));
    let (mut e_drift, mut p_drift) = (0.0f64, 0.0f64);
    let n = (stop / 0.01).round() as usize;
    for k in 1..=n {
        fmu.step_to(0.01 * k as f64, 0.01).unwrap();
        e_drift = e_drift.max((fmu.get("E") - e0).abs());
        p_drift = p_drift.max((fmu.get("p_x") - p0).abs());
    }
    (e0, p0, e_drift, p_drift)
}

#[test]
fn energy_and_momentum_are_constant_without_force_and_drag() {
    // Heights from the track: the energy above the hanging rest, E(0) + (m1 + 2 m2) g l, is
    // the scale of the motion (defaults: m1 = m2 = 0.5, l1 = l2 = 0.5).
    let rest = -(0.5 * 0.5 + 0.5 * 1.0) * 9.81;
    for start in [
        vec![],
        vec![("x_dot", 0.4), ("phi1", 2.0), ("phi2", 1.0)],
        vec![("x_dot", -0.3), ("phi1_dot", 6.0), ("phi2", -2.5)],
    ] {
        let (e0, p0, e_drift, p_drift) = drifts(&start, 1e-10, 10.0);
        let e_scale = e0 - rest;
        // the momentum's scale: the cart's speed times the whole mass, or p_x(0)
        let p_scale = p0.abs().max(2.0 * 0.5);
        println!(
            "{start:?}: E drift {:.1e}, p_x drift {:.1e}",
            e_drift / e_scale,
            p_drift / p_scale
        );
        assert!(
            e_drift <= 1e-8 * e_scale,
            "{start:?}: E drifts by {e_drift:e} of {e_scale}"
        );
        assert!(
            p_drift <= 1e-8 * p_scale,
            "{start:?}: p_x drifts by {p_drift:e} of {p_scale}"
        );
    }
}

/// Pushed by a constant `F` against the drag, `dE/dt = F ẋ - c ẋ²` (the power of the
/// forces on the cart) and `dp_x/dt = F - c ẋ`, integrated along the run by Simpson's rule
/// on a fine grid (`dp_x/dt` exactly: `F t - c (x - x(0))`).
#[test]
fn force_and_drag_change_energy_and_momentum_at_their_rates() {
    let (f, c) = (1.5, 0.8);
    let start = [
        ("F", f),
        ("c", c),
        ("x_dot", 0.5),
        ("phi1", 1.5),
        ("phi2", -0.5),
    ];
    let mut fmu = Fmu::new();
    fmu.initialize(Some(1e-10), 0.0, &start).unwrap();
    let (e0, p0, x0) = (fmu.get("E"), fmu.get("p_x"), fmu.get("x"));
    let power = |v: f64| (f - c * v) * v;
    let h = 1e-3;
    let (mut work, mut dissipated) = (0.0, 0.0);
    let mut earlier = fmu.get("x_dot");
    let (mut worst_e, mut worst_p) = (0.0f64, 0.0f64);
    for k in 1..=2500 {
        let t = 2.0 * h * k as f64;
        fmu.step_to(t - h, h).unwrap();
        let middle = fmu.get("x_dot");
        fmu.step_to(t, h).unwrap();
        let (x, v) = (fmu.get("x"), fmu.get("x_dot"));
        work += h / 3.0 * (power(earlier) + 4.0 * power(middle) + power(v));
        dissipated += h / 3.0 * c * (earlier * earlier + 4.0 * middle * middle + v * v);
        earlier = v;
        worst_e = worst_e.max((fmu.get("E") - e0 - work).abs());
        worst_p = worst_p.max((fmu.get("p_x") - p0 - (f * t - c * (x - x0))).abs());
    }
    // the energy the force and the drag exchange; the impulse of F over the 5 s
    let (e_scale, p_scale) = (work.abs() + 2.0 * dissipated, f * 5.0);
    println!(
        "F and drag: |E - E(0) - W| {:.1e}, |p_x - p_x(0) - J| {:.1e} (relative)",
        worst_e / e_scale,
        worst_p / p_scale
    );
    assert!(dissipated > 0.1, "the drag must act");
    assert!(worst_e <= 1e-8 * e_scale, "{worst_e:e} of {e_scale}");
    assert!(worst_p <= 1e-10 * p_scale, "{worst_p:e} of {p_scale}");
}

#[test]
fn drag_is_tunable_and_changes_no_state() {
    let mut fmu = Fmu::new();
    fmu.initialize(None, 0.0, &[("x_dot", 0.5)]).unwrap();
    fmu.step_to(0.5, 0.01).unwrap();
    let (x, x_dot, e) = (fmu.get("x"), fmu.get("x_dot"), fmu.get("E"));
    let before = fmu.get("x_ddot");
    assert_eq!(fmu.set("c", 2.0), fmi2OK);
    assert_eq!((fmu.get("x"), fmu.get("E")), (x, e));
    // The drag's force -c ẋ on the cart shows at once in its acceleration, against ẋ.
    assert!(x_dot.abs() > 0.01 && (fmu.get("x_ddot") - before) * x_dot < 0.0);
}

#[test]
fn invalid_parameters_are_rejected_at_initialization() {
    for (name, value) in [
        ("M", 0.0),
        ("m1", -0.5),
        ("m2", 0.0),
        ("l1", 0.0),
        ("l2", -0.1),
        ("c", -0.1),
        ("g", -9.81),
    ] {
        mechfmu_testkit::harness::assert_rejected_at_initialization::<DoublePendulumCart>(
            name, value,
        );
    }
}

/// Reset, FMU state, serialization, derivatives and threads: the checks every FMU passes.
#[test]
fn conforms() {
    mechfmu_testkit::conformance::check::<DoublePendulumCart>();
}
