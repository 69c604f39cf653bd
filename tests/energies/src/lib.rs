//! A mechanism declared a second time, from its energies, beside its hand-written crate: the
//! *twin* shares the hand-written mechanism's variables (its declaration, value references
//! and values), its parameters' calculation and its outputs, and replaces its equations of
//! motion by Lagrange's from `T`, `V` and `Q`. The checks compare the two:
//!
//! - [`agreement`]: at random states, inputs and parameter sets, every value `evaluate`
//!   writes (the accelerations, a driven coordinate's force), on `f64` and, with a random
//!   direction, on dual numbers (the exact directional derivatives);
//! - [`same_trajectories`]: over a case simulated through the FMI functions, every value at
//!   every communication point;
//! - [`reference_case`]: the packaged reference results, which the twin must meet as
//!   closely as the hand-written mechanism does.

use mechfmu::model::{Causality, Mechanism, ValueSet, Variability};
use mechfmu_testkit::harness::Harness;
pub use mechfmu_testkit::rng::Rng;
use num_dual::Dual64;
use std::path::Path;

/// `twin!(Twin of Hand, evaluate(v) { ... })`: a mechanism with `Hand`'s variables, values,
/// calculation, outputs, monitor and experiment, whose `evaluate` is the block given (which
/// calls `Self::lagrange(v)`; `v` is the values, generic over the scalar `S`). The
/// `Lagrangian` impl is written beside it.
#[macro_export]
macro_rules! twin {
    ($twin:ident of $hand:ty, evaluate($v:ident) $body:block) => {
        /// The mechanism declared again from its energies.
        #[derive(Clone, Copy, Debug, Default)]
        pub struct $twin;

        impl ::mechfmu::model::Declaration for $twin {
            const NAME: &'static str = <$hand as ::mechfmu::model::Declaration>::NAME;
            const DESCRIPTION: &'static str =
                <$hand as ::mechfmu::model::Declaration>::DESCRIPTION;
            const VARIABLES: &'static [::mechfmu::model::Variable] =
                <$hand as ::mechfmu::model::Declaration>::VARIABLES;
            type Values<S: ::mechfmu::model::Scalar> =
                <$hand as ::mechfmu::model::Declaration>::Values<S>;
            type State = <$hand as ::mechfmu::model::Declaration>::State;
            const STATES: &'static [usize] = <$hand as ::mechfmu::model::Declaration>::STATES;
            const DERIVATIVES: &'static [usize] =
                <$hand as ::mechfmu::model::Declaration>::DERIVATIVES;
            const DERIVATIVES_AMONG_STATES: &'static [Option<usize>] =
                <$hand as ::mechfmu::model::Declaration>::DERIVATIVES_AMONG_STATES;
            const CONTINUOUS: &'static [usize] =
                <$hand as ::mechfmu::model::Declaration>::CONTINUOUS;
            const CONTINUOUS_UNCHECKED: &'static [usize] =
                <$hand as ::mechfmu::model::Declaration>::CONTINUOUS_UNCHECKED;
            const INPUTS: &'static [usize] = <$hand as ::mechfmu::model::Declaration>::INPUTS;
            fn zeros<S: ::mechfmu::model::Scalar>() -> Self::Values<S> {
                <$hand as ::mechfmu::model::Declaration>::zeros()
            }
            fn map_values<A: ::mechfmu::model::Scalar, B: ::mechfmu::model::Scalar>(
                values: &Self::Values<A>,
                f: impl Fn(A) -> B,
            ) -> Self::Values<B> {
                <$hand as ::mechfmu::model::Declaration>::map_values(values, f)
            }
        }

        impl ::mechfmu::model::Mechanism for $twin {
            const EXPERIMENT: ::mechfmu::model::Experiment =
                <$hand as ::mechfmu::model::Mechanism>::EXPERIMENT;
            const PROJECTED: bool = <$hand as ::mechfmu::model::Mechanism>::PROJECTED;
            const MONITORED: bool = <$hand as ::mechfmu::model::Mechanism>::MONITORED;
            const EVENT_INDICATORS: &'static [&'static str] =
                <$hand as ::mechfmu::model::Mechanism>::EVENT_INDICATORS;
            const ARRAYS: &'static [::mechfmu::model::Array] =
                <$hand as ::mechfmu::model::Mechanism>::ARRAYS;
            fn calculate(values: &mut Self::Values<f64>) -> Result<(), String> {
                <$hand as ::mechfmu::model::Mechanism>::calculate(values)
            }
            fn evaluate<S: ::mechfmu::model::Scalar>($v: &mut Self::Values<S>) $body
            fn outputs<S: ::mechfmu::model::Scalar>(values: &mut Self::Values<S>) {
                <$hand as ::mechfmu::model::Mechanism>::outputs(values)
            }
            fn project(values: &mut Self::Values<f64>) {
                <$hand as ::mechfmu::model::Mechanism>::project(values)
            }
            fn monitor(values: &Self::Values<f64>) -> ::mechfmu::model::Monitor {
                <$hand as ::mechfmu::model::Mechanism>::monitor(values)
            }
            fn diagnose(values: &Self::Values<f64>) -> Option<String> {
                Self::mass_matrix_problem(values)
            }
        }
    };
}

