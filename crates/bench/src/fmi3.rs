//! `fmi3DoStep` beside `fmi2DoStep`: the same binary's FMI 3.0 Co-Simulation instance
//! ([`Instance`]), started as the FMI 2.0 one is, its steps timed in the same runs and
//! counted by the same probe.
//!
//! One binary exports both standards' functions over the same simulation, so a
//! `fmi3DoStep` and a `fmi2DoStep` do the same work and differ by their FMI layer only (the
//! four out arguments of FMI 3.0, its state table). The instance is made by
//! `fmi3InstantiateCoSimulation` (no event mode, no early return, no intermediate
//! variables) with the `instantiationToken` of the FMI 3.0 modelDescription the binary
//! renders of itself, and started with `fmi3EnterInitializationMode(tolerance, start)` (no
//! stop time) and `fmi3ExitInitializationMode`, as
//! [`crate::instance::Instance::start`] starts the FMI 2.0 one; both keep the
//! FMU's start values. [`same_run`] checks that the two end a run with the same values, bit
//! for bit (the FMU's counters refuse an FMI 3.0 instance).
//!
//! Timing: [`crate::native`] runs a configuration's `fmi3DoStep` loop right before or after
//! its `fmi2DoStep` loop (the order alternating), on the instance of the same turn and at
//! the same stack depth. Instructions: the probe [`probe`] (`--probe fmi3-step`), as the
//! `fmi2DoStep` one.

use crate::binary::Binary;
use crate::effort::{steps_per_run, Effort};
use crate::instance::{self, step_failed};
use mechfmu::fmi3::ffi::{fmi3OK, fmi3Status, fmi3Warning};
use mechfmu_host::cpu_clock::cpu_ns;
use mechfmu_host::fmi3::instance::Instance as Fmi3Instance;
use mechfmu_host::log::Log;
use std::ffi::CString;
use std::rc::Rc;

/// An FMI 3.0 Co-Simulation instance of a loaded binary.
pub struct Instance<'a> {
    pub binary: &'a Binary,
    fmi: Fmi3Instance,
    log: Rc<Log>,
}

