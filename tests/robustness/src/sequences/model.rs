//! What the sequences know of the model, read from either standard's modelDescription:
//! the variables by value reference (FMI 3.0's arrays with their elements), the
//! continuous states and event indicators, the default experiment.

use crate::fmu::{Experiment, ModelDescription, ModelDescription3, Variable, VariableExt};

pub struct Model {
    /// Every variable (an FMI 3.0 array is one, of [`VariableExt::len`] elements; its start
    /// values by element through [`VariableExt::start_at`]).
    pub vars: Vec<Variable>,
    /// One past the largest value reference.
    pub vr_end: u32,
    /// The FMU declares Model Exchange.
    pub me: bool,
    /// Continuous states and event indicators (elements).
    pub nx: usize,
    pub ni: usize,
    pub experiment: Experiment,
    /// The continuous states' start values (1 where none is declared).
    pub x_start: Vec<f64>,
    /// The value references of the states and of their derivatives, in the state vector's
    /// order (their values, element by element, are the state vector).
    pub state_vrs: Vec<u32>,
    pub derivative_vrs: Vec<u32>,
    /// FMI 3.0: the independent variable's value reference.
    pub time_vr: Option<u32>,
}

impl Model {
    pub fn fmi2(md: &ModelDescription) -> Model {
        Model {
            vars: md.variables.clone(),
            vr_end: md.vr_end(),
            me: md.model_exchange.is_some(),
            nx: md.nx(),
            ni: md.number_of_event_indicators,
            experiment: md.experiment,
            x_start: md.states().iter().map(|v| v.start.unwrap_or(1.0)).collect(),
            state_vrs: md.states().iter().map(|v| v.vr).collect(),
            derivative_vrs: md.derivative_vars().iter().map(|v| v.vr).collect(),
            time_vr: None,
        }
    }

    pub fn fmi3(md: &ModelDescription3) -> Model {
        let state_vrs = md.state_vrs();
        Model {
            vars: md.variables.clone(),
            vr_end: md.vr_end(),
            me: md.model_exchange.is_some(),
            nx: md.nx(),
            ni: md.ni(),
            experiment: md.experiment,
            x_start: state_vrs
                .iter()
                .filter_map(|&vr| md.by_vr(vr))
                .flat_map(|v| (0..v.len()).map(|k| v.start_at(k).unwrap_or(1.0)))
                .collect(),
            state_vrs,
            derivative_vrs: md.derivatives.clone(),
            time_vr: Some(md.time_vr()),
        }
    }

    pub fn var(&self, vr: u32) -> Option<&Variable> {
        self.vars.iter().find(|v| v.vr == vr)
    }

    /// How many values `vrs` have (arrays count their elements), or `None` if one of them
    /// is not a variable.
    pub fn len_of(&self, vrs: &[u32]) -> Option<usize> {
        vrs.iter().map(|&vr| self.var(vr).map(Variable::len)).sum()
    }
}