/// `twin_tests!(Twin of Hand in "folder", seed: s, trajectories: start, to: stop, by: step)`:
/// the tests every twin runs against its hand-written mechanism (in `fmus/<folder>`):
/// [`assert_agreement`] at 1000 random points from the seed, [`assert_reference_case`],
/// [`assert_same_trajectories`] from the start values given (by name) to `stop` by `step`,
/// and the ignored `probe` that `mechfmu bench --energies` runs (see [`probe`]).
#[macro_export]
macro_rules! twin_tests {
    (
        $twin:ident of $hand:ident in $folder:literal,
        seed: $seed:expr,
        trajectories: $start:expr,
        to: $stop:expr, by: $step:expr $(,)?
    ) => {
        #[test]
        fn equations_agree_at_random_points() {
            $crate::assert_agreement::<$hand, $twin>(1000, $seed);
        }

        #[test]
        fn reference_case_agrees() {
            $crate::assert_reference_case::<$hand, $twin>($folder);
        }

        #[test]
        fn trajectories_agree() {
            $crate::assert_same_trajectories::<$hand, $twin>(&$start, $stop, $step);
        }

        /// What `mechfmu bench --energies` counts the instructions of.
        #[test]
        #[ignore]
        fn probe() {
            $crate::probe::<$hand, $twin>();
        }
    };
}

/// A random point: each parameter within a factor of two of its start value (inside its
/// bounds), each state and input its start value moved by up to its own size (at least 1),
/// angles and angular rates (units `rad...`) in (-3, 3), and the calculated parameters
/// computed.
pub fn random_point<M: Mechanism>(rng: &mut Rng) -> M::Values<f64> {
    loop {
        let mut values = M::zeros::<f64>();
        values.set_time(rng.uniform(0.0, 10.0));
        for (vr, variable) in M::VARIABLES.iter().enumerate() {
            let start = variable.start.unwrap_or(0.0);
            let value = match (variable.causality, variable.variability) {
                (Causality::Parameter, _) if start > 0.0 => {
                    let lo = if variable.min == Some(0.0) && !variable.positive {
                        0.0
                    } else {
                        0.5 * start
                    };
                    rng.uniform(lo, 2.0 * start)
                }
                (Causality::Parameter, _) => start,
                (_, Variability::Continuous) if variable.start.is_some() => {
                    if variable.unit.starts_with("rad") {
                        rng.uniform(-3.0, 3.0)
                    } else {
                        let size = start.abs().max(1.0);
                        start + rng.uniform(-size, size)
                    }
                }
                _ => 0.0,
            };
            values.set(vr, value);
        }
        if M::calculate(&mut values).is_ok() {
            return values;
        }
    }
}

/// The worst disagreement found by [`agreement`], over every value `evaluate` and `outputs`
/// write: `|hand - twin|` relative to the largest magnitude the hand-written value takes over
/// the sample (a value that passes through zero has no relative error of its own), for the
/// values and for their derivatives along random directions.
#[derive(Debug)]
pub struct Agreement {
    pub worst_value: f64,
    pub worst_derivative: f64,
    /// Where each was found, with the two numbers.
    pub at: String,
    pub derivative_at: String,
}

/// The variables `evaluate` writes: continuous, neither states nor inputs.
fn written<M: Mechanism>() -> Vec<usize> {
    (M::VARIABLES.iter().enumerate())
        .filter(|(_, v)| {
            v.variability == Variability::Continuous
                && v.causality != Causality::Input
                && v.derivative.is_none()
        })
        .map(|(vr, _)| vr)
        .collect()
}

/// `(hand, twin)` pairs of one variable over the sample: the worst difference relative to
/// the largest `|hand|`, and where.
fn worst_of(pairs: &[(f64, f64)]) -> (f64, usize) {
    let scale = pairs.iter().fold(0.0f64, |m, (a, _)| m.max(a.abs()));
    let mut worst = (0.0, 0);
    for (k, (a, b)) in pairs.iter().enumerate() {
        // Equal numbers (zeros too) agree; NaN disagrees.
        let difference = match (a - b).abs() / scale {
            _ if a == b => 0.0,
            d if d.is_nan() => f64::INFINITY,
            d => d,
        };
        if difference > worst.0 {
            worst = (difference, k);
        }
    }
    worst
}

