//! What every mechanism's Model Exchange interface must do, whatever its physics: give the
//! very derivatives Co-Simulation integrates, converge to Co-Simulation's solution under an
//! importer's solver, keep the state machine and refuse bad calls with a message, restore
//! FMU states bit for bit, and give exact Jacobians at the point it was last given.

use crate::harness::Harness;
use crate::model_exchange::ModelExchange;
use mechfmu::fmi2::ffi::*;
use mechfmu::model::{Causality, Mechanism, Variability};

/// Runs every Model Exchange check; panics with a message naming the first that fails.
pub fn check<M: Mechanism>() {
    derivatives_are_those_co_simulation_integrates::<M>();
    runge_kutta_converges_to_co_simulation::<M>();
    calls_follow_the_state_machine::<M>();
    fmu_state_continues_bit_for_bit::<M>();
    jacobians_match_finite_differences::<M>();
}

fn started<M: Mechanism>() -> ModelExchange<M> {
    let mut me = ModelExchange::<M>::new();
    let e = M::EXPERIMENT;
    me.initialize(Some(e.tolerance), e.start, &[])
        .unwrap_or_else(|m| panic!("{}: {m}", M::NAME));
    me
}

fn co_simulation<M: Mechanism>(tolerance: f64) -> Harness<M> {
    let mut cs = Harness::<M>::new();
    cs.initialize(Some(tolerance), M::EXPERIMENT.start, &[])
        .unwrap_or_else(|m| panic!("{}: {m}", M::NAME));
    cs
}

fn at_fraction<M: Mechanism>(fraction: f64) -> f64 {
    let e = M::EXPERIMENT;
    e.start + fraction * (e.stop - e.start)
}

fn read<M: Mechanism>(fmu: &mut Harness<M>, vrs: &[usize]) -> Vec<f64> {
    let vrs: Vec<u32> = vrs.iter().map(|&v| v as u32).collect();
    let mut values = vec![f64::NAN; vrs.len()];
    assert_eq!(
        fmu.get_real(&vrs, &mut values),
        fmi2OK,
        "{:?}",
        fmu.messages()
    );
    values
}

/// At points of a Co-Simulation run, Model Exchange given the same time, states and inputs
/// returns the derivatives Co-Simulation holds there, bit for bit: the same equations.
pub fn derivatives_are_those_co_simulation_integrates<M: Mechanism>() {
    let mut cs = co_simulation::<M>(M::EXPERIMENT.tolerance);
    let mut me = started::<M>();
    for fraction in [0.0, 0.15, 0.35] {
        cs.step_to(at_fraction::<M>(fraction), M::EXPERIMENT.step)
            .unwrap_or_else(|m| panic!("{}: {m}", M::NAME));
        let x = read(&mut cs, M::STATES);
        let u = read(&mut cs, M::INPUTS);
        let expected = read(&mut cs, M::DERIVATIVES);
        let inputs: Vec<u32> = M::INPUTS.iter().map(|&v| v as u32).collect();
        assert_eq!(me.fmu.set_real(&inputs, &u), fmi2OK);
        assert_eq!(me.set_time(cs.time()), fmi2OK);
        assert_eq!(me.set_states(&x), fmi2OK);
        let dx = me
            .derivatives()
            .unwrap_or_else(|s| panic!("{s}: {:?}", me.messages()));
        assert_eq!(
            dx.iter().map(|d| d.to_bits()).collect::<Vec<_>>(),
            expected.iter().map(|d| d.to_bits()).collect::<Vec<_>>(),
            "{}: at t = {}, Model Exchange's derivatives {dx:?} are not Co-Simulation's {expected:?}",
            M::NAME,
            cs.time()
        );
    }
}

/// Model Exchange under the test kit's RK4 with steps h and h/2 over the first tenth of the
/// default experiment: the error against Co-Simulation at a tight tolerance falls with the
/// step (as h⁴ for smooth equations; at least by half, so that equations with kinks pass
/// too), down to what rounding and the reference allow.
pub fn runge_kutta_converges_to_co_simulation<M: Mechanism>() {
    let t_end = at_fraction::<M>(0.1);
    let h = M::EXPERIMENT.step;
    let mut cs = co_simulation::<M>(1e-12);
    cs.step_to(t_end, h)
        .unwrap_or_else(|m| panic!("{}: {m}", M::NAME));
    let reference = read(&mut cs, M::STATES);
    let error = |step: f64| {
        let mut me = started::<M>();
        me.integrate(t_end, step)
            .unwrap_or_else(|m| panic!("{}: {m}", M::NAME));
        let x = me.states().unwrap_or_else(|s| panic!("{s}"));
        x.iter()
            .zip(&reference)
            .map(|(a, b)| (a - b).abs() / b.abs().max(1.0))
            .fold(0.0, f64::max)
    };
    let (coarse, fine) = (error(h), error(h / 2.0));
    assert!(
        fine <= (coarse / 2.0).max(1e-9),
        "{}: RK4 through Model Exchange does not converge to Co-Simulation: error {coarse:e} with step {h}, {fine:e} with {}",
        M::NAME,
        h / 2.0
    );
}

