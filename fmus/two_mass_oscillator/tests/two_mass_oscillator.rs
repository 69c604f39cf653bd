//! The TwoMassOscillator through its FMI functions, against the notes' closed forms.

use mechfmu::fmi2::ffi::*;
use mechfmu_testkit::harness::Harness;
use two_mass_oscillator::TwoMassOscillator;

type Fmu = Harness<TwoMassOscillator>;

mechfmu_testkit::golden_tests!(TwoMassOscillator);

/// The notes' closed form: the roots of det(K - ω² M) = 0,
/// `m1 m2 ω⁴ - B ω² + C = 0`, `B = m1 k2 + m2 k1 + (m1+m2) k3`, `C = k1 k2 + (k1+k2) k3`,
/// with the shape from the first row of (K - ω² M) a = 0: `a1/a2 = k3 / (k1 + k3 - m1 ω²)`.
/// Returns (ω², a2/a1) per mode, ascending. The smaller root is written 2C / (B + √D) to
/// avoid cancellation (the same number).
fn closed_form(m1: f64, m2: f64, k1: f64, k2: f64, k3: f64) -> [(f64, f64); 2] {
    let b = m1 * k2 + m2 * k1 + (m1 + m2) * k3;
    let c = k1 * k2 + (k1 + k2) * k3;
    let sqrt_d = (b * b - 4.0 * m1 * m2 * c).sqrt();
    let w2 = [2.0 * c / (b + sqrt_d), (b + sqrt_d) / (2.0 * m1 * m2)];
    w2.map(|w2| (w2, (k1 + k3 - m1 * w2) / k3))
}

/// (a1, a2) scaled so that the larger magnitude is +1 (a1 on a tie).
fn scaled(ratio_a2_a1: f64) -> (f64, f64) {
    if ratio_a2_a1.abs() <= 1.0 {
        (1.0, ratio_a2_a1)
    } else {
        (1.0 / ratio_a2_a1, 1.0)
    }
}

fn modes_of(params: &[(&str, f64)]) -> [f64; 6] {
    let mut fmu = Fmu::new();
    fmu.initialize(None, 0.0, params).unwrap();
    [
        "omega_n1", "omega_n2", "mode1_x1", "mode1_x2", "mode2_x1", "mode2_x2",
    ]
    .map(|n| fmu.get(n))
}

#[test]
fn modes_match_the_notes_closed_form() {
    let sets = [
        (1.0, 1.0, 1.0, 1.0, 1.0),
        (1.0, 2.0, 0.0, 0.0, 1.0),
        (2.0, 1.0, 3.0, 0.5, 2.0),
        (0.3, 7.0, 12.0, 0.1, 0.4),
        (5.0, 0.2, 0.0, 3.0, 9.0),
        (1.0, 1.0, 1.0, 4.0, 0.01),
    ];
    for (m1, m2, k1, k2, k3) in sets {
        let got = modes_of(&[("m1", m1), ("m2", m2), ("k1", k1), ("k2", k2), ("k3", k3)]);
        let [(w2a, ra), (w2b, rb)] = closed_form(m1, m2, k1, k2, k3);
        let (a, b) = (scaled(ra), scaled(rb));
        let want = [w2a.sqrt(), w2b.sqrt(), a.0, a.1, b.0, b.1];
        for (i, (g, w)) in got.iter().zip(want).enumerate() {
            let scale = if i < 2 { w2b.sqrt() } else { 1.0 };
            assert!(
                (g - w).abs() <= 1e-13 * scale,
                "m1={m1} m2={m2} k1={k1} k2={k2} k3={k3}: entry {i} is {g}, closed form {w}"
            );
        }
    }
}

