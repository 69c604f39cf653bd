//! How much the benchmark measures, and where: the runs of a figure, the steps of a run,
//! and the instances and stack depths the runs take turns on.

use crate::binary::Binary;

/// How much to measure.
#[derive(Clone, Copy, Debug)]
pub struct Effort {
    /// Timed runs per figure (the median is reported).
    pub runs: usize,
    /// At most this many communication steps per run.
    pub max_steps: usize,
    /// Calls per timed run of `fmi2GetReal`/`fmi2SetReal`.
    pub calls: usize,
}

impl Effort {
    /// A smoke test (`--quick`): few runs and short loops.
    pub fn quick() -> Effort {
        Effort {
            runs: 3,
            max_steps: 2_000,
            calls: 2_000,
        }
    }

    /// The measurement: `runs` timed runs per figure (at least one).
    pub fn full(runs: usize) -> Effort {
        Effort {
            runs: runs.max(1),
            max_steps: 100_000,
            calls: 20_000,
        }
    }

    /// A probe under valgrind: one run of at most `max_steps` steps, whose instruction count
    /// repeats (the probe makes its own calls).
    pub fn probe(max_steps: usize) -> Effort {
        Effort {
            runs: 1,
            max_steps,
            calls: 0,
        }
    }
}

/// The number of steps of size `h` a run takes: the DefaultExperiment's interval, capped.
pub fn steps_per_run(binary: &Binary, h: f64, effort: Effort) -> usize {
    let d = &binary.description;
    (((d.stop - d.start) / h).round() as usize).clamp(10, effort.max_steps)
}

/// Instances (and stack depths) a configuration's runs take turns on.
///
/// Where an instance lands in memory can cost its every step a few percent, for as long as
/// it lives (seen: PendulumCart at h 1e-3, tol 1e-6, 238 ns in all 11 runs of one instance,
/// 225-226 in the other processes; TwoMassOscillator 123 for 115), and so can the stack
/// depth the parts and steps run at for a whole process (TwoMassOscillator's solver loop
/// alone 30 ns slower in every configuration of one process). An importer's instance
/// lands anywhere: taking turns over three of each, no one placement decides a median.
pub const PLACEMENTS: usize = 3;

/// Runs `f` `depth` frames of 1104 bytes further down the stack: a new offset both within
/// the 4 KiB page and within the 64-byte cache line for the stack the timed code uses.
#[inline(never)]
pub fn deeper<R>(depth: usize, f: &mut dyn FnMut() -> R) -> R {
    if depth == 0 {
        return f();
    }
    let pad = std::hint::black_box([0u8; 1104]);
    let result = deeper(depth - 1, f);
    std::hint::black_box(&pad);
    result
}
