//! A model description of either FMI version (`modelDescription.xml`), read by one parser:
//! what the tools that run an FMU need of it, and what the robustness suite's importer
//! learns the model from (the variables' types, bounds and units, the interfaces'
//! capabilities, the model structure).
//!
//! FMI 2.0 declares a variable as a `ScalarVariable` with its type as a child (`<Real
//! start=...>`); FMI 3.0 as an element named by its type (`<Float64 start=...>`), an array
//! with `<Dimension>` children and, in mechfmu's FMUs, the FMI 2.0 scalars it is made of in
//! an annotation (`org.mechfmu.scalars`, row-major). The continuous states are counted from
//! `ModelStructure`: FMI 2.0's `Derivatives/Unknown`, FMI 3.0's `ContinuousStateDerivative`.
//! A variable's unit and quantity are its own, else its declared type's (FMI 2.0's
//! `SimpleType`, FMI 3.0's `Float64Type`).

mod elements;

pub use elements::Variable;
pub use mechfmu::model::Experiment;

use elements::{attribute, declared_type, flag, typed, variable};
use mechfmu::contract::Version;
use mechfmu::model::element_name;
use mechfmu::xml::fmi3::SCALARS_ANNOTATION;
use quick_xml::events::{BytesStart, Event};
use quick_xml::{Reader, XmlVersion};

/// What the tools that run an FMU read of its model description.
#[derive(Clone, Debug, PartialEq)]
pub struct ModelDescription {
    pub version: Version,
    /// The `CoSimulation` element's `modelIdentifier`.
    pub model_identifier: String,
    /// What ties the description to the binary: FMI 2.0's `guid`, FMI 3.0's
    /// `instantiationToken`.
    pub token: String,
    pub variables: Vec<Variable>,
    /// `DefaultExperiment`: start, stop, step size, tolerance (0, 1, 1e-2 and 1e-6 where it
    /// gives none).
    pub start: f64,
    pub stop: f64,
    pub step: f64,
    pub tolerance: f64,
    /// Whether the FMU declares Model Exchange (a `ModelExchange` element).
    pub model_exchange: bool,
    /// The number of continuous states (scalars).
    pub states: usize,
    pub model_name: String,
    /// The `LogCategories`' names.
    pub log_categories: Vec<String>,
    /// What the interface types' elements declare.
    pub interfaces: Interfaces,
    /// FMI 2.0's `numberOfEventIndicators`.
    pub number_of_event_indicators: usize,
    /// FMI 2.0's `Derivatives/Unknown` indices (1-based), in the order of the state vector.
    pub derivative_indices: Vec<usize>,
    /// FMI 3.0's `ContinuousStateDerivative` value references, in the order of the states.
    pub state_derivatives: Vec<u32>,
    /// FMI 3.0's `EventIndicator` value references.
    pub event_indicators: Vec<u32>,
    /// Each output of `<ModelStructure>` by name, with the variables it depends on (`None`
    /// where no `dependencies` are given: then on every known).
    pub output_dependencies: Vec<(String, Option<Vec<String>>)>,
}

/// What the `ModelExchange`, `CoSimulation` and `ScheduledExecution` elements declare.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Interfaces {
    /// `ModelExchange`'s `modelIdentifier`.
    pub model_exchange_identifier: Option<String>,
    /// FMI 2.0's `completedIntegratorStepNotNeeded`.
    pub completed_integrator_step_not_needed: bool,
    /// FMI 3.0's `needsCompletedIntegratorStep`.
    pub needs_completed_integrator_step: bool,
    pub can_not_use_memory_management_functions: bool,
    pub max_output_derivative_order: i32,
    pub might_return_early_from_do_step: bool,
    pub has_event_mode: bool,
    pub provides_intermediate_update: bool,
    /// A `ScheduledExecution` element.
    pub scheduled_execution: bool,
}

impl ModelDescription {
    /// Its `DefaultExperiment`, with the defaults where it gives none.
    pub fn experiment(&self) -> Experiment {
        Experiment {
            start: self.start,
            ..Experiment::until(self.stop)
                .step(self.step)
                .tolerance(self.tolerance)
        }
    }

