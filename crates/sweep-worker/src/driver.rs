//! One case, as `Runtime.run_case` and `Runtime._simulate` in
//! `python/mechfmu_sweep/runner.py` run it through FMPy (itself `fmpy.simulate_fmu`'s
//! Co-Simulation loop): the same FMI calls in the same order, the same communication
//! points, the same input values, the same summaries.

use crate::input::InputTable;
use crate::instance::{Failure, Instance};
use crate::protocol::Case;
use crate::pymath::isclose;
use crate::setup::{Setup, Source};
use crate::summary::{summarize, Series};
use mechfmu::fmi2::ffi::{fmi2Error, fmi2Fatal};
use mechfmu_host::cpu_clock::cpu_ns;
use mechfmu_host::fmi2::functions::Functions;
use mechfmu_host::library::Library;
use mechfmu_host::log::Log;
use std::rc::Rc;
use std::time::Instant;

/// A case keeps the first this many messages (as the Python runner does).
pub const LOG_LIMIT: usize = 20;

/// Rows of samples reserved up front at most; a longer case grows the buffer once.
const RESERVED_ROWS: usize = 1 << 20;

/// How long a case took: wall time and this thread's CPU time, in seconds.
#[derive(Clone, Copy, Debug)]
pub struct Timing {
    pub elapsed_s: f64,
    pub cpu_s: f64,
}

/// Runs the cases of a sweep one after another on one FMU instance, created when a case
/// needs one and replaced after a failure that leaves it unusable.
pub struct Driver {
    functions: Functions,
    /// The FMU's messages during the running case (the instances' callbacks write to it).
    log: Rc<Log>,
    instance: Option<Instance>,
    setup: Setup,
    input: InputTable,
    /// Row-major, one row per communication point: time, then the trajectory's values.
    samples: Vec<f64>,
    finals: Vec<f64>,
    summaries: Vec<f64>,
}

impl Driver {
    /// Loads the setup's library and its functions.
    pub fn new(setup: Setup) -> Result<Driver, String> {
        let functions = Library::open(&setup.library)
            .and_then(|library| Functions::load(&library))
            .map_err(|e| format!("the binary of {}: {e}", setup.model_identifier))?;
        let stride = 1 + setup.trajectory.len();
        Ok(Driver {
            functions,
            log: Rc::new(Log::keeping(LOG_LIMIT)),
            instance: None,
            input: InputTable::new(setup.inputs.len()),
            samples: Vec::with_capacity(setup.expected_points().min(RESERVED_ROWS) * stride),
            finals: vec![0.0; setup.finals.len()],
            summaries: vec![f64::NAN; setup.summaries.len()],
            setup,
        })
    }

    pub fn setup(&self) -> &Setup {
        &self.setup
    }

    /// The FMU's messages during the last case.
    pub fn log(&self) -> &Log {
        &self.log
    }

    /// The summaries of the last case (NaN when it failed).
    pub fn summaries(&self) -> &[f64] {
        &self.summaries
    }

    /// Runs one case: its failure, if any, and how long it took.
    pub fn run_case(&mut self, case: &Case) -> (Option<Failure>, Timing) {
        let (wall, cpu) = (Instant::now(), cpu_ns());
        self.log().clear();
        let failure = self.run(case).err();
        match failure {
            None if !self.setup.bare => self.summarize(),
            None => self.summaries.fill(f64::NAN),
            Some(failure) => {
                self.summaries.fill(f64::NAN);
                if failure.status >= fmi2Fatal {
                    self.instance = None; // a fatal instance is not reused
                }
            }
        }
        let timing = Timing {
            elapsed_s: wall.elapsed().as_secs_f64(),
            cpu_s: cpu_ns().saturating_sub(cpu) as f64 * 1e-9,
        };
        (failure, timing)
    }

    fn run(&mut self, case: &Case) -> Result<(), Failure> {
        let instance = ready_instance(&mut self.instance, &self.functions, &self.log, &self.setup)?;
        let has_input = case.rows > 0 && !self.setup.bare;
        if has_input {
            self.input.load(case.rows, |k| case.table.get(k));
        }
        let mut run = Run {
            instance,
            setup: &self.setup,
            input: has_input.then_some(&mut self.input),
            samples: &mut self.samples,
        };
        run.initialize(case)?;
        run.step_to_the_end()?;
        if !self.setup.finals.is_empty() && !self.setup.bare {
            instance.get_real(&self.setup.finals, &mut self.finals)?;
        }
        instance.terminate()
    }

