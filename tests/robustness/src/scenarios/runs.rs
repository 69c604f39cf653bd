//! Long runs, and runs to compare bit for bit across threads, of FMI 2.0 FMUs.

use super::MeIntegrator;
use crate::ffi::*;
use crate::fmu::{Fmu, VariableExt};
use crate::importer::{rss_bytes, Instance};
use std::time::Instant;

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
    let e = fmu.md.experiment;
    let (vrs, values): (Vec<u32>, Vec<f64>) = pushed_inputs(fmu).into_iter().unzip();
    if inst.setup(Some(tol), e.start, None) != OK
        || inst.enter_init() != OK
        || inst.set_real(&vrs, &values) != OK
        || inst.exit_init() != OK
    {
        return Err(format!("initialization: {}", inst.log_tail()));
    }
    MeIntegrator::fingerprint(&mut inst, h, steps, Instance::all_values)
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
    let e = fmu.md.experiment;
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
