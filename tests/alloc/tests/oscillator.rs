//! `fmi2SetReal`, `fmi2DoStep` and `fmi2GetReal` (and FMI 3.0's) of Oscillator allocate nothing.

mechfmu_alloc::allocation_tests!(oscillator::Oscillator);
