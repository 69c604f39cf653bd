//! What an importer reads from an FMI 2.0 modelDescription.xml.

use std::collections::HashMap;

/// One variable of the modelDescription.
#[derive(Clone, Debug)]
pub struct Var {
    pub name: String,
    pub vr: u32,
    pub causality: String,
    pub variability: String,
    pub initial: Option<String>,
    pub start: Option<f64>,
    pub min: Option<f64>,
    pub max: Option<f64>,
    pub unit: Option<String>,
    pub quantity: Option<String>,
    /// For a derivative: the 1-based index of the variable it is the derivative of.
    pub derivative: Option<usize>,
}

impl Var {
    pub fn is(&self, causality: &str) -> bool {
        self.causality == causality
    }
    pub fn is_tunable_parameter(&self) -> bool {
        self.causality == "parameter" && self.variability == "tunable"
    }
    /// A mass, a length or an inertia (by unit or quantity) declared with `min="0"`: a
    /// parameter that must be strictly positive.
    pub fn must_be_positive(&self) -> bool {
        let physical = matches!(self.unit.as_deref(), Some("kg" | "m" | "kg.m2"))
            || matches!(
                self.quantity.as_deref(),
                Some("Mass" | "Length" | "MomentOfInertia" | "Inertia")
            );
        self.causality == "parameter" && physical && self.min == Some(0.0)
    }
}

