//! FMI 3.0's variables over the declared scalars: an array reads as its scalars in
//! row-major order and setting it sets them; one scalar at two places of an array (a
//! symmetric matrix) takes one value; the number of values is checked; `time` is read,
//! never set.

use super::{at_fraction, bits, run, run_fmi2, started, started_fmi2};
use crate::fmi3::Fmi3Harness;
use crate::harness::Harness;
use mechfmu::fmi3::ffi::*;
use mechfmu::model::{Mechanism, SetPhase};

/// Runs every check of arrays and `time`.
pub fn check<M: Mechanism>() {
    arrays_are_their_scalars_in_row_major_order::<M>();
    setting_an_array_sets_its_scalars::<M>();
    unequal_places_of_one_scalar_are_refused::<M>();
    value_counts_must_match::<M>();
    time_is_readable_and_not_settable::<M>();
}

/// Each array of `Mechanism::ARRAYS` reads as the FMI 2.0 values of the scalars it lists, in
/// that (row-major) order; several variables read in one call (`time` among them, in any
/// order) are each as read alone.
pub fn arrays_are_their_scalars_in_row_major_order<M: Mechanism>() {
    let name = M::NAME;
    let mut fmi2 = started_fmi2::<M>();
    let mut fmi3 = started::<M>();
    for fraction in [0.0, 0.1] {
        run_fmi2(&mut fmi2, fraction);
        run(&mut fmi3, fraction);
        let t = fmi3.time();
        for array in M::ARRAYS {
            let got = fmi3.get_array(array.name);
            let expected: Vec<f64> = array.elements.iter().map(|e| fmi2.get(e)).collect();
            assert_eq!(
                bits(&got),
                bits(&expected),
                "{name}: at t = {t}, {} = {got:?} (FMI 3.0), but its elements {:?} = {expected:?} (FMI 2.0)",
                array.name,
                array.elements
            );
        }
        let mut vrs: Vec<u32> = (fmi3.shapes().variables.iter().rev())
            .map(|s| s.reference as u32)
            .collect();
        vrs.insert(vrs.len() / 2, fmi3.time_vr());
        let together = fmi3
            .get_values(&vrs)
            .unwrap_or_else(|s| panic!("{name}: fmi3GetFloat64 of every variable: {s}"));
        let alone: Vec<f64> = (vrs.iter())
            .flat_map(|&vr| fmi3.get_values(&[vr]).unwrap_or_default())
            .collect();
        assert_eq!(
            bits(&together),
            bits(&alone),
            "{name}: at t = {t}, variables read together differ from each read alone"
        );
    }
}

/// In initialization mode, setting an array through FMI 3.0 is setting its scalars through
/// FMI 2.0: the same status, the values read back, the same values after initialization
/// and after a step. (Arrays of calculated variables are refused by both.)
pub fn setting_an_array_sets_its_scalars<M: Mechanism>() {
    let (name, e) = (M::NAME, M::EXPERIMENT);
    for array in M::ARRAYS {
        let mut fmi2 = Harness::<M>::new();
        let mut fmi3 = Fmi3Harness::<M>::new();
        assert_eq!(
            (
                fmi2.setup_experiment(Some(e.tolerance), e.start, None),
                fmi2.enter_initialization_mode(),
                fmi3.enter_initialization_mode(Some(e.tolerance), e.start, None),
            ),
            (fmi3OK, fmi3OK, fmi3OK),
            "{name}: initialization mode"
        );
        let scalars: Vec<u32> = array.elements.iter().map(|n| Harness::<M>::vr(n)).collect();
        // A little off the start values (a function of the scalar, so its places agree).
        let values: Vec<f64> = (array.elements.iter())
            .map(|n| fmi2.get(n) * (1.0 + 1e-3) + 1e-3)
            .collect();
        let vr = fmi3.vr(array.name);
        let status3 = fmi3.set_float64(&[vr], &values);
        let status2 = fmi2.set_real(&scalars, &values);
        assert_eq!(
            status3,
            status2,
            "{name}: setting {} = {values:?} gave {status3} through FMI 3.0, its scalars {status2} through FMI 2.0: {:?}",
            array.name,
            fmi3.messages()
        );
        if status3 != fmi3OK {
            assert!(
                fmi3.logged("cannot be set"),
                "{name}: {} refused without saying why: {:?}",
                array.name,
                fmi3.messages()
            );
            continue;
        }
        assert_eq!(
            bits(&fmi3.get_array(array.name)),
            bits(&values),
            "{name}: {} does not read back as set",
            array.name
        );
        let exits = (
            fmi3.exit_initialization_mode(),
            fmi2.exit_initialization_mode(),
        );
        assert_eq!(
            exits,
            (fmi3OK, fmi3OK),
            "{name}: initialization with {} = {values:?}: {:?} {:?}",
            array.name,
            fmi3.messages(),
            fmi2.messages()
        );
        for step in 0..2 {
            assert_eq!(
                bits(&fmi3.all_values()),
                bits(&fmi2.all_values()),
                "{name}: with {} set, FMI 3.0's values differ from FMI 2.0's with its scalars set (after {step} steps)",
                array.name
            );
            let t = e.start + step as f64 * e.step;
            assert_eq!(fmi3.do_step(t, e.step).status, fmi2.do_step(t, e.step));
        }
    }
}

