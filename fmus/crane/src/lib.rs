//! `Crane`: a luffing crane whose boom and trolley are moved by their drives, with a payload
//! swinging on a cable (MIT 2.003 Quiz #1 review, section 7, part (a): a Type 3 problem,
//! motion partly prescribed, the rest and the forces computed).
//!
//! The equations, their derivation and the correction of the notes' tangential equation are
//! in [`Mechanism::NOTES`] below (shipped in the FMU's documentation). In short, Newton's law
//! on the payload, `m a = -T i_B - m g J`, is projected on `j_B` (the swing) and `i_B` (the
//! tension) with `i_A·i_B = -sin s`, `j_A·i_B = -cos s`, `i_A·j_B = cos s`,
//! `j_A·j_B = -sin s` and `J = sin φ j_B - cos φ i_B`. The kinematics it shares with
//! `CraneDynamics` (the trolley's acceleration, the tension, the payload's motion, the
//! limits) are written once in the `crane_kinematics` crate.

#![forbid(unsafe_code)]

use crane_kinematics::{
    cable_tension, check_trolley_start, normal_acceleration, payload_kinetic_energy,
    payload_position, payload_velocity, radial_acceleration,
};
use mechfmu::model::{sin_cos, Experiment, Mechanism, Monitor, MovingCase, Scalar, Variable};

mechfmu::mechanism! {
    /// A luffing crane: a boom pivoting at O at angle theta above the horizontal, a trolley
    /// at distance x along it, and a payload of mass m hanging from the trolley on a cable
    /// of length l at angle phi from the downward vertical. Boom and trolley are massless
    /// and their motion is prescribed by the inputs x_ddot and theta_ddot; the FMU computes
    /// the payload's swing, the cable tension T, the force F the trolley drive must exert
    /// along the boom and the torque tau the boom drive must exert about O.
    pub struct Crane / CraneValues {
        /// Payload mass
        m: Variable::parameter("kg", 1000.0).positive(),
        /// Cable length
        l: Variable::parameter("m", 5.0).positive(),
        /// Gravitational acceleration
        g: Variable::parameter("m/s2", 9.81).min(0.0),
        /// Trolley acceleration along the boom (prescribed by the trolley drive)
        x_ddot: Variable::input("m/s2", 0.0),
        /// Boom angular acceleration (prescribed by the boom drive)
        theta_ddot: Variable::input("rad/s2", 0.0),
        /// Trolley distance from the pivot O along the boom (must stay > 0)
        x: Variable::state("m", 10.0, "x_dot"),
        /// Trolley speed along the boom
        x_dot: Variable::state("m/s", 0.0, "x_ddot"),
        /// Boom angle above the horizontal
        theta: Variable::state("rad", 0.5, "theta_dot"),
        /// Boom angular velocity
        theta_dot: Variable::state("rad/s", 0.0, "theta_ddot"),
        /// Cable angle from the downward vertical
        phi: Variable::state("rad", 0.0, "phi_dot"),
        /// Cable angular velocity
        phi_dot: Variable::state("rad/s", 0.0, "phi_ddot"),
        /// Cable tension (negative: the cable would be slack and the model no longer holds)
        T: Variable::output("N"),
        /// Force the trolley drive exerts on the trolley along the boom (i_A)
        F: Variable::output("N"),
        /// Torque the boom drive exerts on the boom about O (K)
        tau: Variable::output("N.m"),
        /// Payload position, horizontal, from O
        payload_x: Variable::output("m"),
        /// Payload position, vertical (up), from O
        payload_y: Variable::output("m"),
        /// Cable angular acceleration
        phi_ddot: Variable::output("rad/s2"),
        /// Mechanical energy of the payload (kinetic + gravitational, height from O); with
        /// boom and trolley massless it is the whole crane's
        E_payload: Variable::output("J"),
        /// Power delivered by the drives, F x_dot + tau theta_dot (= rate of change of E_payload)
        P_drives: Variable::output("W"),
        /// Work done by the drives since the start, the integral of P_drives (equals the
        /// payload's gain of energy)
        W_drives: Variable::state("J", 0.0, "P_drives"),
    }
}

impl Mechanism for Crane {
    const EXPERIMENT: Experiment = Experiment::until(20.0).step(0.01).tolerance(1e-6);

    /// The default experiment is an equilibrium; the documentation plots the reference case
    /// `swing_60deg` of `validation/cases.py` instead.
    const MOVING_CASE: Option<MovingCase> = Some(MovingCase {
        name: "swing_60deg",
        at_rest: "the crane stands still: the payload hangs at rest below the trolley and the \
                  drives are still",
        shows: "the payload released from rest at 60° from the vertical with the drives still, \
                a pendulum whose period, 4 sqrt(l/g) K(sin 30°) = 4.81 s, is 7 % longer than \
                the small-angle one; the cable's pull loads the drives, which do no work",
        values: &[("phi", std::f64::consts::FRAC_PI_3)],
        stop: None,
    });

    const NOTES: &'static str = "
        Frames: ground `I` (horizontal), `J` (up); boom `i_A = (cos θ, sin θ)`,
        `j_A = (-sin θ, cos θ)`; cable `i_B = (sin φ, -cos φ)` (trolley to payload),
        `j_B = (cos φ, sin φ)`; `s = θ - φ`. Boom and trolley are massless and move as the
        inputs `x_ddot` and `theta_ddot` prescribe. The payload accelerates at

            a = (ẍ - θ̇² x) i_A + (2 θ̇ ẋ + θ̈ x) j_A + l φ̈ j_B - l φ̇² i_B

