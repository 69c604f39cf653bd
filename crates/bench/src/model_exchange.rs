//! One derivative evaluation through Model Exchange: what an importer's solver pays per
//! right-hand side (`fmi2SetTime` + `fmi2SetContinuousStates` + `fmi2GetDerivatives` on the
//! exported binary), next to the model's equations alone at the same points.
//!
//! Three walks of the same trajectory, each evaluation at a new point (a new time and new
//! states: nothing an FMU could keep from the last call applies), each waiting for the last
//! one's derivatives, as a solver's stages do:
//!
//! - **API**: the benchmark calls the three exported functions per point through their C
//!   symbols and takes an explicit Euler step with the derivatives they return;
//! - **simulation** (`Part::ModelExchange`): the simulation's code behind the three calls
//!   (`Simulation::set_time`, `set_states`, `derivatives`), without the FMI layer, in the
//!   FMU's own compiled code;
//! - **equations** (`Part::Evaluate`): the minimal work any implementation does per point,
//!   the time and the states stored into the named values, `Mechanism::evaluate`, the
//!   derivatives read out of them; the walk the `fmi2DoStep` table's `rhs` comes from.
//!
//! All three walk evaluation `i` (from 0) at `t0 + (i + 1) span / n` with the states of the
//! Euler walk before it, from the instance's initial point: the same points bit for bit.
//! The overhead of Model Exchange per evaluation is API − equations, split into the FMI
//! layer (API − simulation: three C calls, instance and state checks, unwinding guards,
//! argument checks) and the simulation's Model Exchange code (simulation − equations:
//! flags, finiteness checks, copies in and out).
//!
//! Timing as for `fmi2DoStep` ([`crate::native`]): thread CPU time, the three walks
//! interleaved run by run (so a slow spell of the machine costs each one run, which the
//! median leaves out), their order rotating, and the runs taking turns over
//! [`PLACEMENTS`] instances and stack depths; [`RUNS_PER_RUN`] times as many runs.

use crate::binary::Binary;
use crate::clock::{num, Stat};
use crate::effort::{deeper, Effort, PLACEMENTS};
use crate::instance::Instance;
use mechfmu::fmi2::ffi::{fmi2OK, fmi2Status};
use mechfmu::simulation::Part;
use mechfmu_host::cpu_clock::cpu_ns;
use mechfmu_host::fmi2::instance::ModelExchange;
use serde_json::{json, Value};

/// Timed runs of each walk per run of the `fmi2DoStep` figures ([`Effort::runs`]). A run
/// of the three walks takes a few ms (a run of `fmi2DoStep` up to a second): more of them
/// spread the median over more of the machine's time, so that a slow spell of a second
/// (a neighbour on the other hyperthread slows the call-heavy API walk more than the
/// equations) costs a few runs, not half of them.
pub const RUNS_PER_RUN: usize = 3;

/// The target: ns per evaluation that Model Exchange may add to the equations.
pub const LIMIT_NS: f64 = 15.0;

/// Evaluations (points) per walk for `max_steps` ([`Effort::max_steps`]): 100 000 by
/// default, spread over the DefaultExperiment's interval (2e-4 s apart over 20 s, about
/// the spacing of a solver's stages at a step of 1e-3).
pub fn points(max_steps: usize) -> u64 {
    max_steps.max(10) as u64
}

/// ns per derivative evaluation through Model Exchange and its parts.
#[derive(Clone, Debug)]
pub struct MeFigures {
    /// Evaluations per timed run (one per point).
    pub evaluations: u64,
    /// The time span they walk: the DefaultExperiment's interval.
    pub span: f64,
    /// Model evaluations the FMU counted per point of the API walk: 1 where every point is
    /// evaluated (none reused from the last), NaN without counters.
    pub evals_per_point: f64,
    /// `fmi2SetTime` + `fmi2SetContinuousStates` + `fmi2GetDerivatives` + the Euler step.
    pub api: Stat,
    /// `Part::ModelExchange`: the simulation's code behind the three calls, no FMI layer.
    pub simulation: Stat,
    /// `Part::Evaluate`: the equations alone (states in, `evaluate`, derivatives out).
    pub equations: Stat,
}

