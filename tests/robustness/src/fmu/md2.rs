//! What this importer reads from an FMI 2.0 modelDescription.xml, through
//! `mechfmu_host::description`'s parser, and checks of it.

pub use mechfmu_host::description::Experiment;
use mechfmu_host::description::Variable;
use mechfmu_host::platform::Version;

/// What the importer reads from modelDescription.xml.
#[derive(Clone, Debug)]
pub struct ModelDescription {
    pub model_name: String,
    pub guid: String,
    pub model_identifier: String,
    pub can_not_use_memory_management_functions: bool,
    pub max_output_derivative_order: i32,
    pub log_categories: Vec<String>,
    pub experiment: Experiment,
    /// Every variable (all Real), as the parser gives it: a derivative's `derivative` is
    /// the 1-based index of the variable it is the derivative of.
    pub variables: Vec<Variable>,
    /// `<ModelExchange modelIdentifier>`, when the FMU declares Model Exchange.
    pub model_exchange: Option<String>,
    /// `<ModelExchange completedIntegratorStepNotNeeded>`.
    pub completed_integrator_step_not_needed: bool,
    /// `numberOfEventIndicators`.
    pub number_of_event_indicators: usize,
    /// `<ModelStructure><Derivatives>`: the derivatives' 0-based indices in
    /// [`ModelDescription::variables`], in the order of the state vector.
    pub derivatives: Vec<usize>,
}

impl ModelDescription {
    /// Reads an FMI 2.0 modelDescription.xml (`mechfmu_host::description`'s parser): the
    /// Real variables with their declared types' units, the experiment, the interfaces.
    pub fn parse(xml: &str) -> Result<ModelDescription, String> {
        let d = super::parse_of_version(xml, Version::Fmi2)?;
        if let Some(v) = d.variables.iter().find(|v| v.kind != "Real") {
            return Err(format!(
                "variable {:?} is not a Real: this importer knows Real variables only",
                v.name
            ));
        }
        let i = &d.interfaces;
        let derivatives = (d.derivative_indices.iter())
            .map(|&i| i.checked_sub(1))
            .collect::<Option<_>>()
            .ok_or("a <Derivatives><Unknown> without a valid index")?;
        let md = ModelDescription {
            model_name: d.model_name.clone(),
            guid: d.token.clone(),
            model_identifier: d.model_identifier.clone(),
            can_not_use_memory_management_functions: i.can_not_use_memory_management_functions,
            max_output_derivative_order: i.max_output_derivative_order,
            log_categories: d.log_categories.clone(),
            experiment: d.experiment(),
            variables: d.variables,
            model_exchange: i.model_exchange_identifier.clone(),
            completed_integrator_step_not_needed: i.completed_integrator_step_not_needed,
            number_of_event_indicators: d.number_of_event_indicators,
            derivatives,
        };
        md.check()?;
        Ok(md)
    }

    /// What an importer relies on: a GUID, one binary, `<Derivatives>` listing derivatives.
    fn check(&self) -> Result<(), String> {
        if self.guid.is_empty() || self.model_identifier.is_empty() {
            return Err("modelDescription.xml without guid or CoSimulation modelIdentifier".into());
        }
        super::one_binary(self.model_exchange.as_ref(), &self.model_identifier)?;
        for &d in &self.derivatives {
            let ok = self
                .variables
                .get(d)
                .and_then(|v| v.derivative)
                .is_some_and(|s| s >= 1 && s as usize <= self.variables.len());
            if !ok {
                return Err(format!(
                    "<Derivatives> lists variable {} which is not the derivative of a variable",
                    d + 1
                ));
            }
        }
        Ok(())
    }

    pub fn var(&self, name: &str) -> Option<&Variable> {
        self.variables.iter().find(|v| v.name == name)
    }

    /// Every value reference, in order.
    pub fn all_vrs(&self) -> Vec<u32> {
        self.variables.iter().map(|v| v.vr).collect()
    }

    /// The continuous states, in the order of the state vector (`<Derivatives>`; the order
    /// of the variables if the FMU lists none).
    pub fn states(&self) -> Vec<&Variable> {
        self.derivative_vars()
            .into_iter()
            .filter_map(|v| {
                v.derivative
                    .and_then(|i| self.variables.get((i as usize).checked_sub(1)?))
            })
            .collect()
    }

    /// The states' derivatives, in the order of the state vector.
    pub fn derivative_vars(&self) -> Vec<&Variable> {
        if self.derivatives.is_empty() {
            self.variables
                .iter()
                .filter(|v| v.derivative.is_some())
                .collect()
        } else {
            self.derivatives
                .iter()
                .map(|&i| &self.variables[i])
                .collect()
        }
    }

    /// The number of continuous states (`nx`).
    pub fn nx(&self) -> usize {
        self.derivative_vars().len()
    }

    /// One past the largest value reference.
    pub fn vr_end(&self) -> u32 {
        super::vr_end(&self.variables)
    }
}