    pub fn parse(xml: &str) -> Result<ModelDescription, String> {
        let mut reader = Reader::from_str(xml);
        let mut d = ModelDescription {
            version: Version::Fmi2,
            model_identifier: String::new(),
            token: String::new(),
            variables: Vec::new(),
            start: 0.0,
            stop: 1.0,
            step: 1e-2,
            tolerance: 1e-6,
            model_exchange: false,
            states: 0,
            model_name: String::new(),
            log_categories: Vec::new(),
            interfaces: Interfaces::default(),
            number_of_event_indicators: 0,
            derivative_indices: Vec::new(),
            state_derivatives: Vec::new(),
            event_indicators: Vec::new(),
            output_dependencies: Vec::new(),
        };
        // FMI 2.0's `SimpleType` being read; the declared types' units and quantities.
        let mut simple_type: Option<String> = None;
        let mut types: Vec<(String, Option<String>, Option<String>)> = Vec::new();
        // The elements open around the one being read, outermost first.
        let mut open: Vec<String> = Vec::new();
        let mut in_scalars = false;
        let mut derivatives = Vec::new();
        loop {
            let event = reader
                .read_event()
                .map_err(|e| format!("the model description does not parse: {e}"))?;
            match &event {
                Event::Start(e) | Event::Empty(e) => {
                    let name = e.name().into_inner();
                    let parent = open.last().map_or("", String::as_str);
                    match name {
                        "SimpleType" => simple_type = attribute(e, "name"),
                        "Float64Type" => types.extend(declared_type(e, attribute(e, "name"))),
                        _ if parent == "SimpleType" => {
                            types.extend(declared_type(e, simple_type.clone()))
                        }
                        _ => {}
                    }
                    let scalars = d.element(e, &open, &mut derivatives)?;
                    if let Event::Start(_) = event {
                        in_scalars = scalars;
                        open.push(e.name().into_inner().to_string());
                    }
                }
                Event::Text(t) if in_scalars => {
                    let text = t.xml_content(XmlVersion::Explicit1_0);
                    if let Some(v) = d.variables.last_mut() {
                        v.scalars
                            .extend(text.split_whitespace().map(str::to_string));
                    }
                }
                Event::End(_) => {
                    open.pop();
                    in_scalars = false;
                }
                Event::Eof => break,
                _ => {}
            }
        }
        for v in d.variables.iter_mut() {
            let declared = (types.iter()).find(|t| Some(&t.0) == v.declared_type.as_ref());
            if let Some((_, unit, quantity)) = declared {
                v.unit = v.unit.take().or(unit.clone());
                v.quantity = v.quantity.take().or(quantity.clone());
            }
        }
        d.state_derivatives = derivatives.clone();
        // FMI 3.0 declares an array's derivatives by one element
        for vr in derivatives {
            let variable = d.variables.iter().find(|v| v.vr == vr);
            d.states += variable.map_or(1, |v| v.dimensions.iter().product());
        }
        if d.token.is_empty() || d.model_identifier.is_empty() {
            return Err(format!(
                "the model description has no {} or no CoSimulation modelIdentifier",
                token_attribute(d.version)
            ));
        }
        Ok(d)
    }

