//! `<ModelStructure>`: which unknowns the importer can read, on which knowns each one
//! depends, and how ([`DependencyKind`]), found numerically from the mechanism's own
//! equations.
//!
//! A dependency is detected by perturbing one known and watching the unknown change: at the
//! start values and at two pseudo-random points near them (fixed seed, so the result is
//! deterministic), each known is moved by 1e-3 relative (1e-3 absolute when it is zero),
//! [`Mechanism::calculate`] and the complete evaluation ([`evaluate_all`]: `evaluate`, then
//! `outputs`) are run again, and every unknown whose value changed (by more than rounding)
//! depends on that known. The random points
//! also move the time, the parameters and the states, so that a dependency hidden at the
//! start point (a term `l sin(phi)` at `phi = 0`, `F0 sin(omega t)` at `t = 0`, a damping
//! that starts at 0) still shows. How each dependency enters ([`DependencyKind`]) is found
//! with exact derivatives at the same points.

mod kinds;
mod probe;

use std::collections::BTreeSet;

pub use kinds::DependencyKind;
use kinds::Mode;

use crate::model::{evaluate_all, Causality, Initial, Layout, Mechanism, ValueSet, Variable};

/// One known an unknown depends on, and how it enters.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Dependency {
    /// Its value reference (0-based; the FMI 2.0 XML writes 1-based `ScalarVariable`
    /// indices). With [`Knowns::Fmi3`], `VARIABLES.len()` stands for the time.
    pub known: usize,
    pub kind: DependencyKind,
}

/// One unknown: a variable and the knowns it depends on, ascending by value reference.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Unknown {
    pub vr: usize,
    pub dependencies: Vec<Dependency>,
}

impl Unknown {
    /// The value references of its knowns.
    pub fn knowns(&self) -> impl Iterator<Item = usize> + '_ {
        self.dependencies.iter().map(|d| d.known)
    }
}

/// The lists of `<ModelStructure>`, by scalar variable.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ModelStructure {
    /// Every output, in value-reference order. Knowns: the inputs, the continuous states
    /// (and, for FMI 3.0, the parameters and the time).
    pub outputs: Vec<Unknown>,
    /// The state derivatives in state order. Knowns: as for the outputs.
    pub derivatives: Vec<Unknown>,
    /// Outputs with `initial` approx/calculated, calculated parameters, and
    /// approx/calculated states and state derivatives, by value reference.
    /// Knowns: the inputs and the variables with `initial="exact"` (and, for FMI 3.0, the
    /// time).
    pub initial_unknowns: Vec<Unknown>,
    /// The event indicators (`Mechanism::EVENT_INDICATORS`), in their order. Knowns: as
    /// for the outputs. FMI 3.0 lists them (`<EventIndicator>`); FMI 2.0 has no such list.
    pub event_indicators: Vec<Unknown>,
    /// The knowns of the outputs, derivatives and event indicators, ascending (the time
    /// last, as `VARIABLES.len()`).
    pub knowns: Vec<usize>,
    /// The knowns of the initial unknowns, ascending (the time last).
    pub initial_knowns: Vec<usize>,
}

/// Which variables are the knowns of `dependencies`: the two standards differ.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Knowns {
    /// FMI 2.0.5, section 2.2.8 (attribute `dependencies` of `<Unknown>`): outputs and
    /// derivatives depend on the inputs and the continuous-time states; initial unknowns
    /// on the inputs and the `initial="exact"` variables. The time is a known of both, but
    /// no variable of ours: "it is assumed that the Unknown depends explicitly on the
    /// independent variable".
    Fmi2,
    /// FMI 3.0, section 2.4.8 (attribute `dependencies`): the knowns of `<Output>` and
    /// `<ContinuousStateDerivative>` are the inputs, the continuous states, the parameters
    /// (`causality="parameter"`) and the independent variable; of `<InitialUnknown>` the
    /// inputs, the `initial="exact"` variables and the independent variable. "If the known
    /// is not listed among the dependencies then the partial derivative of the unknown with
    /// respect to that known is identically zero": so a parameter or the time an output or
    /// a derivative depends on is listed.
    Fmi3,
}

