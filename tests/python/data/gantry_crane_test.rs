//! GantryCrane against Newton's law, and the conformance checks: `cargo test`.

use gantry_crane::{GantryCrane, GantryCraneValues};
use mechfmu::model::Mechanism;

/// `(φ̈, F_trolley, F_hoist)` by Newton's law. The payload, at `l` along
/// `e_l = (sin φ, -cos φ)` from the trolley, accelerates at
/// `(ẍ, 0) + (l̈ - l φ̇²) e_l + (l φ̈ + 2 l̇ φ̇) e_φ` with `e_φ = (cos φ, sin φ)`, under the
/// cable's pull `-T e_l`, the wind `(F_wind, 0)` and gravity `(0, -m g)`: along `e_φ` that
/// gives `φ̈`, along `e_l` the tension `T`. The trolley: `M ẍ = F_trolley + T sin φ`. The
/// winch lengthens the cable against its tension: `F_hoist = -T`.
fn newton(v: &GantryCraneValues<f64>) -> (f64, f64, f64) {
    let (sin, cos) = v.phi.sin_cos();
    let phi_ddot =
        (v.F_wind * cos / v.m - v.g * sin - v.x_ddot * cos - 2.0 * v.l_dot * v.phi_dot) / v.l;
    let tension = v.m * (v.g * cos + v.l * v.phi_dot * v.phi_dot - v.l_ddot - v.x_ddot * sin)
        + v.F_wind * sin;
    (phi_ddot, v.M * v.x_ddot - tension * sin, -tension)
}

/// The swing and both drives' forces, from the energies, are Newton's law's.
#[test]
fn swing_and_drive_forces_follow_newtons_law() {
    for k in 0..50 {
        let k = k as f64;
        let mut v = GantryCraneValues::<f64> {
            M: 500.0,
            m: 1000.0 + 20.0 * k,
            g: 9.81,
            x_ddot: (0.7 * k).sin(),
            l_ddot: 0.3 * (0.4 * k).cos(),
            F_wind: 200.0 * (0.9 * k).sin(),
            x_dot: 0.1 * k - 2.0,
            l: 2.0 + 0.1 * k,
            l_dot: (0.2 * k).sin(),
            phi: 0.13 * k - 3.0,
            phi_dot: (0.5 * k).sin(),
            ..Default::default()
        };
        GantryCrane::evaluate(&mut v);
        let (phi_ddot, f_trolley, f_hoist) = newton(&v);
        let close = |a: f64, b: f64, scale: f64| (a - b).abs() <= 1e-12 * scale;
        assert!(close(v.phi_ddot, phi_ddot, 1.0 + phi_ddot.abs()), "{k}: φ̈");
        assert!(close(v.F_trolley, f_trolley, v.m * v.g), "{k}: F_trolley");
        assert!(close(v.F_hoist, f_hoist, v.m * v.g), "{k}: F_hoist");
    }
}

#[test]
fn conforms() {
    mechfmu_testkit::conformance::check::<GantryCrane>();
}
