//! Instantiate/initialize/step/free cycles of an FMI 2.0 FMU (what `scripts/valgrind`
//! runs): Co-Simulation, and every few cycles a Model Exchange life cycle.

use super::MeIntegrator;
use crate::ffi::*;
use crate::fmu::Fmu;
use crate::importer::Instance;

/// Every how many cycles [`cycles`] adds a Model Exchange life cycle ([`me_cycle`]). Each
/// costs about 1.2 Co-Simulation cycles (instantiation and the FMU state functions dominate
/// both; the RK4 steps are cheap), and its paths are the same every time: one in 5 keeps
/// the valgrind run within 30 % of its time without Model Exchange (+25 % instructions).
pub const ME_EVERY: usize = 5;

/// `count` full life cycles: instantiate (with the memory callbacks that abort), set a
/// parameter, initialize, 10 steps, read everything, save/serialize/deserialize/restore
/// an FMU state, a refused call of each kind, terminate or reset, free; every
/// [`ME_EVERY`]-th cycle then the same through Model Exchange ([`me_cycle`]). Returns
/// the number of FMI calls made.
pub fn cycles(fmu: &Fmu, count: usize) -> Result<u64, String> {
    let e = fmu.md.experiment;
    let vrs = fmu.md.all_vrs();
    let mut calls = 0u64;
    let mut cs_state = vec![];
    for cycle in 0..count {
        let fail =
            |what: &str, inst: &Instance| format!("cycle {cycle}: {what}\n{}", inst.log_tail());
        let mut inst = Instance::new(fmu, "cycles")
            .map_err(|m| format!("cycle {cycle}: fmi2Instantiate: {m:?}"))?;
        inst.initialize(&[])
            .map_err(|m| format!("cycle {cycle}: {m}"))?;
        calls += 4;
        let mut t = e.start;
        for _ in 0..10 {
            if inst.do_step(t, e.step) != OK {
                return Err(fail("fmi2DoStep", &inst));
            }
            t += e.step;
            calls += 1;
        }
        let (s, values) = inst.get_real(&vrs);
        if s != OK || values.iter().any(|x| x.is_nan()) {
            return Err(fail("fmi2GetReal", &inst));
        }
        // An FMU state, through its bytes and back.
        let api = *fmu.api;
        let (mut state, bytes, mut copy) =
            state_through_bytes(&inst).map_err(|m| fail(m, &inst))?;
        // SAFETY: valid pointers; the states made here are freed below.
        unsafe {
            if (api.set_fmu_state)(inst.c, copy) != OK
                || (api.free_fmu_state)(inst.c, &mut copy) != OK
                || (api.free_fmu_state)(inst.c, &mut state) != OK
            {
                return Err(fail("FMU state functions", &inst));
            }
            // A refused call allocates a message: it must be freed too.
            let bad = [0u8; 16];
            let mut none: FmuState = std::ptr::null_mut();
            if (api.deserialize_fmu_state)(inst.c, bad.as_ptr().cast(), bad.len(), &mut none)
                != ERROR
            {
                return Err(fail("fmi2DeSerializeFMUstate of garbage", &inst));
            }
            // So does a Model Exchange function refused to a Co-Simulation instance.
            let mut dx = vec![0.0; fmu.md.nx()];
            if fmu.md.model_exchange.is_some()
                && (api.get_derivatives)(inst.c, dx.as_mut_ptr(), dx.len()) != ERROR
            {
                return Err(fail(
                    "fmi2GetDerivatives of a Co-Simulation instance",
                    &inst,
                ));
            }
            cs_state = bytes;
        }
        calls += 9;
        if inst.do_step(t, e.step) != OK {
            return Err(fail("fmi2DoStep after restoring", &inst));
        }
        if cycle % 2 == 0 {
            if inst.terminate() != OK {
                return Err(fail("fmi2Terminate", &inst));
            }
            calls += 1;
        } else {
            // Reuse by reset, as FMPy's parameter sweeps do, then free from Instantiated.
            if inst.reset() != OK {
                return Err(fail("fmi2Reset", &inst));
            }
            calls += 1;
        }
        drop(inst);
        calls += 2;
        if fmu.md.model_exchange.is_some() && cycle % ME_EVERY == 0 {
            calls += me_cycle(fmu, cycle, &cs_state)?;
        }
    }
    Ok(calls)
}

