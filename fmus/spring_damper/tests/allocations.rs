//! `fmi2SetReal`, `fmi2DoStep` and `fmi2GetReal` (and FMI 3.0's) of SpringDamper allocate nothing
//! once it runs, as an importer's loop calls them: `cargo test`.

mechfmu_testkit::allocation_tests!(spring_damper::SpringDamper);