    /// Each summary of the setup from the samples and the final values.
    fn summarize(&mut self) {
        let stride = 1 + self.setup.trajectory.len();
        let samples = &self.samples;
        for (out, summary) in self.summaries.iter_mut().zip(&self.setup.summaries) {
            *out = match summary.source {
                Source::Trajectory(j) => summarize(
                    summary.func,
                    &Series {
                        len: samples.len() / stride,
                        t: |k: usize| samples[k * stride],
                        y: |k: usize| samples[k * stride + 1 + j],
                    },
                ),
                // A single value: one sample, no span.
                Source::Final(j) => summarize(
                    summary.func,
                    &Series {
                        len: 1,
                        t: |_| 0.0,
                        y: |_| self.finals[j],
                    },
                ),
            };
        }
    }
}

/// An instance ready for a case: a new one (whose instantiation's messages are not the
/// case's, as in the Python runner), or the last case's after `fmi2Reset`. An instance that
/// cannot be reset is freed; the next case gets a new one.
fn ready_instance<'a>(
    slot: &'a mut Option<Instance>,
    functions: &Functions,
    log: &Rc<Log>,
    setup: &Setup,
) -> Result<&'a Instance, Failure> {
    let mut instance = match slot.take() {
        Some(instance) => instance,
        None => {
            let instance = Instance::instantiate(functions, log, setup)
                .ok_or(Failure::at(fmi2Error, "fmi2Instantiate"))?;
            log.clear();
            instance
        }
    };
    if instance.fresh {
        instance.fresh = false;
    } else {
        instance.reset()?;
    }
    Ok(slot.insert(instance))
}

/// One simulation from the start time to the stop time (`Runtime._simulate`).
struct Run<'a> {
    instance: &'a Instance,
    setup: &'a Setup,
    input: Option<&'a mut InputTable>,
    samples: &'a mut Vec<f64>,
}

impl Run<'_> {
    /// The experiment, the start values (those settable before initialization mode, then
    /// those settable in it), the inputs at the start time, the first sample.
    fn initialize(&mut self, case: &Case) -> Result<(), Failure> {
        let setup = self.setup;
        self.instance.setup_experiment(setup)?;
        self.set_starts(case, false)?;
        self.instance.enter_initialization_mode()?;
        self.set_starts(case, true)?;
        self.apply_inputs(setup.start_time, false)?;
        self.instance.exit_initialization_mode()?;
        self.samples.clear();
        self.sample(setup.start_time)
    }

    fn set_starts(&self, case: &Case, initialization: bool) -> Result<(), Failure> {
        for (i, start) in self.setup.starts.iter().enumerate() {
            if start.initialization == initialization {
                self.instance.set_start(start, case.starts.get(i))?;
            }
        }
        Ok(())
    }

    /// FMPy's loop: to the next regular communication point, or to the input's next step
    /// before it, clamped to the stop time; each step sampled.
    fn step_to_the_end(&mut self) -> Result<(), Failure> {
        let setup = self.setup;
        let (start, stop, interval) = (setup.start_time, setup.stop_time, setup.output_interval);
        let can_vary = setup.can_vary_step;
        let mut time = start;
        let mut n_steps: u64 = 0;
        loop {
            if time > stop || isclose(time, stop) {
                break;
            }
            let next_regular_point = start + (n_steps + 1) as f64 * interval;
            let mut next_cp = next_regular_point;
            let next_event = match &self.input {
                Some(input) => input.next_event(time),
                None => f64::INFINITY,
            };
            if can_vary && next_cp > next_event && !isclose(next_cp, next_event) {
                next_cp = next_event;
            }
            if next_cp > stop && !isclose(next_cp, stop) {
                if can_vary {
                    next_cp = stop;
                } else {
                    break;
                }
            }
            self.apply_inputs(time, true)?;
            self.instance.do_step(time, next_cp - time)?;
            time = next_cp;
            self.sample(time)?;
            if isclose(time, next_regular_point) {
                n_steps += 1;
            }
        }
        Ok(())
    }

    /// The inputs at `time`, in one `fmi2SetReal` (nothing without an input table).
    fn apply_inputs(&mut self, time: f64, after_event: bool) -> Result<(), Failure> {
        match &mut self.input {
            Some(input) => {
                let values = input.values_at(time, after_event);
                self.instance.set_real(&self.setup.inputs, values)
            }
            None => Ok(()),
        }
    }

    /// Appends a row: the time, then the trajectory's values (no call when there are none;
    /// nothing in a bare run).
    fn sample(&mut self, time: f64) -> Result<(), Failure> {
        if self.setup.bare {
            return Ok(());
        }
        let trajectory = &self.setup.trajectory;
        self.samples.push(time);
        let row = self.samples.len();
        self.samples.resize(row + trajectory.len(), 0.0);
        if trajectory.is_empty() {
            return Ok(());
        }
        self.instance.get_real(trajectory, &mut self.samples[row..])
    }
}
