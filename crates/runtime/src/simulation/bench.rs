//! Hooks for `mechfmu bench`: the parts of a communication step, each run alone in the
//! FMU's own compiled code, so the benchmark can time them from outside and tell the
//! model's equations from the solver and from the FMI layer.

use super::step::complete_point;
use super::system::{fixed_size, System};
use super::Simulation;
use crate::model::{Mechanism, ValueSet};
use crate::solver::{OdeSystem, StateVector};

/// What [`Simulation::bench`] repeats.
/// The discriminants are the codes `mechfmu_bench` takes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[repr(u32)]
pub enum Part {
    /// `Mechanism::evaluate` alone: the right-hand side's own work, each evaluation
    /// waiting for the previous one's derivatives as a solver's stages do (without
    /// `Mechanism::outputs`, which runs once per communication point, not per stage).
    /// The walk is [`Part::Rhs`]'s with the callback's interface taken out: the states
    /// into the named values, `evaluate`, the derivatives out of them, by the callback's own
    /// code (`System::derivatives_at`), so the two differ by what the callback adds: the
    /// solver's slices in and out and its count. (A walk with code of its own can pay
    /// store-forwarding stalls the callback does not, and come out slower than the callback
    /// it is subtracted from.)
    Evaluate = 0,
    /// The solver's callback: load the state into the values, evaluate, read the
    /// derivatives (the evaluation plus the copying around it), chained the same way.
    Rhs = 1,
    /// Whole communication steps of size `h` without the FMI layer (`Simulation::step`).
    Step = 2,
    /// The solver alone over communication steps of size `h` (`Dopri5::integrate` on the
    /// model, as `Simulation::step` calls it, without the step's own checks and copying).
    Integrate = 3,
    /// The model's own work at a communication point, once per step, as
    /// `Simulation::step` does it: `Mechanism::project` and the evaluation after it (for a
    /// mechanism that projects), and `Mechanism::outputs`. Model equations, not plumbing.
    Point = 4,
    /// [`Part::Integrate`] with the calls isolated: [`isolate`] after each, so that no
    /// call overlaps the next in the processor. Back to back, the solver's calls overlap
    /// (the next one starts while the last one's step-size control is still executing);
    /// inside `fmi2DoStep` the step's and the FMI layer's instructions sit between them
    /// and take up the room that overlap needs. Timing both loops isolated tells the
    /// plumbing's own execution from the overlap it costs.
    IntegrateIsolated = 5,
    /// One derivative evaluation of Model Exchange without the FMI layer: the simulation's
    /// own code behind `fmi2SetTime`, `fmi2SetContinuousStates` and `fmi2GetDerivatives`
    /// (`Simulation::set_time`, `Simulation::set_states`, `Simulation::derivatives`), on
    /// [`Part::Evaluate`]'s walk: the same points (time and states bit for bit), each
    /// evaluation waiting for the previous one's derivatives. Its difference to
    /// [`Part::Evaluate`] is what the simulation's Model Exchange code adds to the
    /// equations (flags, checks, copies); the exported calls' difference to it is the FMI
    /// layer's (C calls, instance and state checks, unwinding guards, argument checks).
    /// Codes from 16 are the Model Exchange parts, after the communication step's.
    ModelExchange = 16,
}

/// Whether [`isolate`] is a barrier on this processor (`lfence` on x86_64); elsewhere it
/// does nothing and the isolated figures are not measured.
pub const ISOLATES: bool = cfg!(target_arch = "x86_64");

/// Waits until every earlier instruction has completed before any later one starts
/// (`lfence`), so that timed calls separated by it cannot overlap (see [`ISOLATES`]).
#[inline(always)]
pub fn isolate() {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: `lfence` is part of SSE2, which every x86_64 processor has.
    unsafe {
        core::arch::x86_64::_mm_lfence()
    };
}

impl Part {
    pub fn from_code(code: u32) -> Option<Part> {
        [
            Part::Evaluate,
            Part::Rhs,
            Part::Step,
            Part::Integrate,
            Part::Point,
            Part::IntegrateIsolated,
            Part::ModelExchange,
        ]
        .into_iter()
        .find(|&part| part as u32 == code)
        .filter(|&part| part != Part::IntegrateIsolated || ISOLATES)
    }
}

