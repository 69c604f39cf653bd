//! One model variable as an importer sees it: the row of the modelDescription.

/// FMI 2.0 causality of a variable.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Causality {
    Parameter,
    CalculatedParameter,
    Input,
    Output,
    Local,
}

/// FMI 2.0 variability of a variable.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Variability {
    Fixed,
    Tunable,
    Continuous,
}

/// FMI 2.0 `initial` attribute (absent for inputs).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Initial {
    Exact,
    Approx,
    Calculated,
}

impl Causality {
    pub const fn as_str(self) -> &'static str {
        match self {
            Causality::Parameter => "parameter",
            Causality::CalculatedParameter => "calculatedParameter",
            Causality::Input => "input",
            Causality::Output => "output",
            Causality::Local => "local",
        }
    }
}

impl Variability {
    pub const fn as_str(self) -> &'static str {
        match self {
            Variability::Fixed => "fixed",
            Variability::Tunable => "tunable",
            Variability::Continuous => "continuous",
        }
    }
}

impl Initial {
    pub const fn as_str(self) -> &'static str {
        match self {
            Initial::Exact => "exact",
            Initial::Approx => "approx",
            Initial::Calculated => "calculated",
        }
    }
}

/// A real variable of a mechanism, built with the `const` constructors below and named by
/// the [`mechanism!`](crate::mechanism) macro (the field name is the variable name).
///
/// ```
/// use mechfmu::model::Variable;
/// const MASS: Variable = Variable::parameter("kg", 1.0).positive();
/// assert_eq!(MASS.min, Some(0.0));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Variable {
    pub name: &'static str,
    pub description: &'static str,
    pub causality: Causality,
    pub variability: Variability,
    pub initial: Option<Initial>,
    /// Unit in the modelDescription's notation (`"N.s/m"`, `"m/s2"`, `"kg.m2"`, `"1"`).
    pub unit: &'static str,
    pub start: Option<f64>,
    pub min: Option<f64>,
    pub max: Option<f64>,
    /// The value must be strictly greater than `min` (a mass, a length, an inertia).
    pub positive: bool,
    /// For a state: the name of the variable that holds its time derivative.
    pub derivative: Option<&'static str>,
}

impl Variable {
    const fn base(
        causality: Causality,
        variability: Variability,
        initial: Option<Initial>,
        unit: &'static str,
        start: Option<f64>,
    ) -> Self {
        Variable {
            name: "",
            description: "",
            causality,
            variability,
            initial,
            unit,
            start,
            min: None,
            max: None,
            positive: false,
            derivative: None,
        }
    }

    /// A parameter fixed after initialization (`causality="parameter"`, `variability="fixed"`).
    pub const fn parameter(unit: &'static str, start: f64) -> Self {
        Self::base(
            Causality::Parameter,
            Variability::Fixed,
            Some(Initial::Exact),
            unit,
            Some(start),
        )
    }

    /// A parameter the importer may change between communication steps.
    pub const fn tunable(unit: &'static str, start: f64) -> Self {
        Self::base(
            Causality::Parameter,
            Variability::Tunable,
            Some(Initial::Exact),
            unit,
            Some(start),
        )
    }

    /// A parameter computed from the others at initialization (and again whenever a tunable
    /// parameter changes) by [`Mechanism::calculate`](crate::model::Mechanism::calculate).
    pub const fn calculated(unit: &'static str) -> Self {
        Self::base(
            Causality::CalculatedParameter,
            Variability::Tunable,
            Some(Initial::Calculated),
            unit,
            None,
        )
    }

    /// A continuous real input, held (or interpolated) over a communication step.
    pub const fn input(unit: &'static str, start: f64) -> Self {
        Self::base(
            Causality::Input,
            Variability::Continuous,
            None,
            unit,
            Some(start),
        )
    }

    /// A continuous state, exposed as an output whose start value is its initial condition.
    /// `derivative` names the variable that [`Mechanism::evaluate`](crate::model::Mechanism::evaluate) fills with its rate.
    pub const fn state(unit: &'static str, start: f64, derivative: &'static str) -> Self {
        let mut v = Self::base(
            Causality::Output,
            Variability::Continuous,
            Some(Initial::Exact),
            unit,
            Some(start),
        );
        v.derivative = Some(derivative);
        v
    }

