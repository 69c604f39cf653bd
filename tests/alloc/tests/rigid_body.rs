//! `fmi2SetReal`, `fmi2DoStep` and `fmi2GetReal` (and FMI 3.0's) of RigidBody allocate nothing.

mechfmu_alloc::allocation_tests!(rigid_body::RigidBody);
