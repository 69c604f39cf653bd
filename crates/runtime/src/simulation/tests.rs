//! The split between `Mechanism::evaluate` (every solver stage) and `Mechanism::outputs`
//! (only where values become visible): every output the importer can read is that of a
//! complete evaluation at the point, and the stages never pay for the outputs.

use std::cell::Cell;

use super::{Simulation, StepFailure};
use crate::model::{evaluate_all, Experiment, Layout, Mechanism, Monitor, Scalar, SetPhase};
use crate::model::{Declaration, ValueSet, Variable};

thread_local! {
    /// Calls of `Split::evaluate` and `Split::outputs` on `f64` in this test's thread.
    static EVALUATE: Cell<u64> = const { Cell::new(0) };
    static OUTPUTS: Cell<u64> = const { Cell::new(0) };
}

crate::mechanism! {
    /// A driven, damped mass on a spring whose energy and power are derivative-free outputs.
    pub struct Split / SplitValues {
        /// Mass
        m: Variable::parameter("kg", 2.0).positive(),
        /// Stiffness
        k: Variable::tunable("N/m", 30.0).min(0.0),
        /// Damping
        c: Variable::parameter("N.s/m", 0.5).min(0.0),
        /// The monitor stops the model after this time
        t_stop: Variable::parameter("s", 1e9),
        /// Applied force
        F: Variable::input("N", 1.0),
        /// Position
        x: Variable::state("m", 0.5, "v"),
        /// Velocity
        v: Variable::state("m/s", 0.0, "a"),
        /// Acceleration
        a: Variable::output("m/s2"),
        /// Energy (spring and mass)
        E: Variable::output("J"),
        /// Power of the force
        P: Variable::output("W"),
    }
}

impl Mechanism for Split {
    const EXPERIMENT: Experiment = Experiment::until(10.0).step(0.01).tolerance(1e-6);

    fn evaluate<S: Scalar>(v: &mut SplitValues<S>) {
        if std::any::TypeId::of::<S>() == std::any::TypeId::of::<f64>() {
            EVALUATE.with(|n| n.set(n.get() + 1));
        }
        v.a = (v.F - v.k * v.x - v.c * v.v) / v.m;
    }

    fn outputs<S: Scalar>(v: &mut SplitValues<S>) {
        if std::any::TypeId::of::<S>() == std::any::TypeId::of::<f64>() {
            OUTPUTS.with(|n| n.set(n.get() + 1));
        }
        let half = crate::model::lit::<S>(0.5);
        v.E = half * v.m * v.v * v.v + half * v.k * v.x * v.x;
        v.P = v.F * v.v;
    }

    const MONITORED: bool = true;

    fn monitor(v: &SplitValues<f64>) -> Monitor {
        if v.time > v.t_stop {
            Monitor::Invalid("past t_stop".into())
        } else {
            Monitor::Valid
        }
    }
}

fn calls() -> (u64, u64) {
    (EVALUATE.with(Cell::get), OUTPUTS.with(Cell::get))
}

const F: u32 = 4;
const K: u32 = 1;
const T_STOP: u32 = 3;

fn started(params: &[(u32, f64)]) -> Simulation<Split> {
    let mut sim = Simulation::<Split>::new(Layout::new(Split::VARIABLES).unwrap());
    sim.setup(None, 0.0).unwrap();
    for &(vr, x) in params {
        sim.set_real(&[vr], &[x], SetPhase::Initialization).unwrap();
    }
    sim.update().unwrap();
    sim
}

/// Every value the importer can read, through `get_real`.
fn visible(sim: &mut Simulation<Split>) -> Vec<f64> {
    let vrs: Vec<u32> = (0..Split::VARIABLES.len() as u32).collect();
    let mut out = vec![0.0; vrs.len()];
    sim.get_real(&vrs, &mut out).unwrap();
    out.push(sim.time());
    out
}

/// Every value after a complete evaluation from the states, inputs and parameters alone.
fn complete(sim: &Simulation<Split>) -> Vec<f64> {
    let mut values = *sim.values();
    (values.a, values.E, values.P) = (f64::NAN, f64::NAN, f64::NAN);
    evaluate_all::<Split, f64>(&mut values);
    (0..Split::VARIABLES.len())
        .map(|vr| values.get(vr).unwrap())
        .chain([values.time])
        .collect()
}

fn assert_complete(sim: &mut Simulation<Split>, when: &str) {
    let seen = visible(sim);
    let expected = complete(sim);
    assert_eq!(
        seen.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
        expected.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
        "{when}: {seen:?} != {expected:?}"
    );
}

