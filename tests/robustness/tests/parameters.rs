//! Bad parameters and inputs, on every built FMU, derived from its modelDescription:
//! non-physical parameters (a mass, length or inertia ≤ 0, anything outside its min/max, a
//! non-positive-definite inertia tensor) are refused at initialization with fmi2Error naming
//! the variable and the value; non-finite inputs are refused by fmi2SetReal with a message
//! naming the input and never reach a step, and a finite input that makes the model's values
//! overflow makes the next fmi2DoStep return fmi2Error or fmi2Discard with a message;
//! tunable parameters changed between steps take effect at the next step.

use mechfmu_robustness::ffi::*;
use mechfmu_robustness::fmu::{required_fmu_paths, Fmu, Variable, VariableExt};
use mechfmu_robustness::importer::Instance;

fn fmus() -> Vec<Fmu> {
    required_fmu_paths()
        .iter()
        .map(|p| Fmu::load(p).unwrap())
        .collect()
}

/// Tries to initialize with `vr = value`; returns the error message if it was refused
/// (by fmi2SetReal or fmi2ExitInitializationMode), and checks the instance recovers by reset.
fn refusal(fmu: &Fmu, values: &[(u32, f64)]) -> Option<String> {
    let mut inst = Instance::new(fmu, "bad-parameter").unwrap();
    let e = fmu.md.experiment;
    assert_eq!(inst.setup(Some(e.tolerance), e.start, None), OK);
    assert_eq!(inst.enter_init(), OK);
    let (vrs, xs): (Vec<u32>, Vec<f64>) = values.iter().copied().unzip();
    let refused = match inst.set_real(&vrs, &xs) {
        ERROR => true,
        OK => match inst.exit_init() {
            OK => false,
            ERROR => true,
            s => panic!(
                "{}: fmi2ExitInitializationMode returned {}",
                fmu.name(),
                status_name(s)
            ),
        },
        s => panic!("{}: fmi2SetReal returned {}", fmu.name(), status_name(s)),
    };
    if !refused {
        return None;
    }
    let message = inst
        .messages()
        .iter()
        .rev()
        .find(|m| m.status == ERROR)
        .map(|m| m.text.clone())
        .unwrap_or_else(|| {
            panic!(
                "{}: refused {values:?} without an error message",
                fmu.name()
            )
        });
    // The instance is not lost: reset, and it initializes with the start values.
    assert_eq!(
        inst.reset(),
        OK,
        "{}: fmi2Reset after a refused initialization",
        fmu.name()
    );
    inst.initialize(&[])
        .unwrap_or_else(|e| panic!("{}: initialize after reset: {e}", fmu.name()));
    Some(message)
}

#[test]
fn non_physical_parameters_are_refused_at_initialization() {
    let mut checked = 0;
    for fmu in fmus() {
        let mut cases: Vec<(&Variable, f64)> = vec![];
        for v in fmu.md.variables.iter().filter(|v| v.is("parameter")) {
            if v.must_be_positive() {
                cases.extend([(v, 0.0), (v, -0.0), (v, -1.0), (v, -1e-300)]);
            }
            if let Some(min) = v.min {
                cases.push((v, min - 1.0));
            }
            if let Some(max) = v.max {
                cases.push((v, max + 1.0));
            }
            cases.extend([(v, f64::NAN), (v, f64::INFINITY), (v, f64::NEG_INFINITY)]);
        }
        for (v, x) in cases {
            let message = refusal(&fmu, &[(v.vr, x)])
                .unwrap_or_else(|| panic!("{}: {} = {x} was accepted", fmu.name(), v.name));
            let expected = format!("{} = {x}", v.name);
            assert!(
                message.contains(&expected),
                "{}: the refusal of {} = {x} does not say \"{expected}\": {message}",
                fmu.name(),
                v.name
            );
            checked += 1;
        }
        // A tensor with products of inertia too large for its moments: no body has it.
        if let (Some(ixx), Some(iyy), Some(ixy)) =
            (fmu.md.var("I_xx"), fmu.md.var("I_yy"), fmu.md.var("I_xy"))
        {
            let big = 10.0 * (ixx.start.unwrap_or(1.0) + iyy.start.unwrap_or(1.0));
            let message = refusal(&fmu, &[(ixy.vr, big)]).unwrap_or_else(|| {
                panic!(
                    "{}: I_xy = {big} (not positive definite) was accepted",
                    fmu.name()
                )
            });
            assert!(message.contains("inertia"), "{}: {message}", fmu.name());
            checked += 1;
        }
    }
    println!("{checked} non-physical parameter values refused, each naming variable and value");
}

