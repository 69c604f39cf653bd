//! The FMU called from a native loop: ns per `fmi2DoStep`, the work behind it (solver
//! steps, model evaluations), the right-hand side alone, and ns per `fmi2GetReal` /
//! `fmi2SetReal`.
//!
//! Every figure is the median of repeated runs in thread CPU time ([`crate::clock`]). A run
//! of `fmi2DoStep` is one simulation of the DefaultExperiment's interval (reset, setup,
//! initialization untimed, then the timed loop of steps), so each run does the same work.

use crate::binary::Binary;
use crate::clock::{num, Stat};
use crate::effort::{deeper, steps_per_run, Effort, PLACEMENTS};
use crate::fmi3;
use crate::instance::{step_failed, Instance};
use mechfmu::fmi2::ffi::{fmi2OK, fmi2Warning};
use mechfmu::simulation::{isolate, Part, ISOLATES};
use mechfmu_host::cpu_clock::cpu_ns;
use serde_json::{json, Value};

/// `fmi2DoStep` at one communication step and tolerance, and its parts.
#[derive(Clone, Debug)]
pub struct StepFigures {
    pub h: f64,
    pub tol: f64,
    pub steps_per_run: usize,
    /// CPU ns per `fmi2DoStep`.
    pub ns: Stat,
    /// Model evaluations, accepted and rejected solver steps per `fmi2DoStep` (NaN if the
    /// binary has no counters).
    pub evals: f64,
    pub accepted: f64,
    pub rejected: f64,
    /// Per `fmi2DoStep`, the parts run alone in the FMU (`mechfmu_bench`), on the same
    /// trajectory: the same number of model evaluations (`evaluate`); of the solver's
    /// right-hand-side callbacks (`callback`: load, evaluate, read the derivatives); the
    /// solver over the same steps (`integrate`); whole steps without the FMI layer
    /// (`sim_step`). NaN runs when the binary lacks `mechfmu_bench`.
    pub evaluate_ns: Stat,
    pub callback_ns: Stat,
    pub integrate_ns: Stat,
    pub sim_step_ns: Stat,
    /// The model's work at the communication point (`point`: projection and the
    /// evaluation after it, `outputs`), which `sim_step` includes.
    pub point_ns: Stat,
    /// `fmi2DoStep` and the solver alone (`integrate`) again, each call isolated from the
    /// next (`simulation::isolate`): what they cost without overlapping each other in the
    /// processor. NaN where the processor or the binary cannot isolate calls.
    pub isolated_ns: Stat,
    pub integrate_isolated_ns: Stat,
    /// CPU ns per `fmi3DoStep` of the same binary over the same run, timed beside
    /// `fmi2DoStep` ([`crate::fmi3`]); no runs where the binary has no FMI 3.0 functions.
    pub fmi3_ns: Stat,
}

/// Where the ns of one `fmi2DoStep` go (differences of medians, so a small part can come
/// out slightly negative on a noisy machine).
#[derive(Clone, Copy, Debug)]
pub struct Split {
    /// The model's equations: `Mechanism::evaluate` at the stages, and at the
    /// communication point `project` (with its evaluation) and `outputs`.
    pub rhs: f64,
    /// What the solver's callback adds to each evaluation: the states copied in from the
    /// solver's slice and the derivatives out into its slice, its count, and the check that
    /// reuses an evaluation. (Storing the states into the named values and reading the
    /// derivatives out of them is in `rhs`: equations on named values cannot do without.)
    pub copying: f64,
    /// The solver's own arithmetic: Runge–Kutta stages, error estimate, step-size control.
    pub solver: f64,
    /// `Simulation::step` around the solver: argument and time checks, the values'
    /// snapshot, the finiteness check, the inputs' polynomials.
    pub step: f64,
    /// The FMI layer: the C call, instance and state checks, unwinding guard, stop time.
    pub fmi: f64,
}