#[test]
fn outputs_are_those_of_a_complete_evaluation_wherever_they_are_visible() {
    let mut sim = started(&[]);
    assert_complete(&mut sim, "after initialization");
    let h = 0.01;
    for i in 0..20 {
        sim.step(i as f64 * h, h).unwrap();
        assert_complete(&mut sim, "after a step");
    }
    // A new input: get_real right after it, and a step from it.
    sim.set_real(&[F], &[-3.0], SetPhase::Running).unwrap();
    assert_complete(&mut sim, "after setting an input");
    sim.step(sim.time(), h).unwrap();
    assert_complete(&mut sim, "after a step from a new input");
    // A tunable parameter.
    sim.set_real(&[K], &[45.0], SetPhase::Running).unwrap();
    assert_complete(&mut sim, "after setting a parameter");
    // An input with derivatives: the input moves over the step.
    sim.set_real(&[F], &[2.0], SetPhase::Running).unwrap();
    sim.set_input_derivatives(&[F], &[1], &[5.0]).unwrap();
    sim.step(sim.time(), h).unwrap();
    assert_complete(&mut sim, "after a step with input derivatives");
    // A saved state restored after the simulation moved on.
    let saved = sim.save();
    let at_save = visible(&mut sim);
    for _ in 0..5 {
        sim.step(sim.time(), h).unwrap();
    }
    sim.restore(&saved).unwrap();
    assert_complete(&mut sim, "after restoring a state");
    assert_eq!(visible(&mut sim), at_save);
    // A state saved right after setting an input (outputs stale when saved).
    sim.set_real(&[F], &[7.0], SetPhase::Running).unwrap();
    let saved = sim.save();
    sim.step(sim.time(), h).unwrap();
    sim.restore(&saved).unwrap();
    assert_complete(&mut sim, "after restoring a state saved with a new input");
}

#[test]
fn outputs_are_complete_after_a_discarded_step() {
    // The monitor stops the model inside the step: the values are those of the last
    // valid point, outputs included.
    let mut sim = started(&[(T_STOP, 0.0123)]);
    sim.step(0.0, 0.01).unwrap();
    let failure = sim.step(0.01, 0.01).unwrap_err();
    let StepFailure::Stopped { time, .. } = failure else {
        panic!("{failure:?}")
    };
    assert!((0.01..0.02).contains(&time), "{time}");
    assert_eq!(sim.time(), time);
    assert_complete(&mut sim, "after a discarded step");
}

#[test]
fn solver_stages_do_not_compute_the_outputs() {
    let mut sim = started(&[]);
    let h = 0.01;
    for i in 0..10 {
        let (evaluations, outputs) = calls();
        let before = sim.counters().evaluations;
        sim.step(i as f64 * h, h).unwrap();
        let (evaluations_after, outputs_after) = calls();
        // Several stages, one evaluation of the outputs (at the communication point).
        assert_eq!(
            evaluations_after - evaluations,
            sim.counters().evaluations - before
        );
        assert!(evaluations_after - evaluations >= 5, "{evaluations_after}");
        assert_eq!(outputs_after - outputs, 1);
    }
    // Reading values already up to date evaluates nothing.
    let (e, o) = calls();
    visible(&mut sim);
    assert_eq!(calls(), (e, o));
    // An input changed: one complete evaluation when read.
    sim.set_real(&[F], &[0.25], SetPhase::Running).unwrap();
    visible(&mut sim);
    visible(&mut sim);
    assert_eq!(calls(), (e + 1, o + 1));
}

#[test]
fn derivatives_of_outputs_come_from_outputs() {
    // d E / d v = m v, d P / d F = v: the dual numbers run through `outputs` too.
    let mut sim = started(&[]);
    sim.step(0.0, 0.05).unwrap();
    let (m, v) = (sim.values().m, sim.values().v);
    assert!(v != 0.0);
    let (v_vr, a_vr, e_vr, p_vr) = (6, 7, 8, 9);
    let mut d = [0.0; 3];
    sim.directional_derivative(&[a_vr, e_vr, p_vr], &[v_vr], &[1.0], 0.0, &mut d)
        .unwrap();
    assert_eq!(d[1], m * v);
    let mut d = [0.0; 3];
    sim.directional_derivative(&[a_vr, e_vr, p_vr], &[F], &[1.0], 0.0, &mut d)
        .unwrap();
    assert_eq!(d, [1.0 / m, 0.0, v]);
    let mut rate = [0.0];
    sim.output_derivatives(&[e_vr], &[1], &mut rate).unwrap();
    let w = *sim.values();
    let expected = w.m * w.v * w.a + w.k * w.x * w.v;
    assert!(
        (rate[0] - expected).abs() <= 1e-12 * expected.abs(),
        "{rate:?} {expected}"
    );
}

