//! A tour of every function, right and wrong, with and without a logger: for the check
//! that an FMU prints nothing.

use crate::ffi::*;
use crate::ffi3::boolean_out;
use crate::fmu::{Fmu, Fmu3};
use crate::sequences::{run_many, Fmi2, Fmi3};

/// Every function, called right and wrong, with and without a logger: for the check that
/// an FMU prints nothing. Returns the number of calls.
pub fn tour(fmu: &Fmu) -> Result<u64, String> {
    let mut calls = 0;
    // Random sequences cover every function in every state, with hostile arguments.
    let (stats, failures) = run_many::<Fmi2>(fmu, 0x5117_0000, 300, false, false);
    if let Some(f) = failures.first() {
        return Err(f.clone());
    }
    calls += stats.calls;
    // And a scripted run with no logger at all: failures must stay silent, not go to
    // stderr instead.
    let name = c"silent";
    let guid = std::ffi::CString::new(fmu.md.guid.as_str()).unwrap();
    let cb = CallbackFunctions {
        logger: None,
        allocateMemory: None,
        freeMemory: None,
        stepFinished: None,
        componentEnvironment: std::ptr::null_mut(),
    };
    let api = *fmu.api;
    // SAFETY: valid arguments, then calls on the live instance; freed at the end.
    unsafe {
        let bad = (api.instantiate)(
            name.as_ptr(),
            CO_SIMULATION,
            c"wrong".as_ptr(),
            std::ptr::null(),
            &cb,
            1,
            1,
        );
        if !bad.is_null() {
            return Err("fmi2Instantiate accepted a wrong GUID".into());
        }
        let c = (api.instantiate)(
            name.as_ptr(),
            CO_SIMULATION,
            guid.as_ptr(),
            std::ptr::null(),
            &cb,
            1,
            1,
        );
        if c.is_null() {
            return Err("fmi2Instantiate without a logger failed".into());
        }
        let e = fmu.md.experiment;
        let vr = [fmu.md.vr_end() + 5];
        let mut x = [0.0];
        let _ = (api.do_step)(c, 0.0, 0.1, 1); // illegal: instantiated
        let _ = (api.get_real)(c, vr.as_ptr(), 1, x.as_mut_ptr());
        let _ = (api.setup_experiment)(c, 1, -1.0, 0.0, 0, 0.0);
        let _ = (api.setup_experiment)(c, 1, e.tolerance, e.start, 0, 0.0);
        let _ = (api.enter_initialization_mode)(c);
        let _ = (api.set_real)(c, vr.as_ptr(), 1, x.as_ptr());
        let _ = (api.exit_initialization_mode)(c);
        let _ = (api.do_step)(c, e.start, -1.0, 1);
        let _ = (api.do_step)(c, f64::NAN, e.step, 1);
        let _ = (api.do_step)(c, e.start, e.step, 1);
        let _ = (api.get_integer)(c, vr.as_ptr(), 1, std::ptr::null_mut());
        let _ = (api.get_string_status)(c, PENDING_STATUS, std::ptr::null_mut());
        let _ = (api.terminate)(c);
        let _ = (api.terminate)(c);
        let _ = (api.get_derivatives)(c, x.as_mut_ptr(), 1); // a Model Exchange function
        (api.free_instance)(c);
        calls += 19;
        if fmu.md.model_exchange.is_none() {
            return Ok(calls);
        }
        // The same through Model Exchange, right and wrong, without a logger.
        let c = (api.instantiate)(
            name.as_ptr(),
            MODEL_EXCHANGE,
            guid.as_ptr(),
            std::ptr::null(),
            &cb,
            1,
            1,
        );
        if c.is_null() {
            return Err("fmi2Instantiate (Model Exchange) without a logger failed".into());
        }
        let (nx, ni) = (fmu.md.nx(), fmu.md.number_of_event_indicators);
        let mut xs = vec![0.0; nx + 1];
        let mut z = vec![0.0; ni + 1];
        let mut info = EventInfo {
            newDiscreteStatesNeeded: 0,
            terminateSimulation: 0,
            nominalsOfContinuousStatesChanged: 0,
            valuesOfContinuousStatesChanged: 0,
            nextEventTimeDefined: 0,
            nextEventTime: 0.0,
        };
        let (mut enter, mut terminate) = (0, 0);
        let _ = (api.get_nominals_of_continuous_states)(c, xs.as_mut_ptr(), nx);
        let _ = (api.set_time)(c, 1.0); // illegal: instantiated
        let _ = (api.setup_experiment)(c, 1, e.tolerance, e.start, 0, 0.0);
        let _ = (api.enter_initialization_mode)(c);
        let _ = (api.get_event_indicators)(c, z.as_mut_ptr(), ni);
        let _ = (api.exit_initialization_mode)(c);
        let _ = (api.new_discrete_states)(c, &mut info);
        let _ = (api.new_discrete_states)(c, std::ptr::null_mut());
        let _ = (api.enter_continuous_time_mode)(c);
        let _ = (api.get_continuous_states)(c, xs.as_mut_ptr(), nx);
        let _ = (api.get_continuous_states)(c, xs.as_mut_ptr(), nx + 1); // wrong nx
        let _ = (api.set_time)(c, f64::NAN);
        let _ = (api.set_time)(c, e.start + e.step);
        let mut bad = xs.clone();
        bad[0] = f64::INFINITY;
        let _ = (api.set_continuous_states)(c, bad.as_ptr(), nx);
        let _ = (api.set_continuous_states)(c, xs.as_ptr(), nx);
        let _ = (api.get_derivatives)(c, xs.as_mut_ptr(), nx);
        let _ = (api.get_event_indicators)(c, z.as_mut_ptr(), ni + 1); // wrong ni
        let _ = (api.completed_integrator_step)(c, 1, &mut enter, &mut terminate);
        let _ = (api.completed_integrator_step)(c, 1, std::ptr::null_mut(), &mut terminate);
        let _ = (api.do_step)(c, e.start, e.step, 1); // a Co-Simulation function
        let _ = (api.enter_event_mode)(c);
        let _ = (api.terminate)(c);
        let _ = (api.get_derivatives)(c, xs.as_mut_ptr(), nx);
        (api.free_instance)(c);
        calls += 25;
    }
    Ok(calls)
}

