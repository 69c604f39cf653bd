//! Checks every mechanism must pass whatever its physics, through its real FMI functions:
//! reset, FMU state and its serialized form, directional and output derivatives,
//! independent instances in threads, Model Exchange ([`model_exchange`]) and FMI 3.0
//! against FMI 2.0 ([`fmi3`]). A mechanism crate runs them all with
//! `mechfmu_testkit::conformance::check::<M>()` in one of its tests.

pub mod fmi3;
pub mod model_exchange;

use crate::harness::Harness;
use mechfmu::fmi2::ffi::*;
use mechfmu::model::{evaluate_all, Causality, Layout, Mechanism, ValueSet, Variability};

/// Runs every check; panics with a message naming the first that fails.
pub fn check<M: Mechanism>() {
    reset_equals_a_fresh_instance::<M>();
    rollback_continues_bit_for_bit::<M>();
    serialized_state_continues_bit_for_bit::<M>();
    malformed_serialized_states_are_refused::<M>();
    directional_derivatives_match_finite_differences::<M>();
    output_derivatives_match_finite_differences::<M>();
    threads_match_sequential_runs::<M>();
    model_exchange::check::<M>();
    fmi3::check::<M>();
}

fn layout<M: Mechanism>() -> Layout {
    Layout::new(M::VARIABLES).expect("a valid declaration")
}

/// An instance initialized at the default experiment's start and tolerance.
fn started<M: Mechanism>() -> Harness<M> {
    started_with::<M>(&[])
}

/// An instance initialized at the default experiment's start and tolerance, with these start
/// values.
fn started_with<M: Mechanism>(start: &[(&str, f64)]) -> Harness<M> {
    let mut fmu = Harness::<M>::new();
    let e = M::EXPERIMENT;
    fmu.initialize(Some(e.tolerance), e.start, start)
        .unwrap_or_else(|m| panic!("{}: {m}", M::NAME));
    fmu
}

fn run<M: Mechanism>(fmu: &mut Harness<M>, until_fraction: f64) {
    let e = M::EXPERIMENT;
    let t = e.start + until_fraction * (e.stop - e.start);
    fmu.step_to(t, e.step)
        .unwrap_or_else(|m| panic!("{}: {m}", M::NAME));
}

fn bits(values: &[f64]) -> Vec<u64> {
    values.iter().map(|x| x.to_bits()).collect()
}

pub fn reset_equals_a_fresh_instance<M: Mechanism>() {
    let mut reused = started::<M>();
    run(&mut reused, 0.3);
    // Change every tunable parameter and input a little, as a sweep would.
    for (vr, v) in M::VARIABLES.iter().enumerate() {
        if v.causality == Causality::Input
            || v.variability == Variability::Tunable && v.causality == Causality::Parameter
        {
            let x = reused.all_values()[vr];
            reused.set_real(&[vr as u32], &[x * 1.01 + 1e-3]);
        }
    }
    run(&mut reused, 0.4);
    assert_eq!(reused.reset(), fmi2OK, "{}: fmi2Reset", M::NAME);
    let e = M::EXPERIMENT;
    reused
        .initialize(Some(e.tolerance), e.start, &[])
        .expect("initialize after reset");
    let mut fresh = started::<M>();
    assert_eq!(
        bits(&reused.all_values()),
        bits(&fresh.all_values()),
        "{}: after reset, values differ from a fresh instance",
        M::NAME
    );
    run(&mut reused, 0.5);
    run(&mut fresh, 0.5);
    assert_eq!(
        bits(&reused.all_values()),
        bits(&fresh.all_values()),
        "{}: a reset instance runs differently from a fresh one",
        M::NAME
    );
}

pub fn rollback_continues_bit_for_bit<M: Mechanism>() {
    let mut fmu = started::<M>();
    run(&mut fmu, 0.2);
    let state = fmu.get_fmu_state().expect("fmi2GetFMUstate");
    let t1 = fmu.time();
    run(&mut fmu, 0.4);
    let first = bits(&fmu.all_values());
    assert_eq!(
        fmu.set_fmu_state(state),
        fmi2OK,
        "{}: fmi2SetFMUstate",
        M::NAME
    );
    // The harness's own clock must go back too.
    fmu.rewind(t1);
    run(&mut fmu, 0.4);
    assert_eq!(
        bits(&fmu.all_values()),
        first,
        "{}: a rolled-back run differs",
        M::NAME
    );
    assert_eq!(fmu.free_fmu_state(state), fmi2OK);
}