    /// A continuous output computed by [`Mechanism::evaluate`](crate::model::Mechanism::evaluate) (or, when no derivative
    /// needs it, by [`Mechanism::outputs`](crate::model::Mechanism::outputs)).
    pub const fn output(unit: &'static str) -> Self {
        Self::base(
            Causality::Output,
            Variability::Continuous,
            Some(Initial::Calculated),
            unit,
            None,
        )
    }

    /// An internal continuous variable computed by [`Mechanism::evaluate`](crate::model::Mechanism::evaluate) (e.g. the rate of
    /// a state that is not worth exposing as an output).
    pub const fn local(unit: &'static str) -> Self {
        Self::base(
            Causality::Local,
            Variability::Continuous,
            Some(Initial::Calculated),
            unit,
            None,
        )
    }

    pub const fn min(mut self, min: f64) -> Self {
        self.min = Some(min);
        self
    }

    pub const fn max(mut self, max: f64) -> Self {
        self.max = Some(max);
        self
    }

    /// Must be > 0: declares `min="0"` and rejects 0 too at initialization.
    pub const fn positive(mut self) -> Self {
        self.min = Some(0.0);
        self.positive = true;
        self
    }

    /// Marks a calculated parameter as fixed (it depends on fixed parameters only).
    pub const fn fixed(mut self) -> Self {
        self.variability = Variability::Fixed;
        self
    }

    pub const fn describe(mut self, description: &'static str) -> Self {
        self.description = description;
        self
    }

    /// Used by the `mechanism!` macro.
    #[doc(hidden)]
    pub const fn named(mut self, name: &'static str, doc: &'static str) -> Self {
        self.name = name;
        if self.description.is_empty() {
            self.description = doc;
        }
        self
    }

    /// The description without the leading space doc comments carry.
    pub fn description(&self) -> &'static str {
        self.description.trim()
    }

    /// Whether the importer may set this variable, in the given phase.
    pub const fn settable(&self, phase: SetPhase) -> bool {
        let input = matches!(self.causality, Causality::Input);
        match phase {
            SetPhase::Instantiated | SetPhase::Initialization => {
                input || matches!(self.initial, Some(Initial::Exact | Initial::Approx))
            }
            SetPhase::Running => {
                input
                    || (matches!(self.causality, Causality::Parameter)
                        && matches!(self.variability, Variability::Tunable))
            }
            SetPhase::ContinuousTime => {
                input && matches!(self.variability, Variability::Continuous)
            }
        }
    }

    /// The `initial` this variable has, written or not (FMI 2.0.5, table of section 2.2.7).
    pub fn effective_initial(&self) -> Option<Initial> {
        self.initial.or(match self.causality {
            Causality::Input => None,
            Causality::Parameter => Some(Initial::Exact),
            Causality::CalculatedParameter | Causality::Output | Causality::Local => {
                Some(Initial::Calculated)
            }
        })
    }

    pub fn is_state(&self) -> bool {
        self.derivative.is_some()
    }

    /// Checks a value against the declared bounds; the message names the variable.
    pub fn check_value(&self, value: f64) -> Result<(), String> {
        if !value.is_finite() {
            return Err(format!("{} = {value} is not a finite number", self.name));
        }
        if self.positive && value <= 0.0 {
            return Err(format!(
                "{} = {value} is not allowed: it must be > 0",
                self.name
            ));
        }
        if let Some(min) = self.min {
            if value < min {
                return Err(format!(
                    "{} = {value} is below its minimum {min}",
                    self.name
                ));
            }
        }
        if let Some(max) = self.max {
            if value > max {
                return Err(format!(
                    "{} = {value} is above its maximum {max}",
                    self.name
                ));
            }
        }
        Ok(())
    }
}

/// When a `fmi2SetReal` happens, which decides what may be set.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SetPhase {
    Instantiated,
    Initialization,
    /// After initialization: Co-Simulation between steps, Model Exchange in event mode.
    Running,
    /// Model Exchange in continuous-time mode: continuous inputs only.
    ContinuousTime,
}

impl SetPhase {
    /// After initialization (running or in continuous-time mode).
    pub fn initialized(self) -> bool {
        matches!(self, SetPhase::Running | SetPhase::ContinuousTime)
    }
}
