//! Where each kind of variable sits, derived once from a declaration.

use super::checks::variable_mistake;
use super::const_text::str_eq;
use super::{Causality, Variability, Variable};

/// The value references of each kind of variable, in declaration order.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Layout {
    /// Continuous states (variables with a declared derivative).
    pub states: Vec<usize>,
    /// For each state, the variable holding its time derivative.
    pub derivatives: Vec<usize>,
    pub inputs: Vec<usize>,
    pub outputs: Vec<usize>,
    pub parameters: Vec<usize>,
    pub calculated: Vec<usize>,
}

impl Layout {
    /// Resolves a declaration; `Err` names the first problem (a name declared twice, or a
    /// [`variable_mistake`], which the macro reports at compile time).
    pub fn new(variables: &[Variable]) -> Result<Self, String> {
        let mut layout = Layout {
            states: Vec::new(),
            derivatives: Vec::new(),
            inputs: Vec::new(),
            outputs: Vec::new(),
            parameters: Vec::new(),
            calculated: Vec::new(),
        };
        for (vr, v) in variables.iter().enumerate() {
            if variables[..vr].iter().any(|w| w.name == v.name) {
                return Err(format!("variable `{}` is declared twice", v.name));
            }
            if let Some(mistake) = variable_mistake(variables, vr, "") {
                return Err(mistake.as_str().to_string());
            }
            if let Some(der) = v.derivative {
                let d = variables
                    .iter()
                    .position(|w| w.name == der)
                    .expect("variable_mistake checked the derivative");
                layout.states.push(vr);
                layout.derivatives.push(d);
            }
            match v.causality {
                Causality::Input => layout.inputs.push(vr),
                Causality::Output => layout.outputs.push(vr),
                Causality::Parameter => layout.parameters.push(vr),
                Causality::CalculatedParameter => layout.calculated.push(vr),
                Causality::Local => {}
            }
        }
        Ok(layout)
    }

    /// The position of value reference `vr` among the inputs.
    pub fn input_index(&self, vr: usize) -> Option<usize> {
        self.inputs.iter().position(|&i| i == vr)
    }
}

/// The value references of the `N` states' derivatives, in the states' order:
/// [`Layout::derivatives`] at compile time, so the solver's callbacks index the values with
/// constants (the states' own are `selected_references` of [`Selection::States`]).
#[doc(hidden)]
pub const fn derivative_references<const N: usize>(variables: &[Variable]) -> [usize; N] {
    let mut out = selected_references::<N>(variables, Selection::States);
    let mut k = 0;
    while k < N {
        let i = out[k];
        let Some(der) = variables[i].derivative else {
            unreachable!()
        };
        let mut j = 0;
        while j < variables.len() && (j == i || !str_eq(variables[j].name, der)) {
            j += 1;
        }
        // a derivative that names no other variable is `check_variable`'s to report (once):
        // the state itself stands in for it here
        out[k] = if j == variables.len() { i } else { j };
        k += 1;
    }
    out
}

/// For each of the `N` states' derivatives, the position in the state vector of the state
/// it is, when it is one (`x' = v` with `v` a state), else `None`: the solver takes those
/// straight from its own stage vector instead of reading them back from the values.
#[doc(hidden)]
pub const fn derivatives_among_states<const N: usize>(
    variables: &[Variable],
) -> [Option<usize>; N] {
    let states = selected_references::<N>(variables, Selection::States);
    let derivatives = derivative_references::<N>(variables);
    let mut out = [None; N];
    let mut i = 0;
    while i < N {
        let mut j = 0;
        while j < N {
            if states[j] == derivatives[i] {
                out[i] = Some(j);
            }
            j += 1;
        }
        i += 1;
    }
    out
}

/// A set of variables a mechanism needs as a compile-time list of value references.
#[doc(hidden)]
#[derive(Clone, Copy)]
pub enum Selection {
    /// The states (variables with a declared derivative).
    States,
    /// The continuous variables: the values a step must leave finite.
    Continuous,
    /// The inputs: the values a stage loads when they move over a step.
    Inputs,
    /// The continuous variables the solver does not check at a point it accepts: all but
    /// the states and their derivatives (see `Declaration::CONTINUOUS_UNCHECKED`).
    ContinuousUnchecked,
}

const fn selected(variables: &[Variable], i: usize, selection: Selection) -> bool {
    let variable = &variables[i];
    match selection {
        Selection::States => variable.derivative.is_some(),
        Selection::Continuous => matches!(variable.variability, Variability::Continuous),
        Selection::Inputs => matches!(variable.causality, Causality::Input),
        Selection::ContinuousUnchecked => {
            matches!(variable.variability, Variability::Continuous)
                && variable.derivative.is_none()
                && !is_derivative(variables, i)
        }
    }
}

/// Whether variable `i` is some state's derivative.
const fn is_derivative(variables: &[Variable], i: usize) -> bool {
    let mut j = 0;
    while j < variables.len() {
        if let Some(der) = variables[j].derivative {
            if str_eq(der, variables[i].name) {
                return true;
            }
        }
        j += 1;
    }
    false
}

/// The number of variables in `selection`, at compile time.
#[doc(hidden)]
pub const fn count_selected(variables: &[Variable], selection: Selection) -> usize {
    let (mut i, mut n) = (0, 0);
    while i < variables.len() {
        if selected(variables, i, selection) {
            n += 1;
        }
        i += 1;
    }
    n
}

/// The value references of the `N` variables in `selection`, in declaration order, as
/// constants: a loop over them unrolls into accesses to known fields (checking the values
/// after every step is a few comparisons; storing the inputs at a stage cannot, as far as
/// the compiler knows, overwrite the states stored beside them).
#[doc(hidden)]
pub const fn selected_references<const N: usize>(
    variables: &[Variable],
    selection: Selection,
) -> [usize; N] {
    let mut out = [0; N];
    let (mut i, mut n) = (0, 0);
    while i < variables.len() {
        if selected(variables, i, selection) {
            out[n] = i;
            n += 1;
        }
        i += 1;
    }
    if n != N {
        panic!("mechanism!: variable count mismatch");
    }
    out
}

/// The value references of the event indicators `names`, in their order; `Err` names the
/// first that is not a declared continuous variable, or is listed twice.
pub fn event_indicator_references(
    variables: &[Variable],
    names: &[&str],
) -> Result<Vec<usize>, String> {
    let mut references = Vec::with_capacity(names.len());
    for (k, name) in names.iter().enumerate() {
        let Some(vr) = variables.iter().position(|v| v.name == *name) else {
            return Err(format!(
                "event indicator `{name}` names no declared variable"
            ));
        };
        if variables[vr].variability != Variability::Continuous {
            return Err(format!(
                "event indicator `{name}` is not a continuous variable"
            ));
        }
        if names[..k].contains(name) {
            return Err(format!("event indicator `{name}` is listed twice"));
        }
        references.push(vr);
    }
    Ok(references)
}
