//! What an importer reads from an FMI 3.0 modelDescription.xml: the variables by value
//! reference (an array is one variable of several elements, its `<Dimension>`s fixed by
//! `start`), the independent `time`, the instantiation token, the interface types'
//! capabilities and the `<ModelStructure>` (continuous state derivatives and event
//! indicators, whose elements count the states and indicators).

use super::md2::Experiment;
use std::collections::HashMap;

/// One variable of the FMI 3.0 modelDescription (a scalar or an array).
#[derive(Clone, Debug)]
pub struct Var3 {
    pub name: String,
    pub vr: u32,
    pub causality: String,
    pub variability: String,
    pub initial: Option<String>,
    /// The start values, one per element (empty: none declared).
    pub start: Vec<f64>,
    pub min: Option<f64>,
    pub max: Option<f64>,
    pub unit: Option<String>,
    pub quantity: Option<String>,
    /// For a derivative: the value reference of the variable it is the derivative of.
    pub derivative: Option<u32>,
    /// The array's dimensions (empty: a scalar).
    pub dimensions: Vec<usize>,
}

impl Var3 {
    pub fn is(&self, causality: &str) -> bool {
        self.causality == causality
    }
    /// The number of values the variable has (its elements; 1 for a scalar).
    pub fn len(&self) -> usize {
        self.dimensions.iter().product()
    }
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
    /// A square matrix (two equal dimensions of at least 2).
    pub fn is_square_matrix(&self) -> bool {
        matches!(self.dimensions[..], [a, b] if a == b && a > 1)
    }
}

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
    pub variables: Vec<Var3>,
    /// `<ContinuousStateDerivative>`: the derivatives' value references, in the order of
    /// the state vector.
    pub derivatives: Vec<u32>,
    /// `<EventIndicator>`: their value references.
    pub event_indicators: Vec<u32>,
}

fn flag(attrs: &HashMap<String, String>, key: &str) -> bool {
    attrs.get(key).is_some_and(|v| v == "true")
}

