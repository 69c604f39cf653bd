//! Serialized FMU states of real instances: seeds for the fuzzing corpus (`fuzz/`).

use super::{pushed_inputs, pushed_inputs3, MeIntegrator};
use crate::ffi::*;
use crate::fmu::{Fmu, Fmu3};
use crate::importer::{Instance, Instance3};

/// How [`serialized_state`] runs the instance whose state it serializes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Dump {
    /// Co-Simulation: `steps` default steps (0: right after instantiation).
    CoSimulation,
    /// Model Exchange, initialized with the [`pushed_inputs`], in event mode after
    /// `steps` RK4 steps of the default step size (0: right after initialization).
    EventMode,
    /// The same, in continuous-time mode.
    ContinuousTimeMode,
    /// FMI 3.0 only: Co-Simulation with event mode (`eventModeUsed`), in event mode after
    /// `steps` default steps (0: right after initialization).
    CoSimulationEventMode,
}

/// The serialized FMU state of an instance initialized with the defaults and stepped
/// `steps` times, as `how` says.
pub fn serialized_state(fmu: &Fmu, steps: usize, how: Dump) -> Result<Vec<u8>, String> {
    let e = fmu.md.experiment;
    let mut inst = if how == Dump::CoSimulation {
        Instance::new(fmu, "dump")
    } else {
        Instance::new_me(fmu, "dump")
    }
    .map_err(|m| format!("fmi2Instantiate: {m:?}"))?;
    if how == Dump::CoSimulationEventMode {
        return Err("an FMI 2.0 Co-Simulation instance has no event mode".into());
    }
    if how == Dump::CoSimulation {
        if steps > 0 {
            inst.initialize(&[])?;
            for n in 0..steps {
                if inst.do_step(e.start + n as f64 * e.step, e.step) != OK {
                    return Err(inst.log_tail());
                }
            }
        }
    } else {
        inst.initialize(&pushed_inputs(fmu))?;
        let mut me = MeIntegrator::start(&mut inst, e.step)?;
        for _ in 0..steps {
            me.step(&mut inst)?;
        }
        if how == Dump::EventMode && inst.enter_event_mode() != OK {
            return Err(inst.log_tail());
        }
    }
    let api = *fmu.api;
    let mut state: FmuState = std::ptr::null_mut();
    let mut size = 0;
    // SAFETY: valid pointers; the state is freed before returning.
    unsafe {
        if (api.get_fmu_state)(inst.c, &mut state) != OK
            || (api.serialized_fmu_state_size)(inst.c, state, &mut size) != OK
        {
            return Err(inst.log_tail());
        }
        let mut bytes = vec![0u8; size];
        let s = (api.serialize_fmu_state)(inst.c, state, bytes.as_mut_ptr().cast(), size);
        (api.free_fmu_state)(inst.c, &mut state);
        if s != OK {
            return Err(inst.log_tail());
        }
        Ok(bytes)
    }
}

/// The serialized FMU state of an FMI 3.0 instance initialized with the defaults and
/// stepped `steps` times, as `how` says.
pub fn serialized_state3(fmu: &Fmu3, steps: usize, how: Dump) -> Result<Vec<u8>, String> {
    let e = fmu.md.experiment;
    let mut inst = match how {
        Dump::CoSimulation => Instance3::new_cs(fmu, "dump", false, false),
        Dump::CoSimulationEventMode => Instance3::new_cs(fmu, "dump", true, false),
        Dump::EventMode | Dump::ContinuousTimeMode => Instance3::new_me(fmu, "dump"),
    }
    .map_err(|m| format!("fmi3Instantiate: {m:?}"))?;
    let step = |inst: &mut Instance3, n: usize| {
        let s = inst.do_step(e.start + n as f64 * e.step, e.step);
        if s.status == OK {
            Ok(())
        } else {
            Err(inst.log_tail())
        }
    };
    match how {
        Dump::CoSimulation if steps > 0 => {
            inst.initialize(&[])?;
            for n in 0..steps {
                step(&mut inst, n)?;
            }
        }
        Dump::CoSimulation => {}
        Dump::CoSimulationEventMode => {
            inst.initialize(&[])?;
            if steps > 0 {
                if inst.update_discrete_states().0 != OK || inst.enter_step_mode() != OK {
                    return Err(inst.log_tail());
                }
                for n in 0..steps {
                    step(&mut inst, n)?;
                }
                if inst.enter_event_mode() != OK {
                    return Err(inst.log_tail());
                }
            }
        }
        Dump::EventMode | Dump::ContinuousTimeMode => {
            inst.initialize(&pushed_inputs3(fmu))?;
            let mut me = MeIntegrator::start(&mut inst, e.step)?;
            for _ in 0..steps {
                me.step(&mut inst)?;
            }
            if how == Dump::EventMode && inst.enter_event_mode() != OK {
                return Err(inst.log_tail());
            }
        }
    }
    let mut state = inst.get_state().map_err(|_| inst.log_tail())?;
    // SAFETY: the live state just got.
    let bytes = unsafe { inst.serialize(state) };
    inst.free_state(&mut state);
    bytes.map_err(|_| inst.log_tail())
}
