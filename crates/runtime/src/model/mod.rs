//! The mechanism declaration API: what a mechanism author writes.
//!
//! A mechanism is declared once with the [`mechanism!`](crate::mechanism) macro (its
//! variables) and the [`Mechanism`] trait (its equations). The modelDescription, value
//! references, GUID, FMI functions and documentation are all generated from these two.

mod arrays;
mod case;
mod checks;
mod const_text;
mod declare;
mod layout;
mod order;
pub(crate) mod scalar;
mod terminal;
pub(crate) mod trig;
pub mod units;
mod values;
mod variable;

pub use arrays::{check_arrays, element_name, Array, Shaped, Shapes};
pub use case::{check_moving_case, MovingCase};
pub use checks::{
    check_declaration, check_event_indicators, check_variable, declaration_error, variable_mistake,
};
pub(crate) use checks::{closest_name, edit_distance, position as variable_position};
#[doc(hidden)]
pub use const_text::str_eq;
pub use const_text::ConstMessage;
#[doc(hidden)]
pub use layout::{
    count_selected, derivative_references, derivatives_among_states, selected_references, Selection,
};
pub use layout::{event_indicator_references, Layout};
pub(crate) use order::states_before_derivatives;
pub use scalar::{cos, lit, sin, sin_cos, Scalar};
pub use terminal::{check_terminals, terminal_named, Terminal, TRANSLATIONAL};
#[doc(hidden)]
pub use values::{copy_one_by_one, get_one_by_one, Fields};
pub use variable::{Causality, Initial, SetPhase, Variability, Variable};

/// The FMU's `DefaultExperiment`, and the tolerance used when the importer gives none.
///
/// Written as a chain from its stop time, each call naming what it sets:
/// `Experiment::until(20.0).step(0.01).tolerance(1e-6)`, or as the struct itself for an
/// experiment that starts after time 0.
///
/// ```
/// use mechfmu::model::Experiment;
///
/// let experiment = Experiment::until(20.0).step(0.01).tolerance(1e-8);
/// assert_eq!(experiment, Experiment { start: 0.0, stop: 20.0, step: 0.01, tolerance: 1e-8 });
/// assert_eq!((Experiment::until(20.0).step, Experiment::until(20.0).tolerance), (0.04, 1e-6));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Experiment {
    pub start: f64,
    pub stop: f64,
    pub step: f64,
    pub tolerance: f64,
}

impl Experiment {
    /// From time 0 to `stop`, in communication steps of a five-hundredth of that, at the
    /// relative tolerance 1e-6 (what [`step`](Self::step) and [`tolerance`](Self::tolerance)
    /// change).
    pub const fn until(stop: f64) -> Self {
        Experiment {
            start: 0.0,
            stop,
            step: stop / 500.0,
            tolerance: 1e-6,
        }
    }

    /// The same experiment in communication steps of `step`.
    pub const fn step(self, step: f64) -> Self {
        Experiment { step, ..self }
    }

    /// The same experiment at the relative tolerance `tolerance`.
    pub const fn tolerance(self, tolerance: f64) -> Self {
        Experiment { tolerance, ..self }
    }
}

/// What a mechanism's [`Mechanism::monitor`] says about the current state.
#[derive(Clone, Debug, PartialEq)]
pub enum Monitor {
    /// The model holds.
    Valid,
    /// The model holds only approximately (e.g. a slack cable): logged as a warning once
    /// per episode, i.e. when the condition starts.
    Warning(String),
    /// The model no longer holds (e.g. a trolley at the pivot): the step ends with
    /// `fmi2Discard` at the last valid time.
    Invalid(String),
}

/// The variables of a mechanism. Implemented by the [`mechanism!`](crate::mechanism) macro;
/// do not implement it by hand.
pub trait Declaration: Send + Sync + 'static {
    /// The model identifier (the FMU's file names).
    const NAME: &'static str;
    /// One paragraph describing the mechanism.
    const DESCRIPTION: &'static str;
    /// Every variable, in value-reference order (value reference = index).
    const VARIABLES: &'static [Variable];

    /// One value per variable plus the time, as named fields, generic over the scalar so the
    /// same equations run on `f64` and on dual numbers.
    type Values<S: Scalar>: ValueSet<S>;

    /// The continuous states, as the solver sees them: `[f64; number of states]`.
    type State: crate::solver::StateVector;
    /// The value references of the states, in declaration order ([`Layout::states`]).
    const STATES: &'static [usize];
    /// The value references of the states' derivatives ([`Layout::derivatives`]).
    const DERIVATIVES: &'static [usize];
    /// For each state's derivative, the position in the state vector of the state it is
    /// (`x' = v` with `v` a state), or `None` when `evaluate` computes it.
    const DERIVATIVES_AMONG_STATES: &'static [Option<usize>];
    /// The value references of the continuous variables (which a step must leave finite).
    const CONTINUOUS: &'static [usize];
    /// The continuous variables but the states and their derivatives: what a step still
    /// checks after the solver accepted its end point, where the solver has checked those.
    const CONTINUOUS_UNCHECKED: &'static [usize];
    /// The value references of the inputs, in declaration order ([`Layout::inputs`]).
    const INPUTS: &'static [usize];

    /// Values that are all zero.
    fn zeros<S: Scalar>() -> Self::Values<S>;

    /// The values with every field converted by `f` (e.g. `f64` to a dual number).
    fn map_values<A: Scalar, B: Scalar>(
        values: &Self::Values<A>,
        f: impl Fn(A) -> B,
    ) -> Self::Values<B>;
}