#[derive(Clone, Debug)]
pub struct Experiment {
    pub start: f64,
    pub stop: f64,
    pub step: f64,
    pub tolerance: f64,
}

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
    pub variables: Vec<Var>,
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
    #[allow(deprecated)] // unescape_value: the XML is ours, plain XML 1.0
    pub fn parse(xml: &str) -> Result<ModelDescription, String> {
        use quick_xml::events::Event;
        let mut reader = quick_xml::Reader::from_str(xml);
        let mut md = ModelDescription {
            model_name: String::new(),
            guid: String::new(),
            model_identifier: String::new(),
            can_not_use_memory_management_functions: false,
            max_output_derivative_order: 0,
            log_categories: vec![],
            experiment: Experiment {
                start: 0.0,
                stop: 1.0,
                step: 1e-3,
                tolerance: 1e-6,
            },
            variables: vec![],
            model_exchange: None,
            completed_integrator_step_not_needed: false,
            number_of_event_indicators: 0,
            derivatives: vec![],
        };
        let mut in_derivatives = false;
        let mut simple_types: HashMap<String, (Option<String>, Option<String>)> = HashMap::new();
        let mut current_type: Option<String> = None;
        let mut current_var: Option<(HashMap<String, String>, Option<String>)> = None;
        let mut declared: Vec<(HashMap<String, String>, HashMap<String, String>)> = vec![];
        loop {
            let event = reader.read_event().map_err(|e| format!("XML: {e}"))?;
            let (e, empty) = match &event {
                Event::Start(e) => (e, false),
                Event::Empty(e) => (e, true),
                Event::End(e) => {
                    match e.name().as_ref() {
                        "SimpleType" => current_type = None,
                        "Derivatives" => in_derivatives = false,
                        "ScalarVariable" => {
                            if let Some((attrs, _)) = current_var.take() {
                                declared.push((attrs, HashMap::new()));
                            }
                        }
                        _ => {}
                    }
                    continue;
                }
                Event::Eof => break,
                _ => continue,
            };
            let mut attrs = HashMap::new();
            for a in e.attributes() {
                let a = a.map_err(|e| format!("XML attribute: {e}"))?;
                let key = a.key.as_ref().to_string();
                let value = a
                    .unescape_value()
                    .map_err(|e| format!("XML: {e}"))?
                    .into_owned();
                attrs.insert(key, value);
            }
            match e.name().as_ref() {
                "fmiModelDescription" => {
                    md.model_name = attrs.get("modelName").cloned().unwrap_or_default();
                    md.guid = attrs.get("guid").cloned().unwrap_or_default();
                    md.number_of_event_indicators = attrs
                        .get("numberOfEventIndicators")
                        .and_then(|v| v.parse().ok())
                        .unwrap_or(0);
                }
                "ModelExchange" => {
                    md.model_exchange = attrs.get("modelIdentifier").cloned();
                    md.completed_integrator_step_not_needed = attrs
                        .get("completedIntegratorStepNotNeeded")
                        .is_some_and(|v| v == "true");
                }
                "Derivatives" => in_derivatives = !empty,
                "Unknown" if in_derivatives => md.derivatives.push(
                    attrs
                        .get("index")
                        .and_then(|i| i.parse::<usize>().ok())
                        .and_then(|i| i.checked_sub(1))
                        .ok_or("a <Derivatives><Unknown> without a valid index")?,
                ),
                "CoSimulation" => {
                    md.model_identifier = attrs.get("modelIdentifier").cloned().unwrap_or_default();
                    md.can_not_use_memory_management_functions = attrs
                        .get("canNotUseMemoryManagementFunctions")
                        .is_some_and(|v| v == "true");
                    md.max_output_derivative_order = attrs
                        .get("maxOutputDerivativeOrder")
                        .and_then(|v| v.parse().ok())
                        .unwrap_or(0);
                }
                "Category" => md
                    .log_categories
                    .push(attrs.get("name").cloned().unwrap_or_default()),
                "DefaultExperiment" => {
                    let f =
                        |k: &str, d: f64| attrs.get(k).and_then(|v| v.parse().ok()).unwrap_or(d);
                    md.experiment = Experiment {
                        start: f("startTime", 0.0),
                        stop: f("stopTime", 1.0),
                        step: f("stepSize", 1e-3),
                        tolerance: f("tolerance", 1e-6),
                    };
                }
                "SimpleType" if !empty => current_type = attrs.get("name").cloned(),
                "ScalarVariable" => {
                    if empty {
                        declared.push((attrs, HashMap::new()));
                    } else {
                        current_var = Some((attrs, None));
                    }
                }
                "Real" | "Integer" | "Boolean" | "String" | "Enumeration" => {
                    if let Some(t) = &current_type {
                        simple_types.insert(
                            t.clone(),
                            (attrs.get("unit").cloned(), attrs.get("quantity").cloned()),
                        );
                    } else if let Some((var_attrs, _)) = current_var.take() {
                        let mut real = attrs;
                        real.insert("#type".into(), e.name().as_ref().to_string());
                        declared.push((var_attrs, real));
                    }
                }
                _ => {}
            }
        }
        for (v, real) in declared {
            md.variables.push(Self::variable(&v, &real, &simple_types)?);
        }
        md.check()?;
        Ok(md)
    }

    /// The variable of a `<ScalarVariable>` (attributes `v`) and its type element (`real`,
    /// the element's name under `#type`): a Real, with the unit and quantity of its declared
    /// type in `types` unless it has its own.
    fn variable(
        v: &HashMap<String, String>,
        real: &HashMap<String, String>,
        types: &HashMap<String, (Option<String>, Option<String>)>,
    ) -> Result<Var, String> {
        let num = |k: &str| real.get(k).and_then(|x| x.parse::<f64>().ok());
        let (type_unit, type_quantity) = real
            .get("declaredType")
            .and_then(|t| types.get(t).cloned())
            .unwrap_or((None, None));
        if real.get("#type").map(String::as_str) != Some("Real") {
            return Err(format!(
                "variable {:?} is not a Real: this importer knows Real variables only",
                v.get("name")
            ));
        }
        Ok(Var {
            name: v.get("name").cloned().unwrap_or_default(),
            vr: v
                .get("valueReference")
                .and_then(|x| x.parse().ok())
                .ok_or("a variable without a valid valueReference")?,
            causality: v
                .get("causality")
                .cloned()
                .unwrap_or_else(|| "local".into()),
            variability: v
                .get("variability")
                .cloned()
                .unwrap_or_else(|| "continuous".into()),
            initial: v.get("initial").cloned(),
            start: num("start"),
            min: num("min"),
            max: num("max"),
            unit: real.get("unit").cloned().or(type_unit),
            quantity: real.get("quantity").cloned().or(type_quantity),
            derivative: real.get("derivative").and_then(|x| x.parse().ok()),
        })
    }

    /// What an importer relies on: a GUID, one binary, `<Derivatives>` listing derivatives.
    fn check(&self) -> Result<(), String> {
        if self.guid.is_empty() || self.model_identifier.is_empty() {
            return Err("modelDescription.xml without guid or CoSimulation modelIdentifier".into());
        }
        if self
            .model_exchange
            .as_ref()
            .is_some_and(|id| *id != self.model_identifier)
        {
            return Err(
                "ModelExchange and CoSimulation name different binaries: this importer loads one"
                    .into(),
            );
        }
        for &d in &self.derivatives {
            let ok = self
                .variables
                .get(d)
                .and_then(|v| v.derivative)
                .is_some_and(|s| s >= 1 && s <= self.variables.len());
            if !ok {
                return Err(format!(
                    "<Derivatives> lists variable {} which is not the derivative of a variable",
                    d + 1
                ));
            }
        }
        Ok(())
    }

    pub fn var(&self, name: &str) -> Option<&Var> {
        self.variables.iter().find(|v| v.name == name)
    }

    /// Every value reference, in order.
    pub fn all_vrs(&self) -> Vec<u32> {
        self.variables.iter().map(|v| v.vr).collect()
    }

    /// The continuous states, in the order of the state vector (`<Derivatives>`; the order
    /// of the variables if the FMU lists none).
    pub fn states(&self) -> Vec<&Var> {
        self.derivative_vars()
            .into_iter()
            .filter_map(|v| {
                v.derivative
                    .and_then(|i| self.variables.get(i.checked_sub(1)?))
            })
            .collect()
    }

    /// The states' derivatives, in the order of the state vector.
    pub fn derivative_vars(&self) -> Vec<&Var> {
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
        self.variables.iter().map(|v| v.vr + 1).max().unwrap_or(0)
    }
}