/// The plumbing (as [`Split::runtime`]) from the loops with every call isolated: what its
/// own instructions take. The rest of the plumbing is overlap lost: back to back, the
/// solver's calls overlap each other, and the step's and FMI layer's instructions between
/// them take up the room that overlap needs.
#[derive(Clone, Copy, Debug)]
pub struct Isolated {
    /// `fmi2DoStep` isolated minus the solver isolated, the point's model work and the
    /// callback's copying (timed back to back: each evaluation waits for the last anyway).
    pub plumbing: f64,
    /// The plumbing back to back minus `plumbing`.
    pub overlap_lost: f64,
}

impl Split {
    /// Everything but the model's equations, the solver's arithmetic included (reported
    /// beside the plumbing proper, [`Split::runtime`]).
    pub fn beyond_rhs(&self) -> f64 {
        self.copying + self.solver + self.step + self.fmi
    }

    /// Plumbing proper: everything but the model's equations and the solver's arithmetic
    /// (state checks, value-reference lookup, unwinding guards, copying).
    pub fn runtime(&self) -> f64 {
        self.copying + self.step + self.fmi
    }

    /// Whether the parts the plumbing is made of came out as parts can: none below
    /// `-noise`. Where one does, the parts timed alone did not run as they do inside the
    /// step (code layout, inlining) and the plumbing cannot be judged from them.
    ///
    /// `step` and `fmi` count as one: their sum is `fmi2DoStep` minus the solver loop and
    /// the point's model work, and the `Step` part only splits it. A `Step` part that ran
    /// unlike `fmi2DoStep` (seen: 30-60 ns slower for a whole configuration, `fmi` as
    /// negative) leaves the plumbing as it is; a solver loop that ran slower than inside the
    /// step would not, and shows as a negative sum.
    pub fn adds_up(&self, noise: f64) -> bool {
        [self.copying, self.solver, self.step + self.fmi]
            .iter()
            .all(|&x| x >= -noise)
    }
}

impl StepFigures {
    /// ns per `fmi3DoStep` over ns per `fmi2DoStep` (NaN without FMI 3.0 figures).
    pub fn fmi3_ratio(&self) -> f64 {
        self.fmi3_ns.median / self.ns.median
    }

    pub fn split(&self) -> Split {
        Split {
            rhs: self.evaluate_ns.median + self.point_ns.median,
            copying: self.callback_ns.median - self.evaluate_ns.median,
            solver: self.integrate_ns.median - self.callback_ns.median,
            step: self.sim_step_ns.median - self.integrate_ns.median - self.point_ns.median,
            fmi: self.ns.median - self.sim_step_ns.median,
        }
    }

    /// The plumbing's own execution, and the overlap it costs (see [`Isolated`]).
    pub fn isolated(&self) -> Isolated {
        let s = self.split();
        let plumbing =
            self.isolated_ns.median - self.integrate_isolated_ns.median - self.point_ns.median
                + s.copying;
        Isolated {
            plumbing,
            overlap_lost: s.runtime() - plumbing,
        }
    }

    pub fn to_json(&self) -> Value {
        let s = self.split();
        let iso = self.isolated();
        json!({
            "h": self.h,
            "tol": self.tol,
            "steps_per_run": self.steps_per_run,
            "ns_per_step": self.ns.to_json(),
            "fmi3_do_step_ns_per_step": self.fmi3_ns.to_json(),
            "fmi3_over_fmi2": num(self.fmi3_ratio()),
            "evals_per_step": num(self.evals),
            "accepted_per_step": num(self.accepted),
            "rejected_per_step": num(self.rejected),
            "parts_alone_ns_per_step": {
                "evaluate": self.evaluate_ns.to_json(),
                "rhs_callback": self.callback_ns.to_json(),
                "integrate": self.integrate_ns.to_json(),
                "simulation_step": self.sim_step_ns.to_json(),
                "point": self.point_ns.to_json(),
                "do_step_isolated": self.isolated_ns.to_json(),
                "integrate_isolated": self.integrate_isolated_ns.to_json(),
            },
            "split_ns_per_step": {
                "rhs": num(s.rhs),
                "copying": num(s.copying),
                "solver": num(s.solver),
                "step": num(s.step),
                "fmi": num(s.fmi),
            },
            "rhs_ns_per_eval": num(self.evaluate_ns.median / self.evals),
            "beyond_rhs_ns_per_step": num(s.beyond_rhs()),
            "runtime_plumbing_ns_per_step": num(s.runtime()),
            "runtime_plumbing_isolated_ns_per_step": num(iso.plumbing),
            "overlap_lost_ns_per_step": num(iso.overlap_lost),
        })
    }
}