fn logged<M: Mechanism>(fmu: &Harness<M>, text: &str) -> bool {
    fmu.messages().iter().any(|(_, _, m)| m.contains(text))
}

/// The calls of section 3.2.3 where the table allows them, refused with a message
/// elsewhere; the other interface type's calls refused; bad arguments refused and the
/// instance left as it was.
pub fn calls_follow_the_state_machine<M: Mechanism>() {
    let nx = M::STATES.len();
    // Before initialization: no states to set, no derivatives.
    let mut me = ModelExchange::<M>::new();
    assert_eq!(me.nominals(), Ok(vec![1.0; nx]), "{}: nominals", M::NAME);
    assert_eq!(me.set_states(&vec![0.0; nx]), fmi2Error);
    assert_eq!(me.derivatives(), Err(fmi2Error));
    assert_eq!(me.set_time(0.0), fmi2Error);
    assert!(logged(&me.fmu, "fmi2SetTime: illegal call sequence"));

    let mut me = started::<M>();
    // Co-Simulation's calls are refused, with a message saying why.
    assert_eq!(
        me.fmu.do_step(M::EXPERIMENT.start, M::EXPERIMENT.step),
        fmi2Error
    );
    assert!(
        logged(&me.fmu, "fmi2DoStep: a Co-Simulation function, but the instance was instantiated for Model Exchange"),
        "{:?}",
        me.messages()
    );
    let x = me.states().expect("fmi2GetContinuousStates");
    // Wrong lengths and values that are not numbers: refused, nothing changed.
    let mut longer = x.clone();
    longer.push(0.0);
    assert_eq!(me.set_states(&longer), fmi2Error);
    assert!(logged(
        &me.fmu,
        &format!("nx = {}, but the FMU has {nx}", nx + 1)
    ));
    if nx > 0 {
        let mut bad = x.clone();
        bad[nx - 1] = f64::NAN;
        assert_eq!(me.set_states(&bad), fmi2Error);
        assert!(logged(&me.fmu, "is not a finite number"));
        assert_eq!(
            me.states(),
            Ok(x.clone()),
            "{}: a refused state changed the states",
            M::NAME
        );
    }
    assert_eq!(me.set_time(f64::INFINITY), fmi2Error);
    let dx = me.derivatives().expect("fmi2GetDerivatives");
    assert!(dx.iter().all(|d| d.is_finite()));
    // In continuous-time mode only continuous inputs may be set: a tunable parameter
    // waits for event mode.
    let tunable = M::VARIABLES
        .iter()
        .position(|v| v.causality == Causality::Parameter && v.variability == Variability::Tunable);
    if let Some(p) = tunable {
        let value = M::VARIABLES[p].start.unwrap_or(0.0);
        assert_eq!(me.fmu.set_real(&[p as u32], &[value]), fmi2Error);
        assert_eq!(me.enter_event_mode(), fmi2OK);
        assert_eq!(me.fmu.set_real(&[p as u32], &[value]), fmi2OK);
    } else {
        assert_eq!(me.enter_event_mode(), fmi2OK);
    }
    // Event mode: no states to set, no integrator step.
    assert_eq!(me.set_states(&x), fmi2Error);
    assert_eq!(me.completed_integrator_step().0, fmi2Error);
    assert_eq!(me.enter_continuous_time_mode(), fmi2OK);
    assert_eq!(me.new_discrete_states().0, fmi2Error);
    assert_eq!(me.fmu.terminate(), fmi2OK);
    // Terminated: still readable.
    assert_eq!(
        me.derivatives(),
        Ok(dx),
        "{}: derivatives after fmi2Terminate",
        M::NAME
    );
    assert_eq!(me.set_time(1.0), fmi2Error);

    // A Co-Simulation instance refuses Model Exchange's calls.
    let mut cs = co_simulation::<M>(M::EXPERIMENT.tolerance);
    let mut z = [0.0; 1];
    // SAFETY: live component, an array of the given length.
    let status = unsafe {
        mechfmu::fmi2::functions::fmi2GetContinuousStates::<M>(
            cs.component(),
            z.as_mut_ptr(),
            nx.min(1),
        )
    };
    assert_eq!(status, fmi2Error);
    assert!(
        logged(
            &cs,
            "a Model Exchange function, but the instance was instantiated for Co-Simulation"
        ),
        "{:?}",
        cs.messages()
    );
    assert_eq!(cs.do_step(M::EXPERIMENT.start, M::EXPERIMENT.step), fmi2OK);
}