impl<M: Mechanism> Simulation<M> {
    /// The solver's view of this simulation over a step from `t0`, as `Simulation::step`
    /// builds it.
    fn system<'a>(
        &'a mut self,
        t0: f64,
        warning_active: &'a mut bool,
        warnings: &'a mut Vec<String>,
    ) -> System<'a, M> {
        let inputs_fixed = self.inputs_held();
        System::new(
            &mut self.values,
            &self.inputs,
            &self.input_derivatives,
            t0,
            warning_active,
            warnings,
            inputs_fixed,
        )
    }

    /// Repeats `part` `n` times on a copy of this simulation (which is left as it was).
    /// `h` is the communication step of [`Part::Step`] and [`Part::Integrate`]; for
    /// [`Part::Evaluate`], [`Part::Rhs`] and [`Part::ModelExchange`] it is the time span
    /// the `n` evaluations are spread over (that of the steps they stand for:
    /// time-dependent terms such as `sin(ω t)` cost what they cost there), and the time
    /// moves at every repetition so that no evaluation can be folded into another. They
    /// walk the trajectory with explicit Euler steps of that span over `n`, so each
    /// evaluation depends on the last: timed alone, unchained evaluations overlap in the
    /// processor and would hide the latency that a solver's stages pay. Evaluation `i`
    /// (from 0) is at time `t0 + (i + 1) h / n`. Returns a checksum (for `black_box`), or
    /// `Err` if a step fails.
    pub fn bench(&self, part: Part, n: u64, h: f64) -> Result<f64, String> {
        let mut sim = self.clone();
        sim.update()?;
        let d = self.layout.derivatives.first().copied().unwrap_or(0);
        let t0 = sim.time();
        let dt = if n > 0 { h / n as f64 } else { 0.0 };
        let mut sum = 0.0;
        match part {
            Part::Evaluate => {
                // `Part::Rhs`'s walk without the callback's interface: the same state
                // vector through `black_box`, the same `System` code from the states to
                // the derivatives (`System::derivatives_at`), the same Euler update, but
                // no slices in and out and no count. With the states stored and the
                // derivatives read by a loop of this walk's own, RigidBody's copy of the
                // equations loads the states across the stores that wrote them, which the
                // processor cannot forward (three stalls per evaluation that the callback's
                // code does not have), and the callback comes out 4 ns per evaluation
                // faster than the evaluations it calls.
                //
                // The two walks are written out, each in its own arm. One shared walk
                // taking the derivatives as a closure compiles PendulumCart's callback walk
                // to load the states at an offset of 8 bytes across the two 16-byte stores
                // of the Euler update (a failed store forward per evaluation): its copy
                // reads +23 to +29 ns per step, with fmi2DoStep unchanged. Which loop the
                // compiler gives such a load is its choice; these two loops are measured to
                // have none (copy -4 to +5 ns, all six mechanisms; docs/performance.md).
                let mut y = sim.state_vector();
                let (mut warnings, mut warning_active) = (Vec::new(), false);
                let mut system = sim.system(t0, &mut warning_active, &mut warnings);
                for i in 0..n {
                    let arg: M::State = fixed_size(std::hint::black_box(y.as_slice()));
                    let f = system.derivatives_at(t0 + (i + 1) as f64 * dt, &arg);
                    for (y, &f) in y.as_mut_slice().iter_mut().zip(f.as_slice()) {
                        *y += dt * f;
                    }
                }
                sum += y.as_slice().first().copied().unwrap_or(0.0);
            }
            Part::Rhs => {
                let mut y = sim.state_vector();
                let mut dydt = M::State::ZERO;
                let (mut warnings, mut warning_active) = (Vec::new(), false);
                // A system of its own, whose address nothing else sees. One whose address
                // had escaped (as `Part::Integrate`'s does, into the solver's code) has its
                // pointer to the values read back from memory after every store through it,
                // and the derivatives with it: the solver's stages do not pay that.
                let mut system = sim.system(t0, &mut warning_active, &mut warnings);
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
            }
            Part::Integrate | Part::IntegrateIsolated => {
                let isolated = part == Part::IntegrateIsolated;
                let mut y = sim.state_vector();
                let (mut warnings, mut warning_active) = (Vec::new(), false);
                let tolerance = sim.tolerance;
                let mut solver = sim.solver.clone();
                let mut system = sim.system(t0, &mut warning_active, &mut warnings);
                let mut t = t0;
                for _ in 0..n {
                    let t_end = t + h;
                    system.t0 = t;
                    solver
                        .integrate(&mut system, &mut t, t_end, &mut y, tolerance)
                        .map_err(|e| e.to_string())?;
                    if isolated {
                        isolate();
                    }
                }
                sum = y.as_slice().first().copied().unwrap_or(0.0);
            }
            Part::ModelExchange => {
                // `Part::Evaluate`'s walk through the Model Exchange calls' code. On the
                // clone: `set_time` and `set_states` move its point, not the instance's.
                let mut y = sim.state_vector();
                let mut dydt = M::State::ZERO;
                for i in 0..n {
                    sim.set_time(t0 + (i + 1) as f64 * dt)?;
                    sim.set_states(std::hint::black_box(y.as_slice()))?;
                    sim.derivatives(dydt.as_mut_slice())?;
                    for (y, &f) in y.as_mut_slice().iter_mut().zip(dydt.as_slice()) {
                        *y += dt * f;
                    }
                }
                sum = y.as_slice().first().copied().unwrap_or(0.0);
            }
            Part::Point => {
                let mut values = sim.values.clone();
                for i in 0..n {
                    values.set_time(t0 + (i + 1) as f64 * h);
                    complete_point::<M>(std::hint::black_box(&mut values));
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

#[cfg(test)]
mod tests {
    use super::Part;
    use crate::model::Declaration;
    use crate::model::{Experiment, Layout, Mechanism, Scalar, Variable};
    use crate::simulation::Simulation;

    crate::mechanism! {
        /// A driven oscillator: its derivatives depend on the time and on both states.
        pub struct Driven / DrivenValues {
            /// Stiffness
            k: Variable::parameter("N/m", 30.0).min(0.0),
            /// Position
            x: Variable::state("m", 0.5, "v"),
            /// Velocity
            v: Variable::state("m/s", 0.0, "a"),
            /// Acceleration
            a: Variable::output("m/s2"),
        }
    }

    impl Mechanism for Driven {
        const EXPERIMENT: Experiment = Experiment::until(10.0).step(0.01).tolerance(1e-6);

        fn evaluate<S: Scalar>(v: &mut DrivenValues<S>) {
            v.a = v.time.sin() - v.k * v.x - crate::model::lit::<S>(0.1) * v.v;
        }
    }

    fn started() -> Simulation<Driven> {
        let mut sim = Simulation::<Driven>::new(Layout::new(Driven::VARIABLES).unwrap());
        sim.setup(None, 0.0).unwrap();
        sim.update().unwrap();
        sim
    }

    /// `mechfmu bench` compares the Model Exchange calls with the equations alone at the
    /// same points: `Part::Evaluate`, `Part::ModelExchange` and an importer's walk through
    /// the calls (`t0 + (i + 1) h / n`, `x + dt dx`) end on the same state bit for bit.
    #[test]
    fn the_model_exchange_walks_visit_the_points_of_part_evaluate() {
        let sim = started();
        let (n, span) = (1000, 2.0);
        let evaluate = sim.bench(Part::Evaluate, n, span).unwrap();
        let me = sim.bench(Part::ModelExchange, n, span).unwrap();
        assert_eq!(evaluate.to_bits(), me.to_bits());
        // The importer's walk, on the simulation itself.
        let mut sim = started();
        let (t0, dt) = (sim.time(), span / n as f64);
        let mut x = [0.0; 2];
        sim.states(&mut x);
        let mut dx = [0.0; 2];
        for i in 0..n {
            sim.set_time(t0 + (i + 1) as f64 * dt).unwrap();
            sim.set_states(&x).unwrap();
            sim.derivatives(&mut dx).unwrap();
            for (x, d) in x.iter_mut().zip(dx) {
                *x += dt * d;
            }
        }
        assert_eq!(x[0].to_bits(), evaluate.to_bits());
        // Every point was new: one evaluation each.
        assert_eq!(
            sim.counters().evaluations - started().counters().evaluations,
            n
        );
        assert_ne!(x[0], 0.5, "the walk moved");
        assert_eq!(Part::from_code(16), Some(Part::ModelExchange));
    }
}
