//! What this importer reads from an FMI 3.0 modelDescription.xml (through
//! `mechfmu_host::description`'s parser): the variables by value reference (an array is one
//! variable of several elements, its `<Dimension>`s fixed by `start`), the independent
//! `time`, the instantiation token, the interface types' capabilities and the
//! `<ModelStructure>` (continuous state derivatives and event indicators, whose elements
//! count the states and indicators), and checks of it.

use super::md2::Experiment;
use super::VariableExt;
use mechfmu_host::description::Variable;
use mechfmu_host::platform::Version;

/// What the importer reads from an FMI 3.0 modelDescription.xml.
#[derive(Clone, Debug)]
pub struct ModelDescription3 {
    pub model_name: String,
    pub instantiation_token: String,
    /// `<CoSimulation modelIdentifier>`.
    pub model_identifier: String,
    /// `<ModelExchange modelIdentifier>`, when the FMU declares Model Exchange.
    pub model_exchange: Option<String>,
    /// `<ModelExchange needsCompletedIntegratorStep>`.
    pub needs_completed_integrator_step: bool,
    /// `<CoSimulation>`'s capabilities.
    pub max_output_derivative_order: i32,
    pub might_return_early_from_do_step: bool,
    pub has_event_mode: bool,
    pub provides_intermediate_update: bool,
    pub log_categories: Vec<String>,
    pub experiment: Experiment,
    /// Every variable, `time` among them, in the order of the file.
    pub variables: Vec<Variable>,
    /// `<ContinuousStateDerivative>`: the derivatives' value references, in the order of
    /// the state vector.
    pub derivatives: Vec<u32>,
    /// `<EventIndicator>`: their value references.
    pub event_indicators: Vec<u32>,
}

impl ModelDescription3 {
    /// Reads an FMI 3.0 modelDescription.xml (`mechfmu_host::description`'s parser): the
    /// Float64 variables with their declared types' units, the experiment, the interfaces,
    /// the `<ModelStructure>`.
    pub fn parse(xml: &str) -> Result<ModelDescription3, String> {
        let d = super::parse_of_version(xml, Version::Fmi3)?;
        let i = &d.interfaces;
        if i.scheduled_execution {
            return Err("<ScheduledExecution>: this importer does not drive it".into());
        }
        for v in &d.variables {
            if v.kind != "Float64" {
                return Err(format!(
                    "variable type <{}>: this importer knows Float64 variables only",
                    v.kind
                ));
            }
            if !v.start_values.is_empty() && v.start_values.len() != v.len() {
                return Err(format!(
                    "variable {}: {} start values for {} elements",
                    v.name,
                    v.start_values.len(),
                    v.len()
                ));
            }
        }
        let md = ModelDescription3 {
            model_name: d.model_name.clone(),
            instantiation_token: d.token.clone(),
            model_identifier: d.model_identifier.clone(),
            model_exchange: i.model_exchange_identifier.clone(),
            needs_completed_integrator_step: i.needs_completed_integrator_step,
            max_output_derivative_order: i.max_output_derivative_order,
            might_return_early_from_do_step: i.might_return_early_from_do_step,
            has_event_mode: i.has_event_mode,
            provides_intermediate_update: i.provides_intermediate_update,
            log_categories: d.log_categories.clone(),
            experiment: d.experiment(),
            variables: d.variables,
            derivatives: d.state_derivatives.clone(),
            event_indicators: d.event_indicators.clone(),
        };
        md.check()?;
        Ok(md)
    }

    /// What an importer relies on: one binary, distinct value references, one `time`,
    /// derivatives of variables of as many elements, indicators that are variables.
    fn check(&self) -> Result<(), String> {
        if self.instantiation_token.is_empty() || self.model_identifier.is_empty() {
            return Err(
                "modelDescription.xml without instantiationToken or CoSimulation modelIdentifier"
                    .into(),
            );
        }
        super::one_binary(self.model_exchange.as_ref(), &self.model_identifier)?;
        let mut seen = std::collections::HashSet::new();
        if let Some(v) = self.variables.iter().find(|v| !seen.insert(v.vr)) {
            return Err(format!("value reference {} declared twice", v.vr));
        }
        if self
            .variables
            .iter()
            .filter(|v| v.is("independent"))
            .count()
            != 1
        {
            return Err("not exactly one independent variable".into());
        }
        for &d in &self.derivatives {
            let ok = self.by_vr(d).is_some_and(|v| {
                v.derivative
                    .and_then(|s| self.by_vr(s))
                    .is_some_and(|s| s.len() == v.len())
            });
            if !ok {
                return Err(format!(
                    "<ContinuousStateDerivative valueReference=\"{d}\"> is not the derivative of a variable of as many elements"
                ));
            }
        }
        if let Some(z) = self
            .event_indicators
            .iter()
            .find(|&&z| self.by_vr(z).is_none())
        {
            return Err(format!(
                "<EventIndicator valueReference=\"{z}\"> is no variable"
            ));
        }
        Ok(())
    }

    pub fn var(&self, name: &str) -> Option<&Variable> {
        self.variables.iter().find(|v| v.name == name)
    }

    pub fn by_vr(&self, vr: u32) -> Option<&Variable> {
        self.variables.iter().find(|v| v.vr == vr)
    }

    /// The value reference of the independent variable.
    pub fn time_vr(&self) -> u32 {
        self.variables
            .iter()
            .find(|v| v.is("independent"))
            .map_or(0, |v| v.vr)
    }

    /// How many values `vrs` have (arrays count their elements), or `None` if one of them
    /// is not a variable.
    pub fn len_of(&self, vrs: &[u32]) -> Option<usize> {
        vrs.iter()
            .map(|&vr| self.by_vr(vr).map(Variable::len))
            .sum()
    }

    /// Every value reference but time's, in increasing order.
    pub fn all_vrs(&self) -> Vec<u32> {
        let mut vrs: Vec<u32> = self
            .variables
            .iter()
            .filter(|v| !v.is("independent"))
            .map(|v| v.vr)
            .collect();
        vrs.sort_unstable();
        vrs
    }

    /// The continuous states' value references, in the order of the state vector.
    pub fn state_vrs(&self) -> Vec<u32> {
        self.derivatives
            .iter()
            .filter_map(|&d| self.by_vr(d).and_then(|v| v.derivative))
            .collect()
    }

    /// The number of continuous states (`nx`: the elements of the derivatives).
    pub fn nx(&self) -> usize {
        self.len_of(&self.derivatives).unwrap_or(0)
    }

    /// The number of event indicators (their elements).
    pub fn ni(&self) -> usize {
        self.len_of(&self.event_indicators).unwrap_or(0)
    }

    /// One past the largest value reference.
    pub fn vr_end(&self) -> u32 {
        super::vr_end(&self.variables)
    }
}