impl MeFigures {
    /// What Model Exchange adds to the equations, ns per evaluation (NaN where the binary
    /// has no `mechfmu_bench`).
    pub fn overhead(&self) -> f64 {
        self.api.median - self.equations.median
    }

    /// The FMI layer's share of [`MeFigures::overhead`].
    pub fn fmi_layer(&self) -> f64 {
        self.api.median - self.simulation.median
    }

    /// The simulation's Model Exchange code's share of [`MeFigures::overhead`].
    pub fn simulation_code(&self) -> f64 {
        self.simulation.median - self.equations.median
    }

    /// Whether the overhead is within [`LIMIT_NS`] (None: not measured).
    pub fn met(&self) -> Option<bool> {
        let o = self.overhead();
        o.is_finite().then_some(o <= LIMIT_NS)
    }

    pub fn to_json(&self) -> Value {
        json!({
            "evaluations_per_run": self.evaluations,
            "span": self.span,
            "model_evaluations_per_point": num(self.evals_per_point),
            "ns_per_evaluation": {
                "api": self.api.to_json(),
                "simulation": self.simulation.to_json(),
                "equations": self.equations.to_json(),
            },
            "overhead_ns_per_evaluation": num(self.overhead()),
            "fmi_layer_ns_per_evaluation": num(self.fmi_layer()),
            "simulation_code_ns_per_evaluation": num(self.simulation_code()),
            "limit_ns": LIMIT_NS,
        })
    }
}

/// The walk through the exported functions: per point `fmi2SetTime`,
/// `fmi2SetContinuousStates`, `fmi2GetDerivatives`, then the Euler step to the next
/// point's states (as `Part::Evaluate` walks: the same arithmetic, `x + dt dx` without a
/// fused multiply-add, so the same points bit for bit). `x`
/// holds the initial states and is left at the last point's successor. Returns the worst
/// status of the calls.
#[inline(never)]
pub fn api_walk(
    me: &ModelExchange,
    t0: f64,
    dt: f64,
    n: u64,
    x: &mut [f64],
    dx: &mut [f64],
) -> fmi2Status {
    let nx = x.len().min(dx.len());
    let (x, dx) = (&mut x[..nx], &mut dx[..nx]);
    let mut worst = fmi2OK;
    for i in 0..n {
        worst = worst.max(me.set_time(t0 + (i + 1) as f64 * dt));
        worst = worst.max(me.set_continuous_states(x));
        worst = worst.max(me.get_derivatives(dx));
        // One value at a time (8-byte loads and stores), as a plain loop of an importer
        // does: vector accesses across the FMU's one-value stores (or the FMU's loads
        // across this loop's stores) would fail store forwarding, a cost of the compiler's
        // choosing on either side, which the walk should not add to the FMU's figures.
        for (x, d) in x.iter_mut().zip(dx.iter()) {
            // SAFETY: references to f64s of the two vectors.
            unsafe {
                let v = std::ptr::read_volatile(x) + dt * std::ptr::read_volatile(d);
                std::ptr::write_volatile(x, v);
            }
        }
    }
    worst
}

/// The walks of one mechanism, timed in turns.
struct MeBench<'a> {
    instances: Vec<Instance<'a>>,
    turn: usize,
    tol: f64,
    t0: f64,
    span: f64,
    n: u64,
    /// Whether the binary has `Part::Evaluate` and `Part::ModelExchange`.
    equations: bool,
    simulation: bool,
    x0: Vec<f64>,
    x: Vec<f64>,
    dx: Vec<f64>,
    /// Model evaluations per API walk (counters), if counted.
    evaluations: Option<u64>,
    /// ns per evaluation: api, simulation, equations.
    samples: [Vec<f64>; 3],
}

