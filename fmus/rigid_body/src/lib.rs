//! `RigidBody`: a rigid body turning about a fixed pivot `B` (a ball joint), with gravity
//! (MIT 2.003 Quiz #2 review: the inertia tensor, the parallel axis theorem, principal axes,
//! Euler's equations about a point).
//!
//! ```text
//! I_B = I_C + M [ (r_C·r_C) 1 - r_C ⊗ r_C ]                 parallel axis theorem
//! I_B ω̇ + ω × (I_B ω) = tau + r_C × (Rᵀ (-M g Z))          Euler's equations about B
//! q̇ = ½ q ⊗ (0, ω) - k_q (|q|² - 1) q                      orientation, body → ground
//! ```
//!
//! Everything is in body axes except the outputs marked "ground axes". `R` is the rotation
//! body → ground of the unit quaternion `q` (`v_ground = R v_body = q v_body q*`).
//!
//! How the equations were checked, without reusing them:
//! * Euler's equations: the notes' `Σ τ_B = d/dt(H_B) + M v_B × v_C` with `v_B = 0`, and
//!   `H_B = I_B ω` differentiated in the body frame (`d/dt = ∂/∂t + ω ×`). The gravity term
//!   is the moment about `B` of the weight `-M g Z` applied at `C`, written in body axes
//!   (`Rᵀ Z` is the third row of `R`). Independent route: with `tau = 0` the energy
//!   `½ ωᵀ I_B ω + M g Z·(R r_C)` is conserved, because `ω·(r_C × F) = F·(ω × r_C)` makes the
//!   power of the weight exactly `-d/dt (M g Z·R r_C)`; and a symmetric heavy top precesses
//!   steadily at the rate Lagrange's equation in Euler angles gives,
//!   `M g d = Ω (I_3 ω_3 - I_1 Ω cos θ)`. Both are tested (`tests/rigid_body.rs` and
//!   `tests/python/test_rigid_body.py`); the sign of the gravity torque decides the sense of
//!   precession, so a sign error cannot pass the second.
//! * The notes print the parallel axis theorem correctly (`+M[(r·r)1 - r⊗r]`, same for
//!   `r_C` or `-r_C`); checked against a box about its corner (`I_xx = M(b²+c²)/3`,
//!   `I_xy = -M a b/4`) and a rod about its end (`M L²/3`).
//! * `q̇ = ½ q ⊗ (0, ω)` with `ω` in body axes: a body-fixed vector `v` has ground
//!   coordinates `q v q*`, whose rate is `q (ω × v) q*` exactly when `q̇ = ½ q (0, ω)`.
//!
//! Keeping `|q| = 1`. The exact flow of `q̇ = ½ q ⊗ (0, ω)` keeps `|q|` (the product with a
//! pure quaternion is orthogonal to `q`), but an explicit Runge–Kutta step does not: its
//! stages leave the sphere by O((h|ω|)²) and Dopri5 loses ~(h|ω|)⁶ of `|q|` per step. The
//! term `-k_q (|q|² - 1) q` makes the sphere attracting, `d/dt(|q|² - 1) = -2 k_q |q|²
//! (|q|² - 1)` plus the integration error. It vanishes on the sphere, so the exact solution
//! is unchanged, and it is parallel to `q`, so it changes only `|q|`, never the direction
//! `q/|q|`, i.e. never the rotation: it cannot bias the attitude. The rotation `R` in the
//! equations and the outputs is that of `q/|q|`, so the residual in `|q|` does not leak
//! into the dynamics either. `k_q = 1/s` is deliberate: the term's own truncation error
//! grows with `k_q` (the stages off the sphere feel it), so a stiffer pull is worse, not
//! better. Measured at rtol 1e-8 over 20 s, `max ||q| - 1|`: 2.5e-12 to 7e-12 for spins of
//! ~5 rad/s at 0.01 s communication steps, 1.4e-9 for 20 rad/s, ~1e-8 with 0.1 s steps
//! (the solver's own step size); 10 to 55 times less than without the term. What is left
//! is removed at every communication point by [`Mechanism::project`] (`q ← q/|q|`, the
//! same rotation), so `|q| = 1` to rounding at every output.
//!
//! In Model Exchange the importer's solver integrates and there are no communication
//! points. The pull works as in Co-Simulation, whatever the solver: at the balance of the
//! solver's error and the pull, `|q|` stays put instead of drifting (measured over 200 s of
//! RK4 at 0.05 s: `||q| - 1|` 3.7e-6 with the pull, 1.3e-4 and growing without). The
//! projection is a step event only as a guard against gross drift:
//! `fmi2CompletedIntegratorStep` asks for one when `q/|q|` would move a component by more
//! than 1e-3 ([`mechfmu::simulation::PROJECTION_DRIFT`]), and `fmi2NewDiscreteStates`
//! projects there. A threshold tied to the tolerance would be crossed every few steps of
//! CVode, each event restarting it at order 1: more events and a worse answer the tighter
//! the tolerance. The rotation the outputs show is `q/|q|`'s in every case.

