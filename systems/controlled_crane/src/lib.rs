//! `ControlledCrane`: `CraneDynamics` driven by the `CraneController`, which feeds back the
//! trolley's and the boom's positions and speeds and the payload's swing rate as the drive
//! force and torque.

#![forbid(unsafe_code)]

use crane_controller::CraneController;
use crane_dynamics::CraneDynamics;
use mechfmu::model::Experiment;

mechfmu::system! {
    /// The luffing crane driven by force and torque, held by a controller that moves the
    /// trolley and the boom to their set points and damps the payload's swing.
    pub struct ControlledCrane {
        components {
            /// The crane: trolley on the boom, payload on its cable
            crane: CraneDynamics,
            /// The control law: drive force and torque
            controller: CraneController,
        }
        connections {}
        // the trolley's and the boom's positions and speeds and the payload's swing rate to
        // the controller, its force and torque back to the drives
        terminals {
            crane.motion <=> controller.motion,
            controller.drives <=> crane.drives,
        }
        parameter_sets {
            /// The components' defaults: the crane at rest at x = 10 m, θ = 0.5 rad, moved
            /// to 12 m and 0.6 rad
            default {}
            /// A longer reach at a lower boom
            reach { controller.x_ref = 15.0, controller.theta_ref = 0.3 }
        }
        experiment: Experiment::until(30.0).step(0.01).tolerance(1e-6),
    }
}

// What the system is (its SSP); with the feature `fmu`, the system as one FMU: its
// components' equations integrated together.
#[cfg(not(feature = "fmu"))]
mechfmu::export_system!(ControlledCrane);
#[cfg(feature = "fmu")]
mechfmu::export_fmu!(ControlledCrane);
