//! What every mechanism's FMI 3.0 interface must do, whatever its physics: be FMI 2.0's
//! simulation seen through FMI 3.0's functions. Co-Simulation and Model Exchange give FMI
//! 2.0's values bit for bit, and so do directional and output derivatives; adjoint
//! derivatives are the transpose of the directional Jacobian ([`derivatives`]); arrays are
//! their scalars ([`arrays`]); FMU states and the state machine behave as the standard has them
//! ([`calls`]); the functions not offered refuse with a message ([`unsupported`]).

pub mod arrays;
pub mod calls;
pub mod derivatives;
pub mod unsupported;

use crate::fmi3::Fmi3Harness;
use crate::harness::Harness;
use crate::model_exchange::ModelExchange;
use mechfmu::fmi2::ffi::{fmi2OK, fmi2Warning};
use mechfmu::fmi3::ffi::fmi3OK;
use mechfmu::model::Mechanism;

/// Runs every FMI 3.0 check; panics with a message naming the mechanism and the first
/// check that fails.
pub fn check<M: Mechanism>() {
    co_simulation_equals_fmi2::<M>();
    model_exchange_equals_fmi2::<M>();
    derivatives::derivatives_equal_fmi2::<M>();
    arrays::check::<M>();
    calls::check::<M>();
    unsupported::unsupported_functions_are_refused::<M>();
}

/// An FMI 3.0 Co-Simulation instance initialized at the default experiment's start and
/// tolerance.
fn started<M: Mechanism>() -> Fmi3Harness<M> {
    let mut fmu = Fmi3Harness::<M>::new();
    let e = M::EXPERIMENT;
    fmu.initialize(Some(e.tolerance), e.start, &[])
        .unwrap_or_else(|m| panic!("{}: FMI 3.0: {m}", M::NAME));
    fmu
}

/// The same through FMI 2.0.
fn started_fmi2<M: Mechanism>() -> Harness<M> {
    let mut fmu = Harness::<M>::new();
    let e = M::EXPERIMENT;
    fmu.initialize(Some(e.tolerance), e.start, &[])
        .unwrap_or_else(|m| panic!("{}: FMI 2.0: {m}", M::NAME));
    fmu
}

fn at_fraction<M: Mechanism>(fraction: f64) -> f64 {
    let e = M::EXPERIMENT;
    e.start + fraction * (e.stop - e.start)
}

fn run<M: Mechanism>(fmu: &mut Fmi3Harness<M>, until_fraction: f64) {
    fmu.step_to(at_fraction::<M>(until_fraction), M::EXPERIMENT.step)
        .unwrap_or_else(|m| panic!("{}: {m}", M::NAME));
}

fn run_fmi2<M: Mechanism>(fmu: &mut Harness<M>, until_fraction: f64) {
    fmu.step_to(at_fraction::<M>(until_fraction), M::EXPERIMENT.step)
        .unwrap_or_else(|m| panic!("{}: {m}", M::NAME));
}

fn bits(values: &[f64]) -> Vec<u64> {
    values.iter().map(|x| x.to_bits()).collect()
}

/// Asserts that every FMI 3.0 variable of `fmi3`, element by element, has the bits of the
/// scalar it stands for in `fmi2` (`values2`, by value reference), and `time` is `t`.
fn assert_same_values<M: Mechanism>(
    fmi3: &mut Fmi3Harness<M>,
    values2: &[f64],
    t: f64,
    when: &str,
) {
    let mut vrs: Vec<u32> = fmi3
        .shapes()
        .variables
        .iter()
        .map(|s| s.reference as u32)
        .collect();
    vrs.push(fmi3.time_vr());
    let values3 = fmi3.get_values(&vrs).unwrap_or_else(|s| {
        panic!(
            "{}: fmi3GetFloat64 {when}: {s}: {:?}",
            M::NAME,
            fmi3.messages()
        )
    });
    let shapes = fmi3.shapes();
    let elements = shapes
        .variables
        .iter()
        .flat_map(|s| (0..s.elements.len()).map(move |k| (s, k)));
    for ((s, k), &x3) in elements.zip(&values3) {
        let scalar = s.elements[k];
        assert_eq!(
            x3.to_bits(),
            values2[scalar].to_bits(),
            "{}: {when}: {} = {x3} through FMI 3.0 but {} = {} through FMI 2.0",
            M::NAME,
            s.element_name(k),
            M::VARIABLES[scalar].name,
            values2[scalar]
        );
    }
    let time = values3[values3.len() - 1];
    assert_eq!(
        time.to_bits(),
        t.to_bits(),
        "{}: {when}: time = {time} through FMI 3.0, not {t}",
        M::NAME
    );
}

/// The default experiment through FMI 3.0 Co-Simulation is FMI 2.0's, bit for bit: the same
/// status at every step, every scalar (each array element) and the time at every
/// communication point.
pub fn co_simulation_equals_fmi2<M: Mechanism>() {
    let e = M::EXPERIMENT;
    let mut fmi2 = started_fmi2::<M>();
    let mut fmi3 = started::<M>();
    assert_same_values(
        &mut fmi3,
        &fmi2.all_values(),
        e.start,
        "after initialization",
    );
    crate::harness::step_to(e.start, e.stop, e.step, |t, h| {
        let status2 = fmi2.do_step(t, h);
        let step = fmi3.do_step(t, h);
        assert_eq!(
            step.status,
            status2,
            "{}: fmi3DoStep({t}, {h}) gave {step:?}, fmi2DoStep status {status2}: {:?}",
            M::NAME,
            fmi3.messages()
        );
        assert!(
            status2 <= fmi2Warning,
            "{}: the default experiment fails at t = {t}: {:?}",
            M::NAME,
            fmi2.messages()
        );
        assert!(
            !step.early_return && !step.terminate_simulation && !step.event_handling_needed,
            "{}: {step:?}",
            M::NAME
        );
        assert_eq!(
            step.last_successful_time.to_bits(),
            (t + h).to_bits(),
            "{}: {step:?}",
            M::NAME
        );
        let at = format!("at t = {}", t + h);
        assert_same_values(&mut fmi3, &fmi2.all_values(), t + h, &at);
        Ok(())
    })
    .unwrap_or_else(|m| panic!("{}: {m}", M::NAME));
}

