//! `--interface me`: Model Exchange with the crate's own fixed-step RK4, on the packaged FMUs
//! (build them first with `cargo run --release -- build`).

use mechfmu_fmi_run::{run, run_me, Experiment, MeOptions, Table};
use std::path::PathBuf;
use std::process::{Command, Output};

fn fmu(name: &str) -> PathBuf {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(format!("../../fmus/{name}.fmu"));
    assert!(
        path.exists(),
        "{} is missing: build the FMUs first with `cargo run --release -- build`",
        path.display()
    );
    path
}

/// Runs the executable on `json` (written to a file of its own) with `args`.
fn run_exe(name: &str, json: &str, args: &[&str]) -> Output {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("fmi-run-me-tests");
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join(format!("{name}.json"));
    std::fs::write(&file, json).unwrap();
    Command::new(env!("CARGO_BIN_EXE_mechfmu-fmi-run"))
        .arg(&file)
        .args(args)
        .output()
        .expect("run mechfmu-fmi-run")
}

fn column(table: &Table, name: &str) -> Vec<f64> {
    let i = table.names.iter().position(|n| n == name).unwrap();
    table.rows.iter().map(|row| row[i]).collect()
}

/// The time in "... the simulation stopped at t = T" (the run's last message).
fn stop_time(stderr: &str) -> f64 {
    let marker = "the simulation stopped at t = ";
    let at = stderr.rfind(marker).expect(stderr) + marker.len();
    let end = stderr[at..]
        .find(|c: char| c.is_whitespace() || c == ';')
        .map_or(stderr.len(), |e| at + e);
    stderr[at..end].parse().expect(stderr)
}

/// The Oscillator's DefaultExperiment: m = 1, k = 4, c = 0.4 (ωn = 2, ζ = 0.1), x0 = 1, v0 = 0,
/// h = 0.01 to 20 s.
fn oscillator_default() -> Experiment {
    Experiment::from_json(&format!(
        r#"{{"fmu": {:?}, "relative_tolerance": null, "stop_time": 20.0, "step_size": 0.01,
            "steps": 2000, "record": ["x", "x_dot"]}}"#,
        fmu("Oscillator").display().to_string()
    ))
    .unwrap()
}

/// max |x - x_exact| and max |v - v_exact| over the run (the closed-form free response).
fn oscillator_errors(table: &Table) -> (f64, f64) {
    let (wn, zeta) = (2.0f64, 0.1f64);
    let sigma = zeta * wn;
    let wd = wn * (1.0 - zeta * zeta).sqrt();
    let t = column(table, "time");
    let (x, v) = (column(table, "x"), column(table, "x_dot"));
    let mut err = (0.0f64, 0.0f64);
    for k in 0..t.len() {
        let decay = (-sigma * t[k]).exp();
        let (s, c) = (wd * t[k]).sin_cos();
        let x_exact = decay * (c + sigma / wd * s);
        let v_exact = -decay * wn * wn / wd * s;
        err.0 = err.0.max((x[k] - x_exact).abs());
        err.1 = err.1.max((v[k] - v_exact).abs());
    }
    err
}

#[test]
fn the_oscillator_in_me_matches_the_closed_form_to_rk4_accuracy() {
    let exp = oscillator_default();
    let (table, stats) = run_me(&exp, &MeOptions::default()).unwrap();
    assert_eq!(table.names, ["time", "x", "x_dot"]);
    assert_eq!(table.rows.len(), 2001);
    // the same grid as Co-Simulation: t_k = k·h, not accumulated
    let cs = run(&exp).unwrap();
    assert_eq!(column(&table, "time"), column(&cs, "time"));
    assert_eq!(table.rows[0], [0.0, 1.0, 0.0]);
    // one RK4 step per communication step, nothing else
    assert_eq!(stats.steps, 2000);
    assert_eq!(stats.derivative_evaluations, 4 * 2000);
    assert_eq!(
        stats.state_events + stats.step_events + stats.input_events,
        0
    );

    // RK4 on y' = λy multiplies by R(hλ) = Σ_{j≤4} (hλ)^j/j! instead of e^{hλ}: a relative
    // error of about |hλ|^5/120 per step, |hλ| = h ωn = 0.02 here (2.7e-11). n = 2000 steps
    // on a decaying solution of amplitude ≤ 1 accumulate at most n |hλ|^5/120 = 5.3e-8 in x,
    // ωn times that in x_dot.
    let n = 2000.0;
    let bound = n * (0.01f64 * 2.0).powi(5) / 120.0;
    let (ex, ev) = oscillator_errors(&table);
    assert!(
        ex <= bound && ev <= 2.0 * bound,
        "x {ex:e}, x_dot {ev:e}, bound {bound:e}"
    );
    // and the error is RK4's: fourth order, halving the step divides it by 2^4 = 16
    let (table2, stats2) = run_me(&exp, &MeOptions { substeps: 2 }).unwrap();
    assert_eq!(stats2.steps, 4000);
    assert_eq!(column(&table2, "time"), column(&cs, "time"));
    let (ex2, ev2) = oscillator_errors(&table2);
    assert!(
        (12.0..20.0).contains(&(ex / ex2)) && (12.0..20.0).contains(&(ev / ev2)),
        "x {ex:e} -> {ex2:e}, x_dot {ev:e} -> {ev2:e}: not fourth order"
    );
    // far below what the validation asks of any importer (1e-6 of the signal's range)
    let (ecs, _) = oscillator_errors(&cs);
    assert!(ex < 1e-7 && ecs < 1e-7, "ME {ex:e}, CS {ecs:e}");
}