    /// Reads one element inside the elements `open` (an FMI 3.0 state derivative's value
    /// reference into `derivatives`); true for the annotation of an FMI 3.0 array listing its
    /// FMI 2.0 scalars (whose text follows).
    fn element(
        &mut self,
        e: &BytesStart,
        open: &[String],
        derivatives: &mut Vec<u32>,
    ) -> Result<bool, String> {
        let number = |name: &str| attribute(e, name).and_then(|v| v.parse::<f64>().ok());
        let parent = open.last().map_or("", String::as_str);
        // Inside a variable's element: the variable is the last one read.
        let in_variable = (open.iter())
            .position(|o| o == "ModelVariables")
            .is_some_and(|at| at + 1 < open.len());
        match e.name().into_inner() {
            "fmiModelDescription" => {
                self.model_name = attribute(e, "modelName").unwrap_or_default();
                self.number_of_event_indicators =
                    number("numberOfEventIndicators").map_or(0, |n| n as usize);
                let version = attribute(e, "fmiVersion").unwrap_or_default();
                self.version = if version.starts_with('3') {
                    Version::Fmi3
                } else {
                    Version::Fmi2
                };
                self.token = attribute(e, token_attribute(self.version)).unwrap_or_default();
            }
            "CoSimulation" => {
                self.model_identifier = attribute(e, "modelIdentifier").unwrap_or_default();
                let i = &mut self.interfaces;
                i.can_not_use_memory_management_functions =
                    flag(e, "canNotUseMemoryManagementFunctions");
                i.max_output_derivative_order =
                    number("maxOutputDerivativeOrder").map_or(0, |n| n as i32);
                i.might_return_early_from_do_step = flag(e, "mightReturnEarlyFromDoStep");
                i.has_event_mode = flag(e, "hasEventMode");
                i.provides_intermediate_update = flag(e, "providesIntermediateUpdate");
            }
            "ModelExchange" => {
                self.model_exchange = true;
                let i = &mut self.interfaces;
                i.model_exchange_identifier = attribute(e, "modelIdentifier");
                i.completed_integrator_step_not_needed =
                    flag(e, "completedIntegratorStepNotNeeded");
                i.needs_completed_integrator_step = flag(e, "needsCompletedIntegratorStep");
            }
            "ScheduledExecution" => self.interfaces.scheduled_execution = true,
            "Category" if parent == "LogCategories" => {
                self.log_categories
                    .push(attribute(e, "name").unwrap_or_default());
            }
            "DefaultExperiment" => {
                self.start = number("startTime").unwrap_or(self.start);
                self.stop = number("stopTime").unwrap_or(self.stop);
                self.step = number("stepSize").unwrap_or(self.step);
                self.tolerance = number("tolerance").unwrap_or(self.tolerance);
            }
            _ if parent == "ModelVariables" => self.variables.push(variable(e, self.version)?),
            // FMI 2.0's type element
            "Real" | "Integer" | "Boolean" | "String" | "Enumeration"
                if parent == "ScalarVariable" =>
            {
                if let Some(v) = self.variables.last_mut() {
                    if e.name().into_inner() == "Real" {
                        v.start = number("start");
                    }
                    v.kind = e.name().into_inner().to_string();
                    typed(v, e);
                }
            }
            "Dimension" if in_variable => {
                let start = attribute(e, "start").unwrap_or_default();
                let n = start
                    .parse()
                    .map_err(|_| format!("a <Dimension start=\"{start}\"> is not a size"))?;
                if let Some(v) = self.variables.last_mut() {
                    v.dimensions.push(n);
                }
            }
            "Annotation" if in_variable => {
                return Ok(attribute(e, "type").as_deref() == Some(SCALARS_ANNOTATION));
            }
            "Unknown" if parent == "Derivatives" => {
                self.states += 1;
                self.derivative_indices
                    .extend(number("index").map(|i| i as usize));
            }
            // FMI 2.0: 1-based indices into the variables; FMI 3.0: value references
            "Unknown" if parent == "Outputs" => self.read_dependencies(e, "index", |d, i| {
                d.variables.get((i as usize).wrapping_sub(1))
            })?,
            "Output" if parent == "ModelStructure" => {
                self.read_dependencies(e, "valueReference", |d, vr| {
                    d.variables.iter().find(|v| v.vr == vr)
                })?
            }
            "EventIndicator" if parent == "ModelStructure" => {
                let vr = attribute(e, "valueReference").and_then(|v| v.parse::<u32>().ok());
                self.event_indicators.extend(vr);
            }
            // counted in elements once the variables are known (see `parse`)
            "ContinuousStateDerivative" => {
                let vr = attribute(e, "valueReference").and_then(|v| v.parse::<u32>().ok());
                derivatives.extend(vr);
            }
            _ => {}
        }
        Ok(false)
    }

    /// An output's entry of `<ModelStructure>` (`key` names it; each number of its
    /// `dependencies` names a variable through `lookup`) into `output_dependencies`.
    fn read_dependencies(
        &mut self,
        e: &BytesStart,
        key: &str,
        lookup: impl Fn(&Self, u32) -> Option<&Variable>,
    ) -> Result<(), String> {
        let name_of = |text: &str| -> Result<String, String> {
            let n = text
                .parse::<u32>()
                .map_err(|_| format!("`{text}` in <ModelStructure> is not a number"))?;
            lookup(self, n)
                .map(|v| v.name.clone())
                .ok_or_else(|| format!("<ModelStructure> names no variable as {key} {n}"))
        };
        let output = name_of(&attribute(e, key).unwrap_or_default())?;
        let dependencies = match attribute(e, "dependencies") {
            Some(list) => Some(
                list.split_whitespace()
                    .map(name_of)
                    .collect::<Result<Vec<_>, _>>()?,
            ),
            None => None,
        };
        self.output_dependencies.push((output, dependencies));
        Ok(())
    }

    pub fn with_causality(&self, causality: &str) -> Vec<&Variable> {
        self.variables
            .iter()
            .filter(|v| v.causality == causality)
            .collect()
    }

    pub fn variable(&self, name: &str) -> Option<&Variable> {
        self.variables.iter().find(|v| v.name == name)
    }

    /// For every FMI 2.0 scalar that is an array element in this FMI 3.0 description: (its
    /// FMI 2.0 name, its element's name `array[i,j]`, 1-based). A scalar at several places
    /// (a symmetric matrix) is named by its first.
    pub fn element_names(&self) -> Vec<(String, String)> {
        let mut names: Vec<(String, String)> = Vec::new();
        for v in self.variables.iter().filter(|v| !v.dimensions.is_empty()) {
            for (k, scalar) in v.scalars.iter().enumerate() {
                if !names.iter().any(|(s, _)| s == scalar) {
                    names.push((scalar.clone(), element_name(&v.name, &v.dimensions, k)));
                }
            }
        }
        names
    }
}

