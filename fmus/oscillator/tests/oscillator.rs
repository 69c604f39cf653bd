//! The Oscillator through its FMI functions, against the closed-form solutions.

use mechfmu::fmi2::ffi::*;
use mechfmu_testkit::harness::Harness;
use oscillator::Oscillator;

type Fmu = Harness<Oscillator>;

/// Free response of m ẍ + c ẋ + k x = 0 (all damping regimes), from x0, v0.
fn free_response(m: f64, c: f64, k: f64, x0: f64, v0: f64, t: f64) -> f64 {
    let wn = (k / m).sqrt();
    let zeta = c / (2.0 * (m * k).sqrt());
    if (zeta - 1.0).abs() < 1e-12 {
        x0 * (-wn * t).exp() + (v0 + wn * x0) * t * (-wn * t).exp()
    } else if zeta < 1.0 {
        let wd = wn * (1.0 - zeta * zeta).sqrt();
        (-zeta * wn * t).exp() * (x0 * (wd * t).cos() + (v0 + zeta * wn * x0) / wd * (wd * t).sin())
    } else {
        let s = wn * (zeta * zeta - 1.0).sqrt();
        let (r1, r2) = (-zeta * wn + s, -zeta * wn - s);
        let a = (v0 - r2 * x0) / (r1 - r2);
        let b = x0 - a;
        a * (r1 * t).exp() + b * (r2 * t).exp()
    }
}

fn run(params: &[(&str, f64)], tol: f64, h: f64, t_end: f64, exact: impl Fn(f64) -> f64) -> f64 {
    let mut fmu = Fmu::new();
    fmu.initialize(Some(tol), 0.0, params).unwrap();
    let (mut max_err, mut lo, mut hi) = (0.0f64, f64::MAX, f64::MIN);
    let mut n = 0u64;
    while fmu.time() < t_end - 1e-9 {
        let t = n as f64 * h;
        assert_eq!(fmu.do_step(t, h), fmi2OK, "{:?}", fmu.messages());
        n += 1;
        let (x, e) = (fmu.get("x"), exact(n as f64 * h));
        max_err = max_err.max((x - e).abs());
        lo = lo.min(e);
        hi = hi.max(e);
    }
    max_err / (hi - lo)
}

#[test]
fn free_response_in_every_damping_regime() {
    // (c, k) with m = 1: ζ = 0, 0.1, 1, 2.5
    for (c, k) in [(0.0, 4.0), (0.4, 4.0), (4.0, 4.0), (10.0, 4.0)] {
        for h in [0.01, 0.0137] {
            let err = run(
                &[("c", c), ("k", k), ("x", 0.7), ("x_dot", -0.3)],
                1e-8,
                h,
                20.0,
                |t| free_response(1.0, c, k, 0.7, -0.3, t),
            );
            assert!(
                err < 1e-6,
                "c = {c}, k = {k}, h = {h}: error {err:e} of range"
            );
        }
    }
}

#[test]
fn harmonic_forcing_near_resonance() {
    let (m, c, k, f0, w): (f64, f64, f64, f64, f64) = (1.0, 0.4, 4.0, 1.0, 1.95);
    let x_amp = f0 / ((k - m * w * w).powi(2) + (c * w).powi(2)).sqrt();
    let psi = -(c * w).atan2(k - m * w * w);
    // Transient: the free response that makes x(0) = 1, ẋ(0) = 0 with the steady part.
    let (xp0, vp0) = (x_amp * psi.sin(), x_amp * w * psi.cos());
    let exact = |t: f64| x_amp * (w * t + psi).sin() + free_response(m, c, k, 1.0 - xp0, -vp0, t);
    let err = run(&[("F0", f0), ("omega", w)], 1e-8, 0.01, 20.0, exact);
    assert!(err < 1e-6, "error {err:e} of range");
}

#[test]
fn calculated_parameters_follow_the_parameters() {
    let mut fmu = Fmu::new();
    fmu.initialize(None, 0.0, &[("m", 2.0), ("k", 8.0), ("c", 1.0)])
        .unwrap();
    assert!((fmu.get("omega_n") - 2.0).abs() < 1e-15);
    assert!((fmu.get("zeta") - 1.0 / 8.0).abs() < 1e-15);
    // A tunable change takes effect at once, calculated parameters included.
    assert_eq!(fmu.set("c", 4.0), fmi2OK);
    assert!((fmu.get("zeta") - 0.5).abs() < 1e-15);
}