#[test]
fn the_executable_writes_the_same_csv_format_in_me() {
    let json = format!(
        r#"{{"fmu": {:?}, "relative_tolerance": 1e-8, "stop_time": 1.0, "step_size": 0.1, "steps": 10,
            "start_values": {{"c": 0.4, "k": 4.0}}, "inputs": ["F"],
            "input_values": [[0], [0], [0], [0], [0], [1], [1], [1], [1], [1], [1]],
            "record": ["x", "x_dot"]}}"#,
        fmu("Oscillator").display().to_string()
    );
    let cs = run_exe("csv-cs", &json, &[]);
    let cs_explicit = run_exe("csv-cs2", &json, &["--interface", "cs"]);
    assert!(cs.status.success() && cs_explicit.status.success());
    assert_eq!(
        cs.stdout, cs_explicit.stdout,
        "--interface cs is the default"
    );
    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("fmi-run-me-tests/csv-me.csv");
    let me = run_exe(
        "csv-me",
        &json,
        &["--interface", "me", "--out", out.to_str().unwrap()],
    );
    let stderr = String::from_utf8_lossy(&me.stderr);
    assert!(me.status.success(), "{stderr}");
    assert!(me.stdout.is_empty() && stderr.is_empty(), "{stderr}");
    let me_text = std::fs::read_to_string(&out).unwrap();
    let cs_text = String::from_utf8(cs.stdout).unwrap();
    let (me_lines, cs_lines): (Vec<&str>, Vec<&str>) =
        (me_text.lines().collect(), cs_text.lines().collect());
    assert_eq!(me_lines.len(), cs_lines.len());
    assert_eq!(me_lines[0], r#""time","x","x_dot""#);
    for (m, c) in me_lines[1..].iter().zip(&cs_lines[1..]) {
        let m: Vec<f64> = m.split(',').map(|v| v.parse().unwrap()).collect();
        let c: Vec<f64> = c.split(',').map(|v| v.parse().unwrap()).collect();
        assert_eq!(m[0], c[0], "the same times");
        // h = 0.1 here: RK4's error is (h ωn)^5/120 = 2.7e-6 per step (relative), at most
        // 10 times that after 10 steps, ωn = 2 times that in x_dot; the step in F at t = 0.5
        // is held identically by both (set before the step from 0.5)
        let bound = 10.0 * 0.2f64.powi(5) / 120.0;
        assert!((m[1] - c[1]).abs() < bound, "{m:?} vs {c:?}");
        assert!((m[2] - c[2]).abs() < 2.0 * bound, "{m:?} vs {c:?}");
    }
}