#[test]
fn the_remembered_answer_to_whether_inputs_are_held_is_always_the_fresh_one() {
    // After every kind of call, the remembered answer is the one computed afresh.
    fn check(sim: &mut Simulation<Split>, when: &str) {
        let remembered = sim.inputs_held();
        let mut fresh = sim.clone();
        fresh.held = None;
        assert_eq!(remembered, fresh.inputs_held(), "{when}");
    }
    let mut sim = started(&[]);
    let h = 0.01;
    check(&mut sim, "after initialization");
    sim.step(0.0, h).unwrap();
    check(&mut sim, "after a step with a held input");
    let saved = sim.save();
    sim.set_input_derivatives(&[F], &[1], &[5.0]).unwrap();
    check(&mut sim, "after setting an input derivative");
    assert!(!sim.inputs_held());
    let moving = sim.save();
    let f = sim.values().F;
    sim.step(sim.time(), h).unwrap();
    assert_eq!(sim.values().F, f + 5.0 * h, "the input moved over the step");
    check(&mut sim, "after a step with a moving input");
    sim.set_real(&[F], &[-0.0], SetPhase::Running).unwrap();
    check(&mut sim, "after setting an input to -0");
    sim.set_real(&[F], &[3.0], SetPhase::Running).unwrap();
    check(&mut sim, "after setting an input");
    assert!(sim.inputs_held());
    sim.step(sim.time(), h).unwrap();
    assert_eq!(sim.values().F, 3.0);
    sim.restore(&moving).unwrap();
    check(&mut sim, "after restoring a state with a moving input");
    sim.step(sim.time(), h).unwrap();
    sim.restore(&saved).unwrap();
    check(&mut sim, "after restoring a state");
    sim.set_input_derivatives(&[F], &[2], &[1.0]).unwrap();
    sim.step(sim.time(), h).unwrap();
    sim.reset();
    check(&mut sim, "after a reset");
}

/// One step of `h`: the model evaluations it made, and the stages of its attempts (6 per
/// Dopri5 attempt, 12 per Dop853 one).
fn counted_step(sim: &mut Simulation<Split>, h: f64) -> (u64, u64) {
    let per_attempt = if sim.solver.high_order(h) { 12 } else { 6 };
    let (evaluations, _) = calls();
    let stats = sim.step(sim.time(), h).unwrap();
    let stages = per_attempt * (stats.accepted + stats.rejected);
    (calls().0 - evaluations, stages)
}

#[test]
fn a_step_starts_from_the_evaluation_the_last_one_ended_with() {
    // FSAL across communication steps: the first stage of a step is the evaluation at the
    // end of the previous one, so a step costs its stages only; the stages themselves never
    // skip an evaluation.
    let mut sim = started(&[]);
    let h = 0.01;
    sim.step(0.0, h).unwrap();
    for _ in 0..20 {
        let (evaluations, stages) = counted_step(&mut sim, h);
        assert_eq!(evaluations, stages);
    }
    // Something set in between: the start is evaluated again, once.
    sim.set_real(&[F], &[0.5], SetPhase::Running).unwrap();
    let (evaluations, stages) = counted_step(&mut sim, h);
    assert_eq!(evaluations, stages + 1);
}

#[test]
fn a_system_at_rest_reuses_its_last_stage_at_the_new_point() {
    // At rest every stage is the same point, the new point too: its evaluation is the last
    // stage's (one fewer per attempt, and one attempt per step here); the answer is the same.
    const X: u32 = 5;
    let mut sim = started(&[(F, 0.0), (X, 0.0)]);
    let h = 0.01;
    sim.step(0.0, h).unwrap();
    for _ in 0..5 {
        let (evaluations, stages) = counted_step(&mut sim, h);
        assert!(stages == 6 || stages == 12, "{stages}");
        assert_eq!(evaluations, stages - 1);
        assert_eq!((sim.values().x, sim.values().v), (0.0, 0.0));
    }
}

