//! `TwoOscillators` compiled into one FMU (`system!` makes it one mechanism) is
//! `TwoMassOscillator`: the same equations, cut into three components and put back together,
//! integrated by one solver. Through the FMI 2.0 functions, at a tight tolerance, every state
//! agrees to 1e-8 of its range, with the default parameter set and with other values.

use mechfmu::fmi2::ffi::fmi2OK;
use mechfmu_testkit::harness::Harness;
use two_mass_oscillator::TwoMassOscillator;
use two_oscillators::TwoOscillators;

/// The system's variable and TwoMassOscillator's that must agree.
const PAIRS: [(&str, &str); 4] = [
    ("a.x", "x1"),
    ("b.x", "x2"),
    ("a.x_dot", "x1_dot"),
    ("b.x_dot", "x2_dot"),
];

/// The largest difference of each pair over 30 s in steps of `h`, relative to the range of
/// TwoMassOscillator's variable.
fn largest_differences(
    system_values: &[(&str, f64)],
    tmo_values: &[(&str, f64)],
    h: f64,
) -> Vec<f64> {
    let mut system = Harness::<TwoOscillators>::new();
    system.initialize(Some(1e-10), 0.0, system_values).unwrap();
    let mut tmo = Harness::<TwoMassOscillator>::new();
    tmo.initialize(Some(1e-10), 0.0, tmo_values).unwrap();
    let mut worst = [0.0f64; 4];
    let mut range = [(f64::MAX, f64::MIN); 4];
    let steps = (30.0 / h).round() as u64;
    for n in 0..steps {
        let t = n as f64 * h;
        assert_eq!(system.do_step(t, h), fmi2OK, "{:?}", system.messages());
        assert_eq!(tmo.do_step(t, h), fmi2OK, "{:?}", tmo.messages());
        for (i, (ours, theirs)) in PAIRS.iter().enumerate() {
            let (a, b) = (system.get(ours), tmo.get(theirs));
            worst[i] = worst[i].max((a - b).abs());
            range[i] = (range[i].0.min(b), range[i].1.max(b));
        }
    }
    worst
        .iter()
        .zip(range)
        .map(|(w, (lo, hi))| w / (hi - lo))
        .collect()
}

#[test]
fn the_default_set_is_two_mass_oscillator_at_its_defaults() {
    for h in [0.01, 0.1] {
        let differences = largest_differences(&[], &[], h);
        assert!(
            differences.iter().all(|d| *d < 1e-8),
            "h = {h}: {differences:?}"
        );
    }
}

#[test]
fn other_values_are_two_mass_oscillator_at_the_same_values() {
    let system = [
        ("a.m", 1.5),
        ("b.m", 2.0),
        ("a.k", 3.0),
        ("b.k", 0.5),
        ("spring.k", 2.0),
        ("a.c", 0.1),
        ("b.c", 0.2),
        ("spring.c", 0.05),
        ("a.x", -0.3),
        ("b.x", 0.7),
        ("b.x_dot", 1.1),
    ];
    let tmo = [
        ("m1", 1.5),
        ("m2", 2.0),
        ("k1", 3.0),
        ("k2", 0.5),
        ("k3", 2.0),
        ("c1", 0.1),
        ("c2", 0.2),
        ("c3", 0.05),
        ("x1", -0.3),
        ("x2", 0.7),
        ("x2_dot", 1.1),
    ];
    let differences = largest_differences(&system, &tmo, 0.01);
    assert!(differences.iter().all(|d| *d < 1e-8), "{differences:?}");
}

#[test]
fn the_system_fmu_passes_every_check_of_a_mechanism() {
    mechfmu_testkit::conformance::check::<TwoOscillators>();
}

// its committed model descriptions (modelDescription/) and interface page (docs/mechanisms/)
mechfmu_testkit::golden_tests!(TwoOscillators);
