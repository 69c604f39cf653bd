//! The RigidBody through its FMI functions: the parallel axis theorem and principal axes
//! against hand-computed tensors, the rejection of impossible tensors, conservation laws,
//! the axisymmetric closed form and the heavy top's steady precession (from Lagrange's
//! equation in Euler angles, not from the Newton–Euler equations the FMU integrates).

use mechfmu::fmi2::ffi::*;
use mechfmu_testkit::harness::Harness;
use rigid_body::RigidBody;

type Fmu = Harness<RigidBody>;

mechfmu_testkit::golden_tests!(RigidBody);

fn close(a: f64, b: f64, tol: f64) -> bool {
    (a - b).abs() <= tol * b.abs().max(1e-300)
}

fn initialized(params: &[(&str, f64)], tol: f64) -> Fmu {
    let mut fmu = Fmu::new();
    fmu.initialize(Some(tol), 0.0, params).unwrap();
    fmu
}

fn get3(fmu: &mut Fmu, names: [&str; 3]) -> [f64; 3] {
    names.map(|n| fmu.get(n))
}

fn q_of(fmu: &mut Fmu) -> [f64; 4] {
    ["q_w", "q_x", "q_y", "q_z"].map(|n| fmu.get(n))
}

fn norm(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// Rotates body vector `v` to ground axes with the unit quaternion q = (w, x, y, z):
/// v + 2 w (u × v) + 2 u × (u × v), u the vector part (written out, not via nalgebra).
fn to_ground(q: [f64; 4], v: [f64; 3]) -> [f64; 3] {
    let n = norm(&q);
    let (w, u) = (q[0] / n, [q[1] / n, q[2] / n, q[3] / n]);
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let uv = cross(u, v);
    let uuv = cross(u, uv);
    [0, 1, 2].map(|i| v[i] + 2.0 * w * uv[i] + 2.0 * uuv[i])
}

const BOX: (f64, f64, f64, f64) = (2.0, 0.3, 0.2, 0.1); // M, a, b, c (x, y, z extents)

fn box_inertia() -> [f64; 3] {
    let (m, a, b, c) = BOX;
    [
        m * (b * b + c * c) / 12.0,
        m * (a * a + c * c) / 12.0,
        m * (a * a + b * b) / 12.0,
    ]
}

// ---------------------------------------------------------------------------- inertia

#[test]
fn default_is_the_box_and_its_principal_moments() {
    let mut fmu = initialized(&[], 1e-8);
    let [ixx, iyy, izz] = box_inertia();
    // 2/12 (0.2² + 0.1²) = 1/120, 2/12 (0.3² + 0.1²) = 1/60, 2/12 (0.3² + 0.2²) = 13/600
    assert!(close(ixx, 1.0 / 120.0, 1e-15) && close(iyy, 1.0 / 60.0, 1e-15));
    assert!(close(izz, 13.0 / 600.0, 1e-15));
    assert_eq!(get3(&mut fmu, ["I_xx", "I_yy", "I_zz"]), [ixx, iyy, izz]);
    assert_eq!(get3(&mut fmu, ["I_1", "I_2", "I_3"]), [ixx, iyy, izz]);
    assert_eq!(get3(&mut fmu, ["I_Bxx", "I_Byy", "I_Bzz"]), [ixx, iyy, izz]);
    assert_eq!(get3(&mut fmu, ["e1_x", "e1_y", "e1_z"]), [1.0, 0.0, 0.0]);
    assert_eq!(get3(&mut fmu, ["e2_x", "e2_y", "e2_z"]), [0.0, 1.0, 0.0]);
    assert_eq!(get3(&mut fmu, ["e3_x", "e3_y", "e3_z"]), [0.0, 0.0, 1.0]);
}

#[test]
fn box_about_its_corner() {
    // Pivot at the corner: r_C = (a, b, c)/2. By hand (∫ over [0,a]×[0,b]×[0,c]):
    // I_xx = M (b² + c²)/3, I_xy = -M a b/4, ...
    let (m, a, b, c) = BOX;
    let [ixx, iyy, izz] = box_inertia();
    let p = [
        ("I_xx", ixx),
        ("I_yy", iyy),
        ("I_zz", izz),
        ("r_Cx", a / 2.0),
        ("r_Cy", b / 2.0),
        ("r_Cz", c / 2.0),
    ];
    let mut fmu = initialized(&p, 1e-8);
    let want = [
        ("I_Bxx", m * (b * b + c * c) / 3.0),
        ("I_Byy", m * (a * a + c * c) / 3.0),
        ("I_Bzz", m * (a * a + b * b) / 3.0),
        ("I_Bxy", -m * a * b / 4.0),
        ("I_Bxz", -m * a * c / 4.0),
        ("I_Byz", -m * b * c / 4.0),
    ];
    for (name, value) in want {
        assert!(
            close(fmu.get(name), value, 1e-14),
            "{name} = {} != {value}",
            fmu.get(name)
        );
    }

    // A cube of side s about its corner: the tensor M s² [[2/3, -1/4, -1/4], ...] has the
    // principal moments M s² (1/6, 11/12, 11/12), the first about the body diagonal.
    let s = 0.2;
    let i = m * 2.0 * s * s / 12.0;
    let h = s / 2.0;
    let p = [
        ("I_xx", i),
        ("I_yy", i),
        ("I_zz", i),
        ("r_Cx", h),
        ("r_Cy", h),
        ("r_Cz", h),
    ];
    let mut fmu = initialized(&p, 1e-8);
    let moments = get3(&mut fmu, ["I_1", "I_2", "I_3"]);
    for (got, want) in moments.iter().zip([1.0 / 6.0, 11.0 / 12.0, 11.0 / 12.0]) {
        assert!(close(*got, m * s * s * want, 1e-13), "{moments:?}");
    }
    let e1 = get3(&mut fmu, ["e1_x", "e1_y", "e1_z"]);
    for x in e1 {
        assert!(close(x, 1.0 / 3f64.sqrt(), 1e-12), "{e1:?}");
    }
}

#[test]
fn rod_about_its_end() {
    // A solid cylinder of radius ρ and length L along x, pivoted at its end:
    // I_axis = M ρ²/2 (unchanged by a shift along the axis),
    // I_perp = M (3ρ² + L²)/12 + M (L/2)² = M ρ²/4 + M L²/3 (→ M L²/3 for a thin rod).
    let (m, l, rho) = (1.5, 0.8, 0.01);
    let i_axis = m * rho * rho / 2.0;
    let i_perp = m * (3.0 * rho * rho + l * l) / 12.0;
    let p = [
        ("M", m),
        ("I_xx", i_axis),
        ("I_yy", i_perp),
        ("I_zz", i_perp),
        ("r_Cx", l / 2.0),
    ];
    let mut fmu = initialized(&p, 1e-8);
    let moments = get3(&mut fmu, ["I_1", "I_2", "I_3"]);
    let perp = m * rho * rho / 4.0 + m * l * l / 3.0;
    assert!(close(moments[0], i_axis, 1e-14), "{moments:?}");
    assert!(
        close(moments[1], perp, 1e-14) && close(moments[2], perp, 1e-14),
        "{moments:?}"
    );
    assert!(close(fmu.get("I_Byy"), perp, 1e-14));
    assert_eq!(fmu.get("I_Bxy"), 0.0);
}

/// The tensor Σ d_k c_k c_kᵀ for the orthonormal c1 = (1,2,2)/3, c2 = (2,1,-2)/3,
/// c3 = (2,-2,1)/3 and d = (1, 2, 2.5)·0.01, worked out by hand:
/// (0.01/9) [[19, -4, -1], [-4, 16, -5], [-1, -5, 14.5]].
const PRODUCTS: [(&str, f64); 6] = [
    ("I_xx", 0.19 / 9.0),
    ("I_yy", 0.16 / 9.0),
    ("I_zz", 0.145 / 9.0),
    ("I_xy", -0.04 / 9.0),
    ("I_xz", -0.01 / 9.0),
    ("I_yz", -0.05 / 9.0),
];

#[test]
fn tensor_with_products_of_inertia() {
    let mut fmu = initialized(&PRODUCTS, 1e-8);
    let moments = get3(&mut fmu, ["I_1", "I_2", "I_3"]);
    for (got, want) in moments.iter().zip([0.01, 0.02, 0.025]) {
        assert!(close(*got, want, 1e-13), "{moments:?}");
    }
    // Signs: largest component positive; e3 = e1 × e2 = (-2, 2, -1)/3.
    let axes = [
        (["e1_x", "e1_y", "e1_z"], [1.0, 2.0, 2.0]),
        (["e2_x", "e2_y", "e2_z"], [2.0, 1.0, -2.0]),
        (["e3_x", "e3_y", "e3_z"], [-2.0, 2.0, -1.0]),
    ];
    for (names, want) in axes {
        let got = get3(&mut fmu, names);
        for k in 0..3 {
            assert!(
                (got[k] - want[k] / 3.0).abs() < 1e-12,
                "{names:?} = {got:?}"
            );
        }
    }
    // Moved to a pivot: the parallel axis term adds M [(r·r) 1 - r rᵀ] entry by entry.
    let mut p = PRODUCTS.to_vec();
    p.extend([("r_Cx", 0.1), ("r_Cy", -0.2), ("r_Cz", 0.05)]);
    let mut fmu = initialized(&p, 1e-8);
    let (m, r) = (2.0, [0.1, -0.2, 0.05]);
    let rr = r.iter().map(|x| x * x).sum::<f64>();
    let want = [
        ("I_Bxx", 0.19 / 9.0 + m * (rr - r[0] * r[0])),
        ("I_Byy", 0.16 / 9.0 + m * (rr - r[1] * r[1])),
        ("I_Bzz", 0.145 / 9.0 + m * (rr - r[2] * r[2])),
        ("I_Bxy", -0.04 / 9.0 - m * r[0] * r[1]),
        ("I_Bxz", -0.01 / 9.0 - m * r[0] * r[2]),
        ("I_Byz", -0.05 / 9.0 - m * r[1] * r[2]),
    ];
    for (name, value) in want {
        assert!(close(fmu.get(name), value, 1e-14), "{name}");
    }
}

/// `I_B⁻¹` times `I_B` (both as the FMU reports them) is the identity, for a tensor with
/// products of inertia moved to a pivot, a box about its centre and a thin rod on an arm.
#[test]
fn inverse_inertia_inverts_the_tensor() {
    let mut moved = PRODUCTS.to_vec();
    moved.extend([("r_Cx", 0.1), ("r_Cy", -0.2), ("r_Cz", 0.05)]);
    let rod = [
        ("I_xx", 1e-6),
        ("I_yy", 0.02),
        ("I_zz", 0.02),
        ("r_Cx", 0.0),
        ("r_Cy", 0.0),
        ("r_Cz", -0.5),
    ];
    let entry = |fmu: &mut Fmu, prefix: &str, i: usize, j: usize| {
        let axes = ["x", "y", "z"];
        let (a, b) = (axes[i.min(j)], axes[i.max(j)]);
        fmu.get(&format!("{prefix}{a}{b}"))
    };
    for (params, tol) in [(&moved[..], 1e-14), (&[][..], 1e-15), (&rod[..], 1e-14)] {
        let mut fmu = initialized(params, 1e-8);
        for i in 0..3 {
            for j in 0..3 {
                let product: f64 = (0..3)
                    .map(|k| entry(&mut fmu, "I_Binv_", i, k) * entry(&mut fmu, "I_B", k, j))
                    .sum();
                let want = if i == j { 1.0 } else { 0.0 };
                assert!(
                    (product - want).abs() <= tol,
                    "{params:?}: (I_B⁻¹ I_B)[{i}][{j}] = {product}"
                );
            }
        }
    }
}

// ---------------------------------------------------------------------------- rejections

/// Initialization with `params` fails with fmi2Error and a message containing every
/// string of `texts`.
fn rejected(params: &[(&str, f64)], texts: &[&str]) {
    let mut fmu = Fmu::new();
    assert_eq!(fmu.setup_experiment(None, 0.0, None), fmi2OK);
    assert_eq!(fmu.enter_initialization_mode(), fmi2OK);
    for &(n, v) in params {
        assert_eq!(fmu.set(n, v), fmi2OK);
    }
    assert_eq!(
        fmu.exit_initialization_mode(),
        fmi2Error,
        "{params:?} was accepted"
    );
    for t in texts {
        assert!(
            fmu.logged(t),
            "no message containing {t:?}: {:?}",
            fmu.messages()
        );
    }
    assert_eq!(fmu.do_step(0.0, 0.01), fmi2Error);
}

#[test]
fn a_tensor_violating_the_triangle_inequality_is_rejected() {
    rejected(
        &[("I_xx", 0.01), ("I_yy", 0.01), ("I_zz", 0.025)],
        &["triangle inequality", "I_zz = 0.025", "I_xx = 0.01"],
    );
    // Positive diagonal but products too large: principal moments -0.01, 0.01, 0.03.
    rejected(
        &[
            ("I_xx", 0.01),
            ("I_yy", 0.01),
            ("I_zz", 0.01),
            ("I_xy", -0.02),
        ],
        &["triangle inequality", "negative", "I_xy = -0.02"],
    );
    // The check is on I_C: here I_B = diag(0.51, 0.51, 0.03) would pass it (the point-mass
    // term masks the violation), but no body has I_C = diag(0.01, 0.01, 0.03).
    rejected(
        &[
            ("I_xx", 0.01),
            ("I_yy", 0.01),
            ("I_zz", 0.03),
            ("r_Cz", 0.5),
        ],
        &["triangle inequality", "about C"],
    );
    // Beyond the rounding tolerance (1e-6 of I_3): a thin plate with I_zz 1e-5 too large.
    let [_, iyy, izz] = box_inertia();
    let ixx = izz - iyy;
    rejected(
        &[("I_xx", ixx), ("I_yy", iyy), ("I_zz", izz * (1.0 + 1e-5))],
        &["triangle"],
    );
}

#[test]
fn a_thin_plate_on_the_boundary_is_accepted() {
    // A 0.3 × 0.2 plate in the xy plane: I_zz = I_xx + I_yy exactly (in real numbers).
    let (m, a, b) = (2.0, 0.3, 0.2);
    let (ixx, iyy, izz) = (
        m * b * b / 12.0,
        m * a * a / 12.0,
        m * (a * a + b * b) / 12.0,
    );
    initialized(&[("I_xx", ixx), ("I_yy", iyy), ("I_zz", izz)], 1e-8);
    // ... and with values rounded to 7 significant digits (sum short by ~1e-7 relative).
    initialized(
        &[
            ("I_xx", 0.006666667),
            ("I_yy", 0.015),
            ("I_zz", 0.02166667 * (1.0 + 5e-7)),
        ],
        1e-8,
    );
    // A rod (I_C singular) on an arm perpendicular to it is a regular body about B.
    let a = 0.02;
    let rod = [
        ("I_xx", a / 2.0),
        ("I_yy", a / 2.0),
        ("I_zz", a),
        ("I_xy", a / 2.0),
    ];
    let mut with_arm = rod.to_vec();
    with_arm.push(("r_Cz", 0.3));
    let mut fmu = initialized(&with_arm, 1e-8);
    assert!(fmu.get("I_1") > 0.01);
    // Without the arm the rod has no inertia about its own axis (1,-1,0)/√2: rejected.
    rejected(
        &rod,
        &["not positive definite", "about the pivot", "I_xy = 0.01"],
    );
}

#[test]
fn non_positive_mass_or_moment_is_rejected() {
    for (name, value) in [("M", 0.0), ("M", -2.0), ("I_xx", 0.0), ("I_zz", -1.0)] {
        rejected(&[(name, value)], &[&format!("{name} = {value}")]);
    }
}

// ---------------------------------------------------------------------------- dynamics

struct Extremes {
    h_drift: f64,
    e_drift: f64,
    q_norm: f64,
}

/// Runs 20 s in steps of 0.01 s, tracking the drift of H (ground axes, relative to |H0|),
/// of the total energy E (relative to E0) and of |q|.
fn conservation(
    params: &[(&str, f64)],
    tol: f64,
    visit: &mut dyn FnMut(f64, &mut Fmu),
) -> Extremes {
    let mut fmu = initialized(params, tol);
    let h0 = get3(&mut fmu, ["H_X", "H_Y", "H_Z"]);
    let e0 = fmu.get("E");
    let mut x = Extremes {
        h_drift: 0.0,
        e_drift: 0.0,
        q_norm: 0.0,
    };
    for n in 0..2000 {
        assert_eq!(fmu.do_step(n as f64 * 0.01, 0.01), fmi2OK);
        let h = get3(&mut fmu, ["H_X", "H_Y", "H_Z"]);
        let dh = [h[0] - h0[0], h[1] - h0[1], h[2] - h0[2]];
        x.h_drift = x.h_drift.max(norm(&dh) / norm(&h0));
        x.e_drift = x.e_drift.max((fmu.get("E") - e0).abs() / e0.abs());
        x.q_norm = x.q_norm.max((norm(&q_of(&mut fmu)) - 1.0).abs());
        visit((n + 1) as f64 * 0.01, &mut fmu);
    }
    x
}

#[test]
fn torque_free_body_conserves_momentum_and_energy() {
    let mut full = PRODUCTS.to_vec();
    full.extend([
        ("w_x", 1.0),
        ("w_y", -2.0),
        ("w_z", 3.0),
        ("q_w", 0.5),
        ("q_x", 0.5),
    ]);
    full.extend([("q_y", 0.5), ("q_z", 0.5), ("r_Cy", 0.1), ("g", 0.0)]);
    for params in [&[][..], &full[..]] {
        let x = conservation(params, 1e-8, &mut |_, _| {});
        eprintln!(
            "torque-free: H {:.2e}, E {:.2e}, |q| - 1 {:.2e}",
            x.h_drift, x.e_drift, x.q_norm
        );
        assert!(x.h_drift < 1e-8, "{params:?}: H drift {:e}", x.h_drift);
        assert!(x.e_drift < 1e-8, "{params:?}: E drift {:e}", x.e_drift);
        assert!(x.q_norm < 1e-10, "{params:?}: |q| - 1 = {:e}", x.q_norm);
    }
}

#[test]
fn intermediate_axis_flips_and_the_others_are_stable() {
    // Default start: spin 5 rad/s about y (intermediate), perturbed by 0.01: it flips.
    let mut lowest = f64::MAX;
    conservation(&[], 1e-8, &mut |_, f| lowest = lowest.min(f.get("w_y")));
    assert!(lowest < -4.9, "w_y never reversed (min {lowest})");

    // About x (smallest) and z (largest): the constants of motion bound the transverse
    // spin. About x, D = |H|² - 2 E I_1 = I_2 (I_2 - I_1) w_y² + I_3 (I_3 - I_1) w_z² is
    // constant, so w_y² + w_z² <= D / min(I_2 (I_2 - I_1), I_3 (I_3 - I_1)); likewise
    // about z with 2 E I_3 - |H|².
    let [i1, i2, i3] = box_inertia();
    for (axis, w0) in [(0, [5.0, 0.01, 0.01]), (2, [0.01, 0.01, 5.0])] {
        let [a, b] = if axis == 0 { [1, 2] } else { [0, 1] };
        let i = [i1, i2, i3];
        let c = |k: usize| i[k] * (i[k] - i[axis]).abs();
        let d = c(a) * w0[a] * w0[a] + c(b) * w0[b] * w0[b];
        let bound = (d / c(a).min(c(b))).sqrt();
        let mut widest = 0.0f64;
        let p = [("w_x", w0[0]), ("w_y", w0[1]), ("w_z", w0[2])];
        conservation(&p, 1e-8, &mut |_, f| {
            let w = get3(f, ["w_x", "w_y", "w_z"]);
            widest = widest.max((w[a] * w[a] + w[b] * w[b]).sqrt() / w[axis].abs());
        });
        assert!(
            widest <= bound / 5.0 * 1.001,
            "axis {axis}: cone {widest} > bound {}",
            bound / 5.0
        );
        assert!(widest < 0.005, "axis {axis}: cone half-angle {widest} rad");
    }
}

#[test]
fn axisymmetric_body_precesses_at_the_closed_form_rate() {
    // I_B = diag(I_1, I_1, I_3): d/dt (w_x + i w_y) = i Ω (w_x + i w_y), Ω = (I_3 - I_1)/I_1 w_z.
    // Oblate about its centre, and prolate about a pivot on the axis (no gravity), where
    // I_1 = 0.02 + M d² comes from the parallel axis theorem.
    for (r_cz, i1) in [(0.0, 0.02), (0.2, 0.02 + 2.0 * 0.04)] {
        let (i3, w0) = (0.03, [0.3, 0.1, 4.0]);
        let omega = (i3 - i1) / i1 * w0[2];
        let p = [
            ("I_xx", 0.02),
            ("I_yy", 0.02),
            ("I_zz", 0.03),
            ("r_Cz", r_cz),
            ("g", 0.0),
            ("w_x", w0[0]),
            ("w_y", w0[1]),
            ("w_z", w0[2]),
        ];
        let mut worst = 0.0f64;
        conservation(&p, 1e-10, &mut |t, f| {
            let (c, s) = ((omega * t).cos(), (omega * t).sin());
            let want = [w0[0] * c - w0[1] * s, w0[0] * s + w0[1] * c, w0[2]];
            let got = get3(f, ["w_x", "w_y", "w_z"]);
            let err = norm(&[got[0] - want[0], got[1] - want[1], got[2] - want[2]]);
            worst = worst.max(err / norm(&w0[..2]));
        });
        // A rate error δΩ shows as a phase error δΩ t = δΩ/Ω · |Ω| t.
        let rate_error = worst / (omega.abs() * 20.0);
        assert!(
            rate_error < 1e-9,
            "r_Cz = {r_cz}: relative rate error {rate_error:e}"
        );
    }
}

/// A symmetric top: I_C = diag(0.002, 0.002, 0.003), M = 1, C at d = 0.05 on the axis.
fn top(theta: f64, w: [f64; 3]) -> Vec<(&'static str, f64)> {
    vec![
        ("M", 1.0),
        ("I_xx", 0.002),
        ("I_yy", 0.002),
        ("I_zz", 0.003),
        ("r_Cz", 0.05),
        ("w_x", w[0]),
        ("w_y", w[1]),
        ("w_z", w[2]),
        ("q_w", (theta / 2.0).cos()),
        ("q_x", (theta / 2.0).sin()),
    ]
}

/// Max drift over 20 s of E (relative to E0) and H_Z (relative to |H0|), and the largest
/// change of cos θ (nutation), for a top released at θ = 0.5 spinning at 40 rad/s, with
/// communication steps of `h`.
fn heavy_top_drift(tol: f64, h: f64) -> (f64, f64, f64) {
    let mut fmu = initialized(&top(0.5, [0.0, 0.0, 40.0]), tol);
    let (e0, hz0) = (fmu.get("E"), fmu.get("H_Z"));
    assert!(close(
        fmu.get("E_pot"),
        1.0 * 9.81 * 0.05 * 0.5f64.cos(),
        1e-14
    ));
    let h0 = norm(&get3(&mut fmu, ["H_X", "H_Y", "H_Z"]));
    let (mut de, mut dh, mut nutation) = (0.0f64, 0.0f64, 0.0f64);
    for n in 0..(20.0 / h).round() as usize {
        assert_eq!(fmu.do_step(n as f64 * h, h), fmi2OK);
        de = de.max((fmu.get("E") - e0).abs() / e0);
        dh = dh.max((fmu.get("H_Z") - hz0).abs() / h0);
        nutation = nutation.max((fmu.get("r_CZ") / 0.05 - 0.5f64.cos()).abs());
    }
    (de, dh, nutation)
}

#[test]
fn heavy_top_conserves_vertical_momentum_and_energy() {
    // A model error would not shrink with the tolerance; the solver's error does. At
    // 0.01 s communication steps the solver's steps are the communication steps at both
    // tolerances (one 8th-order step each, hω = 0.4), so the tolerance shows on 0.1 s ones.
    let (de8, dh8, nutation) = heavy_top_drift(1e-8, 0.01);
    let (de10, dh10, _) = heavy_top_drift(1e-10, 0.01);
    eprintln!("heavy top drift, h 0.01: rtol 1e-8: E {de8:.2e}, H_Z {dh8:.2e}; rtol 1e-10: E {de10:.2e}, H_Z {dh10:.2e}");
    assert!(
        de8 < 1e-8 && dh8 < 1e-8 && de10 < 1e-8 && dh10 < 1e-8,
        "E drift {de8:e}, {de10:e}, H_Z drift {dh8:e}, {dh10:e}"
    );
    let (de8, dh8, _) = heavy_top_drift(1e-8, 0.1);
    let (de10, dh10, _) = heavy_top_drift(1e-10, 0.1);
    eprintln!("heavy top drift, h 0.1: rtol 1e-8: E {de8:.2e}, H_Z {dh8:.2e}; rtol 1e-10: E {de10:.2e}, H_Z {dh10:.2e}");
    assert!(
        de10 < de8 / 10.0 && dh10 < dh8 / 10.0,
        "the drift does not shrink with the tolerance"
    );
    assert!(
        nutation > 1e-3,
        "started without precession, the top must nutate"
    );
}

#[test]
fn heavy_top_precesses_steadily_at_the_closed_form_rate() {
    // Lagrange with z-x-z Euler angles (φ, θ, ψ), L = ½ I_1 (θ̇² + φ̇² sin²θ)
    // + ½ I_3 (ψ̇ + φ̇ cos θ)² - M g d cos θ. The θ equation with θ̇ = 0, φ̇ = Ω:
    // M g d = Ω (I_3 ω_3 - I_1 Ω cos θ), ω_3 = ψ̇ + Ω cos θ; I_1, I_3 about the pivot.
    let (m, g, d, theta, w3) = (1.0, 9.81, 0.05, 0.5f64, 40.0);
    let (i1, i3) = (0.002 + m * d * d, 0.003);
    let (a, b, c) = (i1 * theta.cos(), -i3 * w3, m * g * d);
    let root = (b * b - 4.0 * a * c).sqrt();
    for omega in [2.0 * c / (-b + root), (-b + root) / (2.0 * a)] {
        // q0 = rotation θ about x, so the axis e3 starts at (0, -sin θ, cos θ); the body
        // rate is Ω Z + ψ̇ e3 = (0, Ω sin θ, ω_3) in body axes.
        let mut fmu = initialized(&top(theta, [0.0, omega * theta.sin(), w3]), 1e-10);
        let mut worst = 0.0f64;
        for n in 0..2000 {
            assert_eq!(fmu.do_step(n as f64 * 0.01, 0.01), fmi2OK);
            let t = (n + 1) as f64 * 0.01;
            let axis = to_ground(q_of(&mut fmu), [0.0, 0.0, 1.0]);
            let want = [
                theta.sin() * (omega * t).sin(),
                -theta.sin() * (omega * t).cos(),
                theta.cos(),
            ];
            worst = worst.max(norm(&[
                axis[0] - want[0],
                axis[1] - want[1],
                axis[2] - want[2],
            ]));
            let r_c = get3(&mut fmu, ["r_CX", "r_CY", "r_CZ"]);
            assert!((r_c[2] - d * axis[2]).abs() < 1e-15);
        }
        // The axis moves on a circle of radius sin θ: the error relative to the arc swept.
        let relative = worst / (theta.sin() * omega * 20.0);
        assert!(
            relative < 1e-8,
            "Ω = {omega}: axis off the closed form by {worst:e} ({relative:e})"
        );
    }
}

#[test]
fn hanging_body_swings_as_a_compound_pendulum() {
    // C a distance l below B: small swings about x at ω² = M g l / I_Bxx. The sign of the
    // gravity torque decides this (the inverted body would diverge instead).
    let (m, l, ixx): (f64, f64, f64) = (2.0, 0.25, 1.0 / 120.0);
    let i_bxx = ixx + m * l * l;
    let period = 2.0 * std::f64::consts::PI * (i_bxx / (m * 9.81 * l)).sqrt();
    let a0: f64 = 1e-4; // rad
    let p = [
        ("r_Cz", -l),
        ("w_y", 0.0),
        ("w_z", 0.0),
        ("w_x", 0.0),
        ("q_w", (a0 / 2.0).cos()),
        ("q_x", (a0 / 2.0).sin()),
    ];
    let mut fmu = initialized(&p, 1e-10);
    fmu.step_to(period, period / 200.0).unwrap();
    let angle = 2.0 * fmu.get("q_x").atan2(fmu.get("q_w"));
    assert!(
        (angle - a0).abs() < 1e-4 * a0,
        "after one period the angle is {angle:e}, not {a0:e}"
    );
    fmu.step_to(1.5 * period, period / 200.0).unwrap();
    let angle = 2.0 * fmu.get("q_x").atan2(fmu.get("q_w"));
    assert!(
        (angle + a0).abs() < 1e-4 * a0,
        "after 1.5 periods the angle is {angle:e}, not -{a0:e}"
    );
}

#[test]
fn applied_torque_spins_the_body_up() {
    // From rest, tau along the principal axis z: w_z = tau t / I_zz, E_kin = ½ (tau t)²/I_zz.
    let mut fmu = initialized(
        &[("w_x", 0.0), ("w_y", 0.0), ("w_z", 0.0), ("g", 0.0)],
        1e-10,
    );
    assert_eq!(fmu.set("tau_z", 0.3), fmi2OK);
    fmu.step_to(2.0, 0.01).unwrap();
    let izz = box_inertia()[2];
    assert!(close(fmu.get("w_z"), 0.3 * 2.0 / izz, 1e-12));
    assert!(close(fmu.get("w_z_dot"), 0.3 / izz, 1e-14));
    assert!(close(fmu.get("E_kin"), 0.5 * 0.6 * 0.6 / izz, 1e-12));
    // Rotated by θ = ½ (tau/I_zz) t² about z.
    let theta = 0.5 * 0.3 / izz * 4.0;
    let q = q_of(&mut fmu);
    let want = [(theta / 2.0).cos(), 0.0, 0.0, (theta / 2.0).sin()];
    // The solver's global error at rtol 1e-10 is ~1e-10 of the angle turned (27.7 rad).
    for k in 0..4 {
        assert!(
            (q[k] - want[k]).abs() < 1e-9 * theta,
            "q = {q:?}, want {want:?}"
        );
    }
}

#[test]
fn quaternion_stabilization_changes_only_its_length() {
    // k_q = 0 against the default: the same rotation (to the solver's accuracy), and |q| = 1
    // to rounding at every communication point either way (the projection q ← q/|q|).
    let p = |k: f64| vec![("k_q", k), ("w_x", 0.5), ("w_y", 0.2), ("w_z", 20.0)];
    let (mut off, mut on) = (initialized(&p(0.0), 1e-8), initialized(&p(1.0), 1e-8));
    for n in 1..=200 {
        let t = n as f64 * 0.1;
        off.step_to(t, 0.1).unwrap();
        on.step_to(t, 0.1).unwrap();
        for fmu in [&mut off, &mut on] {
            let n = norm(&q_of(fmu));
            assert!(
                (n - 1.0).abs() < 4.0 * f64::EPSILON,
                "|q| - 1 = {:e} at t = {t}",
                n - 1.0
            );
        }
    }
    let (q0, q1) = (q_of(&mut off), q_of(&mut on));
    let dq = [0, 1, 2, 3].map(|k| q0[k] - q1[k]);
    assert!(norm(&dq) < 1e-6, "the rotations differ by {:e}", norm(&dq));
}

/// Reset, FMU state, serialization, derivatives and threads: the checks every FMU passes.
#[test]
fn conforms() {
    mechfmu_testkit::conformance::check::<rigid_body::RigidBody>();
}

/// The largest `||q| - 1|` at the ends of 1 s chunks of a Model Exchange run of `seconds`
/// (RK4, step `h`) at `tolerance`, with the quaternion's pull `k_q`; and the step events.
fn quaternion_drift_in_model_exchange(
    tolerance: f64,
    k_q: f64,
    h: f64,
    seconds: u32,
) -> (f64, usize) {
    let mut me = mechfmu_testkit::model_exchange::ModelExchange::<rigid_body::RigidBody>::new();
    me.initialize(Some(tolerance), 0.0, &[("k_q", k_q)])
        .unwrap();
    let (mut drift, mut events) = (0.0f64, 0);
    for second in 1..=seconds {
        events += me.integrate(second as f64, h).unwrap().step_events;
        let x = me.states().unwrap();
        // States: w_x, w_y, w_z, q_w, q_x, q_y, q_z.
        let norm = x[3..7].iter().map(|q| q * q).sum::<f64>().sqrt();
        drift = drift.max((norm - 1.0).abs());
    }
    (drift, events)
}

#[test]
fn model_exchange_keeps_the_quaternion_a_unit_one_without_events() {
    // Tumbling near the intermediate axis for 200 s under an importer's coarse RK4 (0.05 s,
    // h |ω| = 0.25), whatever tolerance the FMU is given: the stabilized derivative
    // -k_q (|q|² - 1) q pulls |q| back, so the drift stays at the balance of RK4's error and
    // the pull instead of growing, and no step event interrupts the importer's solver (the
    // equations use q/|q|: the drift costs no accuracy).
    let mut stabilized = 0.0f64;
    for tolerance in [1e-4, 1e-8, 1e-12] {
        let (drift, events) = quaternion_drift_in_model_exchange(tolerance, 1.0, 0.05, 200);
        assert_eq!(events, 0, "tolerance {tolerance:e}: {events} step events");
        assert!(
            drift < 1e-5,
            "tolerance {tolerance:e}: ||q| - 1| reached {drift:e}"
        );
        stabilized = stabilized.max(drift);
    }
    let (free, _) = quaternion_drift_in_model_exchange(1e-8, 0.0, 0.05, 200);
    assert!(
        free > 10.0 * stabilized,
        "without the pull {free:e}, with it {stabilized:e}"
    );
    eprintln!("||q| - 1| over 200 s: {stabilized:e} with the pull, {free:e} without");
}

#[test]
fn a_step_event_renormalizes_a_quaternion_that_drifts_beyond_the_guard() {
    // Without the pull and with a coarse RK4 (0.2 s), |q| drifts by more than
    // PROJECTION_DRIFT: a step event projects it back each time, so it never goes far
    // beyond.
    let (drift, events) = quaternion_drift_in_model_exchange(1e-8, 0.0, 0.2, 200);
    eprintln!(
        "||q| - 1| over 200 s without the pull, RK4 at 0.2 s: {drift:e}, {events} step events"
    );
    assert!(events > 0, "no step event in 200 s (drift {drift:e})");
    assert!(
        drift < 2.0 * mechfmu::simulation::PROJECTION_DRIFT,
        "||q| - 1| reached {drift:e}"
    );
}
