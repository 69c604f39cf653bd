//! Instantiate/initialize/step/free cycles of an FMI 3.0 FMU (what `scripts/valgrind`
//! runs for `fmus/fmi3/`): Co-Simulation with and without event mode and early return,
//! and every few cycles a Model Exchange life cycle.

use super::{pushed_inputs3, MeIntegrator, ME_EVERY};
use crate::ffi3::*;
use crate::fmu::Fmu3;
use crate::importer::Instance3;

fn ok(what: &str, s: Status, inst: &Instance3, cycle: usize) -> Result<(), String> {
    if matches!(s, OK | WARNING) {
        Ok(())
    } else {
        Err(format!(
            "cycle {cycle}: {what} returned {}\n{}",
            status_name(s),
            inst.log_tail()
        ))
    }
}

fn refused(what: &str, s: Status, inst: &Instance3, cycle: usize) -> Result<(), String> {
    if s == ERROR {
        Ok(())
    } else {
        Err(format!(
            "cycle {cycle}: {what} returned {}, not fmi3Error\n{}",
            status_name(s),
            inst.log_tail()
        ))
    }
}

/// `count` full life cycles of Co-Simulation instances (event mode used in every other
/// cycle, early return allowed in every third): initialization with a stop time and the
/// [`pushed_inputs3`] (arrays among them), event mode (fmi3UpdateDiscreteStates,
/// fmi3EnterStepMode) when used, 10 steps, every variable read, an FMU state
/// saved/serialized/deserialized/restored/freed, refused calls of each kind (garbage
/// bytes, a Model Exchange function, a clock, a type without variables, a wrong
/// `nValues`, Scheduled Execution), event mode again, one more step, terminate or reset,
/// free; every [`ME_EVERY`]-th cycle then a Model Exchange life cycle ([`me_cycle3`]).
/// Returns the number of FMI calls made.
pub fn cycles3(fmu: &Fmu3, count: usize) -> Result<u64, String> {
    let e = fmu.md.experiment;
    let vrs = fmu.md.all_vrs();
    let inputs = pushed_inputs3(fmu);
    let mut calls = 0u64;
    let mut cs_state = vec![];
    for cycle in 0..count {
        let event_mode = cycle % 2 == 1;
        let mut inst = Instance3::new_cs(fmu, "cycles", event_mode, cycle % 3 == 0)
            .map_err(|m| format!("cycle {cycle}: fmi3InstantiateCoSimulation: {m:?}"))?;
        ok(
            "fmi3EnterInitializationMode",
            inst.enter_init(Some(e.tolerance), e.start, Some(e.stop)),
            &inst,
            cycle,
        )?;
        for (vr, x) in &inputs {
            ok("fmi3SetFloat64", inst.set_float64(&[*vr], x), &inst, cycle)?;
        }
        ok("fmi3ExitInitializationMode", inst.exit_init(), &inst, cycle)?;
        calls += 3 + inputs.len() as u64;
        let event_iteration = |inst: &mut Instance3| -> Result<(), String> {
            ok(
                "fmi3UpdateDiscreteStates",
                inst.update_discrete_states().0,
                inst,
                cycle,
            )?;
            ok("fmi3EnterStepMode", inst.enter_step_mode(), inst, cycle)
        };
        if event_mode {
            event_iteration(&mut inst)?;
            calls += 2;
        }
        let mut t = e.start;
        for _ in 0..10 {
            ok("fmi3DoStep", inst.do_step(t, e.step).status, &inst, cycle)?;
            t += e.step;
        }
        let (s, values) = inst.get_float64(&vrs);
        if s != OK || values.iter().any(|x| x.is_nan()) {
            return Err(format!(
                "cycle {cycle}: fmi3GetFloat64 of every variable: {}",
                inst.log_tail()
            ));
        }
        calls += 11;
        // An FMU state, through its bytes and back.
        let mut state = inst.get_state().map_err(|_| inst.log_tail())?;
        // SAFETY: the live state just got.
        let bytes = unsafe { inst.serialize(state) }.map_err(|_| inst.log_tail())?;
        let mut copy = inst.deserialize(&bytes).map_err(|_| inst.log_tail())?;
        // SAFETY: the live state just deserialized.
        ok(
            "fmi3SetFMUState",
            unsafe { inst.set_state(copy) },
            &inst,
            cycle,
        )?;
        ok("fmi3FreeFMUState", inst.free_state(&mut copy), &inst, cycle)?;
        ok(
            "fmi3FreeFMUState",
            inst.free_state(&mut state),
            &inst,
            cycle,
        )?;
        cs_state = bytes;
        calls += 7;
        // Refused calls allocate messages: they must be freed too.
        refused(
            "fmi3DeserializeFMUState of garbage",
            inst.deserialize(&[0u8; 16]).err().unwrap_or(OK),
            &inst,
            cycle,
        )?;
        let mut dx = vec![0.0; fmu.md.nx()];
        let api = *fmu.api;
        let vr = [vrs[0]];
        let mut x = [0.0f64; 2];
        let mut clock = [0u8; 1];
        // SAFETY: a live instance, arrays of the lengths given.
        unsafe {
            refused(
                "fmi3GetContinuousStateDerivatives of Co-Simulation",
                (api.get_continuous_state_derivatives)(inst.c, dx.as_mut_ptr(), dx.len()),
                &inst,
                cycle,
            )?;
            refused(
                "fmi3GetClock",
                (api.get_clock)(inst.c, vr.as_ptr(), 1, clock.as_mut_ptr().cast()),
                &inst,
                cycle,
            )?;
            refused(
                "fmi3GetFloat32",
                (api.get_float32)(inst.c, vr.as_ptr(), 1, x.as_mut_ptr().cast(), 1),
                &inst,
                cycle,
            )?;
            refused(
                "fmi3SetFloat64 with a wrong nValues",
                (api.set_float64)(inst.c, vr.as_ptr(), 1, x.as_ptr(), 2),
                &inst,
                cycle,
            )?;
            let name = c"cycles";
            let token = std::ffi::CString::new(fmu.md.instantiation_token.as_str()).unwrap();
            let sink = &*inst.sink as *const crate::importer::Sink as Env;
            let se = (api.instantiate_scheduled_execution)(
                name.as_ptr(),
                token.as_ptr(),
                std::ptr::null(),
                false,
                false,
                sink,
                Some(crate::importer::record3),
                None,
                None,
                None,
            );
            if !se.is_null() {
                return Err(format!(
                    "cycle {cycle}: fmi3InstantiateScheduledExecution returned an instance"
                ));
            }
        }
        calls += 6;
        if event_mode {
            ok("fmi3EnterEventMode", inst.enter_event_mode(), &inst, cycle)?;
            event_iteration(&mut inst)?;
            calls += 3;
        }
        ok(
            "fmi3DoStep after restoring",
            inst.do_step(t, e.step).status,
            &inst,
            cycle,
        )?;
        if cycle % 2 == 0 {
            ok("fmi3Terminate", inst.terminate(), &inst, cycle)?;
        } else {
            // Reuse by reset, then free from Instantiated.
            ok("fmi3Reset", inst.reset(), &inst, cycle)?;
        }
        drop(inst);
        calls += 4;
        if fmu.md.model_exchange.is_some() && cycle % ME_EVERY == 0 {
            calls += me_cycle3(fmu, cycle, &cs_state)?;
        }
    }
    Ok(calls)
}