fn is_unknown_initially(v: &Variable) -> bool {
    matches!(
        v.effective_initial(),
        Some(Initial::Approx | Initial::Calculated)
    )
}

/// Computes the model structure of `M` as FMI 2.0 has it.
///
/// Every FMU is a Model Exchange FMU too, and Model Exchange needs `<Derivatives>` and the
/// continuous-time states among the knowns of `dependencies` (FMI 2.0.5, section 2.2.8):
/// so both are always there, whatever the capabilities.
pub fn model_structure<M: Mechanism>() -> Result<ModelStructure, String> {
    model_structure_with::<M>(Knowns::Fmi2)
}

/// Computes the model structure of `M` with the knowns of one standard, by scalar variable.
pub fn model_structure_with<M: Mechanism>(standard: Knowns) -> Result<ModelStructure, String> {
    let variables = M::VARIABLES;
    let layout = Layout::new(variables).map_err(|e| format!("{}: {e}", M::NAME))?;
    let points = probe::points::<M>()?;
    let probe = Probe::<M> {
        points: &points,
        layout: &layout,
    };
    // The time, as a known of FMI 3.0.
    let time = (standard == Knowns::Fmi3).then_some(variables.len());

    // Knowns at communication points and in continuous-time mode: inputs and states (and
    // for FMI 3.0 the parameters and the time).
    let mut knowns: Vec<usize> = layout.inputs.clone();
    knowns.extend(&layout.states);
    if standard == Knowns::Fmi3 {
        knowns.extend(&layout.parameters);
    }
    knowns.sort_unstable();
    knowns.dedup();
    knowns.extend(time);

    let outputs = probe.unknowns(&layout.outputs, &knowns, Mode::ContinuousTime);
    let derivatives = probe.unknowns(&layout.derivatives, &knowns, Mode::ContinuousTime);
    let indicators: Vec<usize> = (M::EVENT_INDICATORS.iter())
        .map(|name| {
            (variables.iter().position(|v| v.name == *name))
                .ok_or_else(|| format!("{}: event indicator `{name}` is not a variable", M::NAME))
        })
        .collect::<Result<_, _>>()?;
    let event_indicators = probe.unknowns(&indicators, &knowns, Mode::ContinuousTime);

    // InitialUnknowns, knowns in Initialization Mode: inputs and initial="exact" (and for
    // FMI 3.0 the time).
    let mut unknowns: Vec<usize> = variables
        .iter()
        .enumerate()
        .filter(|(_, v)| {
            (v.causality == Causality::Output && is_unknown_initially(v))
                || v.causality == Causality::CalculatedParameter
        })
        .map(|(vr, _)| vr)
        .collect();
    unknowns.extend(
        (layout.states.iter())
            .chain(&layout.derivatives)
            .copied()
            .filter(|&vr| is_unknown_initially(&variables[vr])),
    );
    unknowns.sort_unstable();
    unknowns.dedup();
    let mut initial_knowns: Vec<usize> = variables
        .iter()
        .enumerate()
        .filter(|(_, v)| {
            v.causality == Causality::Input || v.effective_initial() == Some(Initial::Exact)
        })
        .map(|(vr, _)| vr)
        .collect();
    initial_knowns.extend(time);
    let initial_unknowns = probe.unknowns(&unknowns, &initial_knowns, Mode::Initialization);

    Ok(ModelStructure {
        outputs,
        derivatives,
        initial_unknowns,
        event_indicators,
        knowns,
        initial_knowns,
    })
}

/// The probe points of one mechanism, and its layout.
struct Probe<'a, M: Mechanism> {
    points: &'a [M::Values<f64>],
    layout: &'a Layout,
}

