//! Tests derived from the mathematics: convergence orders, error control, exact
//! landing, honest failure, bit-exact restore.

use super::dopri5::{tableau, FixedOrder};
use super::*;

// ---------------------------------------------------------------- test systems

/// y' = -y.
struct Decay;
impl OdeSystem for Decay {
    fn rhs(&mut self, _t: f64, y: &[f64], dydt: &mut [f64]) {
        dydt[0] = -y[0];
    }
}

/// x'' = -x as (x, v); exact solution from (1, 0) is (cos t, -sin t).
#[derive(Default)]
struct Oscillator {
    /// Largest max-norm error seen at accepted points.
    max_err: f64,
    /// Largest time the rhs was evaluated at.
    t_max_seen: f64,
}
impl Oscillator {
    fn exact(t: f64) -> [f64; 2] {
        [t.cos(), -t.sin()]
    }
}
impl OdeSystem for Oscillator {
    fn rhs(&mut self, t: f64, y: &[f64], dydt: &mut [f64]) {
        self.t_max_seen = self.t_max_seen.max(t);
        dydt[0] = y[1];
        dydt[1] = -y[0];
    }
    fn accepted(&mut self, t: f64, y: &[f64]) -> Result<(), String> {
        let ex = Self::exact(t);
        let e = (y[0] - ex[0]).abs().max((y[1] - ex[1]).abs());
        self.max_err = self.max_err.max(e);
        Ok(())
    }
}

/// x'' + 2ζω x' + ω² x = F cos(Ωt), x(0) = 1, x'(0) = 0, with its closed form.
struct Forced {
    max_err: f64,
}
impl Forced {
    const W: f64 = 2.0;
    const ZETA: f64 = 0.1;
    const F: f64 = 1.0;
    const OMEGA: f64 = 1.5;

    fn exact(t: f64) -> [f64; 2] {
        let (w, z, f, om) = (Self::W, Self::ZETA, Self::F, Self::OMEGA);
        // Particular solution A cos Ωt + B sin Ωt.
        let p = w * w - om * om;
        let q = 2.0 * z * w * om;
        let d = p * p + q * q;
        let a = f * p / d;
        let b = f * q / d;
        // Homogeneous part e^{-ζωt}(C cos ω_d t + D sin ω_d t) fixing x(0)=1, x'(0)=0.
        let wd = w * (1.0 - z * z).sqrt();
        let c = 1.0 - a;
        let dd = (z * w * c - b * om) / wd;
        let s = z * w;
        let e = (-s * t).exp();
        let (sn, cs) = (wd * t).sin_cos();
        let x = a * (om * t).cos() + b * (om * t).sin() + e * (c * cs + dd * sn);
        let v = -a * om * (om * t).sin()
            + b * om * (om * t).cos()
            + e * (-s * (c * cs + dd * sn) + wd * (-c * sn + dd * cs));
        [x, v]
    }
}
impl OdeSystem for Forced {
    fn rhs(&mut self, t: f64, y: &[f64], dydt: &mut [f64]) {
        dydt[0] = y[1];
        dydt[1] = Self::F * (Self::OMEGA * t).cos()
            - 2.0 * Self::ZETA * Self::W * y[1]
            - Self::W * Self::W * y[0];
    }
    fn accepted(&mut self, t: f64, y: &[f64]) -> Result<(), String> {
        let ex = Self::exact(t);
        let e = (y[0] - ex[0]).abs().max((y[1] - ex[1]).abs());
        self.max_err = self.max_err.max(e);
        Ok(())
    }
}

/// y' = -2t y², y(0) = 1: y = 1/(1+t²). Nonlinear and non-autonomous, so the nodes
/// c_i are exercised too.
struct Rational;
impl OdeSystem for Rational {
    fn rhs(&mut self, t: f64, y: &[f64], dydt: &mut [f64]) {
        dydt[0] = -2.0 * t * y[0] * y[0];
    }
}

fn tol(x: f64) -> Tolerance {
    Tolerance::new(x, x).unwrap()
}

fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

/// The end of the runs whose errors give the observed orders.
const T1: f64 = 2.0;

/// Fixed-step runs of `order` to `T1` with n, 2n, 4n, … steps (`ns`), and the range their
/// errors' observed orders must lie in.
struct Orders<'a> {
    ns: &'a [u32],
    order: FixedOrder,
    expected: std::ops::RangeInclusive<f64>,
}

impl<'a> Orders<'a> {
    fn new(ns: &'a [u32], order: FixedOrder, expected: std::ops::RangeInclusive<f64>) -> Self {
        Orders {
            ns,
            order,
            expected,
        }
    }

    /// Checks the observed orders of `sys` from `y0` at 0 to `exact` at `T1`.
    fn check<S: OdeSystem, const N: usize>(
        &self,
        name: &str,
        sys: &mut S,
        (y0, exact): (&[f64; N], &[f64]),
    ) {
        let (ns, order) = (self.ns, self.order);
        let mut solver = Dopri5::<[f64; N]>::new();
        let errs: Vec<f64> = ns
            .iter()
            .map(|&n| {
                let mut y = *y0;
                solver.integrate_fixed(sys, 0.0, T1, n, &mut y, order);
                max_abs_diff(&y, exact)
            })
            .collect();
        let p: Vec<f64> = errs
            .windows(2)
            .zip(ns.windows(2))
            .map(|(e, n)| (e[0] / e[1]).ln() / (f64::from(n[1]) / f64::from(n[0])).ln())
            .collect();
        let solution = match order {
            FixedOrder::Fifth => "the 5th-order solution",
            FixedOrder::Fourth => "the embedded solution",
        };
        println!("{name}: observed orders of {solution} {p:?}");
        assert!(p.iter().all(|q| self.expected.contains(q)), "{p:?}");
    }
}