pub fn serialized_state_continues_bit_for_bit<M: Mechanism>() {
    let mut fmu = started::<M>();
    run(&mut fmu, 0.2);
    let t1 = fmu.time();
    let state = fmu.get_fmu_state().expect("fmi2GetFMUstate");
    let bytes = fmu.serialize(state).expect("serialize");
    fmu.free_fmu_state(state);
    run(&mut fmu, 0.4);
    let first = bits(&fmu.all_values());

    let mut other = Harness::<M>::new();
    let restored = other.deserialize(&bytes).expect("deserialize");
    assert_eq!(other.set_fmu_state(restored), fmi2OK);
    assert_eq!(
        other.serialize(restored).expect("serialize again"),
        bytes,
        "{}: serialization is not stable",
        M::NAME
    );
    other.free_fmu_state(restored);
    other.rewind(t1);
    run(&mut other, 0.4);
    assert_eq!(
        bits(&other.all_values()),
        first,
        "{}: a deserialized state runs differently",
        M::NAME
    );
}

pub fn malformed_serialized_states_are_refused<M: Mechanism>() {
    let mut fmu = started::<M>();
    run(&mut fmu, 0.1);
    let state = fmu.get_fmu_state().expect("fmi2GetFMUstate");
    let bytes = fmu.serialize(state).expect("serialize");
    fmu.free_fmu_state(state);
    let mut refuse = |bytes: &[u8], what: &str| {
        let before = fmu.messages().len();
        assert_eq!(
            fmu.deserialize(bytes),
            Err(fmi2Error),
            "{}: {what} was accepted",
            M::NAME
        );
        assert!(
            fmu.messages().len() > before,
            "{}: {what} refused without a message",
            M::NAME
        );
    };
    refuse(&[], "an empty buffer");
    refuse(b"garbage garbage garbage garbage", "garbage");
    for cut in [1, 8, 12, bytes.len() / 2, bytes.len() - 1] {
        refuse(&bytes[..cut], "a truncated state");
    }
    for i in (0..bytes.len()).step_by(7) {
        let mut corrupt = bytes.clone();
        corrupt[i] ^= 0x10;
        refuse(&corrupt, "a corrupted state");
    }
    let mut longer = bytes.clone();
    longer.push(0);
    refuse(&longer, "a state with trailing bytes");
    let mut version = bytes.clone();
    version[8] = version[8].wrapping_add(1);
    refuse(&version, "another format version");
    assert!(
        fmu.messages()
            .iter()
            .any(|m| m.2.contains("format version")),
        "{}: no message names the version",
        M::NAME
    );
}

/// Relative step for central differences, and the allowed disagreement.
const FD_STEP: f64 = 1e-6;

pub fn directional_derivatives_match_finite_differences<M: Mechanism>() {
    directional_derivatives_at::<M>(started::<M>(), &[0.0, 0.15, 0.35]);
}

/// [`directional_derivatives_match_finite_differences`] at another operating point: the one
/// these start values (of states, inputs and parameters) give at initialization, for a
/// mechanism whose default experiment leaves terms of its equations at zero (e.g. at rest).
/// Returns the largest disagreement found relative to the one allowed (below 1; 0 only if
/// every central difference equals its derivative exactly).
pub fn directional_derivatives_match_finite_differences_at<M: Mechanism>(
    start: &[(&str, f64)],
) -> f64 {
    directional_derivatives_at::<M>(started_with::<M>(start), &[0.0])
}

