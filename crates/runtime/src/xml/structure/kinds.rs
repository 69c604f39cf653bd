//! `dependenciesKind`: how each known enters an unknown (FMI 2.0.5 section 2.2.8, attribute
//! `dependenciesKind` of `<Unknown>`; FMI 3.0 section 2.4.8, the same attribute of
//! `<Output>`, `<ContinuousStateDerivative>`, `<InitialUnknown>` and `<EventIndicator>`).
//!
//! A known `k` enters an unknown `u` with a factor when `u = c·k + (terms without k)`. The
//! factor `∂u/∂k` is computed exactly (forward-mode automatic differentiation on the
//! complete evaluation) at each probe point, and again at the point with each free quantity
//! of the model moved (every parameter, input and state, and the time), as the dependencies
//! themselves are found. Then, in the standards' words:
//! - `constant`: nothing moves the factor (it is evaluated before initialization);
//! - `fixed`: only fixed parameters move it (evaluated before `ExitInitializationMode`);
//! - `tunable`: a tunable parameter moves it too (evaluated again when one is set);
//! - `dependent`: an input, a state or the time moves it, or it is not a number: no
//!   particular structure.
//!
//! `fixed` and `tunable` are for Event and Continuous-Time Mode and communication points
//! only: in Initialization Mode the parameters are knowns themselves, so a factor they
//! move is `dependent` there. A known the factor cannot be taken for, a parameter (it
//! reaches the equations through `calculate`, which runs on numbers, not on dual numbers)
//! or a known that `calculate` reads, is always `dependent`: the claim that is always true.

use num_dual::Dual64;

use super::probe::{changed, perturbed};
use crate::model::{evaluate_all, Causality, Layout, Mechanism, ValueSet, Variability};

/// How a known enters an unknown, from the most particular structure to none: a list of
/// several claims about one pair is the largest (a constant factor is a fixed one too).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum DependencyKind {
    Constant,
    Fixed,
    Tunable,
    Dependent,
}

impl DependencyKind {
    /// The attribute's value.
    pub fn as_str(self) -> &'static str {
        match self {
            DependencyKind::Constant => "constant",
            DependencyKind::Fixed => "fixed",
            DependencyKind::Tunable => "tunable",
            DependencyKind::Dependent => "dependent",
        }
    }
}

/// Where the unknowns are listed: what their knowns are, and which kinds the standards
/// allow there.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Mode {
    /// `<Outputs>`, `<Derivatives>` (FMI 3.0: `<Output>`, `<ContinuousStateDerivative>`,
    /// `<EventIndicator>`): every kind.
    ContinuousTime,
    /// `<InitialUnknowns>` (FMI 3.0: `<InitialUnknown>`): `dependent` or `constant` only.
    Initialization,
}

/// What moves the factor of one known in one unknown.
#[derive(Clone, Copy, Debug, Default)]
struct Movers {
    /// An input, a state or the time; or the factor is not a number.
    free: bool,
    tunable: bool,
    fixed: bool,
}

/// The kind of each dependency: `kinds[i][j]` for known `dependencies[i][j]` of
/// `unknowns[i]` (value references; `VARIABLES.len()` is the time).
pub(super) fn kinds<M: Mechanism>(
    points: &[M::Values<f64>],
    layout: &Layout,
    unknowns: &[usize],
    dependencies: &[Vec<usize>],
    mode: Mode,
) -> Vec<Vec<DependencyKind>> {
    let variables = M::VARIABLES;
    let time = variables.len();
    let is_free =
        |vr: usize| vr == time || layout.inputs.contains(&vr) || layout.states.contains(&vr);
    // Every quantity the factors may depend on.
    let mut quantities: Vec<usize> = (0..variables.len())
        .filter(|&vr| variables[vr].causality == Causality::Parameter || is_free(vr))
        .collect();
    quantities.push(time);
    // The knowns a factor is taken for: inputs, states and the time.
    let mut knowns: Vec<usize> = dependencies.iter().flatten().copied().collect();
    knowns.sort_unstable();
    knowns.dedup();
    knowns.retain(|&k| is_free(k));

    // movers[i][known] and the knowns `calculate` reads.
    let mut movers = vec![vec![Movers::default(); time + 1]; unknowns.len()];
    let mut opaque = vec![false; time + 1];
    for p in points {
        for &k in &knowns {
            if reads_in_calculate::<M>(p, k, layout) {
                opaque[k] = true;
                continue;
            }
            let base = factors::<M>(p, k, unknowns);
            for (i, f) in base.iter().enumerate() {
                movers[i][k].free |= !f.is_finite();
            }
            for &q in &quantities {
                let moved = perturbed::<M>(p, q).map(|p| factors::<M>(&p, k, unknowns));
                for (i, &f) in base.iter().enumerate() {
                    // A quantity that cannot be moved here moves every factor.
                    if moved
                        .as_ref()
                        .is_some_and(|m| !changed(Some(f), Some(m[i])))
                    {
                        continue;
                    }
                    let m = &mut movers[i][k];
                    match variables.get(q) {
                        _ if is_free(q) => m.free = true,
                        Some(v) if v.variability == Variability::Tunable => m.tunable = true,
                        _ => m.fixed = true,
                    }
                }
            }
        }
    }

    (dependencies.iter().enumerate())
        .map(|(i, known)| {
            known
                .iter()
                .map(|&k| {
                    let m = movers[i][k];
                    if !is_free(k) || opaque[k] || m.free {
                        DependencyKind::Dependent
                    } else if mode == Mode::Initialization {
                        if m.tunable || m.fixed {
                            DependencyKind::Dependent
                        } else {
                            DependencyKind::Constant
                        }
                    } else if m.tunable {
                        DependencyKind::Tunable
                    } else if m.fixed {
                        DependencyKind::Fixed
                    } else {
                        DependencyKind::Constant
                    }
                })
                .collect()
        })
        .collect()
}

/// `∂u/∂k` at `p` for every unknown `u`, exact: the complete evaluation on dual numbers
/// seeded along `k` (a value reference, or `VARIABLES.len()` for the time).
fn factors<M: Mechanism>(p: &M::Values<f64>, k: usize, unknowns: &[usize]) -> Vec<f64> {
    let mut dual = M::map_values(p, Dual64::from_re);
    if k == M::VARIABLES.len() {
        dual.set_time(Dual64::new(p.time(), 1.0));
    } else {
        dual.set(k, Dual64::new(p.get(k).unwrap_or(f64::NAN), 1.0));
    }
    evaluate_all::<M, Dual64>(&mut dual);
    (unknowns.iter())
        .map(|&u| dual.get(u).map_or(f64::NAN, |d| d.eps))
        .collect()
}

/// Whether moving `k` at `p` changes a calculated parameter: then the unknowns see `k`
/// through `calculate` too, which the dual numbers do not follow.
fn reads_in_calculate<M: Mechanism>(p: &M::Values<f64>, k: usize, layout: &Layout) -> bool {
    let Some(q) = perturbed::<M>(p, k) else {
        return true;
    };
    (layout.calculated.iter()).any(|&c| changed(p.get(c), q.get(c)))
}