impl<M: Mechanism> Probe<'_, M> {
    /// `vrs` as unknowns of `knowns`, with the kind of each dependency. An unknown that is
    /// a known itself (an output that is a state, an input that is a state's derivative)
    /// depends on itself only, by a factor of 1.
    fn unknowns(&self, vrs: &[usize], knowns: &[usize], mode: Mode) -> Vec<Unknown> {
        let computed: Vec<usize> = (vrs.iter().copied())
            .filter(|vr| !knowns.contains(vr))
            .collect();
        let deps = dependencies::<M>(self.points, &computed, knowns);
        let kinds = kinds::kinds::<M>(self.points, self.layout, &computed, &deps, mode);
        vrs.iter()
            .map(|&vr| {
                let dependencies = match computed.iter().position(|&c| c == vr) {
                    Some(i) => (deps[i].iter().zip(&kinds[i]))
                        .map(|(&known, &kind)| Dependency { known, kind })
                        .collect(),
                    None => vec![Dependency {
                        known: vr,
                        kind: DependencyKind::Constant,
                    }],
                };
                Unknown { vr, dependencies }
            })
            .collect()
    }
}

/// For each unknown, the knowns (ascending) whose perturbation changes it at any probe
/// point. A known that cannot be perturbed at some point is, conservatively, a dependency
/// of every unknown.
fn dependencies<M: Mechanism>(
    points: &[M::Values<f64>],
    unknowns: &[usize],
    knowns: &[usize],
) -> Vec<Vec<usize>> {
    let mut deps = vec![BTreeSet::new(); unknowns.len()];
    for p in points {
        let mut base = p.clone();
        evaluate_all::<M, f64>(&mut base);
        for &k in knowns {
            let Some(mut q) = probe::perturbed::<M>(p, k) else {
                deps.iter_mut().for_each(|d| {
                    d.insert(k);
                });
                continue;
            };
            evaluate_all::<M, f64>(&mut q);
            for (d, &u) in deps.iter_mut().zip(unknowns) {
                if probe::changed(base.get(u), q.get(u)) {
                    d.insert(k);
                }
            }
        }
    }
    deps.into_iter().map(|d| d.into_iter().collect()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::{Experiment, Scalar};

    crate::mechanism! {
        /// y = a x + sin(u), z = b: a test of dependency detection.
        pub struct Probe / ProbeValues {
            /// Gain
            a: Variable::parameter("1", 2.0),
            /// Parameter-only output
            b: Variable::tunable("m", 0.5),
            /// Input
            u: Variable::input("rad", 0.0),
            /// State
            x: Variable::state("m", 0.0, "x_dot"),
            /// Its rate: -a x + u
            x_dot: Variable::local("m/s"),
            /// a x + sin(u)
            y: Variable::output("m"),
            /// b
            z: Variable::output("m"),
            /// 2 b
            b2: Variable::calculated("m"),
        }
    }

    impl Mechanism for Probe {
        const EXPERIMENT: Experiment = Experiment::until(1.0).step(0.1).tolerance(1e-6);
        fn calculate(v: &mut ProbeValues<f64>) -> Result<(), String> {
            v.b2 = 2.0 * v.b;
            Ok(())
        }
        fn evaluate<S: Scalar>(v: &mut ProbeValues<S>) {
            v.x_dot = -v.a * v.x + v.u;
            v.y = v.a * v.x + v.u.sin();
            v.z = v.b;
        }
    }

    // Value references: a 0, b 1, u 2, x 3, x_dot 4, y 5, z 6, b2 7.

    use DependencyKind::{Constant, Dependent, Fixed};

    fn unknown(vr: usize, dependencies: &[(usize, DependencyKind)]) -> Unknown {
        Unknown {
            vr,
            dependencies: (dependencies.iter())
                .map(|&(known, kind)| Dependency { known, kind })
                .collect(),
        }
    }

    #[test]
    fn states_are_knowns() {
        let s = model_structure::<Probe>().unwrap();
        // The output x is a state: itself, by a factor 1; y = a x + sin(u): the factor of x
        // is the fixed parameter a, sin(u) has none.
        assert_eq!(
            s.outputs,
            vec![
                unknown(3, &[(3, Constant)]),
                unknown(5, &[(2, Dependent), (3, Fixed)]),
                unknown(6, &[])
            ]
        );
        assert_eq!(
            s.derivatives,
            vec![unknown(4, &[(2, Constant), (3, Fixed)])]
        );
        // x_dot (local, calculated) is an initial unknown here too. In Initialization Mode a
        // is a known: the factor it makes is no constant one.
        assert_eq!(
            s.initial_unknowns,
            vec![
                unknown(4, &[(0, Dependent), (2, Constant), (3, Dependent)]),
                unknown(5, &[(0, Dependent), (2, Dependent), (3, Dependent)]),
                unknown(6, &[(1, Dependent)]),
                unknown(7, &[(1, Dependent)])
            ]
        );
        assert_eq!(s.event_indicators, []);
    }

    #[test]
    fn fmi3_has_the_parameters_and_the_time_as_knowns() {
        let s = model_structure_with::<Probe>(Knowns::Fmi3).unwrap();
        // The parameters a (0) and b (1) are knowns now; the time (8) moves nothing here.
        assert_eq!(
            s.outputs,
            vec![
                unknown(3, &[(3, Constant)]),
                unknown(5, &[(0, Dependent), (2, Dependent), (3, Fixed)]),
                unknown(6, &[(1, Dependent)])
            ]
        );
        assert_eq!(
            s.derivatives,
            vec![unknown(4, &[(0, Dependent), (2, Constant), (3, Fixed)])]
        );
        // In Initialization Mode the parameters were knowns already (initial="exact").
        assert_eq!(
            s.initial_unknowns,
            model_structure::<Probe>().unwrap().initial_unknowns
        );
    }

    crate::mechanism! {
        /// y = 2 x0 + x, where x0 is the state's value when `calculate` ran.
        pub struct Offset / OffsetValues {
            /// State
            x: Variable::state("m", 1.0, "x_dot"),
            /// Its rate: -x
            x_dot: Variable::local("m/s"),
            /// Twice the state as calculated
            x0_2: Variable::calculated("m"),
            /// 2 x0 + x
            y: Variable::output("m"),
        }
    }

    impl Mechanism for Offset {
        const EXPERIMENT: Experiment = Experiment::until(1.0).step(0.1).tolerance(1e-6);
        fn calculate(v: &mut OffsetValues<f64>) -> Result<(), String> {
            v.x0_2 = 2.0 * v.x;
            Ok(())
        }
        fn evaluate<S: Scalar>(v: &mut OffsetValues<S>) {
            v.x_dot = -v.x;
            v.y = v.x0_2 + v.x;
        }
    }

    #[test]
    fn a_known_calculate_reads_enters_with_no_particular_structure() {
        // The dual numbers see y = x0_2 + x (a factor 1); `calculate` makes it 3 x. Every
        // unknown depending on a known that `calculate` reads says no more than `dependent`.
        let s = model_structure::<Offset>().unwrap();
        assert_eq!(
            s.outputs,
            vec![unknown(0, &[(0, Constant)]), unknown(3, &[(0, Dependent)])]
        );
        assert_eq!(s.derivatives, vec![unknown(1, &[(0, Dependent)])]);
    }

    #[test]
    fn deterministic() {
        assert_eq!(model_structure::<Probe>(), model_structure::<Probe>());
    }

    #[test]
    fn effective_initial_follows_the_standard() {
        let mut v = Variable::output("m");
        v.initial = None;
        assert_eq!(v.effective_initial(), Some(Initial::Calculated));
        assert_eq!(Variable::input("m", 0.0).effective_initial(), None);
        let mut p = Variable::parameter("m", 1.0);
        p.initial = None;
        assert_eq!(p.effective_initial(), Some(Initial::Exact));
    }
}
