//! `fmi2SetReal`, `fmi2DoStep` and `fmi2GetReal` (and FMI 3.0's) of CraneDynamics allocate nothing.

mechfmu_alloc::allocation_tests!(crane_dynamics::CraneDynamics);
