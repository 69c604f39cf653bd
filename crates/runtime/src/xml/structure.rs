//! `<ModelStructure>`: which unknowns the importer can read, and on which knowns each one
//! depends, found numerically from the mechanism's own equations.
//!
//! A dependency is detected by perturbing one known and watching the unknown change: at the
//! start values and at two pseudo-random points near them (fixed seed, so the result is
//! deterministic), each known is moved by 1e-3 relative (1e-3 absolute when it is zero),
//! [`Mechanism::calculate`] and the complete evaluation ([`evaluate_all`]: `evaluate`, then
//! `outputs`) are run again, and every unknown whose value changed (by more than rounding)
//! depends on that known. The random points
//! also move the time, the parameters and the states, so that a dependency hidden at the
//! start point (a term `l sin(phi)` at `phi = 0`, `F0 sin(omega t)` at `t = 0`, a damping
//! that starts at 0) still shows.

use std::collections::BTreeSet;

use crate::model::{evaluate_all, Causality, Initial, Layout, Mechanism, ValueSet, Variable};
use crate::simulation::start_values;

/// One `<Unknown>`: a variable and the knowns it depends on, as value references (0-based;
/// the FMI 2.0 XML writes 1-based `ScalarVariable` indices), ascending. With
/// [`Knowns::Fmi3`], the value reference `VARIABLES.len()` stands for the time (FMI 3.0's
/// independent variable has the value reference after the last variable's).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Unknown {
    pub vr: usize,
    pub dependencies: Vec<usize>,
}

/// The three lists of `<ModelStructure>`, by scalar variable.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct ModelStructure {
    /// Every output, in value-reference order. Knowns: the inputs, and the continuous
    /// states (and, for FMI 3.0, the parameters and the time).
    pub outputs: Vec<Unknown>,
    /// The state derivatives in state order. Knowns: as for the outputs.
    pub derivatives: Vec<Unknown>,
    /// Outputs with `initial` approx/calculated, calculated parameters, and
    /// approx/calculated states and state derivatives, by value reference.
    /// Knowns: the inputs and the variables with `initial="exact"` (and, for FMI 3.0, the
    /// time).
    pub initial_unknowns: Vec<Unknown>,
}

/// Which variables are the knowns of `dependencies`: the two standards differ.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Knowns {
    /// FMI 2.0.5, section 2.2.8: outputs and derivatives depend on the inputs and the
    /// continuous states; initial unknowns on the inputs and the `initial="exact"`
    /// variables.
    Fmi2,
    /// FMI 3.0, section 2.4.8 (`dependencies`): the parameters (`causality="parameter"`)
    /// and the independent variable are knowns too, for outputs and derivatives; the
    /// independent variable for initial unknowns. An unknown whose dependencies leave a
    /// known out has a partial derivative of zero with respect to it.
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
    let points = points::<M>()?;
    // The time, as a known of FMI 3.0.
    let time = (standard == Knowns::Fmi3).then_some(variables.len());

    // Knowns at communication points and in continuous-time mode: inputs and states (and
    // for FMI 3.0 the parameters and the time).
    let mut knowns: Vec<usize> = layout.inputs.clone();
    knowns.extend(&layout.states);
    if standard == Knowns::Fmi3 {
        knowns.extend(
            (variables.iter().enumerate())
                .filter(|(_, v)| v.causality == Causality::Parameter)
                .map(|(vr, _)| vr),
        );
    }
    knowns.sort_unstable();
    knowns.dedup();
    knowns.extend(time);

    // An output that is a state is a known itself: it depends on itself only.
    let computed: Vec<usize> = layout
        .outputs
        .iter()
        .copied()
        .filter(|vr| !layout.states.contains(vr))
        .collect();
    let deps = dependencies::<M>(&points, &computed, &knowns);
    let outputs = layout
        .outputs
        .iter()
        .map(|&vr| Unknown {
            vr,
            dependencies: match computed.iter().position(|&c| c == vr) {
                Some(i) => deps[i].clone(),
                None => vec![vr],
            },
        })
        .collect();

    let deps = dependencies::<M>(&points, &layout.derivatives, &knowns);
    let derivatives = (layout.derivatives.iter())
        .zip(deps)
        .map(|(&vr, dependencies)| Unknown { vr, dependencies })
        .collect();

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
    let deps = dependencies::<M>(&points, &unknowns, &initial_knowns);
    let initial_unknowns = unknowns
        .iter()
        .zip(deps)
        .map(|(&vr, dependencies)| Unknown { vr, dependencies })
        .collect();

    Ok(ModelStructure {
        outputs,
        derivatives,
        initial_unknowns,
    })
}

/// SplitMix64: a tiny deterministic generator for the probe points.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }

    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        (self.next() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Uniform in [-1, 1).
    fn symmetric(&mut self) -> f64 {
        2.0 * self.unit() - 1.0
    }
}

/// Number of probe points: the start values and this many minus one random neighbours.
const POINTS: usize = 3;

