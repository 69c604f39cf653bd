//! `ControlledCrane` compiled into one FMU, the crane and its controller integrated together,
//! passes every check a mechanism passes (its agreement with an independent solution of its
//! equations is `mechfmu validate`'s: tests/python/refs/controlled_crane.py).

use controlled_crane::ControlledCrane;

#[test]
fn the_system_fmu_passes_every_check_of_a_mechanism() {
    mechfmu_testkit::conformance::check::<ControlledCrane>();
}

// its committed model descriptions (modelDescription/) and interface page (docs/mechanisms/)
mechfmu_testkit::golden_tests!(ControlledCrane);