#[test]
fn a_step_refuses_arguments_it_cannot_do_and_changes_nothing() {
    let rejected = |sim: &mut Simulation<Split>, t: f64, h: f64, why: &str| {
        let before = visible(sim);
        match sim.step(t, h) {
            Err(StepFailure::Rejected(message)) => assert!(
                message.contains(why),
                "step({t:e}, {h:e}): {message:?} does not say {why:?}"
            ),
            other => panic!("step({t:e}, {h:e}) was not refused: {other:?}"),
        }
        assert_eq!(
            visible(sim),
            before,
            "step({t:e}, {h:e}) changed the values"
        );
    };
    let mut sim = started(&[]);
    for h in [
        f64::NAN,
        f64::INFINITY,
        f64::NEG_INFINITY,
        0.0,
        -0.0,
        -1e-3,
        -5e-324,
    ] {
        rejected(&mut sim, 0.0, h, "must be a finite number > 0");
    }
    for t in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 1e-3, -1e-3] {
        rejected(&mut sim, t, 1e-3, "does not match the FMU's time");
    }
    // Within 1e-9 of the step (or of the time) counts as the FMU's time.
    sim.step(0.0, 1e-3).unwrap();
    sim.step(1e-3 + 1e-13, 1e-3).unwrap();
    assert_eq!(sim.time(), 2e-3 + 1e-13);
    // A step that rounds away at this time, or overflows it.
    let mut far = started(&[]);
    far.setup(None, 1e6).unwrap();
    far.update().unwrap();
    rejected(&mut far, 1e6, 1e-20, "too small to advance");
    let mut last = started(&[]);
    last.setup(None, 1.5e308).unwrap();
    last.update().unwrap();
    rejected(&mut last, 1.5e308, 1e308, "too small to advance");
    // The smallest step there is still advances from 0.
    let mut tiny = started(&[]);
    tiny.step(0.0, 5e-324).unwrap();
    assert_eq!(tiny.time(), 5e-324);
}

#[test]
fn every_non_finite_continuous_variable_is_found_and_no_finite_one() {
    let mut sim = started(&[]);
    sim.step(0.0, 0.01).unwrap();
    assert_eq!(sim.first_non_finite(Split::CONTINUOUS), None);
    let good = sim.values;
    for extreme in [f64::MAX, -f64::MAX, f64::MIN_POSITIVE, 5e-324, -0.0] {
        for &vr in Split::CONTINUOUS {
            sim.values = good;
            sim.values.set(vr, extreme);
            assert_eq!(
                sim.first_non_finite(Split::CONTINUOUS),
                None,
                "vr {vr} = {extreme:e}"
            );
        }
    }
    for bad in [f64::NAN, -f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
        for &vr in Split::CONTINUOUS {
            sim.values = good;
            sim.values.set(vr, bad);
            let name = Split::VARIABLES[vr].name;
            assert_eq!(
                sim.first_non_finite(Split::CONTINUOUS),
                Some(name),
                "{name} = {bad}"
            );
        }
    }
    // A fixed parameter is not checked after a step (it cannot change during one).
    sim.values = good;
    sim.values.set(0, f64::NAN);
    assert_eq!(sim.first_non_finite(Split::CONTINUOUS), None);
}

#[test]
fn after_a_step_the_solver_leaves_only_the_other_continuous_variables_to_check() {
    // x, v are states, a is v's derivative (x's is v): the input F and the outputs E, P
    // are what the solver does not check.
    let names = |vrs: &[usize]| {
        vrs.iter()
            .map(|&vr| Split::VARIABLES[vr].name)
            .collect::<Vec<_>>()
    };
    assert_eq!(names(Split::CONTINUOUS), ["F", "x", "v", "a", "E", "P"]);
    assert_eq!(names(Split::CONTINUOUS_UNCHECKED), ["F", "E", "P"]);
}

crate::mechanism! {
    /// x decreasing linearly to 0 at t_end, with an output that has a pole at t_pole.
    pub struct Cliff / CliffValues {
        /// When x reaches 0 (where its derivative, as computed, is 0/0)
        t_end: Variable::parameter("s", 1e9),
        /// Where the output has its pole
        t_pole: Variable::parameter("s", 1e9),
        /// Position
        x: Variable::state("m", 1.0, "v"),
        /// Velocity
        v: Variable::output("m/s"),
        /// Infinite at t_pole
        y: Variable::output("1/s"),
    }
}

impl Mechanism for Cliff {
    const EXPERIMENT: Experiment = Experiment::until(1.0).step(0.1).tolerance(1e-6);

