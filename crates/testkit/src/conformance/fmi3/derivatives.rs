//! Derivatives through FMI 3.0, by its variables (arrays whole): directional and output
//! derivatives are FMI 2.0's of the scalars they stand for; adjoint derivatives are the
//! transpose of that Jacobian.

use super::{bits, run, run_fmi2, started, started_fmi2};
use mechfmu::fmi2::ffi::fmi2OK;
use mechfmu::fmi3::ffi::fmi3OK;
use mechfmu::model::{Causality, Mechanism, Shaped, Variability};

/// The scalar value references of `variables`, element by element.
fn scalars(variables: &[&Shaped]) -> Vec<u32> {
    variables
        .iter()
        .flat_map(|s| s.elements.iter().map(|&e| e as u32))
        .collect()
}

fn references(variables: &[&Shaped]) -> Vec<u32> {
    variables.iter().map(|s| s.reference as u32).collect()
}

/// Directional derivatives (by FMI 3.0 variables: arrays whole) are FMI 2.0's of the scalars
/// they stand for, bit for bit, along every unit direction and a mixed one; adjoint
/// derivatives are `seedᵀ J` of that Jacobian to 1e-12 relative; output derivatives are
/// FMI 2.0's, bit for bit.
pub fn derivatives_equal_fmi2<M: Mechanism>() {
    let name = M::NAME;
    let mut fmi2 = started_fmi2::<M>();
    let mut fmi3 = started::<M>();
    let shapes = fmi3.shapes().clone();
    let of = |keep: &dyn Fn(&mechfmu::model::Variable) -> bool| -> Vec<&Shaped> {
        shapes
            .variables
            .iter()
            .filter(|s| keep(s.variable(M::VARIABLES)))
            .collect()
    };
    let knowns = of(&|v| v.is_state() || v.causality == Causality::Input);
    let unknowns =
        of(&|v| v.variability == Variability::Continuous && v.causality != Causality::Input);
    let outputs = of(&|v| v.causality == Causality::Output);
    let (k3, k2, u3, u2) = (
        references(&knowns),
        scalars(&knowns),
        references(&unknowns),
        scalars(&unknowns),
    );
    let (o3, o2) = (references(&outputs), scalars(&outputs));
    let (nk, nu) = (k2.len(), u2.len());
    for fraction in [0.0, 0.15, 0.35] {
        run_fmi2(&mut fmi2, fraction);
        run(&mut fmi3, fraction);
        let t = fmi3.time();
        // Columns of the Jacobian, then a mixed direction.
        let mut seeds: Vec<Vec<f64>> = (0..nk)
            .map(|j| (0..nk).map(|i| (i == j) as u8 as f64).collect())
            .collect();
        seeds.push((0..nk).map(|i| 1.0 + 0.25 * i as f64).collect());
        let mut jacobian = Vec::with_capacity(nk);
        for seed in &seeds {
            let (mut d3, mut d2) = (vec![f64::NAN; nu], vec![f64::NAN; nu]);
            assert_eq!(
                fmi3.directional_derivative(&u3, &k3, seed, &mut d3),
                fmi3OK,
                "{name}: fmi3GetDirectionalDerivative: {:?}",
                fmi3.messages()
            );
            assert_eq!(
                fmi2.directional_derivative(&u2, &k2, seed, &mut d2),
                fmi2OK,
                "{name}: fmi2GetDirectionalDerivative: {:?}",
                fmi2.messages()
            );
            assert_eq!(
                bits(&d3),
                bits(&d2),
                "{name}: at t = {t}, along {seed:?}: directional derivatives {d3:?} (FMI 3.0), {d2:?} (FMI 2.0)"
            );
            jacobian.push(d3);
        }
        jacobian.pop();
        // seedᵀ J along every unit seed of the unknowns and a mixed one.
        let mut seeds: Vec<Vec<f64>> = (0..nu)
            .map(|j| (0..nu).map(|i| (i == j) as u8 as f64).collect())
            .collect();
        seeds.push((0..nu).map(|i| 0.5 - 0.125 * i as f64).collect());
        for seed in &seeds {
            let mut adjoint = vec![f64::NAN; nk];
            assert_eq!(
                fmi3.adjoint_derivative(&u3, &k3, seed, &mut adjoint),
                fmi3OK,
                "{name}: fmi3GetAdjointDerivative: {:?}",
                fmi3.messages()
            );
            for (j, column) in jacobian.iter().enumerate() {
                let expected: f64 = seed.iter().zip(column).map(|(s, c)| s * c).sum();
                let scale: f64 = seed.iter().zip(column).map(|(s, c)| (s * c).abs()).sum();
                assert!(
                    (adjoint[j] - expected).abs() <= 1e-12 * scale,
                    "{name}: at t = {t}, seed {seed:?}: adjoint derivative by {} {}, seedᵀJ {expected}",
                    M::VARIABLES[k2[j] as usize].name,
                    adjoint[j]
                );
            }
        }
        if !o3.is_empty() {
            let (mut d3, mut d2) = (vec![f64::NAN; o2.len()], vec![f64::NAN; o2.len()]);
            assert_eq!(
                fmi3.output_derivatives(&o3, &vec![1; o3.len()], &mut d3),
                fmi3OK,
                "{name}: fmi3GetOutputDerivatives: {:?}",
                fmi3.messages()
            );
            assert_eq!(
                fmi2.output_derivatives(&o2, &vec![1; o2.len()], &mut d2),
                fmi2OK,
                "{name}: fmi2GetRealOutputDerivatives: {:?}",
                fmi2.messages()
            );
            assert_eq!(
                bits(&d3),
                bits(&d2),
                "{name}: at t = {t}: FMI 3.0's output derivatives {d3:?}, FMI 2.0's {d2:?}"
            );
        }
    }
}