/// Compares `Hand` and `Twin` (which share their values) at `points` random points: every
/// value `evaluate` and `outputs` write, on `f64`, and its derivative along a random
/// direction in the states, inputs and time (the knowns of a directional derivative) on
/// dual numbers, whose values must be the `f64` ones.
pub fn agreement<Hand, Twin>(points: usize, seed: u64) -> Agreement
where
    Hand: Mechanism,
    Twin: Mechanism<Values<f64> = Hand::Values<f64>, Values<Dual64> = Hand::Values<Dual64>>,
{
    let mut rng = Rng(seed);
    let compared = written::<Hand>();
    let mut values = vec![Vec::with_capacity(points); compared.len()];
    let mut derivatives = vec![Vec::with_capacity(points); compared.len()];
    for _ in 0..points {
        let point = random_point::<Hand>(&mut rng);
        let (mut hand, mut twin) = (point.clone(), point.clone());
        mechfmu::model::evaluate_all::<Hand, f64>(&mut hand);
        mechfmu::model::evaluate_all::<Twin, f64>(&mut twin);

        let mut dual = Hand::map_values(&point, Dual64::from_re);
        for (vr, variable) in Hand::VARIABLES.iter().enumerate() {
            // The knowns of a directional derivative: states, inputs (and the time);
            // parameters are constant in the equations (a hand-written mechanism may test one).
            if variable.derivative.is_some() || variable.causality == Causality::Input {
                let x = point.get(vr).unwrap_or(0.0);
                dual.set(vr, Dual64::new(x, rng.uniform(-1.0, 1.0)));
            }
        }
        dual.set_time(Dual64::new(point.time(), rng.uniform(-1.0, 1.0)));
        let (mut hand_dual, mut twin_dual) = (dual.clone(), dual);
        mechfmu::model::evaluate_all::<Hand, Dual64>(&mut hand_dual);
        mechfmu::model::evaluate_all::<Twin, Dual64>(&mut twin_dual);

        for (k, &vr) in compared.iter().enumerate() {
            let (a, b) = (hand.get(vr).unwrap(), twin.get(vr).unwrap());
            let (da, db) = (hand_dual.get(vr).unwrap(), twin_dual.get(vr).unwrap());
            values[k].push((a, b));
            // The dual path's values are the f64 path's, to rounding.
            values[k].push((da.re, db.re));
            derivatives[k].push((da.eps, db.eps));
        }
    }
    let mut worst = Agreement {
        worst_value: 0.0,
        worst_derivative: 0.0,
        at: String::new(),
        derivative_at: String::new(),
    };
    for (k, &vr) in compared.iter().enumerate() {
        let name = Hand::VARIABLES[vr].name;
        let (value, i) = worst_of(&values[k]);
        if value > worst.worst_value {
            let (a, b) = values[k][i];
            worst.worst_value = value;
            worst.at = format!("{name} = {a:e} / {b:e}");
        }
        let (derivative, i) = worst_of(&derivatives[k]);
        if derivative > worst.worst_derivative {
            let (a, b) = derivatives[k][i];
            worst.worst_derivative = derivative;
            worst.derivative_at = format!("d{name} = {a:e} / {b:e}");
        }
    }
    worst
}

/// Inputs as the FMI cross-check gives them (`<Name>_in.csv`): a time column and one column
/// per input, linear between rows, a time listed twice a jump.
pub struct Inputs {
    pub names: Vec<String>,
    pub rows: Vec<Vec<f64>>,
}

impl Inputs {
    /// The inputs over a step starting at `t`: after a jump at `t`, the value after it.
    pub fn at(&self, t: f64) -> Vec<f64> {
        let after = self.rows.iter().rposition(|row| row[0] <= t).unwrap_or(0);
        let row = &self.rows[after];
        match self.rows.get(after + 1) {
            Some(next) if next[0] > row[0] => {
                let w = (t - row[0]) / (next[0] - row[0]);
                (1..row.len())
                    .map(|c| row[c] + w * (next[c] - row[c]))
                    .collect()
            }
            _ => row[1..].to_vec(),
        }
    }
}

/// A cross-check CSV: the names of its first line and its rows of numbers.
pub fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut lines = text.lines();
    let names = (lines.next().unwrap_or_default().split(','))
        .map(|name| name.trim().trim_matches('"').to_string())
        .collect();
    let rows = lines
        .filter(|line| !line.trim().is_empty())
        .map(|line| line.split(',').map(|x| x.trim().parse().unwrap()).collect())
        .collect();
    (names, rows)
}

