//! The tables of the documentation page: variables and capabilities, as each FMI version
//! shows them.

use super::{escape, num};
use crate::contract::{self, Capabilities, FMI3_CAPABILITIES};
use crate::model::{Causality, Mechanism, Shapes, Variable};
use std::fmt::Write as _;

pub(super) fn variable_table(variables: &[Variable]) -> String {
    let mut h = String::from(
        "<table>\n<tr><th>name</th><th>value ref.</th><th>causality</th><th>variability</th><th>initial</th>\
         <th>unit</th><th>start</th><th>min</th><th>max</th><th>description</th></tr>\n",
    );
    for (vr, v) in variables.iter().enumerate() {
        let opt = |x: Option<f64>| x.map(num).unwrap_or_default();
        let min = shown_min(v, "&gt;");
        let mut description = escape(v.description);
        if let Some(d) = v.derivative {
            let _ = write!(
                description,
                " <small>(its derivative: <code>{}</code>)</small>",
                escape(d)
            );
        }
        let _ = writeln!(
            h,
            "<tr><td><code>{}</code></td><td class=\"num\">{vr}</td><td>{}</td><td>{}</td><td>{}</td>\
             <td>{}</td><td class=\"num\">{}</td><td class=\"num\">{min}</td><td class=\"num\">{}</td><td>{description}</td></tr>",
            escape(v.name),
            v.causality.as_str(),
            v.variability.as_str(),
            shown_initial(v),
            escape(v.unit),
            opt(v.start),
            opt(v.max),
        );
    }
    h.push_str("</table>\n");
    h
}

/// The `initial` the variable tables show: the one an importer sees, none for an input.
pub(super) fn shown_initial(v: &Variable) -> &'static str {
    v.effective_initial()
        .filter(|_| v.causality != Causality::Input)
        .map(|i| i.as_str())
        .unwrap_or("")
}

/// The lower bound the variable tables show: `min`, or `{gt} min` when the value must be
/// greater than it; `gt` is how the page writes `>`.
pub(super) fn shown_min(v: &Variable, gt: &str) -> String {
    match (v.min, v.positive) {
        (Some(m), true) => format!("{gt} {}", num(m)),
        (m, _) => m.map(num).unwrap_or_default(),
    }
}

pub(super) fn capability_table(c: &Capabilities) -> String {
    let rows: [(&str, String, &str); 10] = [
        ("canHandleVariableCommunicationStepSize", c.can_handle_variable_communication_step_size.to_string(),
         "any communication step size; the solver lands exactly on every communication point"),
        ("canInterpolateInputs", c.can_interpolate_inputs.to_string(),
         "fmi2SetRealInputDerivatives (orders 1 and 2): inputs follow their Taylor polynomial over a step"),
        ("maxOutputDerivativeOrder", c.max_output_derivative_order.to_string(),
         "fmi2GetRealOutputDerivatives, exact (forward-mode automatic differentiation)"),
        ("providesDirectionalDerivative", c.provides_directional_derivative.to_string(),
         "fmi2GetDirectionalDerivative, exact (forward-mode automatic differentiation)"),
        ("canGetAndSetFMUstate", c.can_get_and_set_fmu_state.to_string(), "fmi2GetFMUstate / fmi2SetFMUstate"),
        ("canSerializeFMUstate", c.can_serialize_fmu_state.to_string(),
         "portable serialized FMU states (no pointers inside; loadable in another process)"),
        ("canBeInstantiatedOnlyOncePerProcess", c.can_be_instantiated_only_once_per_process.to_string(),
         "instances are independent (no global state) and may run on different threads"),
        ("canNotUseMemoryManagementFunctions", c.can_not_use_memory_management_functions.to_string(),
         "the FMU allocates its own memory"),
        ("canRunAsynchronuously", c.can_run_asynchronuously.to_string(), "fmi2DoStep always completes before it returns"),
        ("needsExecutionTool", c.needs_execution_tool.to_string(), "self-contained: no tool or runtime needed"),
    ];
    let mut h = String::from("<table>\n<tr><th>attribute of &lt;CoSimulation&gt;</th><th>value</th><th>meaning</th></tr>\n");
    for (name, value, meaning) in rows {
        let _ = writeln!(
            h,
            "<tr><td><code>{name}</code></td><td>{value}</td><td>{}</td></tr>",
            escape(meaning)
        );
    }
    h.push_str("</table>\n<p>Also: a Dormand&ndash;Prince 5(4) solver with error control under every step \
                (relative tolerance from <code>fmi2SetupExperiment</code>, else the default experiment's); a step the \
                model cannot complete ends with <code>fmi2Discard</code> at the last valid time \
                (<code>fmi2LastSuccessfulTime</code>); every call is checked against the FMI 2.0 state machine.</p>\n");
    h
}

