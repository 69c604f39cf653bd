//! CraneDynamics through its FMI functions: the static loads hold it at rest, Newton's law
//! on each body separately (trolley along and across the boom, boom about O, payload in
//! ground coordinates) against the Lagrangian motion, the energy balance and the model's
//! limits (slack cable, trolley at the pivot, invalid parameters).

use crane_dynamics::CraneDynamics;
use mechfmu::fmi2::ffi::*;
use mechfmu_testkit::harness::Harness;

type Fmu = Harness<CraneDynamics>;

const M: f64 = 1000.0;
const MT: f64 = 200.0;
const JB: f64 = 5000.0;
const G: f64 = 9.81;

fn static_loads(x: f64, theta: f64) -> (f64, f64) {
    ((M + MT) * G * theta.sin(), x * (M + MT) * G * theta.cos())
}

mechfmu_testkit::golden_tests!(CraneDynamics);

/// The documentation says the default experiment stands still and plots the moving case
/// instead: both must stay true of the declaration.
#[test]
fn the_default_experiment_stands_still_and_the_documented_case_moves() {
    mechfmu_testkit::documented::default_experiment_stands_still_and_moving_case_moves::<
        CraneDynamics,
    >();
}

#[test]
fn static_loads_hold_the_crane_at_rest() {
    for (x, theta) in [(10.0, 0.5), (4.0, -0.3), (17.0, 1.1)] {
        let (f, tau) = static_loads(x, theta);
        let mut fmu = Fmu::new();
        fmu.initialize(
            Some(1e-8),
            0.0,
            &[("x", x), ("theta", theta), ("F", f), ("tau", tau)],
        )
        .unwrap();
        let mut worst = 0.0f64;
        for n in 0..2000 {
            assert_eq!(
                fmu.do_step(n as f64 * 0.01, 0.01),
                fmi2OK,
                "{:?}",
                fmu.messages()
            );
            worst = worst
                .max((fmu.get("x") - x).abs())
                .max((fmu.get("theta") - theta).abs())
                .max(fmu.get("phi").abs());
            assert!(
                (fmu.get("T") - M * G).abs() <= 1e-9 * M * G,
                "T = {}",
                fmu.get("T")
            );
        }
        assert!(
            worst <= 1e-9,
            "x = {x}, theta = {theta}: moved by {worst:e}"
        );
    }
}

/// A run with the drive loads switched between values near the static ones.
fn moving_run(mut each_step: impl FnMut(&mut Fmu, f64)) {
    let (f0, tau0) = static_loads(10.0, 0.5);
    let schedule = [
        (0.0, 1.08, 1.0),
        (2.0, 1.0, 1.03),
        (4.0, 0.93, 0.98),
        (6.0, 1.0, 1.0),
    ];
    let mut fmu = Fmu::new();
    fmu.initialize(
        Some(1e-10),
        0.0,
        &[("F", f0), ("tau", tau0), ("phi_dot", 0.2)],
    )
    .unwrap();
    let h = 0.01;
    for n in 0..800 {
        let t = n as f64 * h;
        let &(_, kf, kt) = schedule.iter().rev().find(|s| s.0 <= t + 1e-9).unwrap();
        fmu.set("F", kf * f0);
        fmu.set("tau", kt * tau0);
        assert_eq!(fmu.do_step(t, h), fmi2OK, "{:?}", fmu.messages());
        each_step(&mut fmu, t + h);
    }
}