impl ModelDescription3 {
    #[allow(deprecated)] // unescape_value: the XML is ours, plain XML 1.0
    pub fn parse(xml: &str) -> Result<ModelDescription3, String> {
        use quick_xml::events::Event;
        let mut reader = quick_xml::Reader::from_str(xml);
        let mut md = ModelDescription3 {
            model_name: String::new(),
            instantiation_token: String::new(),
            model_identifier: String::new(),
            model_exchange: None,
            needs_completed_integrator_step: false,
            max_output_derivative_order: 0,
            might_return_early_from_do_step: false,
            has_event_mode: false,
            provides_intermediate_update: false,
            log_categories: vec![],
            experiment: Experiment {
                start: 0.0,
                stop: 1.0,
                step: 1e-3,
                tolerance: 1e-6,
            },
            variables: vec![],
            derivatives: vec![],
            event_indicators: vec![],
        };
        let mut types: HashMap<String, (Option<String>, Option<String>)> = HashMap::new();
        let mut in_variables = false;
        let mut in_structure = false;
        // The variable being read (its attributes), its dimensions so far.
        let mut current: Option<(HashMap<String, String>, Vec<usize>)> = None;
        let mut declared: Vec<(HashMap<String, String>, Vec<usize>)> = vec![];
        loop {
            let event = reader.read_event().map_err(|e| format!("XML: {e}"))?;
            let (e, empty) = match &event {
                Event::Start(e) => (e, false),
                Event::Empty(e) => (e, true),
                Event::End(e) => {
                    match e.name().as_ref() {
                        "ModelVariables" => in_variables = false,
                        "ModelStructure" => in_structure = false,
                        "Float64" if in_variables => {
                            if let Some(v) = current.take() {
                                declared.push(v);
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
                let value = a
                    .unescape_value()
                    .map_err(|e| format!("XML: {e}"))?
                    .into_owned();
                attrs.insert(a.key.as_ref().to_string(), value);
            }
            let name = e.name().as_ref().to_string();
            let vr = |attrs: &HashMap<String, String>| -> Result<u32, String> {
                attrs
                    .get("valueReference")
                    .and_then(|v| v.parse().ok())
                    .ok_or_else(|| format!("a <{name}> without a valid valueReference"))
            };
            match name.as_str() {
                "fmiModelDescription" => {
                    if attrs.get("fmiVersion").map(String::as_str) != Some("3.0") {
                        return Err("not an FMI 3.0 modelDescription".into());
                    }
                    md.model_name = attrs.get("modelName").cloned().unwrap_or_default();
                    md.instantiation_token =
                        attrs.get("instantiationToken").cloned().unwrap_or_default();
                }
                "ModelExchange" => {
                    md.model_exchange = attrs.get("modelIdentifier").cloned();
                    md.needs_completed_integrator_step =
                        flag(&attrs, "needsCompletedIntegratorStep");
                }
                "CoSimulation" => {
                    md.model_identifier = attrs.get("modelIdentifier").cloned().unwrap_or_default();
                    md.max_output_derivative_order = attrs
                        .get("maxOutputDerivativeOrder")
                        .and_then(|v| v.parse().ok())
                        .unwrap_or(0);
                    md.might_return_early_from_do_step = flag(&attrs, "mightReturnEarlyFromDoStep");
                    md.has_event_mode = flag(&attrs, "hasEventMode");
                    md.provides_intermediate_update = flag(&attrs, "providesIntermediateUpdate");
                }
                "ScheduledExecution" => {
                    return Err("<ScheduledExecution>: this importer does not drive it".into())
                }
                "Float64Type" => {
                    if let Some(t) = attrs.get("name") {
                        types.insert(
                            t.clone(),
                            (attrs.get("unit").cloned(), attrs.get("quantity").cloned()),
                        );
                    }
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
                "ModelVariables" => in_variables = !empty,
                "ModelStructure" => in_structure = !empty,
                "Dimension" if in_variables => {
                    let Some((_, dims)) = current.as_mut() else {
                        return Err("a <Dimension> outside a variable".into());
                    };
                    match attrs.get("start").and_then(|s| s.parse().ok()) {
                        Some(n) => dims.push(n),
                        None => {
                            return Err(
                                "a <Dimension> without a fixed start: this importer knows no structural parameters".into(),
                            )
                        }
                    }
                }
                "Float64" if in_variables => {
                    if empty {
                        declared.push((attrs, vec![]));
                    } else {
                        current = Some((attrs, vec![]));
                    }
                }
                "ContinuousStateDerivative" if in_structure => md.derivatives.push(vr(&attrs)?),
                "EventIndicator" if in_structure => md.event_indicators.push(vr(&attrs)?),
                "Output" | "InitialUnknown" | "ClockedState" if in_structure => {}
                _ if in_variables && current.is_none() => {
                    return Err(format!(
                        "variable type <{name}>: this importer knows Float64 variables only"
                    ))
                }
                _ => {}
            }
        }
        for (v, dimensions) in declared {
            md.variables.push(Self::variable(&v, dimensions, &types)?);
        }
        md.check()?;
        Ok(md)
    }

    fn variable(
        v: &HashMap<String, String>,
        dimensions: Vec<usize>,
        types: &HashMap<String, (Option<String>, Option<String>)>,
    ) -> Result<Var3, String> {
        let num = |k: &str| v.get(k).and_then(|x| x.parse::<f64>().ok());
        let (type_unit, type_quantity) = v
            .get("declaredType")
            .and_then(|t| types.get(t).cloned())
            .unwrap_or((None, None));
        let start = match v.get("start") {
            None => vec![],
            Some(s) => s
                .split_whitespace()
                .map(|x| x.parse::<f64>().map_err(|e| format!("start {s:?}: {e}")))
                .collect::<Result<_, _>>()?,
        };
        let var = Var3 {
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
            start,
            min: num("min"),
            max: num("max"),
            unit: v.get("unit").cloned().or(type_unit),
            quantity: v.get("quantity").cloned().or(type_quantity),
            derivative: v.get("derivative").and_then(|x| x.parse().ok()),
            dimensions,
        };
        if !var.start.is_empty() && var.start.len() != var.len() {
            return Err(format!(
                "variable {}: {} start values for {} elements",
                var.name,
                var.start.len(),
                var.len()
            ));
        }
        Ok(var)
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

    pub fn var(&self, name: &str) -> Option<&Var3> {
        self.variables.iter().find(|v| v.name == name)
    }

    pub fn by_vr(&self, vr: u32) -> Option<&Var3> {
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
        vrs.iter().map(|&vr| self.by_vr(vr).map(Var3::len)).sum()
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
        self.variables.iter().map(|v| v.vr + 1).max().unwrap_or(0)
    }
}