#![forbid(unsafe_code)]

use mechfmu::model::{lit, Array, Experiment, Mechanism, Scalar, Variable};
use mechfmu::nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};

/// Relative tolerance of the triangle inequality `I_1 + I_2 ≥ I_3` of the body's own
/// tensor: a thin plate sits exactly on the boundary, so values computed or typed with
/// seven significant digits must not be refused for their rounding.
const TRIANGLE_TOLERANCE: f64 = 1e-6;

/// `I_B` counts as singular when its smallest principal moment is below this fraction of
/// the largest (rounding of the eigen-decomposition is ~1e-16 of the largest).
const SINGULAR_RATIO: f64 = 1e-12;

mechfmu::mechanism! {
    /// A rigid body of mass M turning freely about a fixed pivot B (a ball joint), under
    /// gravity -g Z and an applied torque. Inertia tensor about the centre of mass C in body
    /// axes (entry xy is -integral of x y dm), C at r_C from B; the inertia about B follows
    /// from the parallel axis theorem. Euler's equations about B in body axes; orientation
    /// as the unit quaternion body to ground. r_C = 0 makes a free body turning about C.
    pub struct RigidBody / RigidBodyValues {
        /// Mass of the body
        M: Variable::parameter("kg", 2.0).positive(),
        /// Moment of inertia about C, body x axis (default: a 0.3 x 0.2 x 0.1 m box of 2 kg)
        I_xx: Variable::parameter("kg.m2", 2.0 * (0.2 * 0.2 + 0.1 * 0.1) / 12.0).positive(),
        /// Moment of inertia about C, body y axis
        I_yy: Variable::parameter("kg.m2", 2.0 * (0.3 * 0.3 + 0.1 * 0.1) / 12.0).positive(),
        /// Moment of inertia about C, body z axis
        I_zz: Variable::parameter("kg.m2", 2.0 * (0.3 * 0.3 + 0.2 * 0.2) / 12.0).positive(),
        /// Product of inertia about C, entry xy of the matrix (-integral of x y dm)
        I_xy: Variable::parameter("kg.m2", 0.0),
        /// Product of inertia about C, entry xz of the matrix (-integral of x z dm)
        I_xz: Variable::parameter("kg.m2", 0.0),
        /// Product of inertia about C, entry yz of the matrix (-integral of y z dm)
        I_yz: Variable::parameter("kg.m2", 0.0),
        /// Position of the centre of mass C from the pivot B, body x
        r_Cx: Variable::parameter("m", 0.0),
        /// Position of the centre of mass C from the pivot B, body y
        r_Cy: Variable::parameter("m", 0.0),
        /// Position of the centre of mass C from the pivot B, body z
        r_Cz: Variable::parameter("m", 0.0),
        /// Gravitational acceleration (gravity is -g along the ground's vertical Z)
        g: Variable::parameter("m/s2", 9.81),
        /// Rate at which the quaternion is pulled back to unit length, k_q in
        /// -k_q (|q|^2 - 1) q; changes |q| only, never the rotation (0 turns it off)
        k_q: Variable::parameter("1/s", 1.0).min(0.0),
        /// Applied torque about B, body x
        tau_x: Variable::input("N.m", 0.0),
        /// Applied torque about B, body y
        tau_y: Variable::input("N.m", 0.0),
        /// Applied torque about B, body z
        tau_z: Variable::input("N.m", 0.0),
        /// Angular velocity, body x (default near the intermediate axis y)
        w_x: Variable::state("rad/s", 0.01, "w_x_dot"),
        /// Angular velocity, body y
        w_y: Variable::state("rad/s", 5.0, "w_y_dot"),
        /// Angular velocity, body z
        w_z: Variable::state("rad/s", 0.01, "w_z_dot"),
        /// Orientation quaternion body to ground, scalar part
        q_w: Variable::state("1", 1.0, "q_w_dot"),
        /// Orientation quaternion body to ground, x part
        q_x: Variable::state("1", 0.0, "q_x_dot"),
        /// Orientation quaternion body to ground, y part
        q_y: Variable::state("1", 0.0, "q_y_dot"),
        /// Orientation quaternion body to ground, z part
        q_z: Variable::state("1", 0.0, "q_z_dot"),
        /// Angular momentum about B, ground X
        H_X: Variable::output("kg.m2/s"),
        /// Angular momentum about B, ground Y
        H_Y: Variable::output("kg.m2/s"),
        /// Angular momentum about B, ground Z
        H_Z: Variable::output("kg.m2/s"),
        /// Kinetic energy 1/2 w . I_B w
        E_kin: Variable::output("J"),
        /// Potential energy M g Z_C (zero at the pivot's height)
        E_pot: Variable::output("J"),
        /// Mechanical energy E_kin + E_pot
        E: Variable::output("J"),
        /// Angular acceleration, body x
        w_x_dot: Variable::output("rad/s2"),
        /// Angular acceleration, body y
        w_y_dot: Variable::output("rad/s2"),
        /// Angular acceleration, body z
        w_z_dot: Variable::output("rad/s2"),
        /// Position of C from B, ground X
        r_CX: Variable::output("m"),
        /// Position of C from B, ground Y
        r_CY: Variable::output("m"),
        /// Position of C from B, ground Z
        r_CZ: Variable::output("m"),
        /// Rate of the quaternion, scalar part
        q_w_dot: Variable::local("1/s"),
        /// Rate of the quaternion, x part
        q_x_dot: Variable::local("1/s"),
        /// Rate of the quaternion, y part
        q_y_dot: Variable::local("1/s"),
        /// Rate of the quaternion, z part
        q_z_dot: Variable::local("1/s"),
        /// Smallest principal moment of inertia about B
        I_1: Variable::calculated("kg.m2").fixed(),
        /// Intermediate principal moment of inertia about B
        I_2: Variable::calculated("kg.m2").fixed(),
        /// Largest principal moment of inertia about B
        I_3: Variable::calculated("kg.m2").fixed(),
        /// Inertia tensor about B (parallel axis theorem), entry xx, body axes
        I_Bxx: Variable::calculated("kg.m2").fixed(),
        /// Inertia tensor about B, entry yy
        I_Byy: Variable::calculated("kg.m2").fixed(),
        /// Inertia tensor about B, entry zz
        I_Bzz: Variable::calculated("kg.m2").fixed(),
        /// Inertia tensor about B, entry xy (-integral of x y dm about B)
        I_Bxy: Variable::calculated("kg.m2").fixed(),
        /// Inertia tensor about B, entry xz
        I_Bxz: Variable::calculated("kg.m2").fixed(),
        /// Inertia tensor about B, entry yz
        I_Byz: Variable::calculated("kg.m2").fixed(),
        /// Principal axis of I_1 about B, body x (sign: largest component positive)
        e1_x: Variable::calculated("1").fixed(),
        /// Principal axis of I_1 about B, body y
        e1_y: Variable::calculated("1").fixed(),
        /// Principal axis of I_1 about B, body z
        e1_z: Variable::calculated("1").fixed(),
        /// Principal axis of I_2 about B, body x (sign: largest component positive)
        e2_x: Variable::calculated("1").fixed(),
        /// Principal axis of I_2 about B, body y
        e2_y: Variable::calculated("1").fixed(),
        /// Principal axis of I_2 about B, body z
        e2_z: Variable::calculated("1").fixed(),
        /// Principal axis of I_3 about B, body x (e3 = e1 x e2: a right-handed frame)
        e3_x: Variable::calculated("1").fixed(),
        /// Principal axis of I_3 about B, body y
        e3_y: Variable::calculated("1").fixed(),
        /// Principal axis of I_3 about B, body z
        e3_z: Variable::calculated("1").fixed(),
        /// Inverse of the inertia tensor about B, entry xx, body axes (what Euler's
        /// equations multiply the moment by)
        I_Binv_xx: Variable::calculated("kg-1.m-2").fixed(),
        /// Inverse of the inertia tensor about B, entry yy
        I_Binv_yy: Variable::calculated("kg-1.m-2").fixed(),
        /// Inverse of the inertia tensor about B, entry zz
        I_Binv_zz: Variable::calculated("kg-1.m-2").fixed(),
        /// Inverse of the inertia tensor about B, entry xy
        I_Binv_xy: Variable::calculated("kg-1.m-2").fixed(),
        /// Inverse of the inertia tensor about B, entry xz
        I_Binv_xz: Variable::calculated("kg-1.m-2").fixed(),
        /// Inverse of the inertia tensor about B, entry yz
        I_Binv_yz: Variable::calculated("kg-1.m-2").fixed(),
    }
}

