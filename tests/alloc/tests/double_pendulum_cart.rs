//! `fmi2SetReal`, `fmi2DoStep` and `fmi2GetReal` (and FMI 3.0's) of DoublePendulumCart allocate
//! nothing: Lagrange's equations formed from its energies included.

mechfmu_alloc::allocation_tests!(double_pendulum_cart::DoublePendulumCart);