/// One column per variable, one row per communication point: the values through
/// `fmi2DoStep` from `start` values given by name, to `stop` by `step`, with `inputs` set
/// before each step.
pub fn simulate<M: Mechanism>(
    start: &[(&str, f64)],
    stop: f64,
    step: f64,
    inputs: Option<&Inputs>,
) -> Vec<Vec<f64>> {
    let mut fmu = Harness::<M>::new();
    fmu.initialize(Some(M::EXPERIMENT.tolerance), 0.0, start)
        .unwrap_or_else(|e| panic!("{}: {e}", M::NAME));
    let mut rows = vec![fmu.all_values()];
    let steps = (stop / step).round() as usize;
    for k in 0..steps {
        let t = k as f64 * step;
        if let Some(inputs) = inputs {
            for (name, value) in inputs.names[1..].iter().zip(inputs.at(t)) {
                fmu.set(name, value);
            }
        }
        let status = fmu.do_step(t, step);
        assert_eq!(status, 0, "{}: {:?}", M::NAME, fmu.messages());
        rows.push(fmu.all_values());
    }
    rows
}

/// The largest difference of `a` and `b` over all rows, in each column relative to the
/// column's range in `a` (a constant column: to its value).
pub fn worst_relative_to_range(a: &[Vec<f64>], b: &[Vec<f64>], columns: &[usize]) -> f64 {
    let mut worst: f64 = 0.0;
    for &c in columns {
        let (lo, hi) = (a.iter()).fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), r| {
            (lo.min(r[c]), hi.max(r[c]))
        });
        // A constant column is measured relative to its value.
        let range = if hi > lo {
            hi - lo
        } else {
            hi.abs().max(1e-300)
        };
        for (ra, rb) in a.iter().zip(b) {
            // NaN is the worst difference (`max` would drop it).
            let difference = (ra[c] - rb[c]).abs() / range;
            worst = if difference.is_nan() {
                f64::INFINITY
            } else {
                worst.max(difference)
            };
        }
    }
    worst
}

/// `Hand` and `Twin` simulated from the same start values: every continuous variable at every
/// communication point, relative to its range; the worst difference is returned.
pub fn same_trajectories<Hand: Mechanism, Twin: Mechanism>(
    start: &[(&str, f64)],
    stop: f64,
    step: f64,
) -> f64 {
    let hand = simulate::<Hand>(start, stop, step, None);
    let twin = simulate::<Twin>(start, stop, step, None);
    let continuous: Vec<usize> = (Hand::VARIABLES.iter().enumerate())
        .filter(|(_, v)| v.variability == Variability::Continuous)
        .map(|(vr, _)| vr)
        .collect();
    worst_relative_to_range(&hand, &twin, &continuous)
}

/// The packaged reference results (`reference/<Name>_ref.csv`, with its inputs `_in.csv`,
/// over the default experiment's time and step) against `Hand` and `Twin` simulated at those
/// settings: `(hand's deviation, twin's deviation)`, each the worst over the reference's
/// columns relative to the column's range.
pub fn reference_case<Hand: Mechanism, Twin: Mechanism>(crate_dir: &Path) -> (f64, f64) {
    let folder = crate_dir.join("reference");
    let (header, reference) = read_csv(&folder.join(format!("{}_ref.csv", Hand::NAME)));
    let (names, rows) = read_csv(&folder.join(format!("{}_in.csv", Hand::NAME)));
    let inputs = Inputs { names, rows };
    let experiment = Hand::EXPERIMENT;
    let stop = experiment.stop - experiment.start;
    let hand = simulate::<Hand>(&[], stop, experiment.step, Some(&inputs));
    let twin = simulate::<Twin>(&[], stop, experiment.step, Some(&inputs));
    assert_eq!(
        hand.len(),
        reference.len(),
        "one row per communication point"
    );
    // The simulated rows in the reference's columns (the time is the reference's).
    let pick = |rows: &[Vec<f64>]| -> Vec<Vec<f64>> {
        rows.iter()
            .zip(&reference)
            .map(|(row, reference_row)| {
                (header.iter())
                    .map(|name| match name.as_str() {
                        "time" => reference_row[0],
                        _ => row[Harness::<Hand>::vr(name) as usize],
                    })
                    .collect()
            })
            .collect()
    };
    let columns: Vec<usize> = (1..header.len()).collect();
    (
        worst_relative_to_range(&reference, &pick(&hand), &columns),
        worst_relative_to_range(&reference, &pick(&twin), &columns),
    )
}

