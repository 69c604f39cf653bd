//! The yardstick: the Oscillator's communication step written plainly in C
//! (`c/dopri5_oscillator.c`, compiled by this crate's build script as a C compiler compiles
//! a hand-written FMU): an adaptive Dormand–Prince 5(4) with DOPRI5's error norm and
//! step-size control, at the Oscillator's start values, landing on each communication point.
//! What an FMU's `fmi2DoStep` + one `fmi2GetReal` is held against: the same work without
//! an interface, a declaration or checks.

use crate::clock::{time, Stat};
use std::os::raw::c_int;

/// The communication step and tolerance of the comparison with C.
pub const AGAINST_C: (f64, f64) = (1e-2, 1e-6);
/// Communication steps per run of the C step: the Oscillator's default experiment (20 s).
pub const STEPS: usize = 2000;

/// The C step's state (`CStepOscillator` of the C file, field for field).
#[repr(C)]
#[derive(Default)]
struct State {
    m: f64,
    c: f64,
    k: f64,
    f0: f64,
    omega: f64,
    f: f64,
    t: f64,
    y: [f64; 2],
    k1: [f64; 2],
    h: f64,
    facold: f64,
    tol: f64,
    evaluations: u64,
    accepted: u64,
    rejected: u64,
}

extern "C" {
    fn mechfmu_c_oscillator_start(s: *mut State, tol: f64);
    fn mechfmu_c_oscillator_advance(s: *mut State, t_end: f64) -> c_int;
    fn mechfmu_c_oscillator_x(s: *const State) -> f64;
}

/// The Oscillator integrated by the C step.
pub struct COscillator {
    state: Box<State>,
}

impl COscillator {
    /// At the Oscillator's start values (t = 0), with tolerance `tol` (absolute and
    /// relative, as the FMUs use it).
    pub fn start(tol: f64) -> COscillator {
        let mut state = Box::<State>::default();
        // SAFETY: a valid, exclusively borrowed `State`, laid out as the C struct.
        unsafe { mechfmu_c_oscillator_start(&mut *state, tol) };
        COscillator { state }
    }

    /// Advances to `t_end` and reads `x`, as an importer's `fmi2DoStep` and `fmi2GetReal`.
    #[inline]
    pub fn step(&mut self, t_end: f64) -> Result<f64, String> {
        // SAFETY: as in `start`.
        let status = unsafe { mechfmu_c_oscillator_advance(&mut *self.state, t_end) };
        if status != 0 {
            return Err(format!(
                "the C step failed at t = {} (step size too small)",
                self.state.t
            ));
        }
        // SAFETY: as in `start`.
        Ok(unsafe { mechfmu_c_oscillator_x(&*self.state) })
    }

    /// The time reached.
    pub fn time(&self) -> f64 {
        self.state.t
    }

    /// The states `[x, x_dot]`.
    pub fn states(&self) -> [f64; 2] {
        self.state.y
    }

    /// Evaluations of the right-hand side, accepted and rejected steps so far.
    pub fn work(&self) -> (u64, u64, u64) {
        (
            self.state.evaluations,
            self.state.accepted,
            self.state.rejected,
        )
    }
}

/// One run: `n` communication steps of `h` from the start (the first few settle the step
/// size); the sum of the `x` read, so that nothing is optimized away.
pub fn run(h: f64, tol: f64, n: usize) -> Result<f64, String> {
    let mut oscillator = COscillator::start(tol);
    let mut sum = 0.0;
    for i in 1..=n {
        sum += oscillator.step(i as f64 * h)?;
    }
    Ok(sum)
}

/// CPU ns per communication step of the C step, the median of `runs` runs of `n` steps.
pub fn ns_per_step(h: f64, tol: f64, n: usize, runs: usize) -> Result<Stat, String> {
    let mut samples = Vec::with_capacity(runs);
    for _ in 0..runs {
        let (ns, sum) = time(|| run(h, tol, n));
        std::hint::black_box(sum?);
        samples.push(ns / n as f64);
    }
    Ok(Stat::of(&samples))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The damped free response of `m x'' + c x' + k x = 0` from x = 1, x' = 0.
    fn free_response(t: f64) -> f64 {
        let (m, c, k) = (1.0f64, 0.4f64, 4.0f64);
        let (zeta, wn) = (c / (2.0 * (m * k).sqrt()), (k / m).sqrt());
        let wd = wn * (1.0 - zeta * zeta).sqrt();
        (-zeta * wn * t).exp() * ((wd * t).cos() + zeta * wn / wd * (wd * t).sin())
    }

    #[test]
    fn the_c_step_follows_the_oscillators_closed_form_to_its_tolerance() {
        for tol in [1e-6, 1e-10] {
            let mut oscillator = COscillator::start(tol);
            let mut worst = 0.0f64;
            for i in 1..=2000 {
                let t = i as f64 * 0.01;
                let x = oscillator.step(t).unwrap();
                assert_eq!(oscillator.time(), t, "lands on the communication point");
                worst = worst.max((x - free_response(t)).abs());
            }
            assert!(worst < 100.0 * tol, "tol {tol}: error {worst:e}");
            let (evaluations, accepted, _) = oscillator.work();
            // first same as last: six evaluations per step, and one to start
            assert!(evaluations <= 6 * accepted + 1 + 6 * oscillator.work().2);
        }
    }
}
