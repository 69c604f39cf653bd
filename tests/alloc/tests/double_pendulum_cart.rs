//! `fmi2SetReal`, `fmi2DoStep` and `fmi2GetReal` (and FMI 3.0's) of DoublePendulumCart allocate
//! nothing: Lagrange's equations formed from its energies included.

#[test]
fn the_importer_loop_allocates_nothing() {
    let work = mechfmu_alloc::check::<double_pendulum_cart::DoublePendulumCart>(2_000);
    assert_eq!(work.steps, 2_000);
}

#[test]
fn setting_tunable_parameters_allocates_nothing() {
    let work =
        mechfmu_alloc::check_with_tunables::<double_pendulum_cart::DoublePendulumCart>(2_000);
    assert_eq!(work.steps, 2_000);
}

#[test]
fn the_importer_loop_through_fmi3_allocates_nothing() {
    let work = mechfmu_alloc::fmi3::check::<double_pendulum_cart::DoublePendulumCart>(2_000);
    assert_eq!(work.steps, 2_000);
}
