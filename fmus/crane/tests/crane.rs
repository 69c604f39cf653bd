//! The Crane through its FMI functions: the pendulum limit against the exact period, Newton's
//! law on the payload in ground coordinates (accelerations by finite differences of the
//! payload's position, not from the model's formulas), the drive loads, the work-energy
//! balance and the model's limits (slack cable, trolley at the pivot).

use crane::Crane;
use mechfmu::fmi2::ffi::*;
use mechfmu_testkit::harness::Harness;
use mechfmu_testkit::model_exchange::ModelExchange;

type Fmu = Harness<Crane>;

const M: f64 = 1000.0;
const L: f64 = 5.0;
const G: f64 = 9.81;

/// Complete elliptic integral of the first kind K(k) (modulus k) by the arithmetic-geometric
/// mean: K = π / (2 AGM(1, sqrt(1 - k²))).
fn ellip_k(k: f64) -> f64 {
    let (mut a, mut b) = (1.0f64, (1.0 - k * k).sqrt());
    // Quadratic convergence: a handful of iterations reach full precision (a fixed count,
    // since a and b may end one ulp apart forever).
    for _ in 0..12 {
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
    }
    std::f64::consts::PI / (a + b)
}

/// Root in (0, h) of the cubic Hermite interpolant of values p0, p1 and slopes d0, d1.
fn hermite_root(h: f64, p0: f64, p1: f64, d0: f64, d1: f64) -> f64 {
    let value = |s: f64| {
        let (s2, s3) = (s * s, s * s * s);
        (2.0 * s3 - 3.0 * s2 + 1.0) * p0
            + (s3 - 2.0 * s2 + s) * h * d0
            + (-2.0 * s3 + 3.0 * s2) * p1
            + (s3 - s2) * h * d1
    };
    let (mut lo, mut hi) = (0.0, 1.0);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if (value(mid) > 0.0) == (p0 > 0.0) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi) * h
}

/// Times at which phi crosses zero downwards (swinging from + to -), from the communication
/// points' phi and phi_dot with Hermite interpolation.
fn downward_zero_crossings(fmu: &mut Fmu, t_end: f64, h: f64) -> Vec<f64> {
    let mut crossings = Vec::new();
    let (mut p0, mut d0) = (fmu.get("phi"), fmu.get("phi_dot"));
    let mut n = 0u64;
    while (n as f64) * h < t_end - 1e-9 {
        let t = n as f64 * h;
        assert!(fmu.do_step(t, h) <= fmi2Warning, "{:?}", fmu.messages());
        n += 1;
        let (p1, d1) = (fmu.get("phi"), fmu.get("phi_dot"));
        if p0 > 0.0 && p1 <= 0.0 {
            crossings.push(t + hermite_root(h, p0, p1, d0, d1));
        }
        (p0, d0) = (p1, d1);
    }
    crossings
}

mechfmu_testkit::golden_tests!(Crane);

/// The documentation says the default experiment stands still and plots the moving case
/// instead: both must stay true of the declaration.
#[test]
fn the_default_experiment_stands_still_and_the_documented_case_moves() {
    mechfmu_testkit::documented::default_experiment_stands_still_and_moving_case_moves::<Crane>();
}

#[test]
fn still_drives_swing_with_the_exact_pendulum_period() {
    for phi0_deg in [5.0f64, 45.0, 90.0] {
        let phi0 = phi0_deg.to_radians();
        let exact = 4.0 * (L / G).sqrt() * ellip_k((phi0 / 2.0).sin());
        let mut fmu = Fmu::new();
        fmu.initialize(Some(1e-10), 0.0, &[("phi", phi0)]).unwrap();
        let c = downward_zero_crossings(&mut fmu, 3.2 * exact, 0.01);
        assert_eq!(c.len(), 3, "phi0 = {phi0_deg}°: crossings {c:?}");
        let period = (c[2] - c[0]) / 2.0;
        let rel = (period - exact).abs() / exact;
        assert!(
            rel < 1e-7,
            "phi0 = {phi0_deg}°: period {period} vs {exact}: {rel:e}"
        );
        // The first crossing is a quarter period after the release from rest.
        assert!(
            (c[0] - exact / 4.0).abs() < 1e-7 * exact,
            "{} vs {}",
            c[0],
            exact / 4.0
        );
    }
}