impl<'a> Instance<'a> {
    pub fn new(binary: &'a Binary) -> Result<Instance<'a>, String> {
        let side = binary
            .fmi3
            .as_ref()
            .ok_or_else(|| format!("{} exports no FMI 3.0 functions", binary.path.display()))?;
        let name = CString::new(binary.description.model_identifier.as_str()).unwrap_or_default();
        let token = CString::new(side.token.as_str()).unwrap_or_default();
        let log = Rc::new(Log::new());
        let Some(fmi) = Fmi3Instance::instantiate(&side.functions, &name, &token, c"/tmp/", &log)
        else {
            return Err(format!(
                "fmi3InstantiateCoSimulation of {} failed: {}",
                binary.path.display(),
                warnings(&log).join("; ")
            ));
        };
        Ok(Instance { binary, fmi, log })
    }

    /// The warnings and errors the FMU logged.
    pub fn messages(&self) -> Vec<String> {
        warnings(&self.log)
    }

    fn check(&self, status: fmi3Status, what: &str) -> Result<(), String> {
        if status == fmi3OK {
            return Ok(());
        }
        Err(format!(
            "{what} returned {status}: {}",
            self.messages().join("; ")
        ))
    }

    /// `fmi3Reset` (unless fresh), `fmi3EnterInitializationMode(tolerance, start)` without a
    /// stop time, `fmi3ExitInitializationMode`: in step mode at `start`.
    pub fn start(&mut self, tolerance: f64, start: f64, reset: bool) -> Result<(), String> {
        let f = &self.fmi;
        if reset {
            self.check(f.reset(), "fmi3Reset")?;
        }
        let status = f.enter_initialization_mode(Some(tolerance), start, None);
        self.check(status, "fmi3EnterInitializationMode")?;
        let status = f.exit_initialization_mode();
        self.check(status, "fmi3ExitInitializationMode")
    }

    #[inline]
    pub fn do_step(&mut self, t: f64, h: f64) -> fmi3Status {
        self.fmi.do_step(t, h)
    }

    /// `fmi3GetFloat64` of the value references `vrs`.
    pub fn get_float64(&mut self, vrs: &[u32]) -> Result<Vec<f64>, String> {
        let mut out = vec![0.0; vrs.len()];
        let status = self.fmi.get_float64(vrs, &mut out);
        self.check(status, "fmi3GetFloat64").map(|_| out)
    }
}

/// The warnings and errors in `log`.
fn warnings(log: &Log) -> Vec<String> {
    (log.messages().iter())
        .filter(|m| m.status >= fmi3Warning)
        .map(|m| m.text.clone())
        .collect()
}

/// The timed loop of one run from a started instance: CPU ns of `n` steps of `h`.
pub fn step_loop(inst: &mut Instance, h: f64, n: usize) -> Result<f64, String> {
    let mut t = inst.binary.description.start;
    let t0 = cpu_ns();
    for _ in 0..n {
        let status = inst.do_step(t, h);
        if status > fmi3Warning {
            return Err(step_failed("fmi3DoStep", t, h, status, || inst.messages()));
        }
        t += h;
    }
    Ok((cpu_ns() - t0) as f64)
}

/// One run as [`crate::native::step_run`]: (re)start untimed, then `n` timed steps; CPU ns.
pub fn step_run(
    inst: &mut Instance,
    tol: f64,
    h: f64,
    n: usize,
    fresh: bool,
) -> Result<f64, String> {
    inst.start(tol, inst.binary.description.start, !fresh)?;
    step_loop(inst, h, n)
}

/// Whether an FMI 2.0 and an FMI 3.0 instance that ran the same steps hold the same values,
/// bit for bit: the scalar `Float64` variables of the FMI 3.0 modelDescription that the
/// FMI 2.0 one has by the same name, each read with its own version's value reference
/// (every mechanism has some: its scalar outputs; none is an error, not a pass).
pub fn same_run(two: &mut instance::Instance, three: &mut Instance) -> Result<(), String> {
    let Some(api) = three.binary.fmi3.as_ref() else {
        return Ok(());
    };
    let d = &two.binary.description;
    let common: Vec<(&str, u32, u32)> = (api.scalars.iter())
        .filter_map(|(name, vr3)| d.variable(name).map(|v| (name.as_str(), v.vr, *vr3)))
        .collect();
    if common.is_empty() {
        return Err("the FMI 2.0 and FMI 3.0 descriptions have no scalar in common".into());
    }
    let vrs2: Vec<u32> = common.iter().map(|c| c.1).collect();
    let vrs3: Vec<u32> = common.iter().map(|c| c.2).collect();
    let mut fmi2 = vec![0.0; vrs2.len()];
    let status = two.get_real(&vrs2, &mut fmi2);
    if status > mechfmu::fmi2::ffi::fmi2Warning {
        return Err(format!("fmi2GetReal returned {status}"));
    }
    let fmi3 = three.get_float64(&vrs3)?;
    let differ: Vec<String> = (common.iter().zip(fmi2.iter().zip(&fmi3)))
        .filter(|(_, (a, b))| a.to_bits() != b.to_bits())
        .map(|((name, ..), (a, b))| format!("{name} {a:e} (FMI 2.0) vs {b:e} (FMI 3.0)"))
        .collect();
    if differ.is_empty() {
        return Ok(());
    }
    Err(format!(
        "fmi3DoStep and fmi2DoStep ended the same run apart: {}",
        differ.join(", ")
    ))
}

/// The probe of `fmi3DoStep` under valgrind (`--probe fmi3-step`): a warm-up run, then
/// `repeat` runs, as the `fmi2DoStep` probe.
pub fn probe(
    binary: &Binary,
    h: f64,
    tol: f64,
    repeat: usize,
    max_steps: usize,
) -> Result<(), String> {
    let n = steps_per_run(binary, h, Effort::probe(max_steps));
    let mut inst = Instance::new(binary)?;
    step_run(&mut inst, tol, h, n, true)?;
    for _ in 0..repeat {
        step_run(&mut inst, tol, h, n, false)?;
    }
    Ok(())
}