/// The timed loop of one run, from an initialized instance: CPU ns of the `n` steps and
/// the counters' change.
/// With `isolated`, each call is isolated from the next (`simulation::isolate`).
fn step_loop(
    inst: &mut Instance,
    h: f64,
    n: usize,
    isolated: bool,
) -> Result<(f64, [u64; 4]), String> {
    let before = inst.counters().unwrap_or_default();
    let mut t = inst.binary.description.start;
    let t0 = cpu_ns();
    for _ in 0..n {
        let status = inst.do_step(t, h);
        if isolated {
            isolate();
        }
        if status > fmi2Warning {
            return Err(step_failed("fmi2DoStep", t, h, status, || inst.messages()));
        }
        t += h;
    }
    let ns = (cpu_ns() - t0) as f64;
    let after = inst.counters().unwrap_or_default();
    let mut delta = [0u64; 4];
    for i in 0..4 {
        delta[i] = after[i] - before[i];
    }
    Ok((ns, delta))
}

/// One run: (re)initialization untimed, then `n` timed steps; CPU ns and the work done.
pub fn step_run(
    inst: &mut Instance,
    tol: f64,
    h: f64,
    n: usize,
    fresh: bool,
) -> Result<(f64, [u64; 4]), String> {
    let start = inst.binary.description.start;
    inst.start(tol, start, &[], !fresh)?;
    step_loop(inst, h, n, false)
}

/// One run as an importer's loop makes it: `fmi2DoStep` and one `fmi2GetReal` of `output`
/// per step, after an untimed (re)initialization; CPU ns and the sum of the values read.
pub fn step_get_run(
    inst: &mut Instance,
    tol: f64,
    h: f64,
    n: usize,
    output: u32,
) -> Result<(f64, f64), String> {
    let start = inst.binary.description.start;
    inst.start(tol, start, &[], true)?;
    let (mut t, mut sum, mut value) = (start, 0.0, [0.0]);
    let t0 = cpu_ns();
    for _ in 0..n {
        let status = inst.do_step(t, h);
        if status > fmi2Warning {
            return Err(step_failed("fmi2DoStep", t, h, status, || inst.messages()));
        }
        inst.get_real(&[output], &mut value);
        sum += value[0];
        t += h;
    }
    Ok(((cpu_ns() - t0) as f64, sum))
}

/// ns per `fmi2DoStep` + one `fmi2GetReal` (of the first output) at `(h, tol)`: the median
/// of `effort.runs` runs of [`step_get_run`].
pub fn step_get(binary: &Binary, (h, tol): (f64, f64), effort: Effort) -> Result<Stat, String> {
    let n = steps_per_run(binary, h, effort);
    let output = binary.first_output()?;
    let mut inst = Instance::new(binary)?;
    step_get_run(&mut inst, tol, h, n, output)?; // warm-up
    let mut samples = Vec::with_capacity(effort.runs);
    for _ in 0..effort.runs {
        let (ns, sum) = step_get_run(&mut inst, tol, h, n, output)?;
        std::hint::black_box(sum);
        samples.push(ns / n as f64);
    }
    Ok(Stat::of(&samples))
}

