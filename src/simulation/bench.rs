//! Hooks for `mechfmu bench`: the parts of a communication step, each run alone in the
//! FMU's own compiled code, so the benchmark can time them from outside and tell the
//! model's equations from the solver and from the FMI layer.

use super::{Simulation, System};
use crate::model::{Mechanism, ValueSet};
use crate::solver::{OdeSystem, StateVector};

/// What [`Simulation::bench`] repeats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Part {
    /// `Mechanism::evaluate` alone: the right-hand side's own work, each evaluation
    /// waiting for the previous one's derivatives as a solver's stages do (without
    /// `Mechanism::outputs`, which runs once per communication point, not per stage).
    Evaluate,
    /// The solver's callback: load the state into the values, evaluate, read the
    /// derivatives (the evaluation plus the copying around it), chained the same way.
    Rhs,
    /// Whole communication steps of size `h` without the FMI layer (`Simulation::step`).
    Step,
    /// The solver alone over communication steps of size `h` (`Dopri5::integrate` on the
    /// model, as `Simulation::step` calls it, without the step's own checks and copying).
    Integrate,
    /// The model's own work at a communication point, once per step, as
    /// `Simulation::step` does it: `Mechanism::project` and the evaluation after it (for a
    /// mechanism that projects), and `Mechanism::outputs`. Model equations, not plumbing.
    Point,
}

impl Part {
    pub fn from_code(code: u32) -> Option<Part> {
        match code {
            0 => Some(Part::Evaluate),
            1 => Some(Part::Rhs),
            2 => Some(Part::Step),
            3 => Some(Part::Integrate),
            4 => Some(Part::Point),
            _ => None,
        }
    }
}

impl<M: Mechanism> Simulation<M> {
    /// Repeats `part` `n` times on a copy of this simulation (which is left as it was).
    /// `h` is the communication step of [`Part::Step`] and [`Part::Integrate`]; for
    /// [`Part::Evaluate`] and [`Part::Rhs`] it is the time span the `n` evaluations are
    /// spread over (that of the steps they stand for: time-dependent terms such as
    /// `sin(ω t)` cost what they cost there), and the time moves at every repetition so
    /// that no evaluation can be folded into another. Both walk the trajectory with explicit
    /// Euler steps of that span over `n`, so each evaluation depends on the last: timed
    /// alone, unchained evaluations overlap in the processor and would hide the latency
    /// that a solver's stages pay. Returns a checksum (for
    /// `black_box`), or `Err` if a step fails.
    pub fn bench(&self, part: Part, n: u64, h: f64) -> Result<f64, String> {
        let mut sim = self.clone();
        sim.update()?;
        let d = self.layout.derivatives.first().copied().unwrap_or(0);
        let t0 = sim.time();
        let dt = if n > 0 { h / n as f64 } else { 0.0 };
        let mut sum = 0.0;
        match part {
            Part::Evaluate => {
                let mut values = sim.values.clone();
                for i in 0..n {
                    values.set_time(t0 + (i + 1) as f64 * dt);
                    M::evaluate(std::hint::black_box(&mut values));
                    // Chained as a solver's stages are: the next evaluation's states wait
                    // for this one's derivatives (an explicit Euler walk over the span).
                    for (&s, &d) in M::STATES.iter().zip(M::DERIVATIVES) {
                        let x = values.get(s).unwrap_or(0.0) + dt * values.get(d).unwrap_or(0.0);
                        values.set(s, x);
                    }
                }
                sum += values.get(d).unwrap_or(0.0);
            }
            Part::Rhs | Part::Integrate => {
                let mut y = M::State::ZERO;
                for (y, &vr) in y.as_mut_slice().iter_mut().zip(M::STATES) {
                    *y = sim.values.get(vr).unwrap_or(0.0);
                }
                let mut dydt = M::State::ZERO;
                let mut warnings = Vec::new();
                let mut warning_active = false;
                let inputs_fixed = sim.inputs_held();
                let mut system = System::<M>::new(
                    &mut sim.values,
                    &sim.layout,
                    &sim.inputs,
                    &sim.input_derivatives,
                    t0,
                    &mut warning_active,
                    &mut warnings,
                    inputs_fixed,
                );
                if part == Part::Rhs {
                    for i in 0..n {
                        system.rhs(
                            t0 + (i + 1) as f64 * dt,
                            std::hint::black_box(y.as_slice()),
                            dydt.as_mut_slice(),
                        );
                        // The same Euler walk as `Part::Evaluate`'s, so the difference of
                        // the two is what the callback adds.
                        for (y, &f) in y.as_mut_slice().iter_mut().zip(dydt.as_slice()) {
                            *y += dt * f;
                        }
                    }
                    sum = y.as_slice().first().copied().unwrap_or(0.0);
                } else {
                    let mut t = t0;
                    for _ in 0..n {
                        let t_end = t + h;
                        system.t0 = t;
                        sim.solver
                            .integrate(&mut system, &mut t, t_end, &mut y, sim.tolerance)
                            .map_err(|e| e.to_string())?;
                    }
                    sum = y.as_slice().first().copied().unwrap_or(0.0);
                }
            }
            Part::Point => {
                let mut values = sim.values.clone();
                for i in 0..n {
                    values.set_time(t0 + (i + 1) as f64 * h);
                    super::complete_point::<M>(std::hint::black_box(&mut values));
                }
                sum += values.get(d).unwrap_or(0.0);
            }
            Part::Step => {
                let mut t = t0;
                for _ in 0..n {
                    sim.step(t, h).map_err(|e| format!("{e:?}"))?;
                    t += h;
                }
                sum = sim.values.get(d).unwrap_or(0.0);
            }
        }
        Ok(sum)
    }
}