// ---------------------------------------------------------------- tableau

#[test]
fn tableau_is_consistent() {
    use tableau::{A, B, C, E};
    for i in 0..7 {
        let row: f64 = A[i].iter().sum();
        assert!((row - C[i]).abs() < 1e-14, "row {i}: {row} vs c = {}", C[i]);
    }
    assert!((B.iter().sum::<f64>() - 1.0).abs() < 1e-15);
    assert!(E.iter().sum::<f64>().abs() < 1e-15);
    // Order conditions up to 5 for the quadrature part: Σ b_i c_i^(q-1) = 1/q.
    for q in 1..=5 {
        let s: f64 = B.iter().zip(C).map(|(b, c)| b * c.powi(q - 1)).sum();
        assert!((s - 1.0 / f64::from(q)).abs() < 1e-14, "q = {q}");
    }
    // The embedded weights b̂ = b - e satisfy them up to 4 but not 5.
    for q in 1..=5 {
        let s: f64 = B
            .iter()
            .zip(E)
            .zip(C)
            .map(|((b, e), c)| (b - e) * c.powi(q - 1))
            .sum();
        let ok = (s - 1.0 / f64::from(q)).abs() < 1e-14;
        assert_eq!(ok, q <= 4, "q = {q}");
    }
}

// ---------------------------------------------------------------- 1. order

#[test]
fn fifth_order_solution_converges_with_order_5() {
    // h = 0.1 … 0.0125 on [0, 2]: asymptotic, yet above rounding (errors ≥ 1e-14).
    let fifth = Orders::new(&[20, 40, 80, 160], FixedOrder::Fifth, 4.8..=5.2);
    fifth.check("y' = -y", &mut Decay, (&[1.0], &[(-T1).exp()]));
    let exact = Oscillator::exact(T1);
    fifth.check(
        "oscillator",
        &mut Oscillator::default(),
        (&[1.0, 0.0], &exact),
    );

    // Nonlinear, non-autonomous (checks the nodes c_i too). Its next error term is
    // large, so the observed order approaches 5 from above more slowly.
    let fifth = Orders::new(&[40, 80, 160], FixedOrder::Fifth, 4.8..=5.4);
    fifth.check(
        "y' = -2ty^2",
        &mut Rational,
        (&[1.0], &[1.0 / (1.0 + T1 * T1)]),
    );
}

#[test]
fn embedded_solution_converges_with_order_4() {
    // Propagating y_new - err (the embedded solution) instead of y_new.
    let fourth = Orders::new(&[20, 40, 80, 160], FixedOrder::Fourth, 3.8..=4.2);
    fourth.check("y' = -y", &mut Decay, (&[1.0], &[(-T1).exp()]));
    fourth.check(
        "y' = -2ty^2",
        &mut Rational,
        (&[1.0], &[1.0 / (1.0 + T1 * T1)]),
    );
}

#[test]
fn local_error_estimate_is_order_5() {
    // err = y5 - y4 over one step is O(h^5): halving h divides it by ≈ 32.
    let mut solver = Dopri5::new();
    let hs = [0.2, 0.1, 0.05, 0.025];
    let est: Vec<f64> = hs
        .iter()
        .map(|&h| {
            let mut y = [1.0 / (1.0 + 0.25)];
            solver.single_step_error(&mut Rational, 0.5, h, &mut y)[0].abs()
        })
        .collect();
    let p: Vec<f64> = est.windows(2).map(|e| (e[0] / e[1]).log2()).collect();
    println!("observed orders of the local error estimate {p:?}");
    for &q in &p {
        assert!((4.7..=5.3).contains(&q), "orders {p:?}");
    }
}

// ---------------------------------------------------------------- 2. error control

struct Row {
    tol: f64,
    max_err: f64,
    steps: u64,
    rejected: u64,
    evals: u64,
}

/// Integrates [0, 20] from (1, 0) with method `T` at tolerances 10^-k for k in `ks`.
fn tolerance_sweep<T: Method<[f64; 2]>, S: OdeSystem>(
    ks: std::ops::RangeInclusive<i32>,
    mut make: impl FnMut() -> S,
    err_of: fn(&S) -> f64,
) -> Vec<Row> {
    ks.map(|k| {
        let tl = 10f64.powi(-k);
        let mut sys = make();
        let mut solver = RungeKutta::<[f64; 2], T>::new();
        let (mut t, mut y) = (0.0, [1.0, 0.0]);
        let st = solver
            .integrate(&mut sys, &mut t, 20.0, &mut y, tol(tl))
            .unwrap();
        assert_eq!(t, 20.0);
        Row {
            tol: tl,
            max_err: err_of(&sys),
            steps: st.accepted,
            rejected: st.rejected,
            evals: st.rhs_evals,
        }
    })
    .collect()
}

/// Least-squares slope of log(steps) against log(1/tol): ≈ 1/(p+1)… 1/p for order p.
fn steps_slope(rows: &[Row]) -> f64 {
    let pts: Vec<(f64, f64)> = rows
        .iter()
        .map(|r| (-r.tol.ln(), (r.steps as f64).ln()))
        .collect();
    let n = pts.len() as f64;
    let (mx, my) = pts
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x / n, b + y / n));
    pts.iter().map(|(x, y)| (x - mx) * (y - my)).sum::<f64>()
        / pts.iter().map(|(x, _)| (x - mx).powi(2)).sum::<f64>()
}