#[test]
fn each_body_obeys_newton_on_the_lagrangian_motion() {
    // Free-body diagrams, with the accelerations the FMU computed from the Lagrangian:
    //   trolley along i_A:  m_t (ẍ - x θ̇²)     = F - T sin s - m_t g sin θ
    //   trolley along j_A:  m_t (2 ẋ θ̇ + x θ̈) = N - T cos s - m_t g cos θ
    //   boom about O:       J_boom θ̈            = τ - x N
    // The first and last do not appear in the model's code: T and N are checked by them.
    let mut worst = [0.0f64; 3];
    moving_run(|fmu, _| {
        let get = |fmu: &mut Fmu, n: &str| fmu.get(n);
        let (x, xd, th, thd, ph) = (
            get(fmu, "x"),
            get(fmu, "x_dot"),
            get(fmu, "theta"),
            get(fmu, "theta_dot"),
            get(fmu, "phi"),
        );
        let (xdd, thdd, t, n) = (
            get(fmu, "x_ddot"),
            get(fmu, "theta_ddot"),
            get(fmu, "T"),
            get(fmu, "N"),
        );
        let (f, tau) = (get(fmu, "F"), get(fmu, "tau"));
        let s = th - ph;
        let r1 = MT * (xdd - x * thd * thd) - (f - t * s.sin() - MT * G * th.sin());
        let r2 = MT * (2.0 * xd * thd + x * thdd) - (n - t * s.cos() - MT * G * th.cos());
        let r3 = JB * thdd - (tau - x * n);
        worst[0] = worst[0].max(r1.abs() / (M * G));
        worst[1] = worst[1].max(r2.abs() / (M * G));
        worst[2] = worst[2].max(r3.abs() / (10.0 * M * G));
    });
    assert!(worst.iter().all(|&w| w < 1e-12), "{worst:?}");
}

#[test]
fn payload_obeys_newton_in_ground_coordinates() {
    // m a = -T i_B - m g J, a by central differences of the payload's position.
    let h = 1e-3;
    let (f0, tau0) = static_loads(10.0, 0.5);
    let mut fmu = Fmu::new();
    fmu.initialize(
        Some(1e-12),
        0.0,
        &[
            ("F", 1.05 * f0),
            ("tau", 0.97 * tau0),
            ("phi", 0.3),
            ("theta_dot", 0.05),
        ],
    )
    .unwrap();
    let mut samples = Vec::new();
    for n in 0..3000 {
        samples.push((
            fmu.get("payload_x"),
            fmu.get("payload_y"),
            fmu.get("T"),
            fmu.get("phi"),
        ));
        assert_eq!(fmu.do_step(n as f64 * h, h), fmi2OK, "{:?}", fmu.messages());
    }
    let mut worst = 0.0f64;
    for w in samples.windows(3) {
        let ax = (w[2].0 - 2.0 * w[1].0 + w[0].0) / (h * h);
        let ay = (w[2].1 - 2.0 * w[1].1 + w[0].1) / (h * h);
        let (t, phi) = (w[1].2, w[1].3);
        worst = worst
            .max((ax + t * phi.sin() / M).abs())
            .max((ay - t * phi.cos() / M + G).abs());
    }
    assert!(worst < 1e-5 * G, "Newton's law off by {worst:e} m/s2");
}

#[test]
fn work_of_the_drives_is_the_energy_gain() {
    let mut e0 = None;
    let (mut worst, mut max_gain) = (0.0f64, 0.0f64);
    moving_run(|fmu, _| {
        let e = fmu.get("E");
        let base = *e0.get_or_insert_with(|| e - fmu.get("W_drives"));
        max_gain = max_gain.max((e - base).abs());
        worst = worst.max((fmu.get("W_drives") - (e - base)).abs());
    });
    assert!(max_gain > 1e4, "the case is meaningful: {max_gain}");
    assert!(
        worst < 1e-8 * max_gain,
        "W_drives - ΔE = {worst:e} of {max_gain:e}"
    );
}

