//! The importer's loop through FMI 3.0: `fmi3SetFloat64` of the inputs (arrays whole),
//! `fmi3DoStep` with its four out arguments, `fmi3GetFloat64` of every variable (the time
//! and the arrays among them) and of the outputs: no allocation once running.

use super::Work;
use crate::fmi3::Fmi3Harness;
use mechfmu::fmi3::ffi::*;
use mechfmu::fmi3::functions;
use mechfmu::model::{Causality, Mechanism, Shapes};

/// Runs `M` as [`check`](super::check) does, through its FMI 3.0 Co-Simulation functions.
pub fn check<M: Mechanism>(n: u64) -> Work {
    let e = M::EXPERIMENT;
    let mut fmu = Fmi3Harness::<M>::new();
    fmu.initialize(Some(e.tolerance), e.start, &[])
        .unwrap_or_else(|m| panic!("{}: {m}", M::NAME));
    let c = fmu.instance();
    let shapes = fmu.shapes().clone();
    let of = |keep: &dyn Fn(Causality) -> bool| -> (Vec<u32>, usize) {
        let chosen: Vec<_> = (shapes.variables.iter())
            .filter(|s| keep(s.variable(M::VARIABLES).causality))
            .collect();
        let n = chosen.iter().map(|s| s.elements.len()).sum();
        (chosen.iter().map(|s| s.reference as u32).collect(), n)
    };
    let (mut all, n_all) = of(&|_| true);
    all.push(Shapes::TIME_REFERENCE as u32);
    let (outputs, n_outputs) = of(&|c| c == Causality::Output);
    let (inputs, n_inputs) = of(&|c| c == Causality::Input);
    let mut values = vec![0.0; n_all + 1];
    let mut out = vec![0.0; n_outputs];
    let get = |vrs: &[u32], values: &mut [f64]| {
        // SAFETY: a live instance; every array has the length passed with it.
        unsafe {
            functions::fmi3GetFloat64::<M>(
                c,
                vrs.as_ptr(),
                vrs.len(),
                values.as_mut_ptr(),
                values.len(),
            )
        }
    };
    assert_eq!(get(&inputs, &mut values[..n_inputs]), fmi3OK);
    let input_start = values[..n_inputs].to_vec();
    let mut input_values = input_start.clone();

    let h = e.step;
    let mut t = e.start;
    let cycle = |i: u64, work: &mut Work| {
        for (v, &s) in input_values.iter_mut().zip(&input_start) {
            *v = s + 1e-9 * (i % 7) as f64;
        }
        let (mut event, mut terminate, mut early, mut last) = (false, false, false, 0.0);
        // SAFETY: a live instance; every array has the length passed with it, every out
        // argument is a local.
        unsafe {
            if !inputs.is_empty() {
                let s = functions::fmi3SetFloat64::<M>(
                    c,
                    inputs.as_ptr(),
                    inputs.len(),
                    input_values.as_ptr(),
                    input_values.len(),
                );
                assert_eq!(s, fmi3OK, "{}: fmi3SetFloat64 of the inputs", M::NAME);
                work.sets += 1;
            }
            let s = functions::fmi3DoStep::<M>(
                c,
                t,
                h,
                true,
                &mut event,
                &mut terminate,
                &mut early,
                &mut last,
            );
            assert_eq!(s, fmi3OK, "{}: fmi3DoStep({t}, {h})", M::NAME);
        }
        work.steps += 1;
        t += h;
        assert_eq!(get(&all, &mut values), fmi3OK);
        assert_eq!(get(&outputs, &mut out), fmi3OK);
        work.gets += 2;
    };
    // Whatever the warm-up allocates lazily (the instance's scratch list) is not counted.
    let what = format!("{} through FMI 3.0", M::NAME);
    super::assert_allocates_nothing(&what, n, cycle)
}