/// Prints the sweep and checks every run's error against its tolerance (solution scale 1).
fn check_errors(name: &str, rows: &[Row]) {
    println!("{name}: tol | max error | accepted | rejected | rhs evals");
    for r in rows {
        println!(
            "{:8.0e} | {:9.3e} | {:8} | {:8} | {:9}",
            r.tol, r.max_err, r.steps, r.rejected, r.evals
        );
        assert!(
            r.max_err <= 50.0 * r.tol,
            "{name}: error {} at tol {}",
            r.max_err,
            r.tol
        );
    }
}

/// Checks that the number of steps grows as tol^-slope with the slope in `range`.
fn check_slope(name: &str, rows: &[Row], range: std::ops::RangeInclusive<f64>) {
    let slope = steps_slope(rows);
    println!("{name}: steps ∝ tol^-{slope:.3}");
    assert!(range.contains(&slope), "{name}: slope {slope}");
}

fn check_sweep(name: &str, rows: &[Row]) {
    check_errors(name, rows);
    for r in rows {
        // Each attempt costs 6 evaluations, plus k1 and the initial-step probe.
        assert_eq!(r.evals, 2 + 6 * (r.steps + r.rejected));
    }
    for w in rows.windows(2) {
        assert!(w[1].max_err < w[0].max_err, "{name}: error not decreasing");
        assert!(w[1].steps >= w[0].steps, "{name}: steps not increasing");
    }
    // ≈ 1/5 for an order-5 method.
    check_slope(name, rows, 0.15..=0.25);
}

#[test]
fn error_follows_tolerance_harmonic_oscillator() {
    let rows = tolerance_sweep::<Dp5<_>, _>(4..=12, Oscillator::default, |s| s.max_err);
    check_sweep("harmonic oscillator [0, 20]", &rows);
}

#[test]
fn error_follows_tolerance_forced_damped_oscillator() {
    let rows = tolerance_sweep::<Dp5<_>, _>(4..=12, || Forced { max_err: 0.0 }, |s| s.max_err);
    check_sweep("forced damped oscillator [0, 20]", &rows);
}

// ---------------------------------------------------------------- 3. landing exactly

fn run_communication_steps(dt: f64, t_stop: f64, tl: f64) -> ([f64; 2], Dopri5<[f64; 2]>, f64) {
    let mut sys = Oscillator::default();
    let mut solver = Dopri5::new();
    let (mut t, mut y) = (0.0, [1.0, 0.0]);
    let mut k = 0u32;
    while t < t_stop {
        k += 1;
        let t_end = (f64::from(k) * dt).min(t_stop);
        solver
            .integrate(&mut sys, &mut t, t_end, &mut y, tol(tl))
            .unwrap();
        assert_eq!(t.to_bits(), t_end.to_bits(), "call {k}");
        assert!(sys.t_max_seen <= t_end, "rhs evaluated beyond t_end");
    }
    (y, solver, sys.max_err)
}

#[test]
fn communication_steps_land_exactly_and_agree() {
    let tl = 1e-8;
    let mut one = Oscillator::default();
    let mut solver = Dopri5::new();
    let (mut t, mut y_one) = (0.0, [1.0, 0.0]);
    solver
        .integrate(&mut one, &mut t, 20.0, &mut y_one, tol(tl))
        .unwrap();
    assert_eq!(t, 20.0);
    assert!(one.t_max_seen <= 20.0);
    let exact = Oscillator::exact(20.0);
    for dt in [0.01, 0.0137, 10.0, 20.0, 30.0] {
        let (y, _, max_err) = run_communication_steps(dt, 20.0, tl);
        let d = max_abs_diff(&y, &y_one);
        println!("dt = {dt}: |y - y_one| = {d:.2e}, max err {max_err:.2e}");
        assert!(d <= 50.0 * tl, "dt = {dt}: differs by {d}");
        assert!(max_abs_diff(&y, &exact) <= 50.0 * tl);
    }
}

#[test]
fn tiny_communication_steps_keep_the_natural_step() {
    // 1e-6 is far below the natural step: every call is one clamped step, and the
    // remembered step must not collapse to 1e-6.
    let (y, solver, _) = run_communication_steps(1e-6, 2e-3, 1e-6);
    let h = solver.memory().h_next.unwrap();
    assert!(h > 1e-2, "remembered step collapsed to {h}");
    assert!(max_abs_diff(&y, &Oscillator::exact(2e-3)) < 1e-12);
    // Then a long step still works and is accurate.
    let mut solver = solver;
    let (mut t, mut y) = (2e-3, y);
    let mut sys = Oscillator::default();
    solver
        .integrate(&mut sys, &mut t, 20.0, &mut y, tol(1e-6))
        .unwrap();
    assert_eq!(t, 20.0);
    assert!(max_abs_diff(&y, &Oscillator::exact(20.0)) < 50e-6);
}

#[test]
fn tiny_leftover_is_absorbed_not_micro_stepped() {
    let mut solver = Dopri5::new();
    let h = 0.01;
    let run = |solver: &mut Dopri5<[f64; 2]>, span: f64| {
        solver.restore(SolverMemory {
            h_next: Some(h),
            ..SolverMemory::FRESH
        });
        let (mut t, mut y) = (1.0, Oscillator::exact(1.0));
        let st = solver
            .integrate(
                &mut Oscillator::default(),
                &mut t,
                1.0 + span,
                &mut y,
                tol(1e-6),
            )
            .unwrap();
        assert_eq!(t, 1.0 + span);
        st
    };
    let st = run(&mut solver, h * (1.0 + 1e-11));
    assert_eq!((st.accepted, st.rejected), (1, 0));
    let st = run(&mut solver, h * (1.0 + 1e-6));
    assert_eq!((st.accepted, st.rejected), (2, 0));
}