/// ns per `fmi2DoStep` at each `(h, tol)`, its work, and its parts alone.
///
/// The configurations take turns run by run rather than one after the other: a spell of
/// the machine running slow (a neighbour on the host) then costs every configuration one
/// run, which the medians leave out, instead of all the runs of whichever configuration it
/// fell on (seen: RigidBody at h 1e-2, tol 1e-10, 605 instead of 466 ns in one process of
/// 20, while three instances of it in other processes never read above 470).
pub fn step_figures(
    binary: &Binary,
    configurations: &[(f64, f64)],
    effort: Effort,
    progress: &dyn Fn(&str),
) -> Result<Vec<StepFigures>, String> {
    let mut benches = Vec::with_capacity(configurations.len());
    for &(h, tol) in configurations {
        progress(&format!(
            "fmi2DoStep at h = {h:e}, tol = {tol:e}: warming up"
        ));
        benches.push(StepBench::new(binary, h, tol, effort)?);
    }
    progress(&format!(
        "fmi2DoStep: {} timed runs of each, in turns",
        effort.runs
    ));
    if binary.fmi3.is_some() {
        progress(&format!(
            "fmi2DoStep and fmi3DoStep: {} timed runs of each, in turns",
            effort.runs
        ));
    }
    for _ in 0..effort.runs {
        for bench in &mut benches {
            bench.run()?;
        }
    }
    Ok(benches.into_iter().map(StepBench::figures).collect())
}

/// The runs of one configuration: `fmi2DoStep` and the parts alone, interleaved.
struct StepBench<'a> {
    instances: Vec<Instance<'a>>,
    /// FMI 3.0 instances of the same binary, one per placement (none without FMI 3.0).
    fmi3: Vec<fmi3::Instance<'a>>,
    /// Runs so far: the next run's instance and stack depth.
    turn: usize,
    h: f64,
    tol: f64,
    /// Steps per run.
    n: usize,
    /// The work of a run (counters: steps, accepted, rejected, evaluations).
    work: [u64; 4],
    /// Whether the binary has the parts (`mechfmu_bench`).
    parts: bool,
    /// Isolated calls where the processor has the barrier and the binary the part (a binary
    /// without part 5 answers fmi2Error to it).
    isolating: bool,
    samples: [Vec<f64>; 9],
}

impl<'a> StepBench<'a> {
    fn new(binary: &'a Binary, h: f64, tol: f64, effort: Effort) -> Result<Self, String> {
        let n = steps_per_run(binary, h, effort);
        let mut instances = Vec::with_capacity(PLACEMENTS);
        let mut work = [0; 4];
        for _ in 0..PLACEMENTS {
            let mut inst = Instance::new(binary)?;
            // Warm-up (caches, branch predictors, page faults), and the work per run (the
            // same trajectory, so the same work, on every instance).
            (_, work) = step_run(&mut inst, tol, h, n, true)?;
            instances.push(inst);
        }
        let mut fmi3 = Vec::new();
        if binary.fmi3.is_some() {
            for inst in &mut instances {
                let mut three = fmi3::Instance::new(binary)?;
                fmi3::step_run(&mut three, tol, h, n, true)?;
                fmi3::same_run(inst, &mut three)?;
                fmi3.push(three);
            }
        }
        let parts = binary.has_counters();
        let isolating =
            parts && ISOLATES && instances[0].bench(Part::IntegrateIsolated, 1, h).is_ok();
        Ok(StepBench {
            instances,
            fmi3,
            turn: 0,
            h,
            tol,
            n,
            work,
            parts,
            isolating,
            samples: Default::default(),
        })
    }

    /// One timed run of each figure, on the next instance at the next stack depth.
    /// `fmi3DoStep` runs right before the `fmi2DoStep` run in every other round of the
    /// placements, right after it in the others.
    fn run(&mut self) -> Result<(), String> {
        let placement = self.turn % PLACEMENTS;
        let fmi3_first = (self.turn / PLACEMENTS) % 2 == 1;
        self.turn += 1;
        deeper(placement, &mut || self.run_here(placement, fmi3_first))
    }

