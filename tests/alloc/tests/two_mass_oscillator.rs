//! `fmi2SetReal`, `fmi2DoStep` and `fmi2GetReal` (and FMI 3.0's) of TwoMassOscillator allocate nothing.

mechfmu_alloc::allocation_tests!(two_mass_oscillator::TwoMassOscillator);
