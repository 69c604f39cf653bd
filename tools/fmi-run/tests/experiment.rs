//! The experiment file, the CSV, and the executable's errors (on the packaged Oscillator).

use mechfmu_fmi_run::{Experiment, Table};
use std::path::PathBuf;
use std::process::{Command, Output};

fn oscillator() -> PathBuf {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../fmus/Oscillator.fmu");
    assert!(
        path.exists(),
        "{} is missing: build the FMUs first with `cargo run --release -- build`",
        path.display()
    );
    path
}

/// Runs the executable on `json` (written to a file of its own); returns its output.
fn run_exe(name: &str, json: &str) -> Output {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("fmi-run-tests");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join(format!("{name}.json"));
    std::fs::write(&file, json).unwrap();
    Command::new(env!("CARGO_BIN_EXE_mechfmu-fmi-run"))
        .arg(&file)
        .output()
        .expect("run mechfmu-fmi-run")
}

fn experiment(fmu: &std::path::Path, extra: &str) -> String {
    format!(
        r#"{{"fmu": {:?}, "relative_tolerance": 1e-8, "stop_time": 1.0, "step_size": 0.1, "steps": 10,
            "record": ["x", "x_dot"] {extra}}}"#,
        fmu.display().to_string()
    )
}

#[test]
fn parses_a_full_experiment() {
    let exp = Experiment::from_json(
        r#"{"fmu": "a.fmu", "relative_tolerance": null, "step_size": 0.5, "steps": 2,
            "start_values": {"c": 5.0, "x": 1}, "inputs": ["F"], "input_values": [[0], [1.5], [2]],
            "record": ["x"]}"#,
    )
    .unwrap();
    assert_eq!(exp.fmu, PathBuf::from("a.fmu"));
    assert_eq!(exp.relative_tolerance, None);
    assert_eq!(exp.stop_time, None, "absent: no stop time");
    assert_eq!((exp.step_size, exp.steps), (0.5, 2));
    assert_eq!(exp.start_values["c"], 5.0);
    assert_eq!(exp.start_values["x"], 1.0);
    assert_eq!(exp.input_values, vec![vec![0.0], vec![1.5], vec![2.0]]);
    // numbers read back exactly (serde_json's float_roundtrip)
    let x = 0.1f64 + 0.2;
    let exp = Experiment::from_json(&format!(
        r#"{{"fmu": "a.fmu", "relative_tolerance": {x:?}, "step_size": {:?}, "steps": 1, "record": []}}"#,
        1.0f64 / 3.0
    ))
    .unwrap();
    assert_eq!(exp.relative_tolerance, Some(x));
    assert_eq!(exp.step_size, 1.0 / 3.0);
}

