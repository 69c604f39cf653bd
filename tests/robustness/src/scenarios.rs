//! Deterministic scenarios: instantiate/free cycles (for valgrind), long runs, a tour of
//! every function for the silence check, and runs compared bit for bit across threads.

use crate::ffi::*;
use crate::fmu::Fmu;
use crate::importer::{rss_bytes, Instance};
use std::time::Instant;

/// `count` full life cycles: instantiate (with the memory callbacks that abort), set a
/// parameter, initialize, 10 steps, read everything, save/serialize/deserialize/restore
/// an FMU state, terminate, free. Returns the number of FMI calls made.
pub fn cycles(fmu: &Fmu, count: usize) -> Result<u64, String> {
    let e = fmu.md.experiment.clone();
    let vrs = fmu.md.all_vrs();
    let mut calls = 0u64;
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
        let api = fmu.api;
        let mut state: FmuState = std::ptr::null_mut();
        let mut size = 0usize;
        // SAFETY: valid pointers; the states made here are freed below.
        unsafe {
            if (api.get_fmu_state)(inst.c, &mut state) != OK
                || (api.serialized_fmu_state_size)(inst.c, state, &mut size) != OK
            {
                return Err(fail("fmi2GetFMUstate/fmi2SerializedFMUstateSize", &inst));
            }
            let mut bytes = vec![0u8; size];
            let mut copy: FmuState = std::ptr::null_mut();
            if (api.serialize_fmu_state)(inst.c, state, bytes.as_mut_ptr().cast(), size) != OK
                || (api.deserialize_fmu_state)(inst.c, bytes.as_ptr().cast(), size, &mut copy) != OK
                || (api.set_fmu_state)(inst.c, copy) != OK
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
        }
        calls += 8;
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
    }
    Ok(calls)
}

/// What a long run measured.
#[derive(Debug, Clone)]
pub struct LongRun {
    pub steps: u64,
    pub h: f64,
    pub t0: f64,
    pub last_successful_time: f64,
    pub expected_time: f64,
    pub rss_before: u64,
    pub rss_after: u64,
    pub rss_samples: Vec<u64>,
    pub seconds: f64,
}

impl std::fmt::Display for LongRun {
    fn fmt(&self, w: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(
            w,
            "{} steps of h = {} from t0 = {}: fmi2LastSuccessfulTime = {:?} (t0 + n·h = {:?}), RSS {} KiB before, {} KiB after, {:.2} s ({:.2} µs/step)",
            self.steps,
            self.h,
            self.t0,
            self.last_successful_time,
            self.expected_time,
            self.rss_before / 1024,
            self.rss_after / 1024,
            self.seconds,
            1e6 * self.seconds / self.steps as f64
        )
    }
}

/// `steps` communication steps of size `h` from the default start time, the importer's
/// time computed as t0 + n·h (as FMPy does), reading every variable every step.
pub fn long_run(fmu: &Fmu, steps: u64, h: f64) -> Result<LongRun, String> {
    let mut inst = Instance::new(fmu, "long-run").map_err(|m| format!("fmi2Instantiate: {m:?}"))?;
    let t0 = fmu.md.experiment.start;
    inst.initialize(&[])?;
    let vrs = fmu.md.all_vrs();
    let mut values = vec![0.0; vrs.len()];
    let warm_up = (steps / 100).clamp(1, 1000);
    let mut rss_before = 0;
    let mut samples = vec![];
    let started = Instant::now();
    let sample_every = (steps / 10).max(1);
    for n in 0..steps {
        if n == warm_up {
            rss_before = rss_bytes().unwrap_or(0);
        }
        let t = t0 + n as f64 * h;
        let s = inst.do_step(t, h);
        if s != OK {
            return Err(format!(
                "fmi2DoStep at step {n} (t = {t}) returned {}\n{}",
                status_name(s),
                inst.log_tail()
            ));
        }
        // SAFETY: arrays of vrs.len() elements.
        let g = unsafe { (fmu.api.get_real)(inst.c, vrs.as_ptr(), vrs.len(), values.as_mut_ptr()) };
        if g != OK || values.iter().any(|x| x.is_nan()) {
            return Err(format!(
                "fmi2GetReal at step {n} returned {} or NaN",
                status_name(g)
            ));
        }
        if n % sample_every == 0 {
            samples.push(rss_bytes().unwrap_or(0));
        }
    }
    let seconds = started.elapsed().as_secs_f64();
    let rss_after = rss_bytes().unwrap_or(0);
    let (s, last) = inst.last_successful_time();
    if s != OK {
        return Err(format!(
            "fmi2GetRealStatus(fmi2LastSuccessfulTime): {}",
            status_name(s)
        ));
    }
    if !inst.messages().iter().all(|m| m.status == OK) {
        return Err(format!(
            "a long run logged warnings or errors:\n{}",
            inst.log_tail()
        ));
    }
    Ok(LongRun {
        steps,
        h,
        t0,
        last_successful_time: last,
        expected_time: t0 + steps as f64 * h,
        rss_before,
        rss_after,
        rss_samples: samples,
        seconds,
    })
}

/// Bits of every variable every 10 steps of h = 1e-3 of an instance initialized with
/// relative tolerance `tol`: a run to compare across threads.
pub fn fingerprint(fmu: &Fmu, tol: f64, steps: usize) -> Result<Vec<u64>, String> {
    let mut inst = Instance::new(fmu, "thread").map_err(|m| format!("fmi2Instantiate: {m:?}"))?;
    let e = fmu.md.experiment.clone();
    if inst.setup(Some(tol), e.start, None) != OK
        || inst.enter_init() != OK
        || inst.exit_init() != OK
    {
        return Err(format!("initialization: {}", inst.log_tail()));
    }
    let mut out = vec![];
    let h = 1e-3;
    for n in 0..steps {
        let t = e.start + n as f64 * h;
        if inst.do_step(t, h) != OK {
            return Err(format!("fmi2DoStep at t = {t}: {}", inst.log_tail()));
        }
        if n % 10 == 9 {
            out.extend(inst.all_values().iter().map(|x| x.to_bits()));
        }
    }
    Ok(out)
}

/// Every function, called right and wrong, with and without a logger: for the check that
/// an FMU prints nothing. Returns the number of calls.
pub fn tour(fmu: &Fmu) -> Result<u64, String> {
    let mut calls = 0;
    // Random sequences cover every function in every state, with hostile arguments.
    let (stats, failures) = crate::sequences::run_many(fmu, 0x5117_0000, 300, false, false);
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
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: std::ptr::null_mut(),
    };
    let api = fmu.api;
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
        let e = fmu.md.experiment.clone();
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
        (api.free_instance)(c);
        calls += 18;
    }
    Ok(calls)
}

/// The serialized FMU state of an instance initialized with the defaults and stepped
/// `steps` times (`steps` = 0: right after instantiation).
pub fn serialized_state(fmu: &Fmu, steps: usize) -> Result<Vec<u8>, String> {
    let mut inst = Instance::new(fmu, "dump").map_err(|m| format!("fmi2Instantiate: {m:?}"))?;
    let e = fmu.md.experiment.clone();
    if steps > 0 {
        inst.initialize(&[])?;
        for n in 0..steps {
            if inst.do_step(e.start + n as f64 * e.step, e.step) != OK {
                return Err(inst.log_tail());
            }
        }
    }
    let api = fmu.api;
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