/// Access to a mechanism's values by value reference.
pub trait ValueSet<S: Scalar>: Fields<S> + Clone + Send + 'static {
    /// Value reference `vr`'s value, or `None` when `vr` is not a variable. O(1).
    #[inline(always)]
    fn get(&self, vr: usize) -> Option<S> {
        values::get(self, vr)
    }
    /// Sets value reference `vr`; false when `vr` is not a variable.
    #[inline(always)]
    fn set(&mut self, vr: usize, value: S) -> bool {
        values::set(self, vr, value)
    }
    fn time(&self) -> S;
    fn set_time(&mut self, t: S);
}

/// The equations of a mechanism.
///
/// `evaluate` is generic over the scalar type: it runs on `f64` for simulation and on dual
/// numbers for exact directional derivatives, so it must only use the operations of
/// [`Scalar`] (arithmetic, `sin`, `sqrt`, ... and [`lit`] for constants).
pub trait Mechanism: Declaration {
    /// The `DefaultExperiment` of the FMU.
    const EXPERIMENT: Experiment;

    /// Notes for the FMU's documentation (`documentation/index.html`): the equations as
    /// implemented and where, and why, they depart from the source they come from. A small
    /// Markdown subset: paragraphs, `## headings`, `- ` lists, code blocks (fenced, or
    /// indented by four spaces: use them for equations) and inline `code`.
    const NOTES: &'static str = "";

    /// Computes the calculated parameters from the parameters, and rejects parameter values
    /// that the declared bounds cannot express (e.g. an inertia tensor that is not positive
    /// definite). Called at initialization and whenever a tunable parameter changes; the
    /// declared bounds (`positive`, `min`, `max`) are checked before it is called.
    fn calculate(_values: &mut Self::Values<f64>) -> Result<(), String> {
        Ok(())
    }

    /// Computes every state derivative from the states, inputs, parameters, calculated
    /// parameters and time, and every output that is not left to [`Mechanism::outputs`]
    /// (outputs that a derivative or [`Mechanism::monitor`] needs, or that come for free).
    ///
    /// It must be a function of those alone (not of the outputs it wrote last time) and
    /// write only derivatives and outputs: the runtime reuses an evaluation at the same
    /// point instead of repeating it (the solver's last stage is the next step's first).
    /// It runs at every stage of the solver (6 or 12 times per solver step): keep here only
    /// what the derivatives (and the monitor) need.
    fn evaluate<S: Scalar>(values: &mut Self::Values<S>);

    /// Computes the outputs that no derivative depends on (e.g. energies, momenta, positions
    /// in ground axes), from the states, inputs, parameters, calculated parameters, time and
    /// whatever [`Mechanism::evaluate`] wrote at the same point. The default computes
    /// nothing: then `evaluate` computes everything.
    ///
    /// The runtime calls it right after `evaluate` wherever the values become visible
    /// (communication points, `fmi2GetReal` after a `fmi2SetReal`, initialization, a
    /// restored or rolled-back state, directional and output derivatives, the dependency
    /// detection of the modelDescription), never at the solver's stages. So:
    /// * it must write only outputs (or local variables) that `evaluate` does not read and
    ///   that no derivative and no [`Mechanism::monitor`] reads;
    /// * like `evaluate`, it must be a function of the point alone, generic over the scalar
    ///   (it also runs on dual numbers, for exact derivatives of these outputs).
    ///
    /// Moving an output here changes neither its value (the same operations on the same
    /// numbers) nor the modelDescription; it only stops it being computed at every stage.
    fn outputs<S: Scalar>(_values: &mut Self::Values<S>) {}