/// Model Exchange through FMI 3.0 is FMI 2.0's, bit for bit, at points of an FMI 2.0 run
/// (and off it): the numbers of states and event indicators, the states, nominals,
/// derivatives, event indicators and every value at a point set by `fmi3SetTime` and
/// `fmi3SetContinuousStates`, the verdict of `fmi3CompletedIntegratorStep` and the event
/// iteration of `fmi3UpdateDiscreteStates`.
pub fn model_exchange_equals_fmi2<M: Mechanism>() {
    let e = M::EXPERIMENT;
    let mut fmi2 = ModelExchange::<M>::new();
    fmi2.initialize(Some(e.tolerance), e.start, &[])
        .unwrap_or_else(|m| panic!("{}: FMI 2.0: {m}", M::NAME));
    let mut fmi3 = Fmi3Harness::<M>::model_exchange();
    fmi3.initialize_model_exchange(Some(e.tolerance), e.start, &[])
        .unwrap_or_else(|m| panic!("{}: FMI 3.0: {m}", M::NAME));
    let name = M::NAME;
    assert_eq!(
        fmi3.number_of_continuous_states(),
        Ok(M::STATES.len()),
        "{name}: fmi3GetNumberOfContinuousStates"
    );
    assert_eq!(
        fmi3.number_of_event_indicators(),
        Ok(M::EVENT_INDICATORS.len()),
        "{name}: fmi3GetNumberOfEventIndicators"
    );
    assert_eq!(
        fmi3.nominals(),
        fmi2.nominals(),
        "{name}: nominals of the continuous states"
    );
    let same = |a: Result<Vec<f64>, u32>, b: Result<Vec<f64>, u32>, what: &str, t: f64| {
        assert_eq!(
            a.as_deref().map(bits),
            b.as_deref().map(bits),
            "{name}: {what} at t = {t}: FMI 3.0 {a:?}, FMI 2.0 {b:?}"
        );
    };
    same(
        fmi3.continuous_states(),
        fmi2.states(),
        "continuous states after initialization",
        e.start,
    );
    for fraction in [0.02, 0.05, 0.1] {
        fmi2.integrate(at_fraction::<M>(fraction), e.step)
            .unwrap_or_else(|m| panic!("{name}: {m}"));
        let t = fmi2.time();
        let x = fmi2
            .states()
            .unwrap_or_else(|s| panic!("{name}: fmi2GetContinuousStates: {s}"));
        // Off the trajectory first, so the trajectory's point is the one completed.
        let off: Vec<f64> = x.iter().map(|x| x + 1e-3 * x.abs() + 1e-6).collect();
        for x in [off, x] {
            assert_eq!(
                (fmi2.set_time(t), fmi2.set_states(&x)),
                (fmi2OK, fmi2OK),
                "{name}: {:?}",
                fmi2.messages()
            );
            assert_eq!(
                (fmi3.set_time(t), fmi3.set_continuous_states(&x)),
                (fmi3OK, fmi3OK),
                "{name}: {:?}",
                fmi3.messages()
            );
            same(fmi3.derivatives(), fmi2.derivatives(), "derivatives", t);
            same(
                fmi3.event_indicators(),
                fmi2.event_indicators(),
                "event indicators",
                t,
            );
            same(
                fmi3.continuous_states(),
                fmi2.states(),
                "continuous states",
                t,
            );
            same(
                Ok(fmi3.all_values()),
                Ok(fmi2.fmu.all_values()),
                "values",
                t,
            );
        }
        let completed = (
            fmi3.completed_integrator_step(),
            fmi2.completed_integrator_step(),
        );
        assert_eq!(
            completed.0, completed.1,
            "{name}: fmi3CompletedIntegratorStep (FMI 2.0's second) at t = {t}"
        );
        // The event iteration at this point: the same verdict, the same states after it.
        assert_eq!(
            (fmi3.enter_event_mode(), fmi2.enter_event_mode()),
            (fmi3OK, fmi2OK),
            "{name}: enter event mode"
        );
        let ((status3, update), (status2, info)) =
            (fmi3.update_discrete_states(), fmi2.new_discrete_states());
        assert_eq!(
            status3,
            status2,
            "{name}: fmi3UpdateDiscreteStates at t = {t}: {:?}",
            fmi3.messages()
        );
        let flags3 = [
            update.terminate_simulation,
            update.values_of_continuous_states_changed,
            update.discrete_states_need_update,
            update.next_event_time_defined,
        ];
        let flags2 = [
            info.terminateSimulation,
            info.valuesOfContinuousStatesChanged,
            info.newDiscreteStatesNeeded,
            info.nextEventTimeDefined,
        ];
        assert_eq!(
            flags3,
            flags2.map(|f| f != 0),
            "{name}: at t = {t}, fmi3UpdateDiscreteStates: {update:?}, fmi2NewDiscreteStates: {info:?}"
        );
        same(
            fmi3.continuous_states(),
            fmi2.states(),
            "continuous states after the event iteration",
            t,
        );
        let statuses = (
            fmi3.enter_continuous_time_mode(),
            fmi2.enter_continuous_time_mode(),
        );
        assert_eq!(
            statuses,
            (fmi3OK, fmi2OK),
            "{name}: enter continuous-time mode"
        );
    }
}