#[test]
fn non_positive_mass_is_rejected_at_initialization() {
    for m in [0.0, -1.0] {
        let mut fmu = Fmu::new();
        assert_eq!(fmu.setup_experiment(None, 0.0, None), fmi2OK);
        assert_eq!(fmu.enter_initialization_mode(), fmi2OK);
        assert_eq!(fmu.set("m", m), fmi2OK);
        assert_eq!(fmu.exit_initialization_mode(), fmi2Error);
        assert!(fmu.logged(&format!("m = {m}")), "{:?}", fmu.messages());
        assert_eq!(fmu.do_step(0.0, 0.01), fmi2Error);
    }
}

#[test]
fn illegal_call_sequences_are_errors() {
    let mut fmu = Fmu::new();
    assert_eq!(fmu.do_step(0.0, 0.1), fmi2Error);
    assert!(fmu.logged("fmi2DoStep: illegal call sequence"));
    assert_eq!(fmu.exit_initialization_mode(), fmi2Error);
    assert_eq!(fmu.terminate(), fmi2Error);
    fmu.initialize(None, 0.0, &[]).unwrap();
    assert_eq!(fmu.setup_experiment(None, 0.0, None), fmi2Error);
    assert_eq!(
        fmu.set("m", 2.0),
        fmi2Error,
        "a fixed parameter after initialization"
    );
    assert!(fmu.logged("cannot be set after initialization"));
    assert_eq!(fmu.set("x_ddot", 2.0), fmi2Error, "an output");
    assert_eq!(fmu.do_step(0.0, 0.1), fmi2OK);
    assert_eq!(fmu.terminate(), fmi2OK);
    assert_eq!(fmu.terminate(), fmi2Error);
    assert_eq!(fmu.do_step(0.1, 0.1), fmi2Error);
}

#[test]
fn bad_arguments_are_errors_with_messages() {
    let mut fmu = Fmu::new();
    fmu.initialize(None, 0.0, &[]).unwrap();
    let mut v = [0.0];
    assert_eq!(fmu.get_real(&[999], &mut v), fmi2Error);
    assert!(fmu.logged("value reference 999"));
    assert_eq!(
        fmu.do_step(0.5, 0.1),
        fmi2Error,
        "wrong communication point"
    );
    assert_eq!(fmu.do_step(0.0, -0.1), fmi2Error);
    assert_eq!(fmu.do_step(0.0, f64::NAN), fmi2Error);
    assert_eq!(fmu.set("F", f64::INFINITY), fmi2Error);
    assert_eq!(
        fmu.do_step(0.0, 0.1),
        fmi2OK,
        "argument errors leave the instance usable"
    );
    let wrong = Harness::<Oscillator>::instantiate("o", fmi2CoSimulation, "{not-the-guid}");
    assert!(wrong.is_err_and(|log| log.iter().any(|m| m.2.contains("GUID"))));
    let unknown_type =
        Harness::<Oscillator>::instantiate("o", 2, &mechfmu::contract::guid::<Oscillator>());
    assert!(unknown_type.is_err_and(|log| log.iter().any(|m| m.2.contains("fmuType = 2"))));
}

#[test]
fn tunable_damping_takes_effect_at_the_next_step() {
    let mut a = Fmu::new();
    let mut b = Fmu::new();
    a.initialize(Some(1e-10), 0.0, &[]).unwrap();
    b.initialize(Some(1e-10), 0.0, &[]).unwrap();
    a.step_to(1.0, 0.01).unwrap();
    b.step_to(1.0, 0.01).unwrap();
    assert_eq!(a.get("x"), b.get("x"));
    assert_eq!(b.set("c", 2.0), fmi2OK);
    a.step_to(2.0, 0.01).unwrap();
    b.step_to(2.0, 0.01).unwrap();
    assert!((a.get("x") - b.get("x")).abs() > 1e-3);
}

mechfmu_testkit::golden_tests!(Oscillator);

#[test]
fn conforms() {
    mechfmu_testkit::conformance::check::<Oscillator>();
}

