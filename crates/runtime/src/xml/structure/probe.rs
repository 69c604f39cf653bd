//! The points the model structure is probed at, and the small moves of one quantity there:
//! what both the dependencies and their kinds are found with.

use crate::model::{Mechanism, ValueSet};
use crate::simulation::start_values;

/// SplitMix64: a tiny deterministic generator for the probe points.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [-1, 1).
    fn symmetric(&mut self) -> f64 {
        2.0 * self.unit() - 1.0
    }
}

/// Number of probe points: the start values and this many minus one random neighbours.
const POINTS: usize = 3;

/// The probe points, each with its calculated parameters computed: the start values at the
/// start time, then points whose time lies in the default experiment and whose inputs,
/// parameters and state start values are moved by up to 10 % (up to 0.1 from zero), within
/// their bounds and where `calculate` accepts them.
pub(super) fn points<M: Mechanism>() -> Result<Vec<M::Values<f64>>, String> {
    let experiment = M::EXPERIMENT;
    let mut start = start_values::<M>(experiment.start);
    M::calculate(&mut start)
        .map_err(|e| format!("{}: the start values are rejected: {e}", M::NAME))?;
    let span = experiment.stop - experiment.start;
    let span = if span.is_finite() && span > 0.0 {
        span
    } else {
        1.0
    };
    let mut points = vec![start];
    let mut rng = SplitMix64(0x6d65_6368_666d_7500);
    for _ in 0..100 {
        if points.len() == POINTS {
            break;
        }
        let mut p = start_values::<M>(experiment.start + span * rng.unit());
        for (vr, v) in M::VARIABLES.iter().enumerate() {
            let Some(x) = v.start else { continue };
            let scale = if x != 0.0 { x.abs() } else { 1.0 };
            let dx = 0.1 * scale * rng.symmetric();
            // Outside its bounds, the other way (a damping that starts at its minimum 0 is
            // moved up, so that the terms it multiplies show).
            if let Some(y) = [x + dx, x - dx]
                .into_iter()
                .find(|&y| v.check_value(y).is_ok())
            {
                p.set(vr, y);
            }
        }
        if M::calculate(&mut p).is_ok() {
            points.push(p);
        }
    }
    Ok(points)
}

/// `p` with `vr` moved by 1e-3 relative (1e-3 absolute from zero), upwards unless that
/// leaves its bounds or `calculate` refuses it; `None` when neither direction works.
/// `vr = VARIABLES.len()` is the time, moved upwards.
pub(super) fn perturbed<M: Mechanism>(p: &M::Values<f64>, vr: usize) -> Option<M::Values<f64>> {
    let step = |x: f64| if x != 0.0 { 1e-3 * x.abs() } else { 1e-3 };
    if vr == M::VARIABLES.len() {
        let mut q = p.clone();
        q.set_time(p.time() + step(p.time()));
        return Some(q);
    }
    let x = p.get(vr)?;
    let delta = step(x);
    let variable = &M::VARIABLES[vr];
    [x + delta, x - delta].into_iter().find_map(|y| {
        if variable.check_value(y).is_err() {
            return None;
        }
        let mut q = p.clone();
        q.set(vr, y);
        M::calculate(&mut q).ok().map(|()| q)
    })
}

/// Whether a value moved: by more than rounding (1e-10 relative), so that an expression
/// such as `m a / (m g)` does not make a dependency on `m` out of its last bits. A genuine
/// dependency moves it by about 1e-3 times its relative sensitivity.
pub(super) fn changed(a: Option<f64>, b: Option<f64>) -> bool {
    match (a, b) {
        (Some(a), Some(b)) if a.is_finite() && b.is_finite() => {
            (a - b).abs() > 1e-10 * a.abs().max(b.abs())
        }
        (Some(a), Some(b)) => !(a == b || (a.is_nan() && b.is_nan())),
        _ => false,
    }
}
