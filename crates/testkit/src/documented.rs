//! What a mechanism's interface page says of its runs, checked against its declaration.

use mechfmu::model::Mechanism;

/// Asserts the page's claim for a mechanism whose default experiment stands still (and
/// which the page plots its moving case for instead): the default experiment does stand
/// still, and the declared moving case moves and runs to its stop time.
pub fn default_experiment_stands_still_and_moving_case_moves<M: Mechanism>() {
    assert!(mechfmu::docs::default_experiment::<M>()
        .unwrap()
        .stands_still());
    let case = M::MOVING_CASE.expect("a moving case");
    let run = mechfmu::docs::moving_case::<M>(&case).unwrap();
    assert!(!run.stands_still());
    assert_eq!(run.stopped, None);
}
