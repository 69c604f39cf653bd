//! What a mechanism's FMU does about events, in the notes' Markdown subset: one text, from
//! the declaration, for the FMU's page and the interface page.

use crate::contract::Version;
use crate::model::Mechanism;

/// The events of mechanism `M` in its FMI 2.0 FMU (see [`events_for`]).
pub fn events<M: Mechanism>() -> String {
    events_for::<M>(Version::Fmi2)
}

/// The events of mechanism `M` in its FMU of `version`: its event indicators, what the
/// monitor does in each interface type, and the projection's step events.
pub fn events_for<M: Mechanism>(version: Version) -> String {
    let (completed, update, discard, warning) = match version {
        Version::Fmi2 => (
            "fmi2CompletedIntegratorStep",
            "fmi2NewDiscreteStates",
            "fmi2Discard",
            "fmi2Warning",
        ),
        Version::Fmi3 => (
            "fmi3CompletedIntegratorStep",
            "fmi3UpdateDiscreteStates",
            "fmi3Discard",
            "fmi3Warning",
        ),
    };
    let mut text = String::new();
    if !M::EVENT_INDICATORS.is_empty() {
        let list: Vec<String> = M::EVENT_INDICATORS
            .iter()
            .enumerate()
            .map(|(i, name)| {
                let description = (M::VARIABLES.iter())
                    .find(|v| v.name == *name)
                    .map_or("", |v| v.description);
                format!("- z[{i}] = `{name}`: {}", one_line(description))
            })
            .collect();
        text.push_str(&format!(
            "Model Exchange: {} event indicators, in this order:\n\n{}\n\n\
             The importer's solver locates where each changes sign and enters event mode \
             there.\n\n",
            M::EVENT_INDICATORS.len(),
            list.join("\n")
        ));
    }
    if M::MONITORED {
        text.push_str(&format!(
            "The model's limits are checked at every accepted point: in Co-Simulation at \
             every step of the FMU's own solver (a limit that no longer holds ends the \
             communication step with `{discard}` at the last valid time, a warning is \
             logged once per episode and the step returns `{warning}`); in Model Exchange \
             at every `{completed}` and every `{update}` (a \
             warning is logged once per episode, a limit that no longer holds ends the \
             simulation: `terminateSimulation`, with the reason logged)."
        ));
        if version == Version::Fmi3 {
            text.push_str(
                " An importer that allows early return (`earlyReturnAllowed`) learns where \
                 a limit stopped the step: `fmi3DoStep` returns early there, at the last \
                 valid time (`earlyReturn`, `lastSuccessfulTime`, `terminateSimulation`, \
                 status `fmi3Warning` with the reason logged) instead of discarding the step.",
            );
        }
        if M::EVENT_INDICATORS.is_empty() {
            text.push_str(
                " Without event indicators, Model Exchange notices a limit at the end of \
                 the integrator step that crossed it.",
            );
        }
        text.push_str("\n\n");
    }
    if M::PROJECTED {
        text.push_str(&format!(
            "The states are projected back onto the manifold they must stay on: in \
             Co-Simulation at the end of every communication step; in Model Exchange \
             `{completed}` asks for a step event only when the projection would \
             move a state by more than {drift:e} (relative to states beyond 1), a \
             guard against gross drift, and `{update}` projects there \
             (`valuesOfContinuousStatesChanged`). The equations hold off the manifold: \
             the importer's solver keeps the drift near its own tolerance, with no events \
             at any tolerance.\n\n",
            drift = crate::simulation::PROJECTION_DRIFT
        ));
    }
    if text.is_empty() {
        text.push_str(&match version {
            Version::Fmi2 => format!(
                "None: no event indicators, no limits, nothing to do at `{completed}` \
                 (`completedIntegratorStepNotNeeded`).\n"
            ),
            Version::Fmi3 => format!(
                "None: no event indicators, no limits, nothing to do at `{completed}` \
                 (`needsCompletedIntegratorStep` is false).\n"
            ),
        });
    }
    text.trim_end().to_string() + "\n"
}

/// Whitespace runs (doc-comment line breaks) as single spaces.
fn one_line(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}