/// The attribute holding what ties a description of `version` to its binary.
fn token_attribute(version: Version) -> &'static str {
    match version {
        Version::Fmi2 => "guid",
        Version::Fmi3 => "instantiationToken",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn committed(path: &str) -> ModelDescription {
        let path = format!(
            "{}/../../modelDescription/{path}",
            env!("CARGO_MANIFEST_DIR")
        );
        ModelDescription::parse(&std::fs::read_to_string(path).unwrap()).unwrap()
    }

    #[test]
    fn reads_the_oscillators_fmi2_description() {
        let d = committed("Oscillator.xml");
        assert_eq!(d.version, Version::Fmi2);
        assert_eq!(d.model_identifier, "Oscillator");
        assert!(d.token.starts_with('{'));
        assert_eq!(
            (d.start, d.stop, d.step, d.tolerance),
            (0.0, 20.0, 0.01, 1e-6)
        );
        assert!(d.model_exchange);
        assert_eq!(d.states, 2);
        let x = d.variable("x").unwrap();
        assert_eq!(
            (x.vr, x.causality.as_str(), x.start),
            (6, "output", Some(1.0))
        );
        assert_eq!(d.with_causality("input").len(), 1);
        assert_eq!(d.variable("x_ddot").unwrap().start, None);
    }

    #[test]
    fn reads_the_types_the_structure_and_the_interfaces() {
        let d = committed("Oscillator.xml");
        let m = d.variable("m").unwrap();
        assert_eq!(
            (
                m.kind.as_str(),
                m.initial.as_deref(),
                m.min,
                m.unit.as_deref()
            ),
            ("Real", Some("exact"), Some(0.0), Some("kg"))
        );
        assert_eq!(
            m.quantity.as_deref(),
            Some("Mass"),
            "from its declared type"
        );
        assert_eq!(d.variable("x_dot").unwrap().derivative, Some(7));
        assert_eq!(d.derivative_indices.len(), d.states);
        assert_eq!(d.log_categories.len(), 6);
        let i = &d.interfaces;
        assert_eq!(i.model_exchange_identifier.as_deref(), Some("Oscillator"));
        assert!(i.completed_integrator_step_not_needed);
        assert!(i.can_not_use_memory_management_functions);
        assert_eq!(i.max_output_derivative_order, 1);
        let three = committed("fmi3/RigidBody.xml");
        assert_eq!(three.state_derivatives.len(), 2);
        let inertia = three.variable("I_C").unwrap();
        assert_eq!(
            (inertia.kind.as_str(), inertia.start_values.len()),
            ("Float64", 9)
        );
    }

    #[test]
    fn reads_the_token_the_scalars_and_the_arrays_of_an_fmi3_description() {
        let d = committed("fmi3/RigidBody.xml");
        let two = committed("RigidBody.xml");
        assert_eq!(d.version, Version::Fmi3);
        assert!(d.token.starts_with('{'));
        assert_ne!(d.token, two.token);
        assert_eq!(d.states, two.states);
        let scalar = |n: &str| {
            (d.variables.iter())
                .find(|v| v.name == n && v.dimensions.is_empty())
                .map(|v| v.vr)
        };
        // 1-based places in the model description (`time`, listed last, 0)
        assert_eq!(scalar("M"), Some(1));
        assert_eq!(scalar("E_kin"), Some(10));
        assert_eq!(scalar("time"), Some(0));
        assert_eq!(scalar("w"), None, "an array is not a scalar");
        let inertia = d.variable("I_C").unwrap();
        assert_eq!(inertia.dimensions, [3, 3]);
        assert_eq!(inertia.scalars[..3], ["I_xx", "I_xy", "I_xz"]);
        assert_eq!(d.variable("M").unwrap().start, Some(2.0));
    }

    const ARRAYS: &str = r#"<fmiModelDescription fmiVersion="3.0" instantiationToken="{t}">
<CoSimulation modelIdentifier="M"/><ModelVariables>
<Float64 name="time" valueReference="3"/>
<Float64 name="I" valueReference="0"><Annotations><Annotation type="org.mechfmu.scalars">a b b c</Annotation></Annotations><Dimension start="2"/><Dimension start="2"/></Float64>
<Float64 name="g" valueReference="2"/>
</ModelVariables></fmiModelDescription>"#;

    #[test]
    fn elements_are_named_row_major_and_a_repeated_scalar_by_its_first_place() {
        let names = ModelDescription::parse(ARRAYS).unwrap().element_names();
        let expected = [("a", "I[1,1]"), ("b", "I[1,2]"), ("c", "I[2,2]")];
        assert_eq!(names, expected.map(|(s, e)| (s.to_string(), e.to_string())));
    }

    #[test]
    fn a_description_without_its_token_is_refused() {
        let err = ModelDescription::parse(&ARRAYS.replace("instantiationToken", "guid"));
        assert!(err.unwrap_err().contains("no instantiationToken"));
    }
}