#[test]
fn zero_length_interval_is_a_no_op() {
    let mut solver = Dopri5::new();
    let (mut t, mut y) = (3.0, [1.0, 2.0]);
    let st = solver
        .integrate(&mut Oscillator::default(), &mut t, 3.0, &mut y, tol(1e-6))
        .unwrap();
    assert_eq!(st, StepStats::default());
    assert_eq!((t, y), (3.0, [1.0, 2.0]));
    assert_eq!(solver.memory(), SolverMemory::FRESH);
}

// ---------------------------------------------------------------- 4. failure honesty

/// y' = -y, but NaN for t > 1; checks that the solver itself never feeds it NaN.
struct NanAfterOne;
impl OdeSystem for NanAfterOne {
    fn rhs(&mut self, t: f64, y: &[f64], dydt: &mut [f64]) {
        assert!(
            y.iter().all(|v| v.is_finite()),
            "solver passed a non-finite y"
        );
        dydt[0] = if t > 1.0 { f64::NAN } else { -y[0] };
    }
}

#[test]
fn nan_rhs_reports_non_finite_at_last_good_point() {
    let mut solver = Dopri5::new();
    let (mut t, mut y) = (0.0, [1.0]);
    let err = solver
        .integrate(&mut NanAfterOne, &mut t, 3.0, &mut y, tol(1e-8))
        .unwrap_err();
    println!("{err}");
    let SolverError::NonFinite { t: te } = err else {
        panic!("expected NonFinite, got {err:?}")
    };
    assert_eq!(te, t);
    assert!(t <= 1.0 && t > 1.0 - 1e-6, "stopped at {t}");
    assert!(y[0].is_finite());
    assert!((y[0] - (-t).exp()).abs() < 1e-7);
}

/// x'' = -x as (x, v), except that one evaluation (the `nan_at`-th) returns NaN in one
/// component; checks that the solver never feeds it a non-finite point.
struct NanOnce {
    calls: usize,
    nan_at: usize,
    component: usize,
}
impl OdeSystem for NanOnce {
    fn rhs(&mut self, _t: f64, y: &[f64], dydt: &mut [f64]) {
        assert!(
            y.iter().all(|v| v.is_finite()),
            "solver passed a non-finite y at evaluation {}",
            self.calls + 1
        );
        self.calls += 1;
        dydt[0] = y[1];
        dydt[1] = -y[0];
        if self.calls == self.nan_at {
            dydt[self.component] = f64::NAN;
        }
    }
}

/// A NaN derivative at each stage of a step in turn: the step is rejected and retried,
/// never accepted, and the rhs never sees it (derivatives are checked where they are next
/// used, so a stage whose check was missed would fail here).
fn check_nan_at_every_stage<T: Method<[f64; 2]>>(stages: usize) {
    for stage in 1..=stages {
        for component in 0..2 {
            let mut solver = RungeKutta::<[f64; 2], T>::new();
            let mut sys = NanOnce {
                calls: 0,
                nan_at: usize::MAX,
                component,
            };
            let (mut t, mut y) = (0.0, [1.0, 0.0]);
            solver
                .integrate(&mut sys, &mut t, 0.5, &mut y, tol(1e-8))
                .unwrap();
            // The next call evaluates k1 at its start, then the first step's stages.
            sys.nan_at = sys.calls + 1 + stage;
            let stats = solver
                .integrate(&mut sys, &mut t, 1.0, &mut y, tol(1e-8))
                .unwrap_or_else(|e| panic!("NaN at stage {stage}: {e}"));
            assert!(stats.rejected >= 1, "NaN at stage {stage} was accepted");
            let err = (y[0] - 1f64.cos()).abs().max((y[1] + 1f64.sin()).abs());
            assert!(err < 1e-7, "NaN at stage {stage}: error {err:e}");
        }
    }
}

#[test]
fn a_nan_derivative_at_any_stage_rejects_the_step() {
    check_nan_at_every_stage::<Dp5<[f64; 2]>>(6);
    check_nan_at_every_stage::<Dp853<[f64; 2]>>(12);
}

#[test]
fn an_initial_step_probe_that_overflows_is_not_evaluated() {
    // y' = y at y near the largest double: the heuristic's Euler probe y + h·y overflows.
    struct Growth;
    impl OdeSystem for Growth {
        fn rhs(&mut self, _t: f64, y: &[f64], dydt: &mut [f64]) {
            assert!(y[0].is_finite(), "solver passed a non-finite y");
            dydt[0] = y[0];
        }
    }
    let mut solver = Dopri5::new();
    let (mut t, mut y) = (0.0, [1.79e308]);
    let err = solver
        .integrate(&mut Growth, &mut t, 1.0, &mut y, tol(1e-6))
        .unwrap_err();
    assert!(matches!(err, SolverError::NonFinite { .. }), "{err:?}");
    assert_eq!(err.t(), t);
    assert!(y[0].is_finite());
}

#[test]
fn nan_at_start_is_reported_without_stepping() {
    struct AlwaysNan;
    impl OdeSystem for AlwaysNan {
        fn rhs(&mut self, _t: f64, _y: &[f64], dydt: &mut [f64]) {
            dydt[0] = f64::NAN;
        }
    }
    let mut solver = Dopri5::new();
    let (mut t, mut y) = (0.5, [1.0]);
    let err = solver
        .integrate(&mut AlwaysNan, &mut t, 1.0, &mut y, tol(1e-6))
        .unwrap_err();
    assert_eq!(err, SolverError::NonFinite { t: 0.5 });
    assert_eq!((t, y), (0.5, [1.0]));
}

