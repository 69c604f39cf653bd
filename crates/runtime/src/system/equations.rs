//! A system's equations: its components' own, run in the order of its plan
//! ([`composite::plan`](super::composite::plan)), the connections copied in between. What
//! [`system!`](crate::system) implements [`Mechanism`](crate::model::Mechanism) with.

use super::composite::Step;
use super::values::{Components, SystemValues};
use super::SystemDeclaration;
use crate::model::{Monitor, Scalar, ValueSet};

/// One step of the derivatives' evaluation (the connections and the components' equations in
/// the plan's order): [`system!`](crate::system) calls it once per step of the plan, each
/// time with a constant, so that every call becomes the component's equations or a copy
/// between known fields (a loop over the plan, too long for the compiler to unroll, would
/// look every value reference up at each stage).
#[inline(always)]
pub fn run_step<S: Scalar, L: Components>(values: &mut SystemValues<S, L>, step: Step) {
    match step {
        Step::Copy { from, to } => {
            if let Some(value) = values.get(from) {
                values.set(to, value);
            }
        }
        Step::Evaluate { component, outputs } => {
            L::evaluate(&mut values.components, component, outputs)
        }
    }
}

/// The most steps a system's plan may have (each component's equations and the connections
/// into it): what [`system!`](crate::system) unrolls.
pub const MAX_PLAN: usize = 256;

/// The outputs of the components whose outputs [`evaluate`] left to this.
#[inline]
pub fn outputs<S: Scalar, L: Components>(values: &mut SystemValues<S, L>, plan: &[Step]) {
    for step in plan {
        if let Step::Evaluate {
            component,
            outputs: false,
        } = *step
        {
            L::outputs(&mut values.components, component);
        }
    }
}

/// Every component's calculated parameters; the first refusal, named by its component.
pub fn calculate<L: Components>(
    values: &mut SystemValues<f64, L>,
    system: &SystemDeclaration,
) -> Result<(), String> {
    for (k, component) in system.components.iter().enumerate() {
        L::calculate(&mut values.components, k)
            .map_err(|e| format!("component `{}`: {e}", component.name))?;
    }
    Ok(())
}

/// The first component's diagnosis, named by its component.
pub fn diagnose<L: Components>(
    values: &SystemValues<f64, L>,
    system: &SystemDeclaration,
) -> Option<String> {
    system
        .components
        .iter()
        .enumerate()
        .find_map(|(k, component)| {
            L::diagnose(&values.components, k)
                .map(|d| format!("component `{}`: {d}", component.name))
        })
}

/// Every component's projection.
pub fn project<L: Components>(values: &mut SystemValues<f64, L>, system: &SystemDeclaration) {
    for k in 0..system.components.len() {
        L::project(&mut values.components, k);
    }
}

/// The components' verdicts: the first `Invalid`, else the first `Warning`, each named by
/// its component.
pub fn monitor<L: Components>(
    values: &SystemValues<f64, L>,
    system: &SystemDeclaration,
) -> Monitor {
    let mut verdict = Monitor::Valid;
    for (k, component) in system.components.iter().enumerate() {
        match L::monitor(&values.components, k) {
            Monitor::Valid => {}
            Monitor::Invalid(why) => {
                return Monitor::Invalid(format!("component `{}`: {why}", component.name))
            }
            Monitor::Warning(why) => {
                if verdict == Monitor::Valid {
                    verdict = Monitor::Warning(format!("component `{}`: {why}", component.name));
                }
            }
        }
    }
    verdict
}
