//! Runs of FMI 3.0 FMUs to compare bit for bit across threads: Co-Simulation instances
//! stepped (with and without event mode) and Model Exchange instances integrated by the
//! importer's RK4.

use super::MeIntegrator;
use crate::ffi3::*;
use crate::fmu::{Fmu3, VariableExt};
use crate::importer::Instance3;

/// Every continuous input moved off its start values (each element by 5 % and 0.05), as
/// [`pushed_inputs`](super::pushed_inputs) does for FMI 2.0.
pub fn pushed_inputs3(fmu: &Fmu3) -> Vec<(u32, Vec<f64>)> {
    fmu.md
        .variables
        .iter()
        .filter(|v| v.is("input") && v.variability == "continuous")
        .map(|v| {
            let start = (0..v.len()).map(|k| v.start_at(k).unwrap_or(0.0));
            (v.vr, start.map(|x| x * 1.05 + 0.05).collect())
        })
        .collect()
}

/// Bits of every variable every 10 steps of h = 1e-3 of a Co-Simulation instance
/// initialized with relative tolerance `tol` and the [`pushed_inputs3`]; with
/// `event_mode_used`, through event mode (fmi3UpdateDiscreteStates, fmi3EnterStepMode)
/// at the start and every 1000 steps. The status and out arguments of every step are part
/// of the run, which ends where the model stops holding (a discarded step).
pub fn fingerprint3(
    fmu: &Fmu3,
    tol: f64,
    steps: usize,
    event_mode_used: bool,
) -> Result<Vec<u64>, String> {
    let mut inst = Instance3::new_cs(fmu, "thread", event_mode_used, false)
        .map_err(|m| format!("fmi3InstantiateCoSimulation: {m:?}"))?;
    let e = fmu.md.experiment;
    initialize(&mut inst, tol, e.start, fmu)?;
    let mut out = vec![];
    let h = 1e-3;
    for n in 0..steps {
        if event_mode_used && n % 1000 == 0 {
            if n > 0 && inst.enter_event_mode() != OK {
                return Err(format!("fmi3EnterEventMode: {}", inst.log_tail()));
            }
            let (s, d) = inst.update_discrete_states();
            if s != OK || inst.enter_step_mode() != OK {
                return Err(format!("event mode at step {n}: {}", inst.log_tail()));
            }
            out.extend([d.values_changed as u64, d.terminate_simulation as u64]);
        }
        let t = e.start + n as f64 * h;
        let step = inst.do_step(t, h);
        if !matches!(step.status, OK | WARNING | DISCARD) {
            return Err(format!("fmi3DoStep at t = {t}: {}", inst.log_tail()));
        }
        out.extend([
            step.status as u64,
            step.event_handling_needed as u64,
            step.terminate_simulation as u64,
            step.early_return as u64,
            step.last_successful_time.to_bits(),
        ]);
        if n % 10 == 9 || step.terminate_simulation != 0 {
            out.extend(inst.all_values().iter().map(|x| x.to_bits()));
        }
        if step.terminate_simulation != 0 {
            break; // the model stopped holding: the run ends there
        }
    }
    Ok(out)
}

/// The run of an FMI 3.0 Model Exchange instance initialized with relative tolerance
/// `tol` and the [`pushed_inputs3`]: `steps` RK4 steps of `h`, the bits of the states
/// every 10 steps and of every variable every 100; then the number of events, whether the
/// FMU ended the simulation, and the final time.
pub fn me_fingerprint3(fmu: &Fmu3, tol: f64, steps: u64, h: f64) -> Result<Vec<u64>, String> {
    let mut inst = Instance3::new_me(fmu, "me-thread")
        .map_err(|m| format!("fmi3InstantiateModelExchange: {m:?}"))?;
    let e = fmu.md.experiment;
    initialize(&mut inst, tol, e.start, fmu)?;
    MeIntegrator::fingerprint(&mut inst, h, steps, Instance3::all_values)
}

/// Initialization with relative tolerance `tol` from `start` and the [`pushed_inputs3`].
fn initialize(inst: &mut Instance3, tol: f64, start: f64, fmu: &Fmu3) -> Result<(), String> {
    let fail = |inst: &Instance3| Err(format!("initialization: {}", inst.log_tail()));
    if inst.enter_init(Some(tol), start, None) != OK {
        return fail(inst);
    }
    for (vr, x) in pushed_inputs3(fmu) {
        if inst.set_float64(&[vr], &x) != OK {
            return fail(inst);
        }
    }
    if inst.exit_init() != OK {
        return fail(inst);
    }
    Ok(())
}
