//! FMI 3.0: the packaged FMI 3.0 FMUs (`fmus/fmi3/`) run through the crate's FMI 3.0 import
//! give the FMI 2.0 FMUs' results bit for bit, in Co-Simulation and in Model Exchange, with
//! array elements named as FMI 3.0 writes them (build the FMUs first with
//! `cargo run --release -- build`).

use mechfmu_fmi_run::{run, run_me, Experiment, MeOptions, Table};
use std::path::PathBuf;

fn fmu(dir: &str, name: &str) -> String {
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("../../fmus/{dir}{name}.fmu"));
    assert!(
        path.exists(),
        "{} is missing: build the FMUs first with `cargo run --release -- build`",
        path.display()
    );
    path.display().to_string()
}

/// The same experiment on the FMI 2.0 FMU (`fmi2`) and on the FMI 3.0 one (`fmi3`), whose
/// JSON fields after `fmu` are given for each.
fn pair(name: &str, fmi2: &str, fmi3: &str) -> (Experiment, Experiment) {
    let exp = |dir: &str, rest: &str| {
        Experiment::from_json(&format!(r#"{{"fmu": {:?}, {rest}}}"#, fmu(dir, name))).unwrap()
    };
    (exp("", fmi2), exp("fmi3/", fmi3))
}

fn same_numbers(a: &Table, b: &Table) {
    assert_eq!(a.rows.len(), b.rows.len());
    for (ra, rb) in a.rows.iter().zip(&b.rows) {
        let bits = |r: &[f64]| r.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
        assert_eq!(bits(ra), bits(rb), "rows differ: {ra:?} / {rb:?}");
    }
}

const EXPERIMENT: &str =
    r#""relative_tolerance": 1e-8, "stop_time": 2.0, "step_size": 0.05, "steps": 40"#;

#[test]
fn the_oscillator_gives_the_fmi2_results_bit_for_bit() {
    let rest = format!(
        r#"{EXPERIMENT}, "start_values": {{"c": 0.5, "x": 0.2}}, "inputs": ["F"],
           "input_values": {:?}, "record": ["x", "x_dot", "x_ddot"]"#,
        (0..=40)
            .map(|k| vec![if k < 20 { 0.0 } else { 1.0 }])
            .collect::<Vec<_>>()
    );
    let (fmi2, fmi3) = pair("Oscillator", &rest, &rest);
    let cs = run(&fmi3).unwrap();
    assert_eq!(cs.names, ["time", "x", "x_dot", "x_ddot"]);
    same_numbers(&cs, &run(&fmi2).unwrap());
    let me = MeOptions { substeps: 2 };
    let (table3, stats3) = run_me(&fmi3, &me).unwrap();
    let (table2, stats2) = run_me(&fmi2, &me).unwrap();
    same_numbers(&table3, &table2);
    assert_eq!(stats3, stats2);
    assert_eq!(stats3.input_events, 1);
}

#[test]
fn rigid_body_array_elements_are_set_and_recorded_by_their_fmi3_names() {
    // I_xy is I_C[1,2] and I_C[2,1]; q_x is q[2]; tau_y is tau[2]
    let inputs: Vec<Vec<f64>> = (0..=40)
        .map(|k| vec![if k < 10 { 0.0 } else { 0.02 }])
        .collect();
    let common = format!(r#"{EXPERIMENT}, "input_values": {inputs:?}"#);
    let (fmi2, fmi3) = pair(
        "RigidBody",
        &format!(
            r#"{common}, "start_values": {{"I_xy": 0.001, "w_z": 2.0, "r_Cz": 0.05}}, "inputs": ["tau_y"],
               "record": ["q_x", "w_x", "I_xy", "H_Z", "E", "w_z_dot"]"#
        ),
        &format!(
            r#"{common}, "start_values": {{"I_C[1,2]": 0.001, "I_C[2,1]": 0.001, "w[3]": 2.0, "r_C[3]": 0.05}},
               "inputs": ["tau[2]"], "record": ["q[2]", "w[1]", "I_C[2,1]", "H[3]", "E", "w_dot[3]"]"#
        ),
    );
    let cs = run(&fmi3).unwrap();
    assert_eq!(
        cs.names,
        ["time", "q[2]", "w[1]", "I_C[2,1]", "H[3]", "E", "w_dot[3]"]
    );
    assert!(cs.rows.iter().all(|r| r[3] == 0.001));
    same_numbers(&cs, &run(&fmi2).unwrap());
    let (me3, _) = run_me(&fmi3, &MeOptions::default()).unwrap();
    let (me2, _) = run_me(&fmi2, &MeOptions::default()).unwrap();
    same_numbers(&me3, &me2);
}

#[test]
fn the_crane_reaching_the_pivot_ends_either_run_naming_the_fmi3_call() {
    let exp = Experiment::from_json(&format!(
        r#"{{"fmu": {:?}, "relative_tolerance": 1e-8, "stop_time": 5.0, "step_size": 0.1, "steps": 50,
            "start_values": {{"x": 1.0, "x_dot": -1.05}}, "record": ["x"]}}"#,
        fmu("fmi3/", "Crane")
    ))
    .unwrap();
    let cs = run(&exp).unwrap_err();
    assert!(
        cs.contains("fmi3DoStep(t = 0.9")
            && cs.contains("terminateSimulation = true")
            && cs.contains("lastSuccessfulTime = 0.9"),
        "{cs}"
    );
    let me = run_me(&exp, &MeOptions::default()).unwrap_err();
    assert!(
        me.contains("fmi3CompletedIntegratorStep") && me.contains("terminateSimulation = true"),
        "{me}"
    );
    let marker = "the simulation stopped at t = ";
    let t: f64 = me[me.rfind(marker).unwrap() + marker.len()..]
        .split(|c: char| c.is_whitespace() || c == ';')
        .next()
        .unwrap()
        .parse()
        .unwrap();
    assert!((t - 1.0 / 1.05).abs() < 1e-11, "{t}");
}

#[test]
fn array_names_are_checked() {
    let with = |extra: &str| {
        let exp = Experiment::from_json(&format!(
            r#"{{"fmu": {:?}, {EXPERIMENT}, {extra}}}"#,
            fmu("fmi3/", "RigidBody")
        ))
        .unwrap();
        run(&exp).unwrap_err()
    };
    let e = with(r#""record": ["q"]"#);
    assert!(
        e.contains("`q` (recorded) is an array of 4 elements"),
        "{e}"
    );
    let e = with(r#""record": ["q[5]"]"#);
    assert!(e.contains("no such element of `q`"), "{e}");
    let e = with(r#""record": ["I_C[1]"]"#);
    assert!(e.contains("no such element of `I_C`"), "{e}");
    let e = with(r#""record": ["q_x"]"#);
    assert!(e.contains("unknown variable `q_x`"), "{e}");
    // one place of I_xy only: the FMU refuses the array, and the run names the call
    let e = with(r#""start_values": {"I_C[1,2]": 0.001}, "record": ["E"]"#);
    assert!(
        e.contains("fmi3SetFloat64(I_C[1,2] = [") && e.contains("returned fmi3Error"),
        "{e}"
    );
}