#[test]
fn blow_up_fails_at_the_numerical_singularity() {
    struct Square;
    impl OdeSystem for Square {
        fn rhs(&mut self, _t: f64, y: &[f64], dydt: &mut [f64]) {
            dydt[0] = y[0] * y[0];
        }
    }
    for tl in [1e-3, 1e-6, 1e-10] {
        let mut solver = Dopri5::new();
        let (mut t, mut y) = (0.0, [1.0]);
        let err = solver
            .integrate(&mut Square, &mut t, 2.0, &mut y, tol(tl))
            .unwrap_err();
        println!("tol {tl:e}: {err} (y = {:e})", y[0]);
        // Which limit is hit first depends on how close the steps get to the pole: the
        // minimum step, the step budget, or y² overflowing (reported as NonFinite).
        assert!(
            matches!(
                err,
                SolverError::StepSizeTooSmall { .. }
                    | SolverError::TooManySteps { .. }
                    | SolverError::NonFinite { .. }
            ),
            "{err:?}"
        );
        assert_eq!(err.t(), t);
        assert!(
            y[0].is_finite() && y[0] > 1e10,
            "gave up too early, y = {}",
            y[0]
        );
        // The numerical solution has its own pole, shifted from t = 1 by the global
        // error (earlier or later), so "t < 1" holds only up to the tolerance. What
        // must hold is that the invariant t + 1/y (= 1 exactly) was tracked to tolerance
        // and the solver stopped at its pole rather than stepping across it.
        let drift = (t + 1.0 / y[0] - 1.0).abs();
        assert!(drift < 50.0 * tl, "invariant drifted by {drift}");
        assert!(t < 1.0 + 50.0 * tl, "stepped over the singularity to {t}");
    }
}

#[test]
fn accepted_callback_can_stop_the_integration() {
    /// Refuses points beyond t = 0.5; remembers the last point it accepted.
    struct Stopper {
        last_valid: (f64, f64),
        refused: Option<f64>,
    }
    impl OdeSystem for Stopper {
        fn rhs(&mut self, _t: f64, y: &[f64], dydt: &mut [f64]) {
            dydt[0] = -y[0];
        }
        fn accepted(&mut self, t: f64, y: &[f64]) -> Result<(), String> {
            if t > 0.5 {
                self.refused = Some(t);
                return Err("limit reached".to_string());
            }
            self.last_valid = (t, y[0]);
            Ok(())
        }
    }
    let mut sys = Stopper {
        last_valid: (0.0, 1.0),
        refused: None,
    };
    let mut solver = Dopri5::new();
    let (mut t, mut y) = (0.0, [1.0]);
    let err = solver
        .integrate(&mut sys, &mut t, 10.0, &mut y, tol(1e-6))
        .unwrap_err();
    let (tv, yv) = sys.last_valid;
    assert!(sys.refused.is_some_and(|r| r > 0.5));
    assert_eq!(
        err,
        SolverError::Stopped {
            t: tv,
            message: "limit reached".to_string()
        }
    );
    // The refused point is not kept: the integration ends at the last valid one.
    assert_eq!((t, y[0]), (tv, yv));
    assert!(t <= 0.5);
    assert!(err.to_string().contains("limit reached"));
}

#[test]
fn too_many_steps_keeps_last_point() {
    let mut sys = Oscillator::default();
    let mut solver = Dopri5::new();
    solver.set_max_steps(5);
    let (mut t, mut y) = (0.0, [1.0, 0.0]);
    let err = solver
        .integrate(&mut sys, &mut t, 20.0, &mut y, tol(1e-8))
        .unwrap_err();
    assert_eq!(err, SolverError::TooManySteps { t, max_steps: 5 });
    assert!(t > 0.0 && t < 20.0);
    assert!(max_abs_diff(&y, &Oscillator::exact(t)) < 1e-6);
    // Continuing from there (with the remembered step) reaches the end.
    solver.set_max_steps(1_000_000);
    solver
        .integrate(&mut sys, &mut t, 20.0, &mut y, tol(1e-8))
        .unwrap();
    assert_eq!(t, 20.0);
}

// ---------------------------------------------------------------- 5. memory

#[test]
fn restore_continues_bit_for_bit() {
    let tl = tol(1e-7);
    let (t1, t2) = (3.3, 17.0);
    let mut a = Dopri5::new();
    let (mut t, mut y) = (0.0, [1.0, 0.0]);
    a.integrate(&mut Forced { max_err: 0.0 }, &mut t, t1, &mut y, tl)
        .unwrap();
    let mem = a.memory();
    let y_at_t1 = y;
    a.integrate(&mut Forced { max_err: 0.0 }, &mut t, t2, &mut y, tl)
        .unwrap();
    let y_a = y;

    // A different solver that has done other work first.
    let mut b = Dopri5::new();
    let (mut tb, mut yb) = (0.0, [0.3, -2.0]);
    b.integrate(&mut Oscillator::default(), &mut tb, 7.0, &mut yb, tol(1e-3))
        .unwrap();
    b.restore(mem);
    let (mut tb, mut yb) = (t1, y_at_t1);
    b.integrate(&mut Forced { max_err: 0.0 }, &mut tb, t2, &mut yb, tl)
        .unwrap();
    assert_eq!(y_a.map(f64::to_bits), yb.map(f64::to_bits));
    assert_eq!(a.memory(), b.memory());

    // forget() is the same as a fresh solver.
    b.forget();
    assert_eq!(b.memory(), Dopri5::<[f64; 2]>::new().memory());
    assert_eq!(b.memory(), SolverMemory::default());
}

#[test]
fn runs_are_deterministic() {
    let run = || {
        let mut s = Dopri5::new();
        let (mut t, mut y) = (0.0, [1.0, 0.0]);
        let st = s
            .integrate(
                &mut Forced { max_err: 0.0 },
                &mut t,
                20.0,
                &mut y,
                tol(1e-9),
            )
            .unwrap();
        (y.map(f64::to_bits), st, s.memory().h_next.map(f64::to_bits))
    };
    assert_eq!(run(), run());
}