#[test]
fn fmi3_derivatives_by_the_time_are_the_forcing_rate() {
    // ẍ = (F0 sin(ω t) + F - c ẋ - k x) / m: ∂ẍ/∂t = F0 ω cos(ω t) / m, the time being a
    // known of FMI 3.0 (section 2.4.8); a seed on the time and one on x add up.
    use mechfmu::fmi3::ffi::{fmi3Error, fmi3OK};
    let (m, f0, w) = (2.0, 3.0, 1.7);
    let mut fmu = mechfmu_testkit::fmi3::Fmi3Harness::<Oscillator>::new();
    fmu.initialize(Some(1e-8), 0.0, &[("m", m), ("F0", f0), ("omega", w)])
        .unwrap();
    fmu.step_to(0.4, 0.1).unwrap();
    let t = fmu.time();
    let (time, x, x_ddot) = (fmu.vr("time"), fmu.vr("x"), fmu.vr("x_ddot"));
    let mut d = [f64::NAN];
    assert_eq!(
        fmu.directional_derivative(&[x_ddot], &[time], &[1.0], &mut d),
        fmi3OK
    );
    let expected = f0 * w * (w * t).cos() / m;
    assert!(
        (d[0] - expected).abs() <= 1e-15 * expected.abs(),
        "{} vs {expected}",
        d[0]
    );
    let k = fmu.get("k");
    assert_eq!(
        fmu.directional_derivative(&[x_ddot], &[time, x], &[2.0, 0.5], &mut d),
        fmi3OK
    );
    let expected = 2.0 * expected - 0.5 * k / m;
    assert!(
        (d[0] - expected).abs() <= 1e-15 * expected.abs(),
        "{} vs {expected}",
        d[0]
    );
    let mut adjoint = [f64::NAN; 2];
    assert_eq!(
        fmu.adjoint_derivative(&[x_ddot], &[time, x], &[1.0], &mut adjoint),
        fmi3OK
    );
    assert_eq!(adjoint, [f0 * w * (w * t).cos() / m, -k / m]);
    // The time is no unknown.
    assert_eq!(
        fmu.directional_derivative(&[time], &[x], &[1.0], &mut d),
        fmi3Error
    );
    assert!(
        fmu.logged("the unknowns include time"),
        "{:?}",
        fmu.messages()
    );
}

#[test]
fn derivatives_that_overflow_are_errors_naming_the_variable() {
    // ẍ = (… - c ẋ - k x) / m: seeds of 1e308 on x and ẋ overflow to an infinity, which
    // is no derivative; the messages name variables, not the version's value references.
    use mechfmu::fmi3::ffi::{fmi3Error, fmi3OK};
    let mut fmu = Fmu::new();
    fmu.initialize(None, 0.0, &[]).unwrap();
    let (x, v, x_ddot) = (Fmu::vr("x"), Fmu::vr("x_dot"), Fmu::vr("x_ddot"));
    let mut d = [f64::NAN];
    let status = fmu.directional_derivative(&[x_ddot], &[x, v], &[1e308, 1e308], &mut d);
    assert_eq!(status, fmi2Error, "{d:?}");
    assert!(fmu.logged("the derivative of `x_ddot` is not a finite number"));

    let mut fmu = mechfmu_testkit::fmi3::Fmi3Harness::<Oscillator>::new();
    fmu.initialize(None, 0.0, &[]).unwrap();
    let (x, v, x_ddot, m) = (fmu.vr("x"), fmu.vr("x_dot"), fmu.vr("x_ddot"), fmu.vr("m"));
    let status = fmu.directional_derivative(&[x_ddot], &[x, v], &[1e308, 1e308], &mut d);
    assert_eq!(status, fmi3Error, "{d:?}");
    assert!(fmu.logged("the derivative of `x_ddot` is not a finite number"));
    assert_eq!(
        fmu.directional_derivative(&[x_ddot], &[x, v], &[1.0, 1.0], &mut d),
        fmi3OK
    );
    assert_eq!(
        fmu.directional_derivative(&[x_ddot], &[m], &[1.0], &mut d),
        fmi3Error
    );
    assert!(
        fmu.logged("known `m` is neither a state nor an input"),
        "{:?}",
        fmu.messages()
    );
    assert!(!fmu
        .messages()
        .iter()
        .any(|m| m.2.contains("value reference")));
}