#[test]
fn hanging_payload_is_stable() {
    // The notes' tangential equation gives l φ̈ = +g φ here: |φ| would grow like
    // cosh(sqrt(g/l) t) ≈ 1e12 by t = 20 s. The corrected one keeps the swing at its amplitude.
    let phi0 = 1e-3;
    let mut fmu = Fmu::new();
    fmu.initialize(Some(1e-10), 0.0, &[("phi", phi0)]).unwrap();
    let mut max_phi = 0.0f64;
    for n in 0..2000 {
        assert_eq!(fmu.do_step(n as f64 * 0.01, 0.01), fmi2OK);
        max_phi = max_phi.max(fmu.get("phi").abs());
    }
    assert!(max_phi <= phi0 * (1.0 + 1e-8), "max |phi| = {max_phi}");
    assert!(
        max_phi >= phi0 * (1.0 - 1e-6),
        "max |phi| = {max_phi}: the swing died out"
    );
}

#[test]
fn still_drives_loads_and_energy_follow_the_pendulum() {
    // Drives still: T = m (g cos φ + l φ̇²) and, with l φ̇² = 2 g (cos φ - cos φ0) from the
    // energy, T = m g (3 cos φ - 2 cos φ0); F = T sin(θ - φ), τ = x T cos(θ - φ).
    let (phi0, x, theta) = (0.6f64, 12.0, 0.8);
    let mut fmu = Fmu::new();
    fmu.initialize(
        Some(1e-10),
        0.0,
        &[("phi", phi0), ("x", x), ("theta", theta)],
    )
    .unwrap();
    let e0 = fmu.get("E_payload");
    assert!((e0 - M * G * (x * theta.sin() - L * phi0.cos())).abs() < 1e-9 * e0.abs());
    for n in 0..1000 {
        assert_eq!(fmu.do_step(n as f64 * 0.01, 0.01), fmi2OK);
        let (phi, phi_dot) = (fmu.get("phi"), fmu.get("phi_dot"));
        let t_exact = M * G * (3.0 * phi.cos() - 2.0 * phi0.cos());
        let t = fmu.get("T");
        assert!((t - t_exact).abs() < 1e-8 * M * G, "T = {t} vs {t_exact}");
        assert!((t - M * (G * phi.cos() + L * phi_dot * phi_dot)).abs() < 1e-9 * M * G);
        assert!((fmu.get("F") - t * (theta - phi).sin()).abs() < 1e-9 * M * G);
        assert!((fmu.get("tau") - x * t * (theta - phi).cos()).abs() < 1e-9 * M * G * x);
        let energy =
            0.5 * M * L * L * phi_dot * phi_dot + M * G * (x * theta.sin() - L * phi.cos());
        assert!(
            (energy - e0).abs() < 1e-8 * M * G * L,
            "energy drift {}",
            energy - e0
        );
        assert!((fmu.get("E_payload") - energy).abs() < 1e-9 * M * G * L);
        assert_eq!(fmu.get("W_drives"), 0.0, "still drives do no work");
        assert_eq!((fmu.get("x"), fmu.get("theta")), (x, theta));
    }
}

/// Drives moving with constant accelerations from a moving start.
const MOVING: [(&str, f64); 8] = [
    ("x_ddot", 0.3),
    ("theta_ddot", 0.02),
    ("x_dot", -0.4),
    ("theta_dot", 0.05),
    ("phi", 0.2),
    ("phi_dot", -0.1),
    ("x", 8.0),
    ("theta", 0.3),
];

#[test]
fn newton_on_the_payload_in_ground_coordinates() {
    // m a = -T i_B - m g J with a from central differences of payload_x, payload_y: a route
    // through Cartesian coordinates that shares nothing with the model's frame algebra.
    let h = 1e-3;
    let mut fmu = Fmu::new();
    fmu.initialize(Some(1e-12), 0.0, &MOVING).unwrap();
    let mut samples = Vec::new();
    for n in 0..4000 {
        let t = n as f64 * h;
        samples.push((
            fmu.get("payload_x"),
            fmu.get("payload_y"),
            fmu.get("T"),
            fmu.get("phi"),
        ));
        assert_eq!(fmu.do_step(t, h), fmi2OK, "{:?}", fmu.messages());
    }
    let mut worst = 0.0f64;
    for w in samples.windows(3) {
        let (ax, ay) = (
            (w[2].0 - 2.0 * w[1].0 + w[0].0) / (h * h),
            (w[2].1 - 2.0 * w[1].1 + w[0].1) / (h * h),
        );
        let (t, phi) = (w[1].2, w[1].3);
        let (fx, fy) = (-t * phi.sin() / M, t * phi.cos() / M - G);
        worst = worst.max((ax - fx).abs().max((ay - fy).abs()));
    }
    // Central differences: truncation ~ h² a''''/12, rounding ~ 4 ε |r| / h² ≈ 1e-8.
    assert!(worst < 1e-5 * G, "Newton's law off by {worst:e} m/s2");
}