#[test]
fn slack_cable_is_a_warning_once_per_episode() {
    // The boom driven down hard (tau far below the static torque) drops the trolley faster
    // than the payload can follow: the cable goes slack, once, then the run continues.
    let (f0, tau0) = static_loads(10.0, 0.5);
    let mut fmu = Fmu::new();
    fmu.initialize(Some(1e-8), 0.0, &[("F", f0), ("tau", -3.0 * tau0)])
        .unwrap();
    let mut statuses = Vec::new();
    let mut min_t = f64::MAX;
    for n in 0..30 {
        statuses.push(fmu.do_step(n as f64 * 0.01, 0.01));
        min_t = min_t.min(fmu.get("T"));
    }
    assert!(min_t < 0.0, "the case must go slack: min T = {min_t}");
    assert_eq!(
        statuses.iter().filter(|&&s| s == fmi2Warning).count(),
        1,
        "{statuses:?}"
    );
    assert!(statuses.iter().all(|&s| s == fmi2OK || s == fmi2Warning));
    let warnings: Vec<_> = fmu
        .messages()
        .into_iter()
        .filter(|m| m.0 == fmi2Warning)
        .collect();
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert!(warnings[0].2.contains("slack"), "{warnings:?}");
}

#[test]
fn trolley_reaching_the_pivot_discards_the_step() {
    // The trolley drive pulls inwards (with half the holding torque on the boom): the
    // trolley reaches the pivot at t ≈ 0.946 s. The yank slackens the cable at first (a
    // warning), which does not stop the run.
    let (_, tau0) = static_loads(10.0, 0.5);
    let mut fmu = Fmu::new();
    fmu.initialize(Some(1e-8), 0.0, &[("F", -1e4), ("tau", 0.5 * tau0)])
        .unwrap();
    let mut status = fmi2OK;
    let mut n = 0;
    while (status == fmi2OK || status == fmi2Warning) && n < 1000 {
        status = fmu.do_step(n as f64 * 0.01, 0.01);
        n += 1;
    }
    assert_eq!(status, fmi2Discard, "{:?}", fmu.messages());
    assert_eq!(
        n, 95,
        "the step [0.94, 0.95] is the one that reaches the pivot"
    );
    assert!(
        fmu.logged("the trolley reached the pivot"),
        "{:?}",
        fmu.messages()
    );
    for name in [
        "x",
        "x_dot",
        "theta",
        "phi",
        "T",
        "N",
        "E",
        "x_ddot",
        "theta_ddot",
        "phi_ddot",
    ] {
        assert!(fmu.get(name).is_finite(), "{name} = {}", fmu.get(name));
    }
    assert_eq!(
        fmu.do_step(n as f64 * 0.01, 0.01),
        fmi2Error,
        "no step after a discard"
    );
}

#[test]
fn invalid_parameters_and_start_values_are_rejected_at_initialization() {
    for (name, value) in [
        ("m", 0.0),
        ("l", -1.0),
        ("J_boom", 0.0),
        ("J_boom", -5000.0),
        ("m_trolley", 0.0),
        ("m_trolley", -1.0),
        ("x", 0.0),
        ("x", -3.0),
    ] {
        mechfmu_testkit::harness::assert_rejected_at_initialization::<crane_dynamics::CraneDynamics>(
            name, value,
        );
    }
}

#[test]
fn directional_derivatives_match_finite_differences() {
    // The equations run on dual numbers through the elimination: the exact derivatives
    // of the accelerations, T and N with respect to every state and input, against central
    // differences (the conformance check), at a moving operating point with loads off the
    // static ones.
    let moving = [
        ("x", 8.0),
        ("x_dot", 0.7),
        ("theta", 0.6),
        ("theta_dot", -0.1),
        ("phi", 0.3),
        ("phi_dot", 0.4),
        ("F", 7000.0),
        ("tau", 9.0e4),
    ];
    let worst = mechfmu_testkit::conformance::directional_derivatives_match_finite_differences_at::<
        CraneDynamics,
    >(&moving);
    assert!(worst > 0.0);
}

/// Reset, FMU state, serialization, derivatives and threads: the checks every FMU passes.
#[test]
fn conforms() {
    mechfmu_testkit::conformance::check::<crane_dynamics::CraneDynamics>();
}