#[test]
fn rejects_inconsistent_experiments() {
    let cases = [
        (
            r#""step_size": 0.1, "steps": 2, "record": [], "bogus": 1"#,
            "unknown field `bogus`",
        ),
        (r#""step_size": 0.1, "record": []"#, "missing field `steps`"),
        (
            r#""step_size": 0, "steps": 2, "record": []"#,
            "step_size must be positive",
        ),
        (
            r#""step_size": 0.1, "steps": 2, "record": [], "inputs": ["F"], "input_values": [[0], [1]]"#,
            "input_values has 2 rows: expected steps + 1 = 3",
        ),
        (
            r#""step_size": 0.1, "steps": 1, "record": [], "inputs": ["F"], "input_values": [[0], [1, 2]]"#,
            "input_values row 1 has 2 values",
        ),
        (
            r#""step_size": 0.1, "steps": 1, "record": [], "input_values": [[1]]"#,
            "input_values given without inputs",
        ),
    ];
    for (fields, expected) in cases {
        let json = format!(r#"{{"fmu": "a.fmu", "relative_tolerance": 1e-6, {fields}}}"#);
        let err = Experiment::from_json(&json).unwrap_err();
        assert!(err.contains(expected), "{json}: {err}");
    }
}

#[test]
fn csv_quotes_the_names_and_round_trips_the_values() {
    let values = [0.1, 1.0 / 3.0, -2.5e-300, 1e22, 0.0];
    let table = Table {
        names: vec!["time".into(), "a[1,2]".into(), "say \"hi\"".into()],
        rows: vec![values[..3].to_vec(), values[2..].to_vec()],
    };
    let mut out = Vec::new();
    table.write_csv(&mut out).unwrap();
    let text = String::from_utf8(out).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next(), Some(r#""time","a[1,2]","say ""hi""""#));
    for row in &table.rows {
        let read: Vec<f64> = lines
            .next()
            .unwrap()
            .split(',')
            .map(|v| v.parse().unwrap())
            .collect();
        assert_eq!(&read, row);
    }
    assert_eq!(lines.next(), None);
}

#[test]
fn runs_the_oscillator_on_the_grid() {
    let out = run_exe(
        "ok",
        &experiment(
            &oscillator(),
            r#", "start_values": {"c": 0.4, "k": 4.0}, "inputs": ["F"],
                "input_values": [[0], [0], [0], [0], [0], [1], [1], [1], [1], [1], [1]]"#,
        ),
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let text = String::from_utf8(out.stdout).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines[0], r#""time","x","x_dot""#);
    assert_eq!(lines.len(), 12, "header + n + 1 rows");
    for (k, line) in lines[1..].iter().enumerate() {
        let row: Vec<f64> = line.split(',').map(|v| v.parse().unwrap()).collect();
        assert_eq!(row[0], k as f64 * 0.1, "t_k = k·h, not accumulated");
        assert!(row[1].is_finite() && row[2].is_finite(), "{line}");
    }
    assert!(
        lines[1].starts_with("0.0,1.0,0.0"),
        "x0 = 1, v0 = 0: {}",
        lines[1]
    );
}

#[test]
fn an_unknown_variable_is_an_error_naming_it() {
    let out = run_exe(
        "unknown",
        &experiment(
            &oscillator(),
            r#", "start_values": {"no_such_variable": 1.0}"#,
        ),
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("unknown variable `no_such_variable` (start value)")
            && stderr.contains("Oscillator"),
        "{stderr}"
    );
    assert!(
        !stderr.contains("panicked") && !stderr.contains("RUST_BACKTRACE"),
        "{stderr}"
    );
    assert!(out.stdout.is_empty(), "no partial CSV");
}

#[test]
fn a_refused_call_is_an_error_naming_the_call() {
    // c < 0 is below its minimum: the FMU refuses to leave initialization mode
    let out = run_exe(
        "refused",
        &experiment(&oscillator(), r#", "start_values": {"c": -1.0}"#),
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("mechfmu-fmi-run: fmi2ExitInitializationMode returned fmi2Error"),
        "{stderr}"
    );
    assert!(
        stderr.contains("[FMU ") && stderr.contains("c = -1"),
        "the FMU's message: {stderr}"
    );
}

#[test]
fn a_missing_fmu_and_bad_usage_are_errors() {
    let out = run_exe(
        "missing",
        &experiment(std::path::Path::new("/nonexistent/No.fmu"), ""),
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("cannot import /nonexistent/No.fmu"),
        "{stderr}"
    );
    let out = Command::new(env!("CARGO_BIN_EXE_mechfmu-fmi-run"))
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&out.stderr).contains("usage: mechfmu-fmi-run"));
}

/// `fmu` with `edit` applied to its `modelDescription.xml`, written under `name`.
fn edited_copy(fmu: &std::path::Path, name: &str, edit: impl Fn(&str) -> String) -> PathBuf {
    use std::io::{Read, Write};
    let mut archive = zip::ZipArchive::new(std::fs::File::open(fmu).unwrap()).unwrap();
    let path = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join(format!("fmi-run-tests/{name}.fmu"));
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    let mut writer = zip::ZipWriter::new(std::fs::File::create(&path).unwrap());
    for i in 0..archive.len() {
        let mut file = archive.by_index(i).unwrap();
        let entry = file.name().to_string();
        if file.is_dir() {
            continue;
        }
        let mut data = Vec::new();
        file.read_to_end(&mut data).unwrap();
        if entry == "modelDescription.xml" {
            data = edit(std::str::from_utf8(&data).unwrap()).into_bytes();
        }
        writer
            .start_file(entry.as_str(), zip::write::SimpleFileOptions::default())
            .unwrap();
        writer.write_all(&data).unwrap();
    }
    writer.finish().unwrap();
    path
}

#[test]
fn xml_namespace_declarations_are_not_the_fmus_fault() {
    // legal XML the crate's schema refuses (`unknown field "xmlns:xsi"`): the runner gives
    // the crate the model description without it, and the run is the same to the bit
    let declared = edited_copy(&oscillator(), "namespaces", |xml| {
        let xml = xml.replacen(
            "<fmiModelDescription",
            "<fmiModelDescription xmlns:xsi=\"http://www.w3.org/2001/XMLSchema-instance\" \
             xsi:noNamespaceSchemaLocation=\"fmi2ModelDescription.xsd\"",
            1,
        );
        xml.replacen(
            "<ScalarVariable ",
            "<ScalarVariable canHandleMultipleSetPerTimeInstant=\"true\" ",
            1,
        )
    });
    let exp = |fmu: &std::path::Path| {
        Experiment::from_json(&experiment(fmu, r#", "start_values": {"c": 0.4}"#)).unwrap()
    };
    let plain = mechfmu_fmi_run::run(&exp(&oscillator())).unwrap();
    let with_namespaces = mechfmu_fmi_run::run(&exp(&declared)).unwrap();
    assert_eq!(plain, with_namespaces);
}