/// Principal moments in ascending order and the principal axes as the columns of a
/// rotation matrix: each of the first two axes has its largest component positive (on a
/// tie, the first of them), the third is their cross product. When two moments are equal
/// every axis of their plane is principal; these are the ones the decomposition returns.
fn principal_axes(tensor: &Matrix3<f64>) -> (Vector3<f64>, Matrix3<f64>) {
    let eigen = tensor.symmetric_eigen();
    let mut order = [0, 1, 2];
    order.sort_by(|&a, &b| eigen.eigenvalues[a].total_cmp(&eigen.eigenvalues[b]));
    let moments = Vector3::from_fn(|k, _| eigen.eigenvalues[order[k]]);
    let mut axes = Matrix3::from_fn(|row, col| eigen.eigenvectors[(row, order[col])]);
    for col in 0..2 {
        let mut axis = axes.column(col).into_owned();
        let mut largest = 0;
        for k in 1..3 {
            if axis[k].abs() > axis[largest].abs() * (1.0 + 1e-9) {
                largest = k;
            }
        }
        if axis[largest] < 0.0 {
            axis = -axis;
        }
        axes.set_column(col, &axis);
    }
    let third = axes.column(0).cross(&axes.column(1));
    axes.set_column(2, &third);
    (moments, axes)
}

