//! The Crane through FMI 3.0 Co-Simulation where the model stops holding inside a step
//! (the trolley reaches the pivot): with `earlyReturnAllowed` the step returns early there,
//! without it the step is discarded; either way the importer learns when, and that the
//! simulation must end.

use crane::Crane;
use mechfmu::fmi3::ffi::*;
use mechfmu_testkit::fmi3::{Fmi3Harness, Kind};

/// `x = 1 - 1.05 t` reaches 0 at t = 1/1.05 ≈ 0.952, inside the step [0.9, 1.0] (as in
/// `crane.rs`'s `trolley_reaching_the_pivot_discards_the_step`): the instance after the
/// nine steps before it.
fn before_the_pivot(early_return_allowed: bool) -> Fmi3Harness<Crane> {
    let mut fmu = Fmi3Harness::<Crane>::of_kind(Kind::CoSimulation {
        event_mode_used: false,
        early_return_allowed,
    });
    fmu.initialize(Some(1e-8), 0.0, &[("x", 1.0), ("x_dot", -1.05)])
        .unwrap();
    for n in 0..9 {
        let step = fmu.do_step(n as f64 * 0.1, 0.1);
        assert_eq!(step.status, fmi3OK, "{step:?}: {:?}", fmu.messages());
        assert!(!step.early_return && !step.terminate_simulation);
    }
    fmu
}

/// The last valid time of a step stopped at the pivot: the crossing at 1/1.05 itself,
/// located inside the step (the trolley still on the boom, `x > 0`), and the instance's
/// time and `x` are those there.
fn assert_stopped_inside_the_step(fmu: &mut Fmi3Harness<Crane>, last_successful_time: f64) {
    assert!(
        (last_successful_time - 1.0 / 1.05).abs() < 1e-12,
        "lastSuccessfulTime = {last_successful_time}, not the crossing at 1/1.05"
    );
    assert_eq!(fmu.get("time"), last_successful_time);
    let x = fmu.get("x");
    assert!(x > 0.0 && x <= 1.0 - 1.05 * 0.9 + 1e-12, "x = {x}");
    assert!(
        (x - (1.0 - 1.05 * last_successful_time)).abs() < 1e-9,
        "x = {x} at t = {last_successful_time}"
    );
    assert!(
        fmu.logged("the trolley reached the pivot"),
        "{:?}",
        fmu.messages()
    );
}

#[test]
fn with_early_return_the_step_returns_where_the_trolley_reaches_the_pivot() {
    let mut fmu = before_the_pivot(true);
    let step = fmu.do_step(0.9, 0.1);
    assert_eq!(step.status, fmi3Warning, "{step:?}: {:?}", fmu.messages());
    assert!(step.early_return, "{step:?}");
    assert!(step.terminate_simulation, "{step:?}");
    assert!(!step.event_handling_needed, "{step:?}");
    assert_stopped_inside_the_step(&mut fmu, step.last_successful_time);
    assert!(
        fmu.messages()
            .iter()
            .any(|(s, _, m)| *s == fmi3Warning && m.starts_with("fmi3DoStep: returned early")),
        "{:?}",
        fmu.messages()
    );
    assert_eq!(fmu.terminate(), fmi3OK, "{:?}", fmu.messages());
}

#[test]
fn without_early_return_the_step_is_discarded_at_the_last_valid_time() {
    let mut fmu = before_the_pivot(false);
    let step = fmu.do_step(0.9, 0.1);
    assert_eq!(step.status, fmi3Discard, "{step:?}: {:?}", fmu.messages());
    assert!(!step.early_return, "{step:?}");
    assert!(step.terminate_simulation, "{step:?}");
    assert_stopped_inside_the_step(&mut fmu, step.last_successful_time);
    assert_eq!(
        fmu.do_step(1.0, 0.1).status,
        fmi3Error,
        "no step after a discard"
    );
    assert_eq!(fmu.terminate(), fmi3OK, "{:?}", fmu.messages());
}