impl<'a> MeBench<'a> {
    fn new(binary: &'a Binary, effort: Effort) -> Result<Self, String> {
        let d = &binary.description;
        let n = points(effort.max_steps);
        let mut bench = MeBench {
            instances: Vec::with_capacity(PLACEMENTS),
            turn: 0,
            tol: d.tolerance,
            t0: d.start,
            span: d.stop - d.start,
            n,
            equations: false,
            simulation: false,
            x0: vec![0.0; d.states],
            x: vec![0.0; d.states],
            dx: vec![0.0; d.states],
            evaluations: None,
            samples: Default::default(),
        };
        for _ in 0..PLACEMENTS {
            bench.instances.push(Instance::model_exchange(binary)?);
        }
        // Warm-up (caches, branch predictors, page faults) of every instance and walk, and
        // whether the binary has the parts (one without them answers fmi2Error).
        for k in 0..PLACEMENTS {
            bench.restart(k)?;
            let ns = bench.instances[k].bench(Part::Evaluate, n, bench.span);
            bench.equations = ns.is_ok();
            if bench.equations {
                bench.simulation = bench.instances[k]
                    .bench(Part::ModelExchange, n, bench.span)
                    .is_ok();
            }
            bench.walk(k)?;
        }
        Ok(bench)
    }

    /// Instance `k` back at the initial point, in continuous-time mode (untimed).
    fn restart(&mut self, k: usize) -> Result<(), String> {
        let inst = &mut self.instances[k];
        inst.start(self.tol, self.t0, &[], true)?;
        inst.enter_continuous_time_mode()?;
        inst.continuous_states(&mut self.x0)
    }

    /// The API walk on instance `k` from its initial point: CPU ns per evaluation.
    fn walk(&mut self, k: usize) -> Result<f64, String> {
        let (t0, n, dt) = (self.t0, self.n, self.span / self.n as f64);
        let inst = &mut self.instances[k];
        let me = inst.me()?;
        self.x.copy_from_slice(&self.x0);
        let before = inst.counters();
        let start = cpu_ns();
        let status = api_walk(&me, t0, dt, n, &mut self.x, &mut self.dx);
        let ns = (cpu_ns() - start) as f64 / n as f64;
        if status != fmi2OK {
            return Err(format!(
                "the Model Exchange walk returned {status}: {}",
                inst.messages().join("; ")
            ));
        }
        if let (Some(before), Some(after)) = (before, inst.counters()) {
            self.evaluations = Some(after[3] - before[3]);
        }
        Ok(ns)
    }

    /// One timed run of each walk, on the next instance at the next stack depth, in the
    /// next order.
    fn run(&mut self) -> Result<(), String> {
        let placement = self.turn % PLACEMENTS;
        let order = (self.turn / PLACEMENTS) % 3;
        self.turn += 1;
        deeper(placement, &mut || self.run_here(placement, order))
    }

    fn run_here(&mut self, k: usize, order: usize) -> Result<(), String> {
        self.restart(k)?;
        for w in 0..3 {
            match (w + order) % 3 {
                0 => {
                    let ns = self.walk(k)?;
                    self.samples[0].push(ns);
                }
                part => {
                    let (part, available) = if part == 1 {
                        (Part::ModelExchange, self.simulation)
                    } else {
                        (Part::Evaluate, self.equations)
                    };
                    if available {
                        let start = cpu_ns();
                        self.instances[k].bench(part, self.n, self.span)?;
                        let ns = (cpu_ns() - start) as f64 / self.n as f64;
                        self.samples[if part == Part::ModelExchange { 1 } else { 2 }].push(ns);
                    }
                }
            }
        }
        Ok(())
    }

    fn figures(self) -> MeFigures {
        MeFigures {
            evaluations: self.n,
            span: self.span,
            evals_per_point: self
                .evaluations
                .map_or(f64::NAN, |e| e as f64 / self.n as f64),
            api: Stat::of(&self.samples[0]),
            simulation: Stat::of(&self.samples[1]),
            equations: Stat::of(&self.samples[2]),
        }
    }
}

/// ns per derivative evaluation through Model Exchange, and the equations alone at the
/// same points; `Ok(None)` if the binary does not provide Model Exchange.
pub fn figures(
    binary: &Binary,
    effort: Effort,
    progress: &dyn Fn(&str),
) -> Result<Option<MeFigures>, String> {
    if !binary.fmi2.has_model_exchange() || !binary.description.model_exchange {
        return Ok(None);
    }
    progress("Model Exchange: warming up");
    let mut bench = MeBench::new(binary, effort)?;
    let runs = effort.runs * RUNS_PER_RUN;
    progress(&format!(
        "Model Exchange: {runs} timed runs of {} evaluations through the API, the simulation and the equations, in turns",
        bench.n
    ));
    for _ in 0..runs {
        bench.run()?;
    }
    Ok(Some(bench.figures()))
}