/// The directional derivatives of `fmu` against central differences at each fraction of the
/// default experiment it is run to; the largest disagreement relative to the allowed one.
fn directional_derivatives_at<M: Mechanism>(mut fmu: Harness<M>, fractions: &[f64]) -> f64 {
    let layout = layout::<M>();
    let knowns: Vec<usize> = layout
        .states
        .iter()
        .chain(&layout.inputs)
        .copied()
        .collect();
    let unknowns: Vec<usize> = M::VARIABLES
        .iter()
        .enumerate()
        .filter(|(_, v)| {
            v.variability == Variability::Continuous && v.causality != Causality::Input
        })
        .map(|(vr, _)| vr)
        .collect();
    let unknown_vrs: Vec<u32> = unknowns.iter().map(|&v| v as u32).collect();
    let mut worst = 0.0f64;
    for &fraction in fractions {
        run(&mut fmu, fraction);
        let values = fmu.all_values();
        let mut point = M::zeros::<f64>();
        for (vr, &x) in values.iter().enumerate() {
            point.set(vr, x);
        }
        point.set_time(fmu.time());
        let evaluate = |known: usize, dx: f64| {
            let mut p = point.clone();
            p.set(known, values[known] + dx);
            evaluate_all::<M, f64>(&mut p);
            unknowns
                .iter()
                .map(|&u| p.get(u).unwrap_or(f64::NAN))
                .collect::<Vec<f64>>()
        };
        for &known in &knowns {
            let mut ad = vec![0.0; unknowns.len()];
            assert_eq!(
                fmu.directional_derivative(&unknown_vrs, &[known as u32], &[1.0], &mut ad),
                fmi2OK,
                "{:?}",
                fmu.messages()
            );
            let h = FD_STEP * values[known].abs().max(1.0);
            let (plus, minus, center) = (
                evaluate(known, h),
                evaluate(known, -h),
                evaluate(known, 0.0),
            );
            for (i, &u) in unknowns.iter().enumerate() {
                let fd = (plus[i] - minus[i]) / (2.0 * h);
                // Rounding in f(x ± h) is about 1e-16 |f|, i.e. 1e-16 |f| / h in the quotient.
                let noise = 1e-14 * (1.0 + center[i].abs()) / h;
                let allowed = 1e-6 * ad[i].abs().max(fd.abs()) + noise;
                worst = worst.max((ad[i] - fd).abs() / allowed);
                assert!(
                    (ad[i] - fd).abs() <= allowed,
                    "{}: d {} / d {} at t = {}: automatic {} but central differences {}",
                    M::NAME,
                    M::VARIABLES[u].name,
                    M::VARIABLES[known].name,
                    fmu.time(),
                    ad[i],
                    fd
                );
            }
        }
    }
    // Parameters are not knowns.
    if let Some(p) = layout.parameters.first() {
        let mut out = [0.0];
        assert_eq!(
            fmu.directional_derivative(&unknown_vrs[..1], &[*p as u32], &[1.0], &mut out),
            fmi2Error
        );
    }
    worst
}

pub fn output_derivatives_match_finite_differences<M: Mechanism>() {
    let layout = layout::<M>();
    let outputs: Vec<u32> = layout.outputs.iter().map(|&v| v as u32).collect();
    let orders = vec![1; outputs.len()];
    let mut fmu = Harness::<M>::new();
    let e = M::EXPERIMENT;
    fmu.initialize(Some(1e-12), e.start, &[])
        .expect("initialize");
    run(&mut fmu, 0.2);
    let dt = 1e-4 * (e.stop - e.start).abs().max(1.0) / 20.0;
    let before = fmu.all_values();
    let t = fmu.time();
    assert_eq!(fmu.do_step(t, dt), fmi2OK);
    let mut exact = vec![0.0; outputs.len()];
    assert_eq!(
        fmu.output_derivatives(&outputs, &orders, &mut exact),
        fmi2OK,
        "{:?}",
        fmu.messages()
    );
    let middle = fmu.all_values();
    assert_eq!(fmu.do_step(t + dt, dt), fmi2OK);
    let after = fmu.all_values();
    for (i, &vr) in outputs.iter().enumerate() {
        let vr = vr as usize;
        let fd = (after[vr] - before[vr]) / (2.0 * dt);
        // The solver's error (tolerance 1e-12) divided by the difference step.
        let noise = 1e-11 * middle[vr].abs().max(1.0) / dt;
        assert!(
            (exact[i] - fd).abs() <= 1e-5 * exact[i].abs().max(fd.abs()) + noise,
            "{}: d{}/dt: exact {} but central differences {}",
            M::NAME,
            M::VARIABLES[vr].name,
            exact[i],
            fd
        );
    }
    assert_eq!(
        fmu.output_derivatives(&outputs[..1], &[2], &mut exact[..1]),
        fmi2Error,
        "order 2 is not declared"
    );
}

pub fn threads_match_sequential_runs<M: Mechanism>() {
    let run_one = |i: usize| {
        let mut fmu = Harness::<M>::new();
        let e = M::EXPERIMENT;
        fmu.initialize(Some(e.tolerance * (1.0 + i as f64)), e.start, &[])
            .expect("initialize");
        run(&mut fmu, 0.25);
        bits(&fmu.all_values())
    };
    let sequential: Vec<Vec<u64>> = (0..8).map(run_one).collect();
    let parallel: Vec<Vec<u64>> = std::thread::scope(|s| {
        let handles: Vec<_> = (0..8).map(|i| s.spawn(move || run_one(i))).collect();
        handles
            .into_iter()
            .map(|h| h.join().expect("thread"))
            .collect()
    });
    assert_eq!(
        sequential,
        parallel,
        "{}: instances in threads differ from sequential runs",
        M::NAME
    );
}