        and Newton's law `m a = -T i_B - m g J`, projected on `j_B` and `i_B`, gives

            l φ̈ = -g sin φ - (ẍ - θ̇² x) cos s + (2 θ̇ ẋ + θ̈ x) sin s
            T   = m [(ẍ - θ̇² x) sin s + (2 θ̇ ẋ + θ̈ x) cos s + l φ̇² + g cos φ]

        The massless trolley (`F i_A + N j_A + T i_B = 0`) and boom (`τ = x N`) carry the
        cable's pull to the drives:

            F = T sin s        τ = x T cos s        so T = sqrt(F² + (τ/x)²) while T ≥ 0

        `E_payload` is the payload's kinetic plus gravitational energy (height from `O`),
        `P_drives = F ẋ + τ θ̇` the drives' power and `W_drives` its integral: the cable does
        no work, so `W_drives` equals the gain of `E_payload`.

        ## Departure from the course notes
        The last line of the notes' Quiz #1 solution (the payload's tangential equation) reads
        `0 = -(ẍ - θ̇² x) cos s - (2 θ̇ ẋ + θ̈ x) sin s + l φ̈ - g sin φ`. With the drives still
        and `φ` small it says `l φ̈ = +g φ`: a hanging payload that falls over. The signs of
        its `g` and `ẍ - θ̇² x` terms are wrong; the equation above is the `j_B` component of
        the notes' own vector equation. Checked independently: the payload's Lagrangian with
        `x(t)`, `θ(t)` prescribed, Newton's law in ground coordinates on the simulated
        payload path, and the exact large-amplitude pendulum period `4 sqrt(l/g) K(sin(φ0/2))`.

        ## Limits
        - `T < 0`: a cable cannot push. The FMU goes on as if the cable were a rod and logs a
          warning once per episode (Co-Simulation: the step returns `fmi2Warning`).
        - `x ≤ 0`: the trolley reached the pivot. Co-Simulation: the step ends with
          `fmi2Discard` at the last valid time, with a message. A start value `x ≤ 0` is
          refused at initialization.

        In Model Exchange both limits are event indicators, `x` and `T`: the importer's
        solver locates where either changes sign and enters event mode there. At the event
        a slack cable is logged as a warning (`fmi2NewDiscreteStates` returns
        `fmi2Warning`) and the simulation goes on; the trolley at the pivot ends it
        (`terminateSimulation`, the reason logged), at the time of the crossing.
    ";

    fn calculate(v: &mut CraneValues<f64>) -> Result<(), String> {
        // The trolley rides the boom on the payload's side of the pivot; at x ≤ 0 the boom
        // torque tau = x T cos s and the geometry no longer describe a crane.
        check_trolley_start(v.x)
    }

    fn evaluate<S: Scalar>(v: &mut CraneValues<S>) {
        let s = v.theta - v.phi;
        let (sin_s, cos_s) = sin_cos(s);
        let (sin_phi, cos_phi) = sin_cos(v.phi);
        // The trolley's acceleration in the boom frame: along i_A (radial) and j_A
        // (Coriolis + Euler).
        let a_radial = radial_acceleration(v.x, v.theta_dot, v.x_ddot);
        let a_normal = normal_acceleration(v.x, v.x_dot, v.theta_dot, v.theta_ddot);
        // Payload along j_B (tangential): the corrected sign of the notes' last line.
        v.phi_ddot = (-v.g * sin_phi - a_radial * cos_s + a_normal * sin_s) / v.l;
        // Payload along i_B (along the cable): the notes' formula (a).
        let a_trolley = (a_radial, a_normal);
        v.T = cable_tension(v.m, v.l, v.g, a_trolley, (sin_s, cos_s), v.phi_dot, cos_phi);
        // Massless trolley and boom: the drives carry the cable's pull.
        v.F = v.T * sin_s;
        v.tau = v.x * v.T * cos_s;
        // The trolley drive's force does work only through the trolley's motion along the
        // boom (its reaction on the boom acts at a point moving along j_A); the cable does
        // none (inextensible), so this is the payload's dE/dt.
        v.P_drives = v.F * v.x_dot + v.tau * v.theta_dot;
    }

    /// The payload's position and energy: no derivative needs them (`T`, which the monitor
    /// reads, and `P_drives`, the rate of `W_drives`, stay in `evaluate`).
    fn outputs<S: Scalar>(v: &mut CraneValues<S>) {
        // The cable's and the boom's directions: (sin φ, cos φ) and (sin θ, cos θ).
        let cable = sin_cos(v.phi);
        let boom = sin_cos(v.theta);
        (v.payload_x, v.payload_y) = payload_position(v.x, v.l, boom, cable);
        let vel = payload_velocity(v.x, v.x_dot, v.theta_dot, v.l, v.phi_dot, boom, cable);
        v.E_payload = payload_kinetic_energy(v.m, vel) + v.m * v.g * v.payload_y;
    }

    const MONITORED: bool = true;

    /// Where the monitor's verdict changes: the trolley at the pivot, the cable going slack.
    const EVENT_INDICATORS: &'static [&'static str] = &["x", "T"];

    /// The trolley at the pivot (`x ≤ 0`) ends the step; a slack cable (`T < 0`) is a warning.
    fn monitor(v: &CraneValues<f64>) -> Monitor {
        crane_kinematics::monitor(v.x, v.T)
    }
}

// The FMU's functions; none when the crate is compiled into a system's FMU.
#[cfg(not(feature = "component"))]
mechfmu::export_fmu!(Crane);