/// The parameters as a readable list, for error messages.
fn tensor_text(v: &RigidBodyValues<f64>) -> String {
    format!(
        "I_xx = {}, I_yy = {}, I_zz = {}, I_xy = {}, I_xz = {}, I_yz = {}",
        v.I_xx, v.I_yy, v.I_zz, v.I_xy, v.I_xz, v.I_yz
    )
}

impl Mechanism for RigidBody {
    const EXPERIMENT: Experiment = Experiment::until(20.0).step(0.01).tolerance(1e-6);

    const NOTES: &'static str = "
        A body of mass `M` turning about a fixed pivot `B` (a ball joint). Its inertia tensor
        about its centre of mass `C` is given in body axes (entry `xy` is `-∫ x y dm`), `C` at
        `r_C` from `B`; gravity `-g Z`; `R` the rotation body → ground of the unit quaternion
        `q`. In body axes:

            I_B = I_C + M [ (r_C·r_C) 1 - r_C ⊗ r_C ]               parallel axis theorem
            I_B ω̇ + ω × (I_B ω) = tau + r_C × (Rᵀ (-M g Z))        Euler's equations about B
            q̇ = ½ q ⊗ (0, ω) - k_q (|q|² - 1) q                    orientation

        Outputs: `H = R I_B ω` (about `B`, ground axes), `E_kin = ½ ω·I_B ω`,
        `E_pot = M g Z·(R r_C)`; `I_1 ≤ I_2 ≤ I_3` and the principal axes of `I_B`, and
        `I_B⁻¹` (computed once per parameter set, not at every stage).
        Checked without reusing the equations: energy conservation (the weight's power is
        exactly `-d/dt E_pot`), the steady precession of a heavy top from Lagrange's equation
        in Euler angles (`M g d = Ω (I_3 ω_3 - I_1 Ω cos θ)`, whose sense a sign error in the
        gravity torque would flip), and the closed-form precession of a torque-free
        axisymmetric body.

        ## Departures from the notes
        - The notes' parallel axis theorem and Euler's equations about a point are used as
          printed (checked against a box about its corner and a rod about its end).
        - Orientation: the notes use rotation matrices; the FMU integrates a quaternion. The
          term `-k_q (|q|² - 1) q` (`k_q = 1/s`) pulls `q` back to the unit sphere without
          changing the rotation it stands for (it is parallel to `q` and vanishes on the
          sphere), and `q` is renormalized at every communication point, so `|q| = 1` to
          rounding at every output. In Model Exchange the importer's solver keeps `|q|`
          within about its tolerance of 1 (the pull and the rotation of `q/|q|` make that
          residual harmless); a step event renormalizes `q` only if it drifts by more than
          1e-3 (see Events).
        - A tensor that is not a physical body (not positive definite, or violating
          `I_1 + I_2 ≥ I_3`) is refused at initialization with a message.
    ";