#[test]
fn parameters_after_initialization_follow_their_variability() {
    for fmu in fmus() {
        let mut inst = Instance::new(&fmu, "after-init").unwrap();
        inst.initialize(&[]).unwrap();
        let e = fmu.md.experiment;
        assert_eq!(inst.do_step(e.start, e.step), OK);
        for v in fmu.md.variables.iter().filter(|v| v.is("parameter")) {
            let before = inst.get_real(&[v.vr]).1[0];
            let s = inst.set_real(&[v.vr], &[before * 1.01 + 0.01]);
            if v.variability == "fixed" {
                assert_eq!(
                    s,
                    ERROR,
                    "{}: fixed parameter {} set after initialization",
                    fmu.name(),
                    v.name
                );
                assert!(inst.messages().last().unwrap().text.contains(&v.name));
                assert_eq!(inst.get_real(&[v.vr]).1[0].to_bits(), before.to_bits());
            } else {
                assert_eq!(
                    s,
                    OK,
                    "{}: tunable {}: {}",
                    fmu.name(),
                    v.name,
                    inst.log_tail()
                );
                // Out of its bounds, refused with name and value, and the old value kept.
                if let Some(min) = v.min {
                    let now = inst.get_real(&[v.vr]).1[0];
                    assert_eq!(inst.set_real(&[v.vr], &[min - 1.0]), ERROR);
                    let m = inst.messages().last().unwrap().text.clone();
                    assert!(
                        m.contains(&format!("{} = {}", v.name, min - 1.0)),
                        "{}: {m}",
                        fmu.name()
                    );
                    assert_eq!(inst.get_real(&[v.vr]).1[0].to_bits(), now.to_bits());
                }
            }
        }
        step_ok(&mut inst, &fmu, e.start + e.step, e.step);
    }
}