/// One life cycle of an FMI 3.0 Model Exchange instance: instantiate, initialize with the
/// [`pushed_inputs3`], the event iteration, continuous-time mode, the nominals and
/// counts, 10 RK4 steps (each with fmi3CompletedIntegratorStep and
/// fmi3GetEventIndicators), an FMU state saved in continuous-time mode through its bytes
/// and restored after two more steps (the states come back bit for bit), the serialized
/// state of a Co-Simulation instance (`cs_state`) refused, fmi3DoStep refused, an event,
/// terminate or reset, free. Returns the number of FMI calls made.
pub fn me_cycle3(fmu: &Fmu3, cycle: usize, cs_state: &[u8]) -> Result<u64, String> {
    let e = fmu.md.experiment;
    let mut inst = Instance3::new_me(fmu, "me-cycles")
        .map_err(|m| format!("cycle {cycle}: fmi3InstantiateModelExchange: {m:?}"))?;
    let fail = |what: &str, inst: &Instance3| {
        format!(
            "cycle {cycle} (Model Exchange): {what}\n{}",
            inst.log_tail()
        )
    };
    let inputs = pushed_inputs3(fmu);
    inst.initialize(&inputs).map_err(|m| fail(&m, &inst))?;
    let mut calls = 2 + inputs.len() as u64;
    let mut me = MeIntegrator::start(&mut inst, e.step).map_err(|m| fail(&m, &inst))?;
    let mut nominals = vec![0.0; me.x.len()];
    if inst.get_nominals(&mut nominals) != OK || nominals.iter().any(|x| x.is_nan() || *x <= 0.0) {
        return Err(fail("fmi3GetNominalsOfContinuousStates", &inst));
    }
    let (mut nx, mut ni) = (usize::MAX, usize::MAX);
    // SAFETY: a live instance, valid out pointers.
    let counted = unsafe {
        (fmu.api.get_number_of_continuous_states)(inst.c, &mut nx) == OK
            && (fmu.api.get_number_of_event_indicators)(inst.c, &mut ni) == OK
    };
    if !counted || (nx, ni) != (fmu.md.nx(), fmu.md.ni()) {
        return Err(fail(
            "fmi3GetNumberOfContinuousStates/EventIndicators",
            &inst,
        ));
    }
    calls += 3;
    for _ in 0..10 {
        me.step(&mut inst).map_err(|m| fail(&m, &inst))?;
    }
    let mut state = inst
        .get_state()
        .map_err(|_| fail("fmi3GetFMUState", &inst))?;
    // SAFETY: the live state just got.
    let bytes =
        unsafe { inst.serialize(state) }.map_err(|_| fail("fmi3SerializeFMUState", &inst))?;
    let mut copy = inst
        .deserialize(&bytes)
        .map_err(|_| fail("fmi3DeserializeFMUState", &inst))?;
    let (saved_x, saved_n) = (me.x.clone(), me.n);
    for _ in 0..2 {
        me.step(&mut inst).map_err(|m| fail(&m, &inst))?;
    }
    let mut x = vec![0.0; saved_x.len()];
    // SAFETY: the live state deserialized above.
    if unsafe { inst.set_state(copy) } != OK
        || inst.get_continuous_states(&mut x) != OK
        || x.iter()
            .zip(&saved_x)
            .any(|(a, b)| a.to_bits() != b.to_bits())
    {
        return Err(fail(
            "fmi3SetFMUState in continuous-time mode: states not restored",
            &inst,
        ));
    }
    me.n = saved_n;
    me.x = x;
    // A Co-Simulation instance's state is not this instance's.
    if !cs_state.is_empty() {
        let mut foreign = inst
            .deserialize(cs_state)
            .map_err(|_| fail("fmi3DeserializeFMUState of a Co-Simulation state", &inst))?;
        // SAFETY: the live state just deserialized.
        if unsafe { inst.set_state(foreign) } != ERROR || inst.free_state(&mut foreign) != OK {
            return Err(fail(
                "a Co-Simulation state restored into a Model Exchange instance",
                &inst,
            ));
        }
        calls += 3;
    }
    if inst.free_state(&mut copy) != OK || inst.free_state(&mut state) != OK {
        return Err(fail("fmi3FreeFMUState", &inst));
    }
    // A Co-Simulation function refused (its message allocated and freed).
    if inst.do_step(me.time(), e.step).status != ERROR {
        return Err(fail("fmi3DoStep of a Model Exchange instance", &inst));
    }
    calls += 8;
    me.step(&mut inst).map_err(|m| fail(&m, &inst))?;
    if inst.enter_event_mode() != OK || !matches!(inst.update_discrete_states().0, OK | WARNING) {
        return Err(fail("fmi3EnterEventMode/fmi3UpdateDiscreteStates", &inst));
    }
    calls += me.calls + 2;
    let end = if cycle.is_multiple_of(2) {
        inst.terminate()
    } else {
        inst.reset()
    };
    if end != OK {
        return Err(fail("fmi3Terminate/fmi3Reset", &inst));
    }
    drop(inst);
    Ok(calls + 2)
}