#[test]
fn bad_options_are_usage_errors() {
    let json = format!(
        r#"{{"fmu": {:?}, "relative_tolerance": null, "step_size": 0.1, "steps": 1, "record": []}}"#,
        fmu("Oscillator").display().to_string()
    );
    for args in [
        &["--interface", "xx"][..],
        &["--interface"],
        &["--substeps", "2"],
        &["--interface", "cs", "--substeps", "2"],
        &["--interface", "me", "--substeps", "0"],
        &["--interface", "me", "--interface", "me"],
        &["--bogus", "1"],
    ] {
        let out = run_exe("usage", &json, args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(
            String::from_utf8_lossy(&out.stderr).contains("usage: mechfmu-fmi-run"),
            "{args:?}"
        );
    }
    let out = run_exe("usage-ok", &json, &["--substeps", "3", "--interface", "me"]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

/// The Crane with the drives still but the trolley accelerating inwards, x_ddot = -a from
/// x = 10 m at rest: x = 10 - a t²/2 reaches the pivot at t* = sqrt(20 / a).
fn crane_to_the_pivot(a: f64) -> String {
    let n = 500;
    let rows: Vec<String> = (0..=n).map(|_| format!("[{:?}, 0.0]", -a)).collect();
    format!(
        r#"{{"fmu": {:?}, "relative_tolerance": 1e-8, "stop_time": 5.0, "step_size": 0.01, "steps": {n},
            "start_values": {{"x": 10.0, "x_dot": 0.0}}, "inputs": ["x_ddot", "theta_ddot"],
            "input_values": [{}], "record": ["x", "x_dot", "phi", "T"]}}"#,
        fmu("Crane").display().to_string(),
        rows.join(", ")
    )
}

#[test]
fn the_crane_in_me_stops_where_the_trolley_reaches_the_pivot() {
    let json = crane_to_the_pivot(2.0);
    let t_star = 10.0f64.sqrt();
    let out = run_exe("crane-pivot", &json, &["--interface", "me"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(out.stdout.is_empty(), "no partial CSV: {stderr}");
    // the FMU's reason, then the run's message naming the call, the step and the time
    assert!(
        stderr.contains("[FMU WARN] Crane:") && stderr.contains("the trolley reached the pivot"),
        "{stderr}"
    );
    let last = stderr.lines().last().unwrap();
    assert!(
        last.starts_with("mechfmu-fmi-run: fmi2CompletedIntegratorStep at t = 3.16227766016")
            && last.contains("(in step 317 of 500, from t = 3.16)")
            && last.contains("state event of event indicator 0")
            && last.contains("returned terminateSimulation = true"),
        "{last}"
    );
    // x'' is constant, so RK4 integrates x exactly: the stop is the bisection's, within
    // 1e-12 s after the crossing
    let t = stop_time(&stderr);
    assert!(
        t >= t_star - 1e-15 && t - t_star <= 1.1e-12,
        "stopped at {t:?}, the trolley reaches the pivot at {t_star:?}"
    );
    // Co-Simulation stops there too, at the end of the communication step
    let cs = run_exe("crane-pivot-cs", &json, &[]);
    let cs_err = String::from_utf8_lossy(&cs.stderr);
    assert_eq!(cs.status.code(), Some(1), "{cs_err}");
    assert!(
        cs_err.contains("(step 317 of 500) returned fmi2Discard"),
        "{cs_err}"
    );

    // the library says the same
    let err = run_me(
        &Experiment::from_json(&json).unwrap(),
        &MeOptions::default(),
    )
    .unwrap_err();
    assert_eq!(stop_time(&err), t);
    // a different acceleration, with substeps: still at the crossing
    let out = run_exe(
        "crane-pivot-5",
        &crane_to_the_pivot(5.0),
        &["--interface", "me", "--substeps", "3"],
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    let (t, t_star) = (stop_time(&stderr), 4.0f64.sqrt());
    assert!(
        t >= t_star - 1e-15 && t - t_star <= 1.1e-12,
        "{t:?} vs {t_star:?}: {stderr}"
    );
}

#[test]
fn the_crane_in_me_locates_where_the_cable_goes_slack() {
    // drives still, the payload thrown up past the horizontal: phi0 = 89°, phi_dot0 = 1.5 rad/s.
    // With E conserved, phi'^2 = w0^2 + 2 g/l (cos phi - cos phi0) and T = m (g cos phi +
    // l phi'^2) vanishes at cos phi* = (2 g cos phi0 - l w0^2) / (3 g), reached at
    // t* = ∫_{phi0}^{phi*} dphi / phi' (phi' > 0 all the way).
    let (g, l, phi0, w0) = (9.81f64, 5.0f64, 89f64.to_radians(), 1.5f64);
    let phi_star = ((2.0 * g * phi0.cos() - l * w0 * w0) / (3.0 * g)).acos();
    let rate = |phi: f64| 1.0 / (w0 * w0 + 2.0 * g / l * (phi.cos() - phi0.cos())).sqrt();
    let n = 20_000; // composite Simpson: the integrand is smooth, the error far below 1e-12
    let dphi = (phi_star - phi0) / n as f64;
    let simpson: f64 = (0..=n)
        .map(|i| {
            let w = if i == 0 || i == n {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            };
            w * rate(phi0 + i as f64 * dphi)
        })
        .sum();
    let t_star = simpson * dphi / 3.0;
    let json = format!(
        r#"{{"fmu": {:?}, "relative_tolerance": 1e-8, "stop_time": 3.0, "step_size": 0.01, "steps": 300,
            "start_values": {{"phi": {phi0:?}, "phi_dot": {w0:?}}}, "record": ["phi", "T"]}}"#,
        fmu("Crane").display().to_string()
    );
    let out = run_exe("crane-slack", &json, &["--interface", "me"]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    // T < 0 is a warning, not a stop: but like fmi2DoStep's, any fmi2Warning ends the run
    let last = stderr.lines().last().unwrap();
    assert!(
        last.starts_with("mechfmu-fmi-run: fmi2CompletedIntegratorStep at t = ")
            && last.ends_with("(state event of event indicator 1) returned fmi2Warning"),
        "{last}"
    );
    assert!(stderr.contains("the cable is slack"), "{stderr}");
    let at = "fmi2CompletedIntegratorStep at t = ";
    let from = last.find(at).unwrap() + at.len();
    let t: f64 = last[from..].split(' ').next().unwrap().parse().unwrap();
    // RK4's phase error at h = 0.01 (|h λ| ≈ 0.02) over 34 steps, not the location's 1e-12
    assert!(
        (t - t_star).abs() < 1e-8,
        "slack at {t:?}, expected {t_star:?}"
    );
}

#[test]
fn rigid_body_step_events_renormalize_the_quaternion() {
    // the heavy top spun at 40 rad/s without the pull back to the sphere (k_q = 0): RK4 at
    // h = 0.02 lets |q| drift past the FMU's guard (1e-3), the FMU asks for a step event
    // (fmi2CompletedIntegratorStep), renormalizes q in fmi2NewDiscreteStates
    // (valuesOfContinuousStatesChanged) and the states are read back
    let json = format!(
        r#"{{"fmu": {:?}, "relative_tolerance": 1e-10, "stop_time": 20.0, "step_size": 0.02, "steps": 1000,
            "start_values": {{"M": 1.0, "I_xx": 0.002, "I_yy": 0.002, "I_zz": 0.003, "r_Cz": 0.05, "k_q": 0.0,
                "q_w": {:?}, "q_x": {:?}, "q_y": 0.0, "q_z": 0.0, "w_x": 0.0, "w_y": 0.0, "w_z": 40.0}},
            "record": ["q_w", "q_x", "q_y", "q_z"]}}"#,
        fmu("RigidBody").display().to_string(),
        0.25f64.cos(),
        0.25f64.sin()
    );
    let exp = Experiment::from_json(&json).unwrap();
    let (table, stats) = run_me(&exp, &MeOptions::default()).unwrap();
    assert!(stats.step_events > 0, "{stats:?}");
    assert_eq!(stats.state_changes, stats.step_events, "{stats:?}");
    assert_eq!(stats.state_events, 0);
    // the guard holds |q| within one RK4 step's drift beyond 1e-3
    let norm_error = table
        .rows
        .iter()
        .map(|r| ((r[1] * r[1] + r[2] * r[2] + r[3] * r[3] + r[4] * r[4]).sqrt() - 1.0).abs())
        .fold(0.0, f64::max);
    assert!(norm_error < 2e-3, "||q| - 1| reached {norm_error:e}");
}

#[test]
fn an_fmu_with_me_runs_from_the_same_experiment_as_cs() {
    // start values before and during initialization, as in CS: c is tunable (settable in
    // initialization mode), x exact
    let json = format!(
        r#"{{"fmu": {:?}, "relative_tolerance": 1e-8, "stop_time": 2.0, "step_size": 0.01, "steps": 200,
            "start_values": {{"c": 5.0, "x": 0.5, "x_dot": -1.0}}, "record": ["x", "x_dot", "x_ddot"]}}"#,
        fmu("Oscillator").display().to_string()
    );
    let exp = Experiment::from_json(&json).unwrap();
    let cs = run(&exp).unwrap();
    let (me, _) = run_me(&exp, &MeOptions { substeps: 4 }).unwrap();
    assert_eq!(me.rows[0], cs.rows[0], "the same initial point");
    for (m, c) in me.rows.iter().zip(&cs.rows) {
        for i in 1..4 {
            assert!((m[i] - c[i]).abs() < 1e-9, "{m:?} vs {c:?}");
        }
    }
    // a refused start value is refused the same way
    let bad = Experiment::from_json(&json.replace(r#""c": 5.0"#, r#""c": -1.0"#)).unwrap();
    let err = run_me(&bad, &MeOptions::default()).unwrap_err();
    assert_eq!(err, "fmi2ExitInitializationMode returned fmi2Error");
}