// ---------------------------------------------------------------- 6. edge cases

#[test]
fn zero_dimensional_system_is_a_no_op() {
    struct Empty;
    impl OdeSystem for Empty {
        fn rhs(&mut self, _t: f64, _y: &[f64], _dydt: &mut [f64]) {
            panic!("rhs of an empty system called");
        }
    }
    let mut solver = Dopri5::new();
    assert_eq!(solver.dim(), 0);
    let mut t = 0.0;
    let st = solver
        .integrate(&mut Empty, &mut t, 5.0, &mut [], tol(1e-6))
        .unwrap();
    assert_eq!(t, 5.0);
    assert_eq!(st, StepStats::default());
}

#[test]
fn rtol_is_clamped_at_ten_ulp() {
    let run = |rtol: f64| {
        let mut sys = Oscillator::default();
        let mut s = Dopri5::new();
        let (mut t, mut y) = (0.0, [1.0, 0.0]);
        let st = s
            .integrate(
                &mut sys,
                &mut t,
                5.0,
                &mut y,
                Tolerance::new(rtol, 1e-14).unwrap(),
            )
            .unwrap();
        assert_eq!(t, 5.0);
        (y, st, sys.max_err)
    };
    let (y_tiny, st_tiny, _) = run(1e-20);
    let (y_clamp, st_clamp, err) = run(MIN_RTOL);
    assert_eq!(y_tiny.map(f64::to_bits), y_clamp.map(f64::to_bits));
    assert_eq!(st_tiny, st_clamp);
    println!("rtol clamp: {st_clamp:?}, max error {err:e}");
    assert!(err < 1e-12);
    let (_, st14, err14) = run(1e-14);
    println!("rtol 1e-14: {st14:?}, max error {err14:e}");
    assert!(err14 < 1e-12);
}

#[test]
fn very_loose_tolerances_still_land() {
    for tl in [1e-2, 1e-1, 1.0] {
        let mut sys = Oscillator::default();
        let mut s = Dopri5::new();
        let (mut t, mut y) = (0.0, [1.0, 0.0]);
        let st = s
            .integrate(&mut sys, &mut t, 20.0, &mut y, tol(tl))
            .unwrap();
        println!("tol {tl}: {st:?}, max error {:e}", sys.max_err);
        assert_eq!(t, 20.0);
        assert!(y.iter().all(|v| v.is_finite()));
        // Beyond ~1e-2 nothing but landing and finiteness is promised: a relative
        // tolerance of 1 lets every step double the amplitude.
        if tl <= 1e-2 {
            assert!(sys.max_err < 50.0 * tl);
        }
    }
}

#[test]
fn pure_relative_tolerance_with_zero_component() {
    // atol = 0 with a component that stays exactly 0 must not produce NaN norms.
    struct Half;
    impl OdeSystem for Half {
        fn rhs(&mut self, _t: f64, y: &[f64], dydt: &mut [f64]) {
            dydt[0] = -y[0];
            dydt[1] = 0.0;
        }
    }
    let mut s = Dopri5::new();
    let (mut t, mut y) = (0.0, [1.0, 0.0]);
    s.integrate(
        &mut Half,
        &mut t,
        2.0,
        &mut y,
        Tolerance::new(1e-8, 0.0).unwrap(),
    )
    .unwrap();
    assert!((y[0] - (-2f64).exp()).abs() < 1e-7);
    assert_eq!(y[1], 0.0);
}

#[test]
fn errors_display_their_numbers() {
    let msgs = [
        SolverError::StepSizeTooSmall { t: 0.75, h: 1e-17 }.to_string(),
        SolverError::NonFinite { t: 1.5 }.to_string(),
        SolverError::TooManySteps {
            t: 2.5,
            max_steps: 42,
        }
        .to_string(),
    ];
    assert!(msgs[0].contains("0.75") && msgs[0].contains("1e-17"));
    assert!(msgs[1].contains("1.5"));
    assert!(msgs[2].contains("2.5") && msgs[2].contains("42"));
}

// ---------------------------------------------------------------- Dormand–Prince 8(5,3)

#[test]
fn dop853_tableau_satisfies_the_order_conditions() {
    use super::dop853::tableau::{A, B, C};
    for i in 0..12 {
        let row: f64 = A[i].iter().sum();
        assert!((row - C[i]).abs() < 1e-14, "row {i}: {row} vs c = {}", C[i]);
    }
    // Quadrature conditions Σ b_i c_i^(q-1) = 1/q up to q = 8.
    for q in 1..=8 {
        let s: f64 = B.iter().zip(C).map(|(b, c)| b * c.powi(q - 1)).sum();
        assert!((s - 1.0 / f64::from(q)).abs() < 1e-13, "q = {q}: {s}");
    }
    // Conditions through A: Σ_i b_i c_i^m Σ_j a_ij c_j^n = 1/((n+1)(m+n+2)) (the bushy
    // trees with one inner node), for all orders up to 8. A wrong digit in any a_ij of a
    // stage with b_i ≠ 0 breaks one of them.
    for m in 0..=6 {
        for n in 0..=(6 - m) {
            let s: f64 = (0..12)
                .map(|i| {
                    let inner: f64 = (0..11).map(|j| A[i][j] * C[j].powi(n)).sum();
                    B[i] * C[i].powi(m) * inner
                })
                .sum();
            let exact = 1.0 / (f64::from(n + 1) * f64::from(m + n + 2));
            assert!(
                (s - exact).abs() < 1e-13,
                "m = {m}, n = {n}: {s} vs {exact}"
            );
        }
    }
    // And a chain (tall tree) of order 8: b·A^6·c = 1/8!.
    let mut v: Vec<f64> = C.to_vec();
    for _ in 0..6 {
        v = (0..12)
            .map(|i| (0..11).map(|j| A[i][j] * v[j]).sum())
            .collect();
    }
    let s: f64 = B.iter().zip(&v).map(|(b, x)| b * x).sum();
    assert!((s - 1.0 / 40320.0).abs() < 1e-15, "tall tree: {s}");
}