#[test]
fn non_finite_inputs_are_refused_and_never_reach_a_step() {
    let mut checked = 0;
    for fmu in fmus() {
        let e = fmu.md.experiment;
        for input in fmu.md.variables.iter().filter(|v| v.is("input")) {
            let mut inst = Instance::new(&fmu, "inputs").unwrap();
            inst.initialize(&[]).unwrap();
            assert_eq!(inst.do_step(e.start, e.step), OK);
            let held = inst.get_real(&[input.vr]).1[0];
            for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                assert_eq!(
                    inst.set_real(&[input.vr], &[x]),
                    ERROR,
                    "{}: {} = {x} accepted",
                    fmu.name(),
                    input.name
                );
                let m = inst.messages().last().unwrap().text.clone();
                assert!(
                    m.contains(&format!("{} = {x}", input.name)),
                    "{}: {m}",
                    fmu.name()
                );
                assert_eq!(inst.get_real(&[input.vr]).1[0].to_bits(), held.to_bits());
                checked += 1;
            }
            // The next step runs on the last valid input.
            step_ok(&mut inst, &fmu, e.start + e.step, e.step);
            // A finite input so large the model's values overflow, at once or a few steps
            // on (an Oscillator pushed by F = f64::MAX gains 1e306 m/s per 0.01 s: finite,
            // and right, for a while): every step succeeds with no value NaN, until one is
            // refused (fmi2Error) or discarded (fmi2Discard), with a message, and then too
            // no value is NaN. Without a state, nothing accumulates: the first step refuses
            // or keeps every value finite (SpringDamper's default damping c = 0 times
            // v_a = f64::MAX is 0).
            assert_eq!(inst.set_real(&[input.vr], &[f64::MAX]), OK);
            let mut t = e.start + 2.0 * e.step;
            let s = loop {
                let n = inst.messages().len();
                let s = inst.do_step(t, e.step);
                let (g, values) = inst.get_real(&fmu.md.all_vrs());
                assert!(
                    g != OK || values.iter().all(|x| !x.is_nan()),
                    "{}: NaN after fmi2DoStep returned {}",
                    fmu.name(),
                    status_name(s)
                );
                if s != OK {
                    assert!(
                        matches!(s, ERROR | DISCARD),
                        "{}: {} = {:e}: fmi2DoStep returned {}",
                        fmu.name(),
                        input.name,
                        f64::MAX,
                        status_name(s)
                    );
                    assert!(
                        inst.messages()[n..].iter().any(|m| m.status == s),
                        "{}: {} without a message",
                        fmu.name(),
                        status_name(s)
                    );
                    break s;
                }
                t += e.step;
                if fmu.md.derivatives.is_empty() {
                    // No state accumulates the input: a step that takes it with every value
                    // finite is the whole answer (a later one computes the same).
                    assert!(
                        g == OK && values.iter().all(|x| x.is_finite()),
                        "{}: {} = {:e} gave a value that is not finite, without an error",
                        fmu.name(),
                        input.name,
                        f64::MAX
                    );
                    break OK;
                }
                assert!(
                    t < e.start + 1000.0 * e.step,
                    "{}: {} = {:e} never overflowed",
                    fmu.name(),
                    input.name,
                    f64::MAX
                );
            };
            // And the instance carries on: after a refused step, with a sane input again;
            // after a discarded one, from a reset.
            if s == ERROR || s == OK {
                assert_eq!(inst.set_real(&[input.vr], &[held]), OK);
                step_ok(&mut inst, &fmu, t, e.step);
            } else {
                assert_eq!(inst.reset(), OK);
                inst.initialize(&[]).unwrap();
                assert_eq!(inst.do_step(e.start, e.step), OK);
            }
            checked += 1;
        }
    }
    println!("{checked} non-finite or overflowing inputs refused");
}

/// One step that must succeed, the log in the message otherwise.
#[track_caller]
fn step_ok(inst: &mut Instance, fmu: &Fmu, t: f64, h: f64) {
    assert_eq!(
        inst.do_step(t, h),
        OK,
        "{}: {}",
        fmu.name(),
        inst.log_tail()
    );
}

/// A value different from `v`'s start, within its bounds.
fn changed(v: &Variable) -> f64 {
    let x = v.start.unwrap_or(1.0) * 1.5 + 0.1;
    x.max(v.min.unwrap_or(f64::MIN))
        .min(v.max.unwrap_or(f64::MAX))
}

/// Every variable's value, indexed by its value reference (`all_values` is in the model
/// description's order, which puts each state before its derivative: not the references'
/// order where a mechanism declares a derivative first, as CraneDynamics does `P_drives`).
fn values_by_vr(instance: &mut Instance, fmu: &Fmu) -> Vec<f64> {
    let values = instance.all_values();
    let size = fmu
        .md
        .variables
        .iter()
        .map(|v| v.vr as usize + 1)
        .max()
        .unwrap_or(0);
    let mut by_vr = vec![f64::NAN; size];
    for (v, x) in fmu.md.variables.iter().zip(values) {
        by_vr[v.vr as usize] = x;
    }
    by_vr
}

