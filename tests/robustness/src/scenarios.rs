//! Deterministic scenarios: instantiate/free cycles (for valgrind), long runs, a tour of
//! every function for the silence check, and runs compared bit for bit across threads;
//! an importer's fixed-step Model Exchange integrator ([`MeIntegrator`]) for them.

use crate::ffi::*;
use crate::fmu::Fmu;
use crate::importer::{rss_bytes, Instance};
use std::time::Instant;

/// An importer's Model Exchange integrator: fixed-step classical Runge-Kutta (RK4) through
/// fmi2SetTime, fmi2SetContinuousStates and fmi2GetDerivatives, the time of step n
/// computed as t0 + n·h; after each step fmi2CompletedIntegratorStep and
/// fmi2GetEventIndicators, and an event (fmi2EnterEventMode, the event iteration,
/// fmi2EnterContinuousTimeMode) where an indicator changes sign or the FMU asks for one
/// (no event location: the event is taken at the end of the step).
pub struct MeIntegrator {
    pub t0: f64,
    pub h: f64,
    /// Steps done.
    pub n: u64,
    /// The continuous states.
    pub x: Vec<f64>,
    /// The event indicators at the last accepted point.
    pub z: Vec<f64>,
    /// Events handled (after initialization's).
    pub events: u64,
    /// The FMU said terminateSimulation.
    pub terminated: bool,
    /// FMI calls made.
    pub calls: u64,
    k: [Vec<f64>; 4],
    tmp: Vec<f64>,
}

fn ok(what: &str, s: Status, inst: &Instance) -> Result<(), String> {
    if matches!(s, OK | WARNING) {
        Ok(())
    } else {
        Err(format!(
            "{what} returned {}\n{}",
            status_name(s),
            inst.log_tail()
        ))
    }
}

impl MeIntegrator {
    /// Takes over an initialized Model Exchange instance (in event mode): the event
    /// iteration at the start, continuous-time mode, the states and indicators.
    pub fn start(inst: &mut Instance, h: f64) -> Result<MeIntegrator, String> {
        let md = &inst.fmu.md;
        let (nx, ni) = (md.nx(), md.number_of_event_indicators);
        let mut me = MeIntegrator {
            t0: md.experiment.start,
            h,
            n: 0,
            x: vec![0.0; nx],
            z: vec![0.0; ni],
            events: 0,
            terminated: false,
            calls: 0,
            k: std::array::from_fn(|_| vec![0.0; nx]),
            tmp: vec![0.0; nx],
        };
        me.event(inst)?;
        me.events = 0;
        Ok(me)
    }

    /// The time of step `n`.
    pub fn time(&self) -> f64 {
        self.t0 + self.n as f64 * self.h
    }

    /// From event mode: the event iteration, then continuous-time mode; reads the states
    /// (the FMU may have changed them) and the indicators.
    fn event(&mut self, inst: &mut Instance) -> Result<(), String> {
        let mut iterations = 0;
        loop {
            let (s, info) = inst.new_discrete_states();
            self.calls += 1;
            ok("fmi2NewDiscreteStates", s, inst)?;
            iterations += 1;
            if info.terminate_simulation != 0 {
                self.terminated = true;
                return Ok(());
            }
            if info.new_discrete_states_needed == 0 {
                break;
            }
            if iterations == 100 {
                return Err("the event iteration did not end in 100 iterations".into());
            }
        }
        ok(
            "fmi2EnterContinuousTimeMode",
            inst.enter_continuous_time_mode(),
            inst,
        )?;
        let s = inst.get_continuous_states(&mut self.x);
        ok("fmi2GetContinuousStates", s, inst)?;
        let s = inst.get_event_indicators(&mut self.z);
        ok("fmi2GetEventIndicators", s, inst)?;
        self.calls += 3;
        self.events += 1;
        Ok(())
    }

    /// `dx` = f(t, x).
    fn f(inst: &mut Instance, t: f64, x: &[f64], dx: &mut [f64]) -> Result<(), String> {
        ok("fmi2SetTime", inst.set_time(t), inst)?;
        ok(
            "fmi2SetContinuousStates",
            inst.set_continuous_states(x),
            inst,
        )?;
        let s = inst.get_derivatives(dx);
        ok("fmi2GetDerivatives", s, inst)
    }

