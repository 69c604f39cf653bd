//! The cost of declaring a mechanism from its energies: the hand-written mechanisms and their
//! twins declared from `T`, `V` and `Q` (`tests/energies`), each counted under valgrind in
//! the twin's test executable, which links both (its ignored `probe` test, run with the
//! settings of `mechfmu_energies::probe` in its environment): instructions per `fmi2DoStep`
//! (h 1e-2, tolerance 1e-6) and per Model Exchange evaluation (`fmi2SetTime`,
//! `fmi2SetContinuousStates`, `fmi2GetDerivatives`).
//!
//! These run the FMI functions in the test's process, not through a built binary: a twin
//! and its hand-written mechanism share one declaration, so the two cannot be two FMUs of
//! the workspace, and in one process their calls run the same code the exported symbols
//! wrap.

use crate::instructions::instructions_with;
use serde_json::{json, Value};
use std::path::{Path, PathBuf};

/// `fmi2DoStep`s or Model Exchange evaluations per probe run: `mechfmu_energies::PROBE_STEPS`
/// (a test crate, which the lab cannot depend on; a mismatch halves or doubles every count
/// of both sides alike, and the ratios stay).
const PROBE_STEPS: f64 = 1000.0;

/// The target: the twin's instructions at most this many times the hand-written one's.
pub const LIMIT: f64 = 3.0;

/// A twin's test executable, by the mechanism it declares again.
#[derive(Clone, Debug)]
pub struct TwinProbe {
    pub mechanism: String,
    pub executable: PathBuf,
}

/// Instructions of a mechanism and of its twin.
#[derive(Clone, Debug)]
pub struct EnergyCounts {
    pub mechanism: String,
    /// Per `fmi2DoStep`: (hand-written, from energies).
    pub step: (f64, f64),
    /// Per Model Exchange evaluation: (hand-written, from energies).
    pub model_exchange: (f64, f64),
}

impl EnergyCounts {
    pub fn step_ratio(&self) -> f64 {
        self.step.1 / self.step.0
    }

    pub fn model_exchange_ratio(&self) -> f64 {
        self.model_exchange.1 / self.model_exchange.0
    }

    pub fn to_json(&self) -> Value {
        json!({
            "mechanism": self.mechanism,
            "per_step": { "hand_written": self.step.0, "from_energies": self.step.1, "ratio": self.step_ratio() },
            "per_model_exchange_evaluation": {
                "hand_written": self.model_exchange.0,
                "from_energies": self.model_exchange.1,
                "ratio": self.model_exchange_ratio(),
            },
        })
    }
}

/// Counts each twin's probe: step and Model Exchange, hand-written and from energies.
pub fn count(probes: &[TwinProbe]) -> Result<Vec<EnergyCounts>, String> {
    probes
        .iter()
        .map(|p| {
            let per = |probe: &str, twin: bool| per_unit(&p.executable, probe, twin);
            Ok(EnergyCounts {
                mechanism: p.mechanism.clone(),
                step: (per("step", false)?, per("step", true)?),
                model_exchange: (per("me", false)?, per("me", true)?),
            })
        })
        .collect()
}

/// Instructions of one step or evaluation: three runs minus one, over two runs' work.
fn per_unit(executable: &Path, probe: &str, twin: bool) -> Result<f64, String> {
    let run = |repeat: usize| {
        let settings = [
            ("MECHFMU_ENERGIES_PROBE", probe.to_string()),
            (
                "MECHFMU_ENERGIES_TWIN",
                if twin { "1" } else { "0" }.to_string(),
            ),
            ("MECHFMU_ENERGIES_REPEAT", repeat.to_string()),
        ];
        let args = ["probe", "--ignored", "--exact", "--test-threads=1"].map(String::from);
        instructions_with(executable, &args, &settings)
    };
    let (one, three) = (run(1)?, run(3)?);
    if three <= one {
        return Err(format!(
            "{}: three runs of the {probe} probe counted {three} instructions, one run {one}: no work was measured",
            executable.display()
        ));
    }
    Ok((three - one) as f64 / (2.0 * PROBE_STEPS))
}