/// An FMU state taken in continuous-time mode brings the instance back to that point: the
/// integration from there repeats bit for bit, in this instance and (serialized) in
/// another; a Co-Simulation instance refuses it.
pub fn fmu_state_continues_bit_for_bit<M: Mechanism>() {
    let h = M::EXPERIMENT.step;
    let mut me = started::<M>();
    me.integrate(at_fraction::<M>(0.05), h)
        .unwrap_or_else(|m| panic!("{}: {m}", M::NAME));
    let t = me.time();
    let state = me.fmu.get_fmu_state().expect("fmi2GetFMUstate");
    let bytes = me.fmu.serialize(state).expect("fmi2SerializeFMUstate");
    let run = |me: &mut ModelExchange<M>| {
        me.integrate(at_fraction::<M>(0.1), h)
            .unwrap_or_else(|m| panic!("{}: {m}", M::NAME));
        me.states()
            .expect("fmi2GetContinuousStates")
            .iter()
            .map(|x| x.to_bits())
            .collect::<Vec<_>>()
    };
    let first = run(&mut me);
    assert_eq!(me.fmu.set_fmu_state(state), fmi2OK);
    me.set_time(t);
    assert_eq!(run(&mut me), first, "{}: after fmi2SetFMUstate", M::NAME);
    let mut other = ModelExchange::<M>::new();
    let restored = other
        .fmu
        .deserialize(&bytes)
        .expect("fmi2DeSerializeFMUstate");
    assert_eq!(other.fmu.set_fmu_state(restored), fmi2OK);
    other.set_time(t);
    assert_eq!(run(&mut other), first, "{}: in another instance", M::NAME);
    let mut cs = Harness::<M>::new();
    let foreign = cs.deserialize(&bytes).expect("fmi2DeSerializeFMUstate");
    assert_eq!(cs.set_fmu_state(foreign), fmi2Error);
    assert!(
        logged(&cs, "saved by a Model Exchange instance"),
        "{:?}",
        cs.messages()
    );
    for (fmu, s) in [
        (&mut me.fmu, state),
        (&mut other.fmu, restored),
        (&mut cs, foreign),
    ] {
        fmu.free_fmu_state(s);
    }
}

/// In continuous-time mode, `fmi2GetDirectionalDerivative` gives ∂ẋ/∂x and ∂ẋ/∂u at the
/// point last given (not at the last one evaluated), against central differences of
/// `fmi2GetDerivatives` around it.
pub fn jacobians_match_finite_differences<M: Mechanism>() {
    let mut me = started::<M>();
    me.integrate(at_fraction::<M>(0.1), M::EXPERIMENT.step)
        .unwrap_or_else(|m| panic!("{}: {m}", M::NAME));
    let t = me.time();
    // A point off the trajectory, so nothing evaluated before can stand in for it (moved
    // away from zero: a state whose domain has a bound at zero stays inside it).
    let x: Vec<f64> = me
        .states()
        .expect("fmi2GetContinuousStates")
        .iter()
        .map(|x| x + 1e-3 * x.abs() + 1e-6)
        .collect();
    let unknowns: Vec<u32> = M::DERIVATIVES.iter().map(|&v| v as u32).collect();
    let knowns: Vec<usize> = M::STATES.iter().chain(M::INPUTS).copied().collect();
    let u: Vec<f64> = {
        let vrs: Vec<u32> = M::INPUTS.iter().map(|&v| v as u32).collect();
        let mut u = vec![0.0; vrs.len()];
        assert_eq!(me.fmu.get_real(&vrs, &mut u), fmi2OK);
        u
    };
    let at = |me: &mut ModelExchange<M>, known: usize, dx: f64| {
        let mut x = x.clone();
        let mut u = u.clone();
        match M::STATES.iter().position(|&s| s == known) {
            Some(i) => x[i] += dx,
            None => u[M::INPUTS.iter().position(|&s| s == known).unwrap_or(0)] += dx,
        }
        let inputs: Vec<u32> = M::INPUTS.iter().map(|&v| v as u32).collect();
        assert_eq!(me.fmu.set_real(&inputs, &u), fmi2OK);
        me.set_time(t);
        assert_eq!(me.set_states(&x), fmi2OK);
        me.derivatives().unwrap_or_else(|s| panic!("{s}"))
    };
    for &known in &knowns {
        let center = at(&mut me, known, 0.0);
        let mut exact = vec![0.0; unknowns.len()];
        assert_eq!(
            me.fmu
                .directional_derivative(&unknowns, &[known as u32], &[1.0], &mut exact),
            fmi2OK,
            "{:?}",
            me.messages()
        );
        let value = x
            .iter()
            .chain(&u)
            .nth(knowns.iter().position(|&k| k == known).unwrap_or(0))
            .copied()
            .unwrap_or(0.0);
        let h = 1e-6 * value.abs().max(1.0);
        let (plus, minus) = (at(&mut me, known, h), at(&mut me, known, -h));
        for i in 0..unknowns.len() {
            let fd = (plus[i] - minus[i]) / (2.0 * h);
            let noise = 1e-14 * (1.0 + center[i].abs()) / h;
            let allowed = 1e-6 * exact[i].abs().max(fd.abs()) + noise;
            assert!(
                (exact[i] - fd).abs() <= allowed,
                "{}: d {} / d {} at t = {t}: directional derivative {} but central differences {fd}",
                M::NAME,
                M::VARIABLES[M::DERIVATIVES[i]].name,
                M::VARIABLES[known].name,
                exact[i]
            );
        }
    }
}