fn check_dop853_sweep(name: &str, rows: &[Row]) {
    let name = format!("{name} (DOP853)");
    check_errors(&name, rows);
    // ≈ 1/8 for an order-8 method.
    check_slope(&name, rows, 0.09..=0.16);
}

#[test]
fn dop853_error_follows_tolerance_with_order_8() {
    let rows = tolerance_sweep::<Dp853<_>, _>(4..=13, Oscillator::default, |s| s.max_err);
    check_dop853_sweep("harmonic oscillator [0, 20]", &rows);
    let rows = tolerance_sweep::<Dp853<_>, _>(4..=13, || Forced { max_err: 0.0 }, |s| s.max_err);
    check_dop853_sweep("forced damped oscillator [0, 20]", &rows);
}

#[test]
fn dop853_needs_fewer_evaluations_than_dopri5_at_tight_tolerances() {
    for k in [8, 10, 12] {
        let tl = 10f64.powi(-k);
        let run = |high: bool| {
            let mut sys = Forced { max_err: 0.0 };
            let (mut t, mut y) = (0.0, [1.0, 0.0]);
            let st = if high {
                Dop853::new().integrate(&mut sys, &mut t, 20.0, &mut y, tol(tl))
            } else {
                Dopri5::new().integrate(&mut sys, &mut t, 20.0, &mut y, tol(tl))
            }
            .unwrap();
            (st.rhs_evals, sys.max_err)
        };
        let (e8, err8) = run(true);
        let (e5, err5) = run(false);
        println!("tol {tl:e}: DOP853 {e8} evaluations (error {err8:e}), Dopri5 {e5} ({err5:e})");
        assert!(e8 < e5, "tol {tl:e}: {e8} vs {e5}");
    }
}

/// `n` communication intervals of `h` on the unit oscillator through `solver`: the
/// evaluations, the largest error at the communication points, and after each interval
/// whether the solver is on its 8th-order method.
fn communicate(
    solver: &mut Solver<[f64; 2]>,
    (t, y): (&mut f64, &mut [f64; 2]),
    h: f64,
    n: usize,
    tl: f64,
) -> (u64, f64, Vec<bool>) {
    let (mut evals, mut err, mut high) = (0, 0.0f64, Vec::new());
    let t0 = *t;
    for k in 1..=n {
        let t_end = t0 + k as f64 * h;
        let st = solver
            .integrate(&mut Oscillator::default(), t, t_end, y, tol(tl))
            .unwrap();
        assert_eq!(*t, t_end);
        evals += st.rhs_evals;
        let ex = Oscillator::exact(*t);
        err = err.max((y[0] - ex[0]).abs().max((y[1] - ex[1]).abs()));
        high.push(solver.memory().high_order);
    }
    (evals, err, high)
}

#[test]
fn solver_is_dopri5_while_one_step_covers_each_interval() {
    // Short intervals: after the start-up interval every one is a single Dopri5 step, and
    // the solver gives exactly what Dopri5 alone gives.
    let mut a = Solver::new();
    let mut b = Dopri5::new();
    let (mut ta, mut ya) = (0.0, [1.0, 0.0]);
    let (mut tb, mut yb) = (0.0, [1.0, 0.0]);
    for k in 1..=300 {
        let t_end = f64::from(k) * 0.01;
        a.integrate(
            &mut Oscillator::default(),
            &mut ta,
            t_end,
            &mut ya,
            tol(1e-6),
        )
        .unwrap();
        b.integrate(
            &mut Oscillator::default(),
            &mut tb,
            t_end,
            &mut yb,
            tol(1e-6),
        )
        .unwrap();
        assert_eq!((ta, ya), (tb, yb), "interval {k}");
        assert!(!a.memory().high_order, "interval {k}");
        assert_eq!(a.memory(), b.memory());
    }
}

#[test]
fn solver_takes_dop853_where_dopri5_needs_several_steps() {
    for tl in [1e-6, 1e-8, 1e-10] {
        // Intervals of 1 s: several Dopri5 steps each.
        let mut a = Solver::new();
        let (evals, err, high) = communicate(&mut a, (&mut 0.0, &mut [1.0, 0.0]), 1.0, 20, tl);
        assert!(high[1..].iter().all(|&h| h), "tol {tl:e}: {high:?}");
        let mut b = Dopri5::new();
        let (mut t, mut y, mut evals5) = (0.0, [1.0, 0.0], 0);
        for k in 1..=20 {
            let st = b
                .integrate(
                    &mut Oscillator::default(),
                    &mut t,
                    f64::from(k),
                    &mut y,
                    tol(tl),
                )
                .unwrap();
            evals5 += st.rhs_evals;
        }
        let ex = Oscillator::exact(20.0);
        let err5 = (y[0] - ex[0]).abs().max((y[1] - ex[1]).abs());
        println!(
            "tol {tl:e}: solver {evals} evaluations (error {err:e}), Dopri5 {evals5} ({err5:e})"
        );
        assert!(evals < evals5, "tol {tl:e}: {evals} vs {evals5}");
        assert!(err <= 50.0 * tl, "tol {tl:e}: error {err:e}");
    }
}