#[test]
fn the_notes_two_examples() {
    // m1 = m2 = m, k1 = k2 = k3 = k: sqrt(k/m) with 1 : 1, sqrt(3k/m) with 1 : -1.
    let (m, k) = (1.7_f64, 2.3_f64);
    let got = modes_of(&[("m1", m), ("m2", m), ("k1", k), ("k2", k), ("k3", k)]);
    let want = [(k / m).sqrt(), (3.0 * k / m).sqrt(), 1.0, 1.0, 1.0, -1.0];
    for (g, w) in got.iter().zip(want) {
        assert!(
            (g - w).abs() <= 1e-14 * w.abs().max(1.0),
            "{got:?} != {want:?}"
        );
    }
    // The ties are exact: x1 is +1 and x2 is exactly ±1.
    assert_eq!(&got[2..], &[1.0, 1.0, 1.0, -1.0]);

    // 2 m1 = m2 = 2m, k1 = k2 = 0: 0 (rigid translation 1 : 1) and sqrt(3k/(2m)) with
    // a1/a2 = -2, i.e. (1, -1/2) once the larger component is +1 (momentum m1 a1 + m2 a2 = 0).
    let got = modes_of(&[
        ("m1", m),
        ("m2", 2.0 * m),
        ("k1", 0.0),
        ("k2", 0.0),
        ("k3", k),
    ]);
    assert_eq!(got[0], 0.0, "a free-floating pair has a zero frequency");
    let w2 = (3.0 * k / (2.0 * m)).sqrt();
    assert!((got[1] - w2).abs() <= 1e-14 * w2, "{} != {w2}", got[1]);
    assert_eq!(&got[2..4], &[1.0, 1.0]);
    assert_eq!(got[4], 1.0);
    assert!((got[5] + 0.5).abs() <= 1e-15, "{}", got[5]);
}

#[test]
fn frequencies_follow_a_tunable_stiffness() {
    let mut fmu = Fmu::new();
    fmu.initialize(None, 0.0, &[]).unwrap();
    assert!((fmu.get("omega_n2") - 3f64.sqrt()).abs() < 1e-14);
    assert_eq!(fmu.set("k3", 4.0), fmi2OK);
    // k1 = k2 = 1, k3 = 4, m = 1: ω² = 1 and 1 + 2 k3 = 9.
    assert!((fmu.get("omega_n1") - 1.0).abs() < 1e-14);
    assert!((fmu.get("omega_n2") - 3.0).abs() < 1e-14);
    assert_eq!(fmu.set("m1", 2.0), fmi2Error, "m1 is fixed");
}

/// A start on a mode shape (at rest) stays `a cos(ω t)` for 30 s.
#[test]
fn a_start_on_a_mode_stays_a_pure_sinusoid() {
    let params = [
        ("m1", 1.3),
        ("m2", 0.7),
        ("k1", 2.0),
        ("k2", 0.5),
        ("k3", 1.1),
    ];
    let modes = modes_of(&params);
    for mode in 0..2 {
        let (w, a1, a2) = (modes[mode], modes[2 + 2 * mode], modes[3 + 2 * mode]);
        let amplitude = 0.2;
        let mut start = params.to_vec();
        start.extend([("x1", amplitude * a1), ("x2", amplitude * a2)]);
        let mut fmu = Fmu::new();
        fmu.initialize(Some(1e-8), 0.0, &start).unwrap();
        let (h, mut max_err) = (0.01, 0.0f64);
        for n in 0..3000 {
            assert_eq!(fmu.do_step(n as f64 * h, h), fmi2OK);
            let c = (w * (n + 1) as f64 * h).cos();
            max_err = max_err
                .max((fmu.get("x1") - amplitude * a1 * c).abs())
                .max((fmu.get("x2") - amplitude * a2 * c).abs());
        }
        assert!(
            max_err <= 1e-6 * amplitude,
            "mode {}: error {max_err:e}",
            mode + 1
        );
    }
}