    fn evaluate<S: Scalar>(v: &mut CliffValues<S>) {
        // x(t) = (t_end - t) / t_end, from x(0) = 1, written so that it fails at t_end.
        v.v = -v.x / (v.t_end - v.time);
    }

    fn outputs<S: Scalar>(v: &mut CliffValues<S>) {
        v.y = v.x / (v.t_pole - v.time);
    }
}

fn cliff(t_end: f64, t_pole: f64) -> Simulation<Cliff> {
    let mut sim = Simulation::<Cliff>::new(Layout::new(Cliff::VARIABLES).unwrap());
    sim.setup(None, 0.0).unwrap();
    sim.set_real(&[0, 1], &[t_end, t_pole], SetPhase::Initialization)
        .unwrap();
    sim.update().unwrap();
    sim
}

/// The step checks only what the solver does not (`Declaration::CONTINUOUS_UNCHECKED`):
/// a state's derivative that is not a number at the step's end point must fail the step
/// in the solver, and an output that is not one must fail it in the step.
#[test]
fn a_step_never_ends_on_a_derivative_or_an_output_that_is_not_a_number() {
    for (t_end, t_pole, stopped_in_solver) in [(0.5, 1e9, true), (1e9, 0.5, false)] {
        let mut sim = cliff(t_end, t_pole);
        let h = 0.1;
        for i in 0..4 {
            sim.step(i as f64 * h, h).unwrap();
        }
        let at = sim.time();
        let before = *sim.values();
        let failure = sim.step(at, h).unwrap_err();
        let StepFailure::Stopped { time, message, .. } = failure else {
            panic!("{failure:?}")
        };
        let values = *sim.values();
        let finite = (0..Cliff::VARIABLES.len()).all(|vr| values.get(vr).unwrap().is_finite());
        assert!(finite, "{message}: {values:?}");
        if stopped_in_solver {
            // Stopped just short of t_end, on the straight line x = (t_end - t) / t_end,
            // naming the derivative that gave no number.
            assert!(time > at && time < t_end, "{time}: {message}");
            assert!(message.contains(": `v` evaluated to "), "{message}");
            assert!(
                (values.x - (t_end - time) / t_end).abs() < 1e-9,
                "{values:?}"
            );
            assert_eq!(values.v.to_bits(), (-values.x / (t_end - time)).to_bits());
        } else {
            // The solver reached t = 0.5; the output's pole there undid the step.
            assert!(message.contains("`y` became non-finite"), "{message}");
            assert_eq!((time, sim.time()), (at, at));
            assert_eq!(format!("{values:?}"), format!("{before:?}"));
        }
    }
}

/// `mechfmu bench` times the solver's calls isolated from each other to tell the
/// plumbing's own instructions from the overlap they cost: the isolated loop must run the
/// very steps of the back-to-back one, on a copy, and the codes the benchmark sends must
/// name the parts the FMU runs.
#[test]
fn the_isolated_solver_loop_integrates_what_the_back_to_back_one_does() {
    use super::{Part, ISOLATES};
    for part in [
        Part::Evaluate,
        Part::Rhs,
        Part::Step,
        Part::Integrate,
        Part::Point,
        Part::ModelExchange,
    ] {
        assert_eq!(Part::from_code(part as u32), Some(part));
    }
    assert_eq!(
        Part::from_code(Part::IntegrateIsolated as u32),
        ISOLATES.then_some(Part::IntegrateIsolated)
    );
    assert_eq!(Part::from_code(Part::IntegrateIsolated as u32 + 1), None);

    let mut sim = started(&[]);
    let before = visible(&mut sim);
    let back_to_back = sim.bench(Part::Integrate, 50, 0.01).unwrap();
    let isolated = sim.bench(Part::IntegrateIsolated, 50, 0.01).unwrap();
    assert_eq!(back_to_back.to_bits(), isolated.to_bits());
    // The checksum is x after the 50 steps: it moved from x(0) = 0.5, as a step does.
    let mut stepped = started(&[]);
    let mut t = 0.0;
    for _ in 0..50 {
        stepped.step(t, 0.01).unwrap();
        t += 0.01;
    }
    let x = stepped.values().get(5).unwrap();
    assert_eq!(
        isolated.to_bits(),
        x.to_bits(),
        "{isolated} != x(0.5) = {x}"
    );
    assert_ne!(x, 0.5);
    assert_eq!(visible(&mut sim), before, "the part ran on a copy");
}