#[test]
fn tension_is_the_resultant_of_the_drive_loads() {
    // T = sqrt(F² + (τ/x)²) (the notes' F1) wherever the cable is taut; checked at scattered
    // states and inputs, evaluated at initialization.
    let mut seed = 12345u64;
    let mut uniform = |lo: f64, hi: f64| {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        lo + (hi - lo) * ((seed >> 11) as f64 / (1u64 << 53) as f64)
    };
    let mut checked = 0;
    for _ in 0..200 {
        let values = [
            ("x", uniform(0.5, 20.0)),
            ("x_dot", uniform(-2.0, 2.0)),
            ("theta", uniform(-0.5, 1.4)),
            ("theta_dot", uniform(-0.3, 0.3)),
            ("phi", uniform(-1.0, 1.0)),
            ("phi_dot", uniform(-1.0, 1.0)),
            ("x_ddot", uniform(-1.0, 1.0)),
            ("theta_ddot", uniform(-0.1, 0.1)),
        ];
        let mut fmu = Fmu::new();
        fmu.initialize(None, 0.0, &values).unwrap();
        let (t, f, tau, x) = (fmu.get("T"), fmu.get("F"), fmu.get("tau"), fmu.get("x"));
        if t > 0.0 {
            let resultant = (f * f + (tau / x).powi(2)).sqrt();
            assert!(
                (resultant - t).abs() <= 1e-12 * t,
                "T = {t}, sqrt(F² + (tau/x)²) = {resultant}"
            );
            checked += 1;
        }
    }
    assert!(checked > 150);
}

#[test]
fn work_of_the_drives_is_the_payload_energy_gain() {
    let mut fmu = Fmu::new();
    fmu.initialize(Some(1e-10), 0.0, &MOVING).unwrap();
    let e0 = fmu.get("E_payload");
    let mut max_gain = 0.0f64;
    let mut worst = 0.0f64;
    for n in 0..1000 {
        assert_eq!(fmu.do_step(n as f64 * 0.01, 0.01), fmi2OK);
        let gain = fmu.get("E_payload") - e0;
        max_gain = max_gain.max(gain.abs());
        worst = worst.max((fmu.get("W_drives") - gain).abs());
    }
    assert!(max_gain > 1e5, "the case is meaningful: gain {max_gain}");
    assert!(
        worst < 1e-8 * max_gain,
        "W_drives - ΔE = {worst:e} J of {max_gain:e} J"
    );
}

#[test]
fn slack_cable_is_a_warning_once_per_episode() {
    // Still drives, released from rest at 120°: T = m g (3 cos φ - 2 cos φ0) < 0 while
    // cos φ < -1/3, near each turning point: at the release (t = 0) and around t = P/2.
    let phi0 = 120f64.to_radians();
    let period = 4.0 * (L / G).sqrt() * ellip_k((phi0 / 2.0).sin());
    let mut fmu = Fmu::new();
    fmu.initialize(Some(1e-8), 0.0, &[("phi", phi0)]).unwrap();
    let h = 0.01;
    let steps = (0.8 * period / h) as u64;
    let mut warned_steps = Vec::new();
    for n in 0..steps {
        let status = fmu.do_step(n as f64 * h, h);
        assert!(status == fmi2OK || status == fmi2Warning, "{status}");
        if status == fmi2Warning {
            warned_steps.push(n as f64 * h);
        }
        assert!(fmu.get("T").is_finite());
    }
    let warnings: Vec<_> = fmu
        .messages()
        .into_iter()
        .filter(|(s, _, m)| *s == fmi2Warning && m.contains("slack"))
        .collect();
    assert_eq!(warnings.len(), 2, "{warnings:?}");
    assert_eq!(warned_steps.len(), 2, "{warned_steps:?}");
    assert!(warned_steps[0] == 0.0);
    assert!(
        (warned_steps[1] - 0.5 * period).abs() < 0.3 * period,
        "{warned_steps:?}"
    );
}

#[test]
fn trolley_reaching_the_pivot_discards_the_step() {
    // x = 1 - 1.05 t reaches 0 at t ≈ 0.952, inside the step [0.9, 1.0].
    let mut fmu = Fmu::new();
    fmu.initialize(Some(1e-8), 0.0, &[("x", 1.0), ("x_dot", -1.05)])
        .unwrap();
    for n in 0..9 {
        assert_eq!(fmu.do_step(n as f64 * 0.1, 0.1), fmi2OK);
    }
    assert_eq!(fmu.do_step(0.9, 0.1), fmi2Discard);
    assert!(
        fmu.logged("the trolley reached the pivot"),
        "{:?}",
        fmu.messages()
    );
    for name in [
        "x",
        "x_dot",
        "phi",
        "phi_dot",
        "T",
        "F",
        "tau",
        "payload_x",
        "payload_y",
        "E_payload",
    ] {
        assert!(fmu.get(name).is_finite(), "{name} = {}", fmu.get(name));
    }
    // The step ends at the last valid point: where the trolley reaches the pivot (located
    // inside the solver's step), with x > 0 still.
    let x = fmu.get("x");
    assert!(x > 0.0 && x <= 1.0 - 1.05 * 0.9 + 1e-12, "x = {x}");
    let mut last = f64::NAN;
    // SAFETY: a live instance of this harness; `last` is a writable f64.
    let status = unsafe {
        mechfmu::fmi2::functions::fmi2GetRealStatus::<Crane>(
            fmu.component(),
            fmi2LastSuccessfulTime,
            &mut last,
        )
    };
    assert_eq!(status, fmi2OK);
    assert!((last - 1.0 / 1.05).abs() < 1e-12, "stopped at t = {last}");
    assert_eq!(fmu.do_step(1.0, 0.1), fmi2Error, "no step after a discard");
}