    /// The vectors and tensors of the notes as FMI 3.0 arrays (FMI 2.0 has their scalars).
    const ARRAYS: &'static [Array] = &[
        Array::new(
            "I_C",
            "Inertia tensor about C, body axes (symmetric, row-major)",
            &[3, 3],
            &[
                "I_xx", "I_xy", "I_xz", "I_xy", "I_yy", "I_yz", "I_xz", "I_yz", "I_zz",
            ],
        ),
        Array::new(
            "r_C",
            "Position of the centre of mass C from the pivot B, body axes",
            &[3],
            &["r_Cx", "r_Cy", "r_Cz"],
        ),
        Array::new(
            "tau",
            "Applied torque about B, body axes",
            &[3],
            &["tau_x", "tau_y", "tau_z"],
        ),
        Array::new(
            "w",
            "Angular velocity, body axes",
            &[3],
            &["w_x", "w_y", "w_z"],
        ),
        Array::new(
            "q",
            "Orientation quaternion body to ground (w, x, y, z)",
            &[4],
            &["q_w", "q_x", "q_y", "q_z"],
        ),
        Array::new(
            "H",
            "Angular momentum about B, ground axes",
            &[3],
            &["H_X", "H_Y", "H_Z"],
        ),
        Array::new(
            "w_dot",
            "Angular acceleration, body axes",
            &[3],
            &["w_x_dot", "w_y_dot", "w_z_dot"],
        ),
        Array::new(
            "q_dot",
            "Rate of the orientation quaternion",
            &[4],
            &["q_w_dot", "q_x_dot", "q_y_dot", "q_z_dot"],
        ),
        Array::new(
            "I_principal",
            "Principal moments of inertia about C, ascending",
            &[3],
            &["I_1", "I_2", "I_3"],
        ),
    ];

    const PROJECTED: bool = true;

    /// Back onto the unit sphere: `q/|q|` is the same rotation, so this removes the
    /// integration's drift in `|q|` and nothing else.
    fn project(v: &mut RigidBodyValues<f64>) {
        let norm = (v.q_w * v.q_w + v.q_x * v.q_x + v.q_y * v.q_y + v.q_z * v.q_z).sqrt();
        if norm.is_finite() && norm > 0.0 {
            v.q_w /= norm;
            v.q_x /= norm;
            v.q_y /= norm;
            v.q_z /= norm;
        }
    }

    fn calculate(v: &mut RigidBodyValues<f64>) -> Result<(), String> {
        #[rustfmt::skip]
        let i_c = Matrix3::new(
            v.I_xx, v.I_xy, v.I_xz,
            v.I_xy, v.I_yy, v.I_yz,
            v.I_xz, v.I_yz, v.I_zz,
        );
        // The triangle inequality is a property of the body's own tensor I_C: with
        // S = ∫ r rᵀ dm (positive semi-definite) the tensor is tr(S) 1 - S, whose principal
        // moments s2+s3, s1+s3, s1+s2 satisfy I_1 + I_2 - I_3 = 2 s_min ≥ 0 (and hence
        // I_1 ≥ 0). Checking I_B instead would let an impossible body through: the
        // parallel-axis term is itself the tensor of a point mass and can mask the
        // violation (I_C = diag(1, 1, 3) with r_C along z passes once M d² ≥ 1/2). If I_C
        // passes, I_B (a sum of two physical tensors) passes too.
        let (moments_c, _) = principal_axes(&i_c);
        let (c1, c2, c3) = (moments_c[0], moments_c[1], moments_c[2]);
        if c1 + c2 < c3 * (1.0 - TRIANGLE_TOLERANCE) {
            let sign = if c1 < 0.0 {
                " (its smallest principal moment is negative: it is not even positive semi-definite)"
            } else {
                ""
            };
            return Err(format!(
                "the inertia tensor about C ({}) is not that of any body: its principal moments \
                 {c1}, {c2}, {c3} violate the triangle inequality I_1 + I_2 >= I_3 \
                 ({} < {c3}){sign}",
                tensor_text(v),
                c1 + c2
            ));
        }

        let r = Vector3::new(v.r_Cx, v.r_Cy, v.r_Cz);
        let i_b = i_c + (Matrix3::identity() * r.dot(&r) - r * r.transpose()) * v.M;
        // Euler's equations invert I_B: it must be positive definite. A physical I_C may be
        // singular (a thin rod, a point mass) and still give a regular I_B (a rod on an
        // arm), so definiteness is asked of I_B, the tensor the equations use.
        let (moments, axes) = principal_axes(&i_b);
        if moments[0] <= SINGULAR_RATIO * moments[2] {
            return Err(format!(
                "the inertia tensor about the pivot B is not positive definite: principal \
                 moments I_1 = {}, I_2 = {}, I_3 = {} (from {}, M = {}, r_C = ({}, {}, {})); \
                 the body would have no inertia about the axis ({}, {}, {})",
                moments[0],
                moments[1],
                moments[2],
                tensor_text(v),
                v.M,
                v.r_Cx,
                v.r_Cy,
                v.r_Cz,
                axes[(0, 0)],
                axes[(1, 0)],
                axes[(2, 0)]
            ));
        }

        (v.I_1, v.I_2, v.I_3) = (moments[0], moments[1], moments[2]);
        (v.I_Bxx, v.I_Byy, v.I_Bzz) = (i_b[(0, 0)], i_b[(1, 1)], i_b[(2, 2)]);
        (v.I_Bxy, v.I_Bxz, v.I_Byz) = (i_b[(0, 1)], i_b[(0, 2)], i_b[(1, 2)]);
        let inverse = inverse_of_inertia(&i_b);
        (v.I_Binv_xx, v.I_Binv_yy, v.I_Binv_zz) =
            (inverse[(0, 0)], inverse[(1, 1)], inverse[(2, 2)]);
        (v.I_Binv_xy, v.I_Binv_xz, v.I_Binv_yz) =
            (inverse[(0, 1)], inverse[(0, 2)], inverse[(1, 2)]);
        (v.e1_x, v.e1_y, v.e1_z) = (axes[(0, 0)], axes[(1, 0)], axes[(2, 0)]);
        (v.e2_x, v.e2_y, v.e2_z) = (axes[(0, 1)], axes[(1, 1)], axes[(2, 1)]);
        (v.e3_x, v.e3_y, v.e3_z) = (axes[(0, 2)], axes[(1, 2)], axes[(2, 2)]);
        Ok(())
    }

    // Inlined into the solver's stages, the states and derivatives pass in registers, not
    // through memory (a quarter of the step at tol 1e-6). `I_B⁻¹` is a calculated parameter,
    // so the twelve inlined copies of the 8th-order method do not each work it out.
    #[inline(always)]
    fn evaluate<S: Scalar>(v: &mut RigidBodyValues<S>) {
        let w = Vector3::new(v.w_x, v.w_y, v.w_z);
        let q = Quaternion::new(v.q_w, v.q_x, v.q_y, v.q_z);
        let tau = Vector3::new(v.tau_x, v.tau_y, v.tau_z);
        let r_c = Vector3::new(v.r_Cx, v.r_Cy, v.r_Cz);
        let i_b = inertia_about_pivot(v);
        let i_b_inverse = inverse_inertia_about_pivot(v);

        // Rᵀ Z, the ground vertical in body axes, is the third row of R (body → ground) of
        // q/|q|: R's entries are quadratic in q, so it is that row written in q, over |q|²
        // (no square root, no rotation of a constant vector at every stage).
        let two = lit::<S>(2.0);
        let norm_squared = q.norm_squared();
        let z_body = Vector3::new(
            two * (v.q_x * v.q_z - v.q_w * v.q_y),
            two * (v.q_y * v.q_z + v.q_w * v.q_x),
            v.q_w * v.q_w - v.q_x * v.q_x - v.q_y * v.q_y + v.q_z * v.q_z,
        ) / norm_squared;
        let weight = z_body * -(v.M * v.g);

        // Euler's equations about the fixed pivot, body axes:
        // I_B ω̇ = tau + r_C × (Rᵀ(-M g Z)) - ω × (I_B ω).
        let h_body = i_b * w;
        let moment = tau + r_c.cross(&weight) - w.cross(&h_body);
        let w_dot = i_b_inverse * moment;
        (v.w_x_dot, v.w_y_dot, v.w_z_dot) = (w_dot.x, w_dot.y, w_dot.z);

        // q̇ = ½ q ⊗ (0, ω) - k_q (|q|² - 1) q: the second term only changes |q| (see the
        // module documentation).
        let drift = norm_squared - S::one();
        let q_dot = q * Quaternion::from_imag(w) * lit::<S>(0.5) - q * (v.k_q * drift);
        (v.q_w_dot, v.q_x_dot, v.q_y_dot, v.q_z_dot) = (q_dot.w, q_dot.i, q_dot.j, q_dot.k);
    }

    /// What no derivative needs, computed only where the values are seen: the angular
    /// momentum and the position of `C` in ground axes, the energies.
    fn outputs<S: Scalar>(v: &mut RigidBodyValues<S>) {
        let w = Vector3::new(v.w_x, v.w_y, v.w_z);
        let q = Quaternion::new(v.q_w, v.q_x, v.q_y, v.q_z);
        let r_c = Vector3::new(v.r_Cx, v.r_Cy, v.r_Cz);
        let i_b = inertia_about_pivot(v);
        // R (body → ground) of q/|q| and I_B ω, as in `evaluate`.
        let rotation = UnitQuaternion::new_normalize(q);
        let h_body = i_b * w;

        // Angular momentum about B in ground axes, H = R I_B ω; energies.
        let h = rotation * h_body;
        (v.H_X, v.H_Y, v.H_Z) = (h.x, h.y, h.z);
        v.E_kin = lit::<S>(0.5) * w.dot(&h_body);
        let r_c_ground = rotation * r_c;
        (v.r_CX, v.r_CY, v.r_CZ) = (r_c_ground.x, r_c_ground.y, r_c_ground.z);
        v.E_pot = v.M * v.g * r_c_ground.z;
        v.E = v.E_kin + v.E_pot;
    }
}