    /// One RK4 step (nothing once the FMU said terminateSimulation).
    pub fn step(&mut self, inst: &mut Instance) -> Result<(), String> {
        if self.terminated {
            return Ok(());
        }
        let (t, h) = (self.time(), self.h);
        let t1 = self.t0 + (self.n + 1) as f64 * h;
        let tm = t + 0.5 * h;
        let [k1, k2, k3, k4] = &mut self.k;
        let tmp = &mut self.tmp;
        Self::f(inst, t, &self.x, k1)?;
        for ((y, x), k) in tmp.iter_mut().zip(&self.x).zip(k1.iter()) {
            *y = x + 0.5 * h * k;
        }
        Self::f(inst, tm, tmp, k2)?;
        for ((y, x), k) in tmp.iter_mut().zip(&self.x).zip(k2.iter()) {
            *y = x + 0.5 * h * k;
        }
        Self::f(inst, tm, tmp, k3)?;
        for ((y, x), k) in tmp.iter_mut().zip(&self.x).zip(k3.iter()) {
            *y = x + h * k;
        }
        Self::f(inst, t1, tmp, k4)?;
        for (i, x) in self.x.iter_mut().enumerate() {
            *x += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
        ok("fmi2SetTime", inst.set_time(t1), inst)?;
        ok(
            "fmi2SetContinuousStates",
            inst.set_continuous_states(&self.x),
            inst,
        )?;
        self.calls += 14;
        self.n += 1;
        let (s, enter, terminate) = inst.completed_integrator_step(true);
        ok("fmi2CompletedIntegratorStep", s, inst)?;
        let mut z = vec![0.0; self.z.len()];
        let s = inst.get_event_indicators(&mut z);
        ok("fmi2GetEventIndicators", s, inst)?;
        self.calls += 2;
        if terminate {
            self.terminated = true;
            return Ok(());
        }
        let crossed = self.z.iter().zip(&z).any(|(a, b)| (*a > 0.0) != (*b > 0.0));
        self.z = z;
        if enter || crossed {
            ok("fmi2EnterEventMode", inst.enter_event_mode(), inst)?;
            self.calls += 1;
            self.event(inst)?;
        }
        Ok(())
    }
}

/// Every continuous input moved off its start value (by 5 % and 0.05): a mechanism at
/// rest in its default configuration then moves.
pub fn pushed_inputs(fmu: &Fmu) -> Vec<(u32, f64)> {
    fmu.md
        .variables
        .iter()
        .filter(|v| v.is("input") && v.variability == "continuous")
        .map(|v| (v.vr, v.start.unwrap_or(0.0) * 1.05 + 0.05))
        .collect()
}

/// The run of a Model Exchange instance initialized with relative tolerance `tol` and
/// the [`pushed_inputs`]: `steps` RK4 steps of `h`, the bits of the states every 10 steps
/// and of every variable every 100; then the number of events, whether the FMU ended the
/// simulation, and the final time. A run to compare across threads.
pub fn me_fingerprint(fmu: &Fmu, tol: f64, steps: u64, h: f64) -> Result<Vec<u64>, String> {
    let mut inst =
        Instance::new_me(fmu, "me-thread").map_err(|m| format!("fmi2Instantiate: {m:?}"))?;
    let e = fmu.md.experiment.clone();
    let (vrs, values): (Vec<u32>, Vec<f64>) = pushed_inputs(fmu).into_iter().unzip();
    if inst.setup(Some(tol), e.start, None) != OK
        || inst.enter_init() != OK
        || inst.set_real(&vrs, &values) != OK
        || inst.exit_init() != OK
    {
        return Err(format!("initialization: {}", inst.log_tail()));
    }
    let mut me = MeIntegrator::start(&mut inst, h)?;
    let mut out = vec![];
    for n in 0..steps {
        me.step(&mut inst)
            .map_err(|m| format!("step {n} (t = {}): {m}", me.time()))?;
        if n % 10 == 9 {
            out.extend(me.x.iter().map(|x| x.to_bits()));
        }
        if n % 100 == 99 {
            out.extend(inst.all_values().iter().map(|x| x.to_bits()));
        }
    }
    out.extend([me.events, me.terminated as u64, me.time().to_bits()]);
    Ok(out)
}

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
    let e = fmu.md.experiment.clone();
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
    let e = fmu.md.experiment.clone();
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
    let api = fmu.api;
    // SAFETY: valid pointers; the states made here are freed below.
    unsafe {
        let mut state: FmuState = std::ptr::null_mut();
        let mut size = 0usize;
        if (api.get_fmu_state)(inst.c, &mut state) != OK
            || (api.serialized_fmu_state_size)(inst.c, state, &mut size) != OK
        {
            return Err(fail("fmi2GetFMUstate/fmi2SerializedFMUstateSize", &inst));
        }
        let mut bytes = vec![0u8; size];
        let mut copy: FmuState = std::ptr::null_mut();
        if (api.serialize_fmu_state)(inst.c, state, bytes.as_mut_ptr().cast(), size) != OK
            || (api.deserialize_fmu_state)(inst.c, bytes.as_ptr().cast(), size, &mut copy) != OK
        {
            return Err(fail("fmi2SerializeFMUstate/fmi2DeSerializeFMUstate", &inst));
        }
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
            new_discrete_states_needed: 0,
            terminate_simulation: 0,
            nominals_of_continuous_states_changed: 0,
            values_of_continuous_states_changed: 0,
            next_event_time_defined: 0,
            next_event_time: 0.0,
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
}

/// The serialized FMU state of an instance initialized with the defaults and stepped
/// `steps` times, as `how` says.
pub fn serialized_state(fmu: &Fmu, steps: usize, how: Dump) -> Result<Vec<u8>, String> {
    let e = fmu.md.experiment.clone();
    let mut inst = if how == Dump::CoSimulation {
        Instance::new(fmu, "dump")
    } else {
        Instance::new_me(fmu, "dump")
    }
    .map_err(|m| format!("fmi2Instantiate: {m:?}"))?;
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