#[test]
fn energy_is_constant_without_damping_and_forces() {
    let mut fmu = Fmu::new();
    fmu.initialize(
        Some(1e-8),
        0.0,
        &[("x2", -0.4), ("x1_dot", 0.3), ("k1", 0.0)],
    )
    .unwrap();
    // ½ (0.3²) + ½ k2 x2² + ½ k3 (x1 - x2)² with x1 = 1, x2 = -0.4
    let e0 = 0.5 * 0.09 + 0.5 * 0.16 + 0.5 * 1.4 * 1.4;
    assert!((fmu.get("E") - e0).abs() < 1e-15);
    fmu.step_to(30.0, 0.05).unwrap();
    assert!(
        (fmu.get("E") - e0).abs() < 1e-7 * e0,
        "E = {}",
        fmu.get("E")
    );
}

#[test]
fn accelerations_are_newtons_law_on_each_mass() {
    let mut fmu = Fmu::new();
    let p = [
        ("m1", 2.0),
        ("m2", 0.5),
        ("k1", 3.0),
        ("k2", 5.0),
        ("k3", 7.0),
        ("c1", 0.1),
        ("c2", 0.2),
        ("c3", 0.3),
        ("F1", 1.5),
        ("F2", -2.5),
        ("x1", 0.4),
        ("x2", -0.6),
        ("x1_dot", 1.1),
        ("x2_dot", -0.9),
    ];
    fmu.initialize(None, 0.0, &p).unwrap();
    // Forces on each mass written out: its wall spring and damper, the coupling spring
    // stretched by x2 - x1 and the coupling damper, the external force.
    let f1 = -3.0 * 0.4 - 0.1 * 1.1 + 7.0 * (-0.6 - 0.4) + 0.3 * (-0.9 - 1.1) + 1.5;
    let f2 = -5.0 * -0.6 - 0.2 * -0.9 - 7.0 * (-0.6 - 0.4) - 0.3 * (-0.9 - 1.1) - 2.5;
    assert!((fmu.get("x1_ddot") - f1 / 2.0).abs() < 1e-14);
    assert!((fmu.get("x2_ddot") - f2 / 0.5).abs() < 1e-14);
}

#[test]
fn free_floating_pair_is_legal() {
    let mut fmu = Fmu::new();
    fmu.initialize(
        Some(1e-8),
        0.0,
        &[
            ("k1", 0.0),
            ("k2", 0.0),
            ("x1_dot", 0.5),
            ("x2_dot", 0.5),
            ("x1", 0.0),
        ],
    )
    .unwrap();
    assert_eq!(fmu.get("omega_n1"), 0.0);
    fmu.step_to(10.0, 0.1).unwrap();
    // Rigid translation at 0.5 m/s.
    assert!((fmu.get("x1") - 5.0).abs() < 1e-9 && (fmu.get("x2") - 5.0).abs() < 1e-9);
}

#[test]
fn invalid_parameters_are_rejected_at_initialization() {
    for (name, value) in [
        ("m1", 0.0),
        ("m2", -1.0),
        ("k1", -0.5),
        ("k3", -1.0),
        ("c3", -0.1),
    ] {
        mechfmu_testkit::harness::assert_rejected_at_initialization::<TwoMassOscillator>(
            name, value,
        );
    }
}

/// Reset, FMU state, serialization, derivatives and threads: the checks every FMU passes.
#[test]
fn conforms() {
    mechfmu_testkit::conformance::check::<TwoMassOscillator>();
}

/// `K` is computed from the stiffnesses: setting it is refused for that, whatever its
/// values (a non-symmetric matrix included), in every state before and after
/// initialization.
#[test]
fn fmi3_the_calculated_stiffness_matrix_cannot_be_set() {
    use mechfmu::fmi3::ffi::fmi3Error;
    let mut fmu = mechfmu_testkit::fmi3::Fmi3Harness::<TwoMassOscillator>::new();
    let k = fmu.vr("K");
    for values in [[1.0, 2.0, 3.0, 4.0], [1.0, 2.0, 2.0, 4.0]] {
        assert_eq!(fmu.set_float64(&[k], &values), fmi3Error);
        assert!(
            fmu.logged("cannot be set (it is computed by the model)"),
            "{:?}",
            fmu.messages()
        );
        assert!(!fmu.logged("must be equal"), "{:?}", fmu.messages());
    }
}
