//! `fmi2SetReal`, `fmi2DoStep` and `fmi2GetReal` (and FMI 3.0's) of Crane allocate nothing.

mechfmu_alloc::allocation_tests!(crane::Crane);