/// The symmetric matrix with diagonal `(xx, yy, zz)` and off-diagonal entries `xy`, `xz`,
/// `yz`.
#[rustfmt::skip]
fn symmetric<S: Scalar>([xx, yy, zz, xy, xz, yz]: [S; 6]) -> Matrix3<S> {
    Matrix3::new(
        xx, xy, xz,
        xy, yy, yz,
        xz, yz, zz,
    )
}

/// `I_B`, the inertia tensor about the pivot (body axes), from its calculated entries.
fn inertia_about_pivot<S: Scalar>(v: &RigidBodyValues<S>) -> Matrix3<S> {
    symmetric([v.I_Bxx, v.I_Byy, v.I_Bzz, v.I_Bxy, v.I_Bxz, v.I_Byz])
}

/// `I_B⁻¹`, from its calculated entries.
fn inverse_inertia_about_pivot<S: Scalar>(v: &RigidBodyValues<S>) -> Matrix3<S> {
    symmetric([
        v.I_Binv_xx,
        v.I_Binv_yy,
        v.I_Binv_zz,
        v.I_Binv_xy,
        v.I_Binv_xz,
        v.I_Binv_yz,
    ])
}

/// `I_B⁻¹` in closed form, the adjugate over the determinant (symmetric by construction).
/// `I_B` is positive definite (checked in `calculate`: its smallest principal moment
/// exceeds 1e-12 of the largest), so `det I_B > 0`; like a Cholesky solve, the result is
/// exact up to rounding errors of the order of cond(I_B) times the unit roundoff.
fn inverse_of_inertia(i_b: &Matrix3<f64>) -> Matrix3<f64> {
    let (a, b, c) = (i_b[(0, 0)], i_b[(1, 1)], i_b[(2, 2)]);
    let (d, e, f) = (i_b[(0, 1)], i_b[(0, 2)], i_b[(1, 2)]);
    // Cofactors of the symmetric [[a, d, e], [d, b, f], [e, f, c]].
    let (c11, c22, c33) = (b * c - f * f, a * c - e * e, a * b - d * d);
    let (c12, c13, c23) = (e * f - d * c, d * f - b * e, d * e - a * f);
    let inv_det = (a * c11 + d * c12 + e * c13).recip();
    #[rustfmt::skip]
    let inverse = Matrix3::new(
        c11, c12, c13,
        c12, c22, c23,
        c13, c23, c33,
    ) * inv_det;
    inverse
}

// The FMU's functions; none when the crate is compiled into a system's FMU.
#[cfg(not(feature = "component"))]
mechfmu::export_fmu!(RigidBody);