/// The probe points, each with its calculated parameters computed: the start values at the
/// start time, then points whose time lies in the default experiment and whose inputs,
/// parameters and state start values are moved by up to 10 % (up to 0.1 from zero), within
/// their bounds and where `calculate` accepts them.
fn points<M: Mechanism>() -> Result<Vec<M::Values<f64>>, String> {
    let experiment = M::EXPERIMENT;
    let mut start = start_values::<M>(experiment.start);
    M::calculate(&mut start)
        .map_err(|e| format!("{}: the start values are rejected: {e}", M::NAME))?;
    let span = experiment.stop - experiment.start;
    let span = if span.is_finite() && span > 0.0 {
        span
    } else {
        1.0
    };
    let mut points = vec![start];
    let mut rng = SplitMix64(0x6d65_6368_666d_7500);
    for _ in 0..100 {
        if points.len() == POINTS {
            break;
        }
        let mut p = start_values::<M>(experiment.start + span * rng.unit());
        for (vr, v) in M::VARIABLES.iter().enumerate() {
            let Some(x) = v.start else { continue };
            let scale = if x != 0.0 { x.abs() } else { 1.0 };
            let dx = 0.1 * scale * rng.symmetric();
            // Outside its bounds, the other way (a damping that starts at its minimum 0 is
            // moved up, so that the terms it multiplies show).
            if let Some(y) = [x + dx, x - dx]
                .into_iter()
                .find(|&y| v.check_value(y).is_ok())
            {
                p.set(vr, y);
            }
        }
        if M::calculate(&mut p).is_ok() {
            points.push(p);
        }
    }
    Ok(points)
}

/// `p` with known `vr` moved by 1e-3 relative (1e-3 absolute from zero), upwards unless
/// that leaves its bounds or `calculate` refuses it; `None` when neither direction works.
/// `vr = VARIABLES.len()` is the time, moved upwards.
fn perturbed<M: Mechanism>(p: &M::Values<f64>, vr: usize) -> Option<M::Values<f64>> {
    let step = |x: f64| if x != 0.0 { 1e-3 * x.abs() } else { 1e-3 };
    if vr == M::VARIABLES.len() {
        let mut q = p.clone();
        q.set_time(p.time() + step(p.time()));
        return Some(q);
    }
    let x = p.get(vr)?;
    let delta = step(x);
    let variable = &M::VARIABLES[vr];
    [x + delta, x - delta].into_iter().find_map(|y| {
        if variable.check_value(y).is_err() {
            return None;
        }
        let mut q = p.clone();
        q.set(vr, y);
        M::calculate(&mut q).ok().map(|()| q)
    })
}

/// Whether an unknown moved: by more than rounding (1e-10 relative), so that an expression
/// such as `m a / (m g)` does not make a dependency on `m` out of its last bits. A genuine
/// dependency moves it by about 1e-3 times its relative sensitivity.
fn changed(a: Option<f64>, b: Option<f64>) -> bool {
    match (a, b) {
        (Some(a), Some(b)) if a.is_finite() && b.is_finite() => {
            (a - b).abs() > 1e-10 * a.abs().max(b.abs())
        }
        (Some(a), Some(b)) => !(a == b || (a.is_nan() && b.is_nan())),
        _ => false,
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
            let Some(mut q) = perturbed::<M>(p, k) else {
                deps.iter_mut().for_each(|d| {
                    d.insert(k);
                });
                continue;
            };
            evaluate_all::<M, f64>(&mut q);
            for (d, &u) in deps.iter_mut().zip(unknowns) {
                if changed(base.get(u), q.get(u)) {
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
        const EXPERIMENT: Experiment = Experiment {
            start: 0.0,
            stop: 1.0,
            step: 0.1,
            tolerance: 1e-6,
        };
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

    fn unknown(vr: usize, dependencies: &[usize]) -> Unknown {
        Unknown {
            vr,
            dependencies: dependencies.to_vec(),
        }
    }

    #[test]
    fn states_are_knowns() {
        let s = model_structure::<Probe>().unwrap();
        assert_eq!(
            s.outputs,
            vec![unknown(3, &[3]), unknown(5, &[2, 3]), unknown(6, &[])]
        );
        assert_eq!(s.derivatives, vec![unknown(4, &[2, 3])]);
        // x_dot (local, calculated) is an initial unknown here too.
        assert_eq!(
            s.initial_unknowns,
            vec![
                unknown(4, &[0, 2, 3]),
                unknown(5, &[0, 2, 3]),
                unknown(6, &[1]),
                unknown(7, &[1])
            ]
        );
    }

    #[test]
    fn fmi3_has_the_parameters_and_the_time_as_knowns() {
        let s = model_structure_with::<Probe>(Knowns::Fmi3).unwrap();
        // The parameters a (0) and b (1) are knowns now; the time (8) moves nothing here.
        assert_eq!(
            s.outputs,
            vec![unknown(3, &[3]), unknown(5, &[0, 2, 3]), unknown(6, &[1])]
        );
        assert_eq!(s.derivatives, vec![unknown(4, &[0, 2, 3])]);
        // In Initialization Mode the parameters were knowns already (initial="exact").
        assert_eq!(
            s.initial_unknowns,
            model_structure::<Probe>().unwrap().initial_unknowns
        );
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
