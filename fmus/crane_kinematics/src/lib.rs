//! The luffing crane's kinematics and limits, written once for its two models: `Crane` (the
//! boom and trolley moved as their drives prescribe) and `CraneDynamics` (moved by the drives'
//! force and torque). Frames as in their notes: boom `i_A = (cos θ, sin θ)`,
//! `j_A = (-sin θ, cos θ)`; cable `i_B = (sin φ, -cos φ)` (trolley to payload),
//! `j_B = (cos φ, sin φ)`; `s = θ - φ`. The trolley rides the boom at `x i_A` from the pivot
//! `O`, the payload hangs at `x i_A + l i_B`.
//!
//! The equations are generic over the scalar as the mechanisms' are (`f64` to simulate, dual
//! numbers for exact derivatives) and always inlined into them. Angles come in by their sines
//! and cosines, which each mechanism computes its own way (`Crane` calls `sin_cos(θ - φ)`,
//! `CraneDynamics` uses the angle-difference identities).

#![forbid(unsafe_code)]

use mechfmu::model::{lit, Monitor, Scalar};

/// The trolley's acceleration along the boom, `i_A` (radial): `ẍ - θ̇² x`.
#[inline(always)]
pub fn radial_acceleration<S: Scalar>(x: S, theta_dot: S, x_ddot: S) -> S {
    x_ddot - theta_dot * theta_dot * x
}

/// The trolley's acceleration across the boom, `j_A` (Coriolis + Euler): `2 θ̇ ẋ + θ̈ x`.
#[inline(always)]
pub fn normal_acceleration<S: Scalar>(x: S, x_dot: S, theta_dot: S, theta_ddot: S) -> S {
    lit::<S>(2.0) * theta_dot * x_dot + theta_ddot * x
}

/// The cable tension: Newton's law on the payload along the cable (`i_B`), the notes'
/// formula (a), from the trolley's acceleration `(radial, normal)` in the boom frame and
/// `(sin s, cos s)`:
///
/// ```text
/// T = m [(ẍ - θ̇² x) sin s + (2 θ̇ ẋ + θ̈ x) cos s + l φ̇² + g cos φ]
/// ```
#[inline(always)]
pub fn cable_tension<S: Scalar>(
    m: S,
    l: S,
    g: S,
    (a_radial, a_normal): (S, S),
    (sin_s, cos_s): (S, S),
    phi_dot: S,
    cos_phi: S,
) -> S {
    m * (a_radial * sin_s + a_normal * cos_s + l * phi_dot * phi_dot + g * cos_phi)
}

/// The payload's position from `O`, horizontal and vertical (up): `x i_A + l i_B`, from
/// `(sin θ, cos θ)` and `(sin φ, cos φ)`.
#[inline(always)]
pub fn payload_position<S: Scalar>(
    x: S,
    l: S,
    (sin_th, cos_th): (S, S),
    (sin_phi, cos_phi): (S, S),
) -> (S, S) {
    (x * cos_th + l * sin_phi, x * sin_th - l * cos_phi)
}

/// The payload's velocity, horizontal and vertical: `ẋ i_A + x θ̇ j_A + l φ̇ j_B`, from
/// `(sin θ, cos θ)` and `(sin φ, cos φ)`.
#[inline(always)]
pub fn payload_velocity<S: Scalar>(
    x: S,
    x_dot: S,
    theta_dot: S,
    l: S,
    phi_dot: S,
    (sin_th, cos_th): (S, S),
    (sin_phi, cos_phi): (S, S),
) -> (S, S) {
    (
        x_dot * cos_th - x * theta_dot * sin_th + l * phi_dot * cos_phi,
        x_dot * sin_th + x * theta_dot * cos_th + l * phi_dot * sin_phi,
    )
}

/// The payload's kinetic energy `½ m |v|²`, from its velocity `(v_x, v_y)`.
#[inline(always)]
pub fn payload_kinetic_energy<S: Scalar>(m: S, (vel_x, vel_y): (S, S)) -> S {
    lit::<S>(0.5) * m * (vel_x * vel_x + vel_y * vel_y)
}

/// Refuses a start value `x ≤ 0`: the trolley rides the boom on the payload's side of the
/// pivot, and at `x ≤ 0` the boom torque `τ = x T cos s` and the geometry no longer describe
/// a crane.
#[inline]
pub fn check_trolley_start(x: f64) -> Result<(), String> {
    if x <= 0.0 {
        return Err(format!(
            "x = {x} is not allowed: the trolley must start at x > 0 (beyond the pivot O)"
        ));
    }
    Ok(())
}

/// The crane's limits at an accepted step, from the trolley's distance `x` and the cable
/// tension `T`: the trolley at the pivot (`x ≤ 0`) invalidates the model; a slack cable
/// (`T < 0`: a cable cannot push) is a warning, the model going on as if it were a rod.
#[inline]
pub fn monitor(x: f64, tension: f64) -> Monitor {
    if x <= 0.0 {
        Monitor::Invalid(format!(
            "the trolley reached the pivot O (x = {x:e} m): the crane model no longer holds"
        ))
    } else if tension < 0.0 {
        Monitor::Warning(format!(
            "the cable is slack (T = {tension:.6e} N < 0): a cable cannot push, the results no \
             longer describe a real crane until T is positive again"
        ))
    } else {
        Monitor::Valid
    }
}