    /// Why the equations have no solution at the point the values hold, when they can
    /// tell (a mechanism declared from its energies: a mass matrix that is not positive
    /// definite, [`Lagrangian::mass_matrix_problem`](crate::lagrange::Lagrangian::mass_matrix_problem)).
    /// Asked only where an evaluation left a derivative or output that is not finite, and
    /// added to the message that refuses the point (at initialization, after
    /// `fmi2SetReal`, in a step that stops there). `None` by default.
    fn diagnose(_values: &Self::Values<f64>) -> Option<String> {
        None
    }

    /// Whether [`Mechanism::project`] does anything (saves an evaluation per step).
    const PROJECTED: bool = false;

    /// Projects the states back onto the manifold they must stay on (e.g. a unit
    /// quaternion), at the end of every communication step. It must not change the physical
    /// state, only remove the integration's drift off the manifold. In Model Exchange it
    /// runs at a step event only when a state would move by more than
    /// [`PROJECTION_DRIFT`](crate::simulation::PROJECTION_DRIFT): the equations must hold
    /// off the manifold too (evaluate what the states stand for, as `q/|q|` for a
    /// quaternion), since the importer's solver leaves them there by about its tolerance.
    fn project(_values: &mut Self::Values<f64>) {}

    /// Whether [`Mechanism::monitor`] has anything to say (saves evaluating it).
    const MONITORED: bool = false;

    /// Checks the model's validity at every accepted solver step (values evaluated there by
    /// [`Mechanism::evaluate`] alone: it must not read what [`Mechanism::outputs`] writes).
    /// In Model Exchange, where the importer's solver takes the steps, it is asked at every
    /// `fmi2CompletedIntegratorStep` and at every event: `Warning` is logged once per
    /// episode, `Invalid` ends the simulation (`terminateSimulation`, with the message).
    fn monitor(_values: &Self::Values<f64>) -> Monitor {
        Monitor::Valid
    }

    /// The event indicators of Model Exchange, by variable name: continuous variables
    /// (states, or variables [`Mechanism::evaluate`] computes) whose sign changes where
    /// [`Mechanism::monitor`]'s verdict changes, e.g. `x` for a trolley that must stay on
    /// its side of the pivot (`x > 0`) and `T` for a cable that must pull (`T ≥ 0`). The
    /// importer's solver locates each change of sign and stops there, so the monitor is
    /// asked at the very time a limit is crossed rather than at the end of the step that
    /// crossed it. A name that is not a continuous variable does not compile.
    const EVENT_INDICATORS: &'static [&'static str] = &[];

    /// Declared scalars grouped into the arrays the physics has (an inertia tensor, a
    /// quaternion): FMI 3.0 shows each as one array variable, FMI 2.0 keeps the scalars.
    /// An array of states needs the array of their derivatives, in the same order. See
    /// [`Array`].
    const ARRAYS: &'static [Array] = &[];

    /// A case that moves, for a mechanism whose default experiment stands still (an
    /// equilibrium): the documentation says why it does ([`MovingCase::at_rest`]) and plots
    /// this case instead of flat lines. A name that is not a variable settable before
    /// initialization does not compile.
    const MOVING_CASE: Option<MovingCase> = None;

    /// The mechanism's ports, each a group of its variables that connects as one (a mass's
    /// position, velocity and the force on it): a system connects terminal to terminal, and
    /// the FMI 3.0 FMU lists them in `terminalsAndIcons/terminalsAndIcons.xml`. A member that
    /// names no declared variable does not compile.
    const TERMINALS: &'static [Terminal] = &[];
}

/// The variable whose field `select` picks from a mechanism's values (`|v| &v.theta`). Tests
/// and tools that name variables this way name them through the declaration: a misspelled or
/// renamed variable does not compile, and rustc's error names it.
///
/// Panics when `select` returns a reference to something other than a variable's field.
pub fn variable_of<M: Declaration>(
    select: impl FnOnce(&M::Values<f64>) -> &f64,
) -> &'static Variable {
    let values = M::zeros::<f64>();
    let field = select(&values);
    let vr = values::reference_of(&values, field).unwrap_or_else(|| {
        panic!(
            "variable_of::<{}>: the selected value is not a variable of its values",
            M::NAME
        )
    });
    &M::VARIABLES[vr]
}

/// A complete evaluation at the point the values hold: [`Mechanism::evaluate`] (the
/// derivatives) then [`Mechanism::outputs`] (the outputs no derivative needs). The one
/// place that knows the order; the solver's stages call `evaluate` alone.
#[inline]
pub fn evaluate_all<M: Mechanism, S: Scalar>(values: &mut M::Values<S>) {
    M::evaluate(values);
    M::outputs(values);
}