/// One life cycle of a Model Exchange instance: instantiate, initialize, the event
/// iteration, continuous-time mode, the nominals, 10 RK4 steps (each with
/// fmi2CompletedIntegratorStep and fmi2GetEventIndicators), an FMU state saved in
/// continuous-time mode through its bytes and restored after two more steps (the states
/// come back bit for bit), the serialized state of a Co-Simulation instance
/// (`cs_state`) refused, fmi2DoStep refused, an event, terminate or reset, free. Returns
/// the number of FMI calls made.
pub fn me_cycle(fmu: &Fmu, cycle: usize, cs_state: &[u8]) -> Result<u64, String> {
    let fail = |what: &str, inst: &Instance| {
        format!(
            "cycle {cycle} (Model Exchange): {what}\n{}",
            inst.log_tail()
        )
    };
    let e = fmu.md.experiment;
    let mut inst = Instance::new_me(fmu, "me-cycles")
        .map_err(|m| format!("cycle {cycle}: fmi2Instantiate (Model Exchange): {m:?}"))?;
    inst.initialize(&[])
        .map_err(|m| format!("cycle {cycle} (Model Exchange): {m}"))?;
    let mut calls = 4;
    let mut me = MeIntegrator::start(&mut inst, e.step).map_err(|m| fail(&m, &inst))?;
    let mut nominals = vec![0.0; me.x.len()];
    if inst.get_nominals_of_continuous_states(&mut nominals) != OK
        || nominals.iter().any(|x| x.is_nan() || *x <= 0.0)
    {
        return Err(fail("fmi2GetNominalsOfContinuousStates", &inst));
    }
    calls += 1;
    for _ in 0..10 {
        me.step(&mut inst).map_err(|m| fail(&m, &inst))?;
    }
    let api = *fmu.api;
    let (mut state, _, mut copy) = state_through_bytes(&inst).map_err(|m| fail(m, &inst))?;
    // SAFETY: valid pointers; the states made here are freed below.
    unsafe {
        let (saved_x, saved_n) = (me.x.clone(), me.n);
        for _ in 0..2 {
            me.step(&mut inst).map_err(|m| fail(&m, &inst))?;
        }
        let mut x = vec![0.0; saved_x.len()];
        if (api.set_fmu_state)(inst.c, copy) != OK
            || inst.get_continuous_states(&mut x) != OK
            || x.iter()
                .zip(&saved_x)
                .any(|(a, b)| a.to_bits() != b.to_bits())
        {
            return Err(fail(
                "fmi2SetFMUstate in continuous-time mode: states not restored",
                &inst,
            ));
        }
        me.n = saved_n;
        me.x = x;
        // A Co-Simulation instance's state (step complete) is not this instance's.
        let mut foreign: FmuState = std::ptr::null_mut();
        if !cs_state.is_empty()
            && ((api.deserialize_fmu_state)(
                inst.c,
                cs_state.as_ptr().cast(),
                cs_state.len(),
                &mut foreign,
            ) != OK
                || (api.set_fmu_state)(inst.c, foreign) != ERROR
                || (api.free_fmu_state)(inst.c, &mut foreign) != OK)
        {
            return Err(fail(
                "a Co-Simulation state restored into a Model Exchange instance",
                &inst,
            ));
        }
        if (api.free_fmu_state)(inst.c, &mut copy) != OK
            || (api.free_fmu_state)(inst.c, &mut state) != OK
        {
            return Err(fail("fmi2FreeFMUstate", &inst));
        }
        // A Co-Simulation function refused (its message allocated and freed).
        if (api.do_step)(inst.c, me.time(), e.step, 1) != ERROR {
            return Err(fail("fmi2DoStep of a Model Exchange instance", &inst));
        }
    }
    calls += 12;
    me.step(&mut inst).map_err(|m| fail(&m, &inst))?;
    if inst.enter_event_mode() != OK {
        return Err(fail("fmi2EnterEventMode", &inst));
    }
    let (s, _) = inst.event_iteration(10);
    if !matches!(s, OK | WARNING) {
        return Err(fail("fmi2NewDiscreteStates", &inst));
    }
    calls += me.calls + 2;
    if cycle.is_multiple_of(2) {
        if inst.terminate() != OK {
            return Err(fail("fmi2Terminate", &inst));
        }
    } else if inst.reset() != OK {
        return Err(fail("fmi2Reset", &inst));
    }
    drop(inst);
    Ok(calls + 2)
}

/// An FMU state of `inst`, its bytes, and the state deserialized from them (GetFMUstate,
/// SerializedFMUstateSize, SerializeFMUstate, DeSerializeFMUstate); the caller frees both
/// states. The failed calls' names otherwise.
fn state_through_bytes(inst: &Instance) -> Result<(FmuState, Vec<u8>, FmuState), &'static str> {
    let api = *inst.fmu.api;
    let mut state: FmuState = std::ptr::null_mut();
    let mut size = 0usize;
    // SAFETY: a live instance, valid pointers, a buffer of `size` bytes.
    unsafe {
        if (api.get_fmu_state)(inst.c, &mut state) != OK
            || (api.serialized_fmu_state_size)(inst.c, state, &mut size) != OK
        {
            return Err("fmi2GetFMUstate/fmi2SerializedFMUstateSize");
        }
        let mut bytes = vec![0u8; size];
        let mut copy: FmuState = std::ptr::null_mut();
        if (api.serialize_fmu_state)(inst.c, state, bytes.as_mut_ptr().cast(), size) != OK
            || (api.deserialize_fmu_state)(inst.c, bytes.as_ptr().cast(), size, &mut copy) != OK
        {
            return Err("fmi2SerializeFMUstate/fmi2DeSerializeFMUstate");
        }
        Ok((state, bytes, copy))
    }
}