/// Where one scalar stands at two places of an array (a symmetric matrix's off-diagonal),
/// setting the array with different values there is refused with fmi3Error, a message
/// naming both elements and their values (or, for an array the model computes, saying it
/// cannot be set), and nothing changed.
pub fn unequal_places_of_one_scalar_are_refused<M: Mechanism>() {
    let (name, e) = (M::NAME, M::EXPERIMENT);
    for array in M::ARRAYS {
        let places = array.elements;
        let Some((i, j)) = (0..places.len())
            .flat_map(|i| (i + 1..places.len()).map(move |j| (i, j)))
            .find(|&(i, j)| places[i] == places[j])
        else {
            continue;
        };
        let mut fmu = Fmi3Harness::<M>::new();
        assert_eq!(
            fmu.enter_initialization_mode(Some(e.tolerance), e.start, None),
            fmi3OK
        );
        let vr = fmu.vr(array.name);
        let before = fmu.get_array(array.name);
        let mut values = before.clone();
        values[j] = values[i] + 1.0;
        assert_eq!(
            fmu.set_float64(&[vr], &values),
            fmi3Error,
            "{name}: {} = {values:?}, whose places {i} and {j} are both {}, was accepted",
            array.name,
            places[i]
        );
        let shaped = fmu.shapes().get(vr as usize).cloned().expect("an array");
        let (a, b) = (shaped.element_name(i), shaped.element_name(j));
        let settable = (M::VARIABLES.iter())
            .find(|v| v.name == places[i])
            .is_some_and(|v| v.settable(SetPhase::Initialization));
        let why = if settable {
            format!("{a} = {} and {b} = {}", values[i], values[j])
        } else {
            "cannot be set (it is computed by the model)".to_string()
        };
        assert!(
            fmu.logged(&why),
            "{name}: no message says \"{why}\": {:?}",
            fmu.messages()
        );
        assert_eq!(
            bits(&fmu.get_array(array.name)),
            bits(&before),
            "{name}: a refused {} changed it",
            array.name
        );
    }
}

/// A get or set whose `nValues` is not the number of values of its value references (an
/// array counting each element) is refused with a message and changes nothing; so is a
/// value reference of no FMI 3.0 variable (an array's element other than its first, one past
/// the last variable's).
pub fn value_counts_must_match<M: Mechanism>() {
    let name = M::NAME;
    let mut fmu = started::<M>();
    let shapes = fmu.shapes().clone();
    let shaped = (shapes.variables.iter().find(|s| s.is_array())).unwrap_or(&shapes.variables[0]);
    let (vr, n) = (shaped.reference as u32, shaped.elements.len());
    let before = fmu.all_values();
    for wrong in [n - 1, n + 1] {
        let mut values = vec![0.0; wrong];
        assert_eq!(
            fmu.get_float64(&[vr], &mut values),
            fmi3Error,
            "{name}: {} read with nValues = {wrong}",
            shaped.name
        );
        assert_eq!(
            fmu.set_float64(&[vr], &values),
            fmi3Error,
            "{name}: {} set with nValues = {wrong}",
            shaped.name
        );
        let message = format!("nValues = {wrong}, but the value references given have {n} values");
        assert!(
            fmu.logged(&message),
            "{name}: {message}: {:?}",
            fmu.messages()
        );
    }
    assert_eq!(
        bits(&fmu.all_values()),
        bits(&before),
        "{name}: a refused call changed values"
    );
    // Past the last variable: the value references are the variables' places, 1 to the end.
    for vr in [shapes.references_end(), shapes.references_end() + 100] {
        let mut value = [0.0];
        assert_eq!(
            fmu.get_float64(&[vr as u32], &mut value),
            fmi3Error,
            "{name}: value reference {vr}"
        );
        let message = format!("value reference {vr} is not a variable of this FMU");
        assert!(
            fmu.logged(&message),
            "{name}: {message}: {:?}",
            fmu.messages()
        );
    }
}

/// `time` (value reference 0) reads as the communication point reached,
/// and in Model Exchange as the time `fmi3SetTime` set; setting it is refused with a
/// message.
pub fn time_is_readable_and_not_settable<M: Mechanism>() {
    let name = M::NAME;
    let mut cs = started::<M>();
    run(&mut cs, 0.1);
    let mut me = Fmi3Harness::<M>::model_exchange();
    me.initialize_model_exchange(Some(M::EXPERIMENT.tolerance), M::EXPERIMENT.start, &[])
        .unwrap_or_else(|m| panic!("{name}: {m}"));
    let t = at_fraction::<M>(0.01);
    assert_eq!(me.set_time(t), fmi3OK, "{name}: fmi3SetTime");
    for (fmu, t) in [(&mut cs, None), (&mut me, Some(t))] {
        let t = t.unwrap_or(fmu.time());
        let vr = fmu.time_vr();
        assert_eq!(vr, 0, "{name}: the value reference of time");
        assert_eq!(
            fmu.get_values(&[vr]).map(|v| bits(&v)),
            Ok(vec![t.to_bits()]),
            "{name}: time is not {t}"
        );
        assert_eq!(
            fmu.set_float64(&[vr], &[t]),
            fmi3Error,
            "{name}: time was set"
        );
        assert!(
            fmu.logged("time is the independent variable: it cannot be set"),
            "{name}: {:?}",
            fmu.messages()
        );
    }
}