#[test]
fn solver_hands_back_to_dopri5_when_the_intervals_shorten() {
    let mut a = Solver::new();
    let (mut t, mut y) = (0.0, [1.0, 0.0]);
    let (_, _, high) = communicate(&mut a, (&mut t, &mut y), 0.5, 10, 1e-6);
    assert!(high[9], "long intervals: {high:?}");
    let (evals, err, high) = communicate(&mut a, (&mut t, &mut y), 0.01, 50, 1e-6);
    let back = high.iter().position(|&h| !h).expect("never handed back");
    assert!(back < 3, "{high:?}");
    assert!(high[back..].iter().all(|&h| !h), "{high:?}");
    // Every call evaluates its first stage afresh (this system has no cache, unlike an
    // FMU's): 1 + 6 per Dopri5 interval, 1 + 12 per Dop853 one.
    assert!(
        evals <= 7 * 50 + 6 * (back as u64 + 1),
        "{evals} evaluations, {high:?}"
    );
    assert!(err <= 50.0 * 1e-6, "error {err:e}");
}

#[test]
fn solver_memory_restores_bit_for_bit_on_either_method() {
    for (h, high_order) in [(0.01, false), (1.0, true)] {
        let mut a = Solver::new();
        let (mut ta, mut ya) = (0.0, [1.0, 0.0]);
        communicate(&mut a, (&mut ta, &mut ya), h, 10, 1e-8);
        let saved = a.memory();
        assert_eq!(saved.high_order, high_order);
        let (t0, y0) = (ta, ya);
        let ra = communicate(&mut a, (&mut ta, &mut ya), h, 5, 1e-8);
        let mut c = Solver::new();
        c.restore(saved);
        let (mut tc, mut yc) = (t0, y0);
        let rc = communicate(&mut c, (&mut tc, &mut yc), h, 5, 1e-8);
        assert_eq!((ta, ya, a.memory(), ra), (tc, yc, c.memory(), rc));
    }
}

/// Every call restored into a fresh solver from the memory before it: the same steps, to the
/// last bit. The intervals hold several steps, so each call's first step is the remembered
/// proposal, which the fresh controller must make exactly as the running one did.
#[test]
fn a_memory_restored_in_a_fresh_solver_continues_bit_for_bit() {
    let tl = tol(1e-9);
    let mut a = Dopri5::new();
    let (mut t, mut y) = (0.0, [1.0, 0.0]);
    let mut several = 0;
    for k in 1..=400 {
        let t_end = 0.25 * f64::from(k);
        let (memory, t_start, y_start) = (a.memory(), t, y);
        let st = a
            .integrate(&mut Forced { max_err: 0.0 }, &mut t, t_end, &mut y, tl)
            .unwrap();
        several += usize::from(st.accepted > 1);
        let mut b = Dopri5::new();
        b.restore(memory);
        let (mut tb, mut yb) = (t_start, y_start);
        let stb = b
            .integrate(&mut Forced { max_err: 0.0 }, &mut tb, t_end, &mut yb, tl)
            .unwrap();
        assert_eq!(
            (y.map(f64::to_bits), st, a.memory()),
            (yb.map(f64::to_bits), stb, b.memory()),
            "call {k}"
        );
    }
    assert!(several > 300, "only {several} calls took several steps");
}

#[test]
fn only_memories_the_solver_can_have_are_valid() {
    let mut solver = Dopri5::new();
    assert!(solver.memory().is_valid());
    let (mut t, mut y) = (0.0, [1.0, 0.0]);
    solver
        .integrate(&mut Forced { max_err: 0.0 }, &mut t, 3.0, &mut y, tol(1e-8))
        .unwrap();
    let ran = solver.memory();
    assert!(ran.is_valid() && ran.h_next.is_some());
    assert!(ran.log2_err_prev > SolverMemory::FRESH.log2_err_prev && ran.log2_err_prev <= 0.0);
    let forged = |h_next: Option<f64>, log2_err_prev: f64| SolverMemory {
        h_next,
        log2_err_prev,
        ..ran
    };
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        assert!(
            !forged(Some(bad), ran.log2_err_prev).is_valid(),
            "h_next {bad}"
        );
    }
    for bad in [f64::NAN, 0.5, -13.3, f64::NEG_INFINITY] {
        assert!(!forged(ran.h_next, bad).is_valid(), "log2_err_prev {bad}");
    }
    assert!(forged(None, 0.0).is_valid());
}

#[test]
fn the_integration_stops_where_the_system_stops_holding_not_at_the_step_before() {
    /// y' = -y from 1 is valid while y ≥ 1/2: until t = ln 2.
    struct Half;
    impl OdeSystem for Half {
        fn rhs(&mut self, _t: f64, y: &[f64], dydt: &mut [f64]) {
            dydt[0] = -y[0];
        }
        fn accepted(&mut self, _t: f64, y: &[f64]) -> Result<(), String> {
            if y[0] < 0.5 {
                return Err("below one half".to_string());
            }
            Ok(())
        }
    }
    for rtol in [1e-4, 1e-8] {
        let mut solver = Dopri5::new();
        let (mut t, mut y) = (0.0, [1.0]);
        let err = solver
            .integrate(&mut Half, &mut t, 10.0, &mut y, tol(rtol))
            .unwrap_err();
        assert!(matches!(err, SolverError::Stopped { t: s, .. } if s == t));
        // Located to the step's accuracy, on the valid side.
        assert!(y[0] >= 0.5 && y[0] - 0.5 < 10.0 * rtol, "y = {}", y[0]);
        let crossing = std::f64::consts::LN_2;
        assert!(
            t <= crossing + 10.0 * rtol && crossing - t < 10.0 * rtol,
            "t = {t}"
        );
    }
}