/// The same for an FMI 3.0 FMU: random sequences, then a scripted run of both interface
/// types with no logger, right and wrong. Returns the number of calls.
pub fn tour3(fmu: &Fmu3) -> Result<u64, String> {
    let (stats, failures) = run_many::<Fmi3>(fmu, 0x5117_0000, 300, false, false);
    if let Some(f) = failures.first() {
        return Err(f.clone());
    }
    let mut calls = stats.calls;
    let name = c"silent";
    let token = std::ffi::CString::new(fmu.md.instantiation_token.as_str()).unwrap();
    let api = *fmu.api;
    let e = fmu.md.experiment;
    let vr = [fmu.md.vr_end() + 5];
    let (nx, ni) = (fmu.md.nx(), fmu.md.ni());
    let mut x = vec![0.0; nx + ni + 2];
    let (mut a, mut b, mut c_, mut t) = (0u8, 0u8, 0u8, 0.0);
    let mut f = [0u8; 5];
    // the bytes the FMU writes its booleans into, as the header's `fmi3Boolean*`
    let (a, b, c_) = (
        boolean_out(&mut a),
        boolean_out(&mut b),
        boolean_out(&mut c_),
    );
    let f = f.as_mut_ptr();
    let f: [*mut bool; 5] = std::array::from_fn(|k| f.wrapping_add(k).cast());
    // SAFETY: valid arguments, then calls on the live instances; freed at the end.
    unsafe {
        let bad = (api.instantiate_co_simulation)(
            name.as_ptr(),
            c"wrong".as_ptr(),
            std::ptr::null(),
            true,
            true,
            false,
            false,
            std::ptr::null(),
            0,
            std::ptr::null_mut(),
            None,
            None,
        );
        if !bad.is_null() {
            return Err("fmi3InstantiateCoSimulation accepted a wrong token".into());
        }
        let se = (api.instantiate_scheduled_execution)(
            name.as_ptr(),
            token.as_ptr(),
            std::ptr::null(),
            true,
            true,
            std::ptr::null_mut(),
            None,
            None,
            None,
            None,
        );
        if !se.is_null() {
            return Err("fmi3InstantiateScheduledExecution returned an instance".into());
        }
        let c = (api.instantiate_co_simulation)(
            name.as_ptr(),
            token.as_ptr(),
            std::ptr::null(),
            true,
            true,
            true,
            true,
            std::ptr::null(),
            0,
            std::ptr::null_mut(),
            None,
            None,
        );
        if c.is_null() {
            return Err("fmi3InstantiateCoSimulation without a logger failed".into());
        }
        let _ = (api.do_step)(c, 0.0, 0.1, true, a, b, c_, &mut t); // illegal
        let _ = (api.get_float64)(c, vr.as_ptr(), 1, x.as_mut_ptr(), 1);
        let _ = (api.enter_initialization_mode)(c, true, -1.0, e.start, false, 0.0);
        let _ = (api.enter_initialization_mode)(c, true, e.tolerance, e.start, false, 0.0);
        let _ = (api.set_float64)(c, vr.as_ptr(), 1, x.as_ptr(), 1);
        let _ = (api.exit_initialization_mode)(c);
        let _ = (api.do_step)(c, e.start, e.step, true, a, b, c_, &mut t); // event mode
        let _ = (api.update_discrete_states)(c, f[0], f[1], f[2], f[3], f[4], &mut t);
        let _ = (api.enter_step_mode)(c);
        let _ = (api.do_step)(c, e.start, -1.0, true, a, b, c_, &mut t);
        let _ = (api.do_step)(
            c,
            e.start,
            e.step,
            true,
            std::ptr::null_mut(),
            b,
            c_,
            &mut t,
        );
        let _ = (api.do_step)(c, e.start, e.step, true, a, b, c_, &mut t);
        let _ = (api.get_clock)(c, vr.as_ptr(), 1, a);
        let _ = (api.enter_configuration_mode)(c);
        let _ = (api.get_int32)(c, vr.as_ptr(), 1, x.as_mut_ptr().cast(), 1);
        let _ = (api.get_continuous_states)(c, x.as_mut_ptr(), nx); // a Model Exchange function
        let _ = (api.terminate)(c);
        let _ = (api.terminate)(c);
        (api.free_instance)(c);
        calls += 20;
        if fmu.md.model_exchange.is_none() {
            return Ok(calls);
        }
        let c = (api.instantiate_model_exchange)(
            name.as_ptr(),
            token.as_ptr(),
            std::ptr::null(),
            true,
            true,
            std::ptr::null_mut(),
            None,
        );
        if c.is_null() {
            return Err("fmi3InstantiateModelExchange without a logger failed".into());
        }
        let _ = (api.set_time)(c, 1.0); // illegal: instantiated
        let _ = (api.enter_initialization_mode)(c, true, e.tolerance, e.start, false, 0.0);
        let _ = (api.get_event_indicators)(c, x.as_mut_ptr(), ni);
        let _ = (api.exit_initialization_mode)(c);
        let _ = (api.update_discrete_states)(c, f[0], f[1], f[2], f[3], f[4], &mut t);
        let _ = (api.enter_continuous_time_mode)(c);
        let _ = (api.get_continuous_states)(c, x.as_mut_ptr(), nx + 1); // wrong nx
        let _ = (api.set_time)(c, f64::NAN);
        let _ = (api.get_continuous_states)(c, x.as_mut_ptr(), nx);
        x[0] = f64::INFINITY;
        let _ = (api.set_continuous_states)(c, x.as_ptr(), nx);
        let _ = (api.get_continuous_state_derivatives)(c, x.as_mut_ptr(), nx);
        let _ = (api.completed_integrator_step)(c, true, std::ptr::null_mut(), b);
        let _ = (api.completed_integrator_step)(c, true, a, b);
        let _ = (api.do_step)(c, e.start, e.step, true, a, b, c_, &mut t); // Co-Simulation's
        let _ = (api.enter_event_mode)(c);
        let _ = (api.terminate)(c);
        (api.free_instance)(c);
        calls += 18;
    }
    Ok(calls)
}