/// [`agreement`] at `points` random points from `seed`: every value and every derivative
/// within 1e-12 of the hand-written mechanism's.
pub fn assert_agreement<Hand, Twin>(points: usize, seed: u64)
where
    Hand: Mechanism,
    Twin: Mechanism<Values<f64> = Hand::Values<f64>, Values<Dual64> = Hand::Values<Dual64>>,
{
    let found = agreement::<Hand, Twin>(points, seed);
    println!("{found:?}");
    assert!(found.worst_value <= 1e-12, "{found:?}");
    assert!(found.worst_derivative <= 1e-12, "{found:?}");
}

/// [`reference_case`] of the mechanism in `fmus/<folder>`: the twin meets the packaged
/// reference results as closely as the hand-written mechanism does (to 1e-9).
pub fn assert_reference_case<Hand: Mechanism, Twin: Mechanism>(folder: &str) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../fmus")
        .join(folder);
    let (hand, twin) = reference_case::<Hand, Twin>(&dir);
    println!("reference: hand {hand:e}, twin {twin:e}");
    assert!(twin <= hand + 1e-9, "hand {hand:e}, twin {twin:e}");
}

/// [`same_trajectories`] from `start` to `stop` by `step`: within 1e-9 of each variable's range.
pub fn assert_same_trajectories<Hand: Mechanism, Twin: Mechanism>(
    start: &[(&str, f64)],
    stop: f64,
    step: f64,
) {
    let worst = same_trajectories::<Hand, Twin>(start, stop, step);
    println!("trajectories: {worst:e}");
    assert!(worst <= 1e-9, "{worst:e}");
}

/// What `mechfmu bench --energies` counts: a run of [`PROBE_STEPS`] `fmi2DoStep` of
/// 0.01 s at tolerance 1e-6 from the start values, or [`PROBE_STEPS`] Model Exchange
/// evaluations (`fmi2SetTime`, `fmi2SetContinuousStates`, `fmi2GetDerivatives`) at states
/// near the start, of the hand-written mechanism or of its twin, repeated.
pub const PROBE_STEPS: usize = 1000;

/// The probe `mechfmu bench --energies` runs under valgrind, from each test file's ignored
/// `probe` test, as the environment says: `MECHFMU_ENERGIES_PROBE` (`step` or `me`),
/// `MECHFMU_ENERGIES_TWIN` (`1`: the twin) and `MECHFMU_ENERGIES_REPEAT` (how many runs).
pub fn probe<Hand: Mechanism, Twin: Mechanism>() {
    let setting = |name: &str| std::env::var(name).unwrap_or_default();
    let repeat: usize = setting("MECHFMU_ENERGIES_REPEAT").parse().unwrap_or(1);
    let twin = setting("MECHFMU_ENERGIES_TWIN") == "1";
    let run = match (setting("MECHFMU_ENERGIES_PROBE").as_str(), twin) {
        ("step", false) => probe_steps::<Hand>,
        ("step", true) => probe_steps::<Twin>,
        ("me", false) => probe_model_exchange::<Hand>,
        ("me", true) => probe_model_exchange::<Twin>,
        (other, _) => panic!("MECHFMU_ENERGIES_PROBE = `{other}`: expected `step` or `me`"),
    };
    for _ in 0..repeat {
        run();
    }
}

fn probe_steps<M: Mechanism>() {
    let mut fmu = Harness::<M>::new();
    fmu.initialize(Some(1e-6), 0.0, &[])
        .unwrap_or_else(|e| panic!("{}: {e}", M::NAME));
    for k in 0..PROBE_STEPS {
        assert_eq!(fmu.do_step(k as f64 * 0.01, 0.01), 0, "{}", M::NAME);
    }
}

fn probe_model_exchange<M: Mechanism>() {
    let mut fmu = mechfmu_testkit::model_exchange::ModelExchange::<M>::new();
    fmu.initialize(Some(1e-6), 0.0, &[])
        .unwrap_or_else(|e| panic!("{}: {e}", M::NAME));
    let start = fmu.states().expect("the start states");
    let (mut x, mut dx) = (start.clone(), vec![0.0; start.len()]);
    for k in 0..PROBE_STEPS {
        for (i, (x, x0)) in x.iter_mut().zip(&start).enumerate() {
            *x = x0 + 1e-3 * ((k * (i + 1)) % 17) as f64;
        }
        assert_eq!(fmu.set_time(k as f64 * 1e-3), 0);
        assert_eq!(fmu.set_states(&x), 0);
        assert_eq!(fmu.derivatives_into(&mut dx), 0, "{}", M::NAME);
    }
}