    /// One timed run of `fmi3DoStep` on the FMI 3.0 instance of `placement`.
    fn run_fmi3(&mut self, placement: usize) -> Result<(), String> {
        if let Some(three) = self.fmi3.get_mut(placement) {
            let ns = fmi3::step_run(three, self.tol, self.h, self.n, false)?;
            self.samples[8].push(ns / self.n as f64);
        }
        Ok(())
    }

    fn run_here(&mut self, placement: usize, fmi3_first: bool) -> Result<(), String> {
        let (inst, h, n) = (&mut self.instances[placement], self.h, self.n);
        let start = inst.binary.description.start;
        inst.start(self.tol, start, &[], true)?;
        if self.parts {
            // The parts alone, from the same initial point, interleaved with the step runs
            // so that all see the same machine.
            let span = n as f64 * h;
            for (k, part, count, h) in [
                (1, Part::Evaluate, self.work[3], span),
                (2, Part::Rhs, self.work[3], span),
                (3, Part::Integrate, n as u64, h),
                (4, Part::Step, n as u64, h),
                (5, Part::Point, n as u64, h),
            ] {
                let t0 = cpu_ns();
                inst.bench(part, count, h)?;
                self.samples[k].push((cpu_ns() - t0) as f64 / n as f64);
            }
        }
        if self.isolating {
            let t0 = cpu_ns();
            inst.bench(Part::IntegrateIsolated, n as u64, h)?;
            self.samples[7].push((cpu_ns() - t0) as f64 / n as f64);
            let (ns, _) = step_loop(inst, h, n, true)?;
            self.samples[6].push(ns / n as f64);
            inst.start(self.tol, start, &[], true)?;
        }
        if fmi3_first {
            self.run_fmi3(placement)?;
        }
        let inst = &mut self.instances[placement];
        let (ns, _) = step_loop(inst, h, n, false)?;
        self.samples[0].push(ns / n as f64);
        if !fmi3_first {
            self.run_fmi3(placement)?;
        }
        Ok(())
    }

    fn figures(self) -> StepFigures {
        let per_step = |k: usize| {
            if self.parts {
                self.work[k] as f64 / self.n as f64
            } else {
                f64::NAN
            }
        };
        let samples = &self.samples;
        StepFigures {
            h: self.h,
            tol: self.tol,
            steps_per_run: self.n,
            ns: Stat::of(&samples[0]),
            evals: per_step(3),
            accepted: per_step(1),
            rejected: per_step(2),
            evaluate_ns: Stat::of(&samples[1]),
            callback_ns: Stat::of(&samples[2]),
            integrate_ns: Stat::of(&samples[3]),
            sim_step_ns: Stat::of(&samples[4]),
            point_ns: Stat::of(&samples[5]),
            isolated_ns: Stat::of(&samples[6]),
            integrate_isolated_ns: Stat::of(&samples[7]),
            fmi3_ns: Stat::of(&samples[8]),
        }
    }
}

/// ns per call of `call` on an instance initialized with the default experiment and
/// stepped a little (`effort.calls` calls per timed run).
fn per_call(
    binary: &Binary,
    effort: Effort,
    mut call: impl FnMut(&mut Instance) -> u32,
) -> Result<Stat, String> {
    let d = &binary.description;
    let mut inst = Instance::new(binary)?;
    inst.start(d.tolerance, d.start, &[], false)?;
    let mut t = d.start;
    for _ in 0..10 {
        if inst.do_step(t, d.step) > fmi2Warning {
            return Err(format!("fmi2DoStep failed: {}", inst.messages().join("; ")));
        }
        t += d.step;
    }
    for _ in 0..effort.calls.min(1000) {
        call(&mut inst);
    }
    let mut samples = Vec::with_capacity(effort.runs);
    for _ in 0..effort.runs {
        let mut worst = fmi2OK;
        let t0 = cpu_ns();
        for _ in 0..effort.calls {
            worst = worst.max(call(&mut inst));
        }
        samples.push((cpu_ns() - t0) as f64 / effort.calls as f64);
        if worst != fmi2OK {
            return Err(format!(
                "the call returned {worst}: {}",
                inst.messages().join("; ")
            ));
        }
    }
    Ok(Stat::of(&samples))
}