#[test]
fn tunable_parameters_take_effect_at_the_next_step() {
    let tol = 1e-10;
    let mut checked = 0;
    for fmu in fmus() {
        let tunables: Vec<&Variable> = fmu
            .md
            .variables
            .iter()
            .filter(|v| v.is_tunable_parameter())
            .collect();
        if tunables.is_empty() {
            println!("{}: no tunable parameters", fmu.name());
            continue;
        }
        let e = fmu.md.experiment;
        let k = 20;
        let t_k = e.start + k as f64 * e.step;
        let start = |inst: &mut Instance| {
            assert_eq!(inst.setup(Some(tol), e.start, None), OK);
            assert_eq!(inst.enter_init(), OK);
            assert_eq!(inst.exit_init(), OK);
            for n in 0..k {
                assert_eq!(inst.do_step(e.start + n as f64 * e.step, e.step), OK);
            }
        };
        let (mut a, mut b) = (
            Instance::new(&fmu, "a").unwrap(),
            Instance::new(&fmu, "b").unwrap(),
        );
        start(&mut a);
        start(&mut b);
        let at_k = values_by_vr(&mut a, &fmu);
        let vrs: Vec<u32> = tunables.iter().map(|v| v.vr).collect();
        let new: Vec<f64> = tunables.iter().map(|v| changed(v)).collect();
        assert_eq!(
            b.set_real(&vrs, &new),
            OK,
            "{}: {}",
            fmu.name(),
            b.log_tail()
        );
        assert_eq!(b.get_real(&vrs).1, new);
        assert_eq!(a.do_step(t_k, e.step), OK);
        assert_eq!(b.do_step(t_k, e.step), OK);
        // C starts at t_k from A's states with the new parameters: what B must have done.
        let mut c = Instance::new(&fmu, "c").unwrap();
        assert_eq!(c.setup(Some(tol), t_k, None), OK);
        assert_eq!(c.enter_init(), OK);
        let mut set: Vec<(u32, f64)> = tunables.iter().zip(&new).map(|(v, &x)| (v.vr, x)).collect();
        for v in fmu
            .md
            .states()
            .into_iter()
            .chain(fmu.md.variables.iter().filter(|v| v.is("input")))
        {
            set.push((v.vr, at_k[v.vr as usize]));
        }
        let (svr, sx): (Vec<u32>, Vec<f64>) = set.into_iter().unzip();
        assert_eq!(
            c.set_real(&svr, &sx),
            OK,
            "{}: {}",
            fmu.name(),
            c.log_tail()
        );
        assert_eq!(c.exit_init(), OK, "{}: {}", fmu.name(), c.log_tail());
        assert_eq!(c.do_step(t_k, e.step), OK);
        let (va, vb, vc) = (
            values_by_vr(&mut a, &fmu),
            values_by_vr(&mut b, &fmu),
            values_by_vr(&mut c, &fmu),
        );
        let mut differs = false;
        for v in &fmu.md.variables {
            let i = v.vr as usize;
            if v.causality == "calculatedParameter" {
                assert_eq!(
                    vb[i].to_bits(),
                    vc[i].to_bits(),
                    "{}: calculated {} not recomputed after the change",
                    fmu.name(),
                    v.name
                );
            }
            if v.variability == "continuous" {
                assert!(
                    (vb[i] - vc[i]).abs() <= 1e-7 * vb[i].abs().max(1.0),
                    "{}: after the change, {} = {} but a run started with the new parameters gives {}",
                    fmu.name(),
                    v.name,
                    vb[i],
                    vc[i]
                );
                differs |= (vb[i] - va[i]).abs() > 1e-9 * va[i].abs().max(1.0);
            }
        }
        assert!(
            differs,
            "{}: changing {:?} changed nothing at the next step",
            fmu.name(),
            tunables.iter().map(|v| &v.name).collect::<Vec<_>>()
        );
        checked += 1;
    }
    println!("{checked} FMUs: tunable changes take effect at the next step");
}