#[test]
fn model_exchange_stops_where_the_trolley_reaches_the_pivot() {
    // x = 1 - 1.05 t: the indicator x crosses 0 at t = 1/1.05, inside the RK4 step
    // [0.9, 1.0] (exact for a straight line); the importer locates it and the FMU asks to
    // stop there, with the reason.
    let mut me = ModelExchange::<Crane>::new();
    me.initialize(Some(1e-8), 0.0, &[("x", 1.0), ("x_dot", -1.05)])
        .unwrap();
    let run = me.integrate(2.0, 0.1).unwrap();
    let t = run
        .terminated_at
        .expect("the simulation goes on past the pivot");
    assert!((t - 1.0 / 1.05).abs() < 1e-12, "stopped at t = {t}");
    assert_eq!(run.state_events, 1);
    let terminated: Vec<_> = me
        .messages()
        .into_iter()
        .filter(|(s, _, m)| *s == fmi2Warning && m.contains("terminateSimulation"))
        .collect();
    assert_eq!(terminated.len(), 1, "{:?}", me.messages());
    assert!(terminated[0].2.contains("the trolley reached the pivot"));
    assert!(me.fmu.get("x").abs() < 1e-12);
    assert_eq!(me.fmu.terminate(), fmi2OK);
}

#[test]
fn model_exchange_warns_once_per_slack_episode_at_the_crossing() {
    // As in Co-Simulation: released at 120°, T < 0 at the release and again around t = P/2.
    // The indicator T locates the second episode's start: T ≈ 0 there.
    let phi0 = 120f64.to_radians();
    let period = 4.0 * (L / G).sqrt() * ellip_k((phi0 / 2.0).sin());
    let mut me = ModelExchange::<Crane>::new();
    me.initialize(Some(1e-8), 0.0, &[("phi", phi0)]).unwrap();
    let run = me.integrate(0.8 * period, 0.001).unwrap();
    assert_eq!(run.terminated_at, None);
    let warnings: Vec<_> = me
        .messages()
        .into_iter()
        .filter(|(s, _, m)| *s == fmi2Warning && m.contains("slack"))
        .collect();
    assert_eq!(warnings.len(), 2, "{warnings:?}");
    // T changes sign twice per episode: into slack and out of it.
    assert!(run.state_events >= 3, "{run:?}");
    // The second warning is logged at the located crossing, where T is -0 or a rounding.
    let at = warnings[1]
        .2
        .split("T = ")
        .nth(1)
        .and_then(|s| s.split(' ').next());
    let tension: f64 = at.and_then(|s| s.parse().ok()).unwrap_or(f64::NAN);
    assert!(
        tension <= 0.0 && tension > -1e-6 * M * G,
        "{}",
        warnings[1].2
    );
}

#[test]
fn invalid_parameters_and_start_values_are_rejected_at_initialization() {
    for (name, value) in [
        ("m", 0.0),
        ("m", -1.0),
        ("l", 0.0),
        ("l", -5.0),
        ("x", 0.0),
        ("x", -2.0),
        ("g", -9.81),
    ] {
        mechfmu_testkit::harness::assert_rejected_at_initialization::<crane::Crane>(name, value);
    }
}

#[test]
fn directional_derivatives_match_finite_differences() {
    // The default experiment is a crane at rest, where most terms of the equations vanish:
    // the conformance check again at a moving operating point, with every state and input
    // as known.
    let moving = [
        ("x", 8.0),
        ("x_dot", 0.7),
        ("theta", 0.6),
        ("theta_dot", -0.1),
        ("phi", 0.3),
        ("phi_dot", 0.4),
        ("x_ddot", 0.5),
        ("theta_ddot", -0.05),
    ];
    mechfmu_testkit::conformance::directional_derivatives_match_finite_differences_at::<Crane>(
        &moving,
    );
}

/// Reset, FMU state, serialization, derivatives and threads: the checks every FMU passes.
#[test]
fn conforms() {
    mechfmu_testkit::conformance::check::<crane::Crane>();
}