/// ns per `fmi2GetReal` of the value references `vrs`.
pub fn get_real(binary: &Binary, vrs: &[u32], effort: Effort) -> Result<Stat, String> {
    let mut out = vec![0.0; vrs.len()];
    per_call(binary, effort, |inst| inst.get_real(vrs, &mut out))
}

/// ns per `fmi2SetReal` of the value references `vrs` to `values` (after initialization:
/// inputs and tunable parameters only).
pub fn set_real(
    binary: &Binary,
    vrs: &[u32],
    values: &[f64],
    effort: Effort,
) -> Result<Stat, String> {
    per_call(binary, effort, |inst| inst.set_real(vrs, values))
}

/// ns per co-simulation cycle as an importer runs it: set the inputs (to their start
/// values), `fmi2DoStep`, get the outputs; over the default experiment at `(h, tol)`.
pub fn cycle(binary: &Binary, h: f64, tol: f64, effort: Effort) -> Result<Stat, String> {
    let d = &binary.description;
    let inputs: Vec<u32> = d.with_causality("input").iter().map(|v| v.vr).collect();
    let input_values: Vec<f64> = d
        .with_causality("input")
        .iter()
        .map(|v| v.start.unwrap_or(0.0))
        .collect();
    let outputs: Vec<u32> = d.with_causality("output").iter().map(|v| v.vr).collect();
    let mut out = vec![0.0; outputs.len()];
    let n = steps_per_run(binary, h, effort);
    let mut inst = Instance::new(binary)?;
    let mut samples = Vec::with_capacity(effort.runs);
    for run in 0..=effort.runs {
        inst.start(tol, d.start, &[], run > 0)?;
        let mut t = d.start;
        let mut worst = fmi2OK;
        let t0 = cpu_ns();
        for _ in 0..n {
            if !inputs.is_empty() {
                worst = worst.max(inst.set_real(&inputs, &input_values));
            }
            worst = worst.max(inst.do_step(t, h));
            worst = worst.max(inst.get_real(&outputs, &mut out));
            t += h;
        }
        let ns = (cpu_ns() - t0) as f64 / n as f64;
        if worst > fmi2Warning {
            return Err(format!("the cycle failed: {}", inst.messages().join("; ")));
        }
        if run > 0 {
            samples.push(ns);
        }
    }
    Ok(Stat::of(&samples))
}

#[cfg(test)]
mod tests {
    use super::Split;

    fn split(copying: f64, solver: f64, step: f64, fmi: f64) -> Split {
        Split {
            rhs: 100.0,
            copying,
            solver,
            step,
            fmi,
        }
    }

    #[test]
    fn the_plumbing_is_judged_from_the_parts_it_is_made_of() {
        assert!(split(1.0, 40.0, 10.0, 8.0).adds_up(10.0));
        // The `Step` part alone ran slow: step and fmi move, their sum does not.
        assert!(split(1.0, 40.0, 56.0, -28.0).adds_up(10.0));
        // The callback's walk ran faster than the evaluations it calls.
        assert!(!split(-24.0, 80.0, 3.0, 4.0).adds_up(10.0));
        // The solver loop ran slower than fmi2DoStep itself.
        assert!(!split(1.0, 60.0, -20.0, 5.0).adds_up(10.0));
        assert!(!split(1.0, -11.0, 10.0, 8.0).adds_up(10.0));
    }
}
