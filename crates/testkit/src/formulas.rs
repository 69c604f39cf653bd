//! A mechanism without states (a coupling element, a control law): [`outputs_follow`]
//! checks it against its formulas at random parameters and inputs, and
//! [`declares_direct_feedthrough`] what its model descriptions say of it.

use std::collections::BTreeMap;

use mechfmu::model::Mechanism;

use crate::harness::Harness;
use crate::rng::Rng;

/// Draws by name: the parameters and inputs of one point.
pub type Point = BTreeMap<&'static str, f64>;

/// Checks `M`'s outputs against `formula` at `sets` random parameter sets (drawn uniform in
/// the ranges `parameters` gives, `(name, low, high)`), each initialized, then given 20
/// random input sets (`inputs`) in turn: every other set is read at once after the inputs
/// are set (no step between: direct feedthrough), the others after a step, which holds
/// them.
///
/// `formula` gives, for a point, each output's `(name, value, size)`: `size` is the sum of
/// the magnitudes of the terms that make the value, which rounding is relative to (a value
/// that cancels to near 0 keeps its terms' rounding). An output further than `1e-14 size`
/// from its value panics, naming it and the point.
pub fn outputs_follow<M: Mechanism>(
    parameters: &[(&'static str, f64, f64)],
    inputs: &[(&'static str, f64, f64)],
    sets: usize,
    formula: impl Fn(&Point) -> Vec<(&'static str, f64, f64)>,
) {
    let mut rng = Rng(0x5eed_f0a3_1a5e);
    let mut draw = |ranges: &[(&'static str, f64, f64)], point: &mut Point| {
        for &(name, lo, hi) in ranges {
            point.insert(name, rng.uniform(lo, hi));
        }
    };
    for _ in 0..sets {
        let mut point = Point::new();
        draw(parameters, &mut point);
        let start: Vec<(&str, f64)> = point.iter().map(|(&n, &v)| (n, v)).collect();
        let mut fmu = Harness::<M>::new();
        fmu.initialize(None, 0.0, &start).unwrap();
        for round in 0..20 {
            draw(inputs, &mut point);
            for &(name, _, _) in inputs {
                fmu.set(name, point[name]);
            }
            if round % 2 == 1 {
                let t = fmu.time();
                fmu.step_to(t + M::EXPERIMENT.step, M::EXPERIMENT.step)
                    .unwrap();
            }
            for (name, want, size) in formula(&point) {
                let got = fmu.get(name);
                assert!(
                    (got - want).abs() <= 1e-14 * size,
                    "{name} = {got}, its formula gives {want} at {point:?}"
                );
            }
        }
    }
}

/// Checks that `M`'s model descriptions declare no state (no `<Derivatives>` in FMI 2.0, no
/// `ContinuousStateDerivative` in FMI 3.0) and no event indicator, and that each output of
/// `feedthrough` depends, in FMI 2.0's `<ModelStructure>`, on exactly the inputs it lists,
/// in declaration order: `("F", &["x1", "v1"])`.
pub fn declares_direct_feedthrough<M: Mechanism>(feedthrough: &[(&str, &[&str])]) {
    let fmi2 = mechfmu::xml::model_description::<M>().unwrap();
    assert!(fmi2.contains("numberOfEventIndicators=\"0\""), "{fmi2}");
    assert!(!fmi2.contains("<Derivatives>"), "{fmi2}");
    // A variable's 1-based index: its place among the `ScalarVariable`s (a unit may have its
    // name, so the search starts at them).
    let variables = fmi2.find("<ModelVariables>").expect("<ModelVariables>");
    let index = |name: &str| {
        let at = variables
            + fmi2[variables..]
                .find(&format!("name=\"{name}\""))
                .expect(name);
        fmi2[..at].matches("<ScalarVariable").count()
    };
    for (output, inputs) in feedthrough {
        let knowns: Vec<String> = inputs.iter().map(|n| index(n).to_string()).collect();
        let unknown = format!(
            "<Unknown index=\"{}\" dependencies=\"{}\"",
            index(output),
            knowns.join(" ")
        );
        assert!(fmi2.contains(&unknown), "no `{unknown}` in\n{fmi2}");
    }
    let fmi3 = mechfmu::xml::fmi3::model_description::<M>().unwrap();
    assert!(!fmi3.contains("<ContinuousStateDerivative"), "{fmi3}");
    assert!(!fmi3.contains("<EventIndicator"), "{fmi3}");
}