/// FMI 3.0's variables: the independent time, then every scalar in no array and every
/// array (its dimensions, and its start values element by element, row-major).
pub(super) fn fmi3_variable_table<M: Mechanism>() -> Result<String, String> {
    let shapes = Shapes::new(M::VARIABLES, M::ARRAYS)?;
    let mut h = String::from(
        "<table>\n<tr><th>name</th><th>value ref.</th><th>dimensions</th><th>causality</th><th>variability</th><th>initial</th>\
         <th>unit</th><th>start</th><th>min</th><th>max</th><th>description</th></tr>\n",
    );
    let _ = writeln!(
        h,
        "<tr><td><code>time</code></td><td class=\"num\">{}</td><td></td><td>independent</td><td>continuous</td>\
         <td></td><td>s</td><td></td><td></td><td></td><td>Simulation time</td></tr>",
        Shapes::TIME_REFERENCE
    );
    for shaped in &shapes.variables {
        let v = shaped.variable(M::VARIABLES);
        let elements: Vec<&Variable> = shaped.elements.iter().map(|&e| &M::VARIABLES[e]).collect();
        let starts: Vec<String> = elements.iter().filter_map(|e| e.start.map(num)).collect();
        let same = |f: &dyn Fn(&Variable) -> String| {
            let first = f(elements[0]);
            if elements.iter().all(|e| f(e) == first) {
                first
            } else {
                "(per element)".into()
            }
        };
        let min = same(&|e| shown_min(e, "&gt;"));
        let max = same(&|e| e.max.map(num).unwrap_or_default());
        let dimensions: Vec<String> = shaped.dimensions.iter().map(usize::to_string).collect();
        let mut description = escape(shaped.description);
        if shaped.is_array() {
            let names: Vec<String> = elements
                .iter()
                .map(|e| format!("<code>{}</code>", escape(e.name)))
                .collect();
            let _ = write!(
                description,
                " <small>(elements, row-major: {})</small>",
                names.join(" ")
            );
        }
        let _ = writeln!(
            h,
            "<tr><td><code>{}</code></td><td class=\"num\">{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>\
             <td>{}</td><td class=\"num\">{}</td><td class=\"num\">{min}</td><td class=\"num\">{max}</td><td>{description}</td></tr>",
            escape(shaped.name),
            shaped.reference,
            dimensions.join(" &times; "),
            v.causality.as_str(),
            v.variability.as_str(),
            shown_initial(v),
            escape(v.unit),
            starts.join(" "),
        );
    }
    h.push_str("</table>\n");
    Ok(h)
}

/// FMI 3.0's capability flags, and what the runtime does for each.
pub(super) fn fmi3_capability_table<M: Mechanism>() -> String {
    let c = FMI3_CAPABILITIES;
    let rows: [(&str, String, &str); 9] = [
        (
            "canHandleVariableCommunicationStepSize",
            c.can_handle_variable_communication_step_size.to_string(),
            "any communication step size; the solver lands exactly on every communication point",
        ),
        (
            "maxOutputDerivativeOrder",
            c.max_output_derivative_order.to_string(),
            "fmi3GetOutputDerivatives, exact (forward-mode automatic differentiation)",
        ),
        (
            "providesDirectionalDerivatives",
            c.provides_directional_derivatives.to_string(),
            "fmi3GetDirectionalDerivative, exact (forward-mode automatic differentiation)",
        ),
        (
            "providesAdjointDerivatives",
            c.provides_adjoint_derivatives.to_string(),
            "fmi3GetAdjointDerivative: seedᵀ J, one exact directional derivative per known",
        ),
        (
            "canGetAndSetFMUState",
            c.can_get_and_set_fmu_state.to_string(),
            "fmi3GetFMUState / fmi3SetFMUState",
        ),
        (
            "canSerializeFMUState",
            c.can_serialize_fmu_state.to_string(),
            "portable serialized FMU states (no pointers inside; loadable in another process)",
        ),
        (
            "hasEventMode",
            c.has_event_mode.to_string(),
            "Co-Simulation's event mode, for an importer that asks for it (eventModeUsed)",
        ),
        (
            "mightReturnEarlyFromDoStep",
            contract::might_return_early_from_do_step::<M>().to_string(),
            "fmi3DoStep returns early where the model stops holding (when earlyReturnAllowed)",
        ),
        (
            "providesIntermediateUpdate",
            c.provides_intermediate_update.to_string(),
            "no intermediate update: inputs are held over a communication step",
        ),
    ];
    let mut h =
        String::from("<table>\n<tr><th>capability</th><th>value</th><th>meaning</th></tr>\n");
    for (name, value, meaning) in rows {
        let _ = writeln!(
            h,
            "<tr><td><code>{name}</code></td><td>{value}</td><td>{}</td></tr>",
            escape(meaning)
        );
    }
    h.push_str("</table>\n<p>Also: a Dormand&ndash;Prince 5(4) solver with error control under every step \
                (relative tolerance from <code>fmi3EnterInitializationMode</code>, else the default experiment's); \
                every call is checked against the FMI 3.0 state machine. Not offered: clocks, structural \
                parameters and configuration mode, Scheduled Execution (those functions return \
                <code>fmi3Error</code> with a message).</p>\n");
    h
}
