//! Mechanisms declared from their energies: the generalized coordinates, the kinetic energy
//! `T`, the potential energy `V` and the generalized forces `Q`; the runtime forms and solves
//! Lagrange's equations
//!
//! ```text
//! M(q) q̈ = Q + ∂T/∂q - ∂V/∂q - (∂²T/∂q̇∂q) q̇ - ∂²T/∂q̇∂t,        M = ∂²T/∂q̇²
//! ```
//!
//! with derivatives that are exact (dual numbers), never finite differences.
//!
//! A coordinate is a state whose derivative is a state (its velocity), whose derivative is
//! its acceleration. A *free* coordinate's acceleration is an output (or local) variable
//! that Lagrange's equations give. A *driven* coordinate's acceleration is an input: its
//! motion is prescribed, and the generalized force its drive must exert to prescribe it
//! (Lagrange's expression for that coordinate) is written to the output it names.
//!
//! ```
//! use mechfmu::lagrange::{Coordinate, Lagrangian};
//! use mechfmu::model::{cos, lit, Experiment, Mechanism, Scalar, Variable};
//!
//! mechfmu::mechanism! {
//!     /// A pendulum: a point mass m on a massless rod of length l.
//!     pub struct Pendulum / PendulumValues {
//!         /// Mass
//!         m: Variable::parameter("kg", 1.0).positive(),
//!         /// Length
//!         l: Variable::parameter("m", 1.0).positive(),
//!         /// Gravity
//!         g: Variable::parameter("m/s2", 9.81),
//!         /// Angle from the downward vertical
//!         phi: Variable::state("rad", 0.5, "phi_dot"),
//!         /// Angular velocity
//!         phi_dot: Variable::state("rad/s", 0.0, "phi_ddot"),
//!         /// Angular acceleration
//!         phi_ddot: Variable::output("rad/s2"),
//!     }
//! }
//!
//! impl Lagrangian<1> for Pendulum {
//!     const COORDINATES: [Coordinate; 1] = [Coordinate::free("phi")];
//!     #[inline(always)]
//!     fn kinetic_energy<S: Scalar>(v: &PendulumValues<S>) -> S {
//!         lit::<S>(0.5) * v.m * v.l * v.l * v.phi_dot * v.phi_dot
//!     }
//!     #[inline(always)]
//!     fn potential_energy<S: Scalar>(v: &PendulumValues<S>) -> S {
//!         -v.m * v.g * v.l * cos(v.phi)
//!     }
//! }
//!
//! impl Mechanism for Pendulum {
//!     const EXPERIMENT: Experiment =
//!         Experiment::until(1.0).step(0.01).tolerance(1e-8);
//!     fn evaluate<S: Scalar>(v: &mut PendulumValues<S>) {
//!         Self::lagrange(v);
//!     }
//!     fn diagnose(v: &PendulumValues<f64>) -> Option<String> {
//!         Self::mass_matrix_problem(v)
//!     }
//! }
//!
//! let mut v = PendulumValues { m: 1.0, l: 2.0, g: 9.81, phi: 0.5, ..Default::default() };
//! Pendulum::evaluate(&mut v);
//! assert!((v.phi_ddot + 9.81 / 2.0 * 0.5f64.sin()).abs() < 1e-15);
//! ```

mod cholesky;
mod coordinates;
mod jet;
mod solve;
#[cfg(test)]
mod tests;

pub use coordinates::{resolve, Coordinate, Resolved};
pub use jet::Jet;

use crate::model::{Declaration, Scalar};

/// A mechanism declared from its energies, in `N` generalized coordinates.
///
/// `T`, `V` and `Q` are functions of the values, generic over the scalar like
/// [`Mechanism::evaluate`](crate::model::Mechanism::evaluate): the runtime evaluates them on
/// dual numbers for the derivatives Lagrange's equations need. `T` is a function of the
/// coordinates, their velocities, the parameters and the time; `V` of the coordinates, the
/// parameters and the time; `Q` of anything but the accelerations.
///
/// The mechanism's [`Mechanism::evaluate`](crate::model::Mechanism::evaluate) calls
/// [`Lagrangian::lagrange`] (and may compute more after it, from the accelerations), and its
/// [`Mechanism::diagnose`](crate::model::Mechanism::diagnose) calls
/// [`Lagrangian::mass_matrix_problem`].
///
/// Mark `kinetic_energy` and `potential_energy` `#[inline(always)]`. The runtime evaluates
/// them on [`Jet`]s, which skip the derivatives a value does not have (a parameter has none);
/// inlined into the solver, the compiler knows which those are and drops their work. A step
/// then costs 1.4–2.4 times the hand-written equations' (`mechfmu bench --instructions`);
/// not inlined, the jets travel through memory and it costs several times more.
///
/// A jet holds `N² + 3N + 2` numbers, and the runtime evaluates `T` on one per variable of
/// the mechanism, on the importer's thread's stack: a few coordinates (a dozen is about
/// 1.3 KB per variable) are what the form is for; a long chain of bodies is better written
/// with its own recursive equations.
pub trait Lagrangian<const N: usize>: Declaration + Sized {
    /// The generalized coordinates, by the names of their position states.
    const COORDINATES: [Coordinate; N];

    /// The kinetic energy `T(q, q̇, t)`.
    fn kinetic_energy<S: Scalar>(values: &Self::Values<S>) -> S;

    /// The potential energy `V(q, t)`.
    fn potential_energy<S: Scalar>(values: &Self::Values<S>) -> S;

    /// The generalized forces `Q` of what `V` does not hold (forces at points, dampers,
    /// drag), one per coordinate in the order of [`Lagrangian::COORDINATES`]: the virtual
    /// work of those forces is `Σ Q_i δq_i`. None by default.
    fn generalized_forces<S: Scalar>(_values: &Self::Values<S>) -> [S; N] {
        [S::zero(); N]
    }

    /// The coordinates' value references, checked at compile time: a name that is not a
    /// coordinate (a state whose derivative is a state) does not compile, and the error
    /// names it.
    #[doc(hidden)]
    const RESOLVED: [Resolved; N] = resolve(Self::VARIABLES, &Self::COORDINATES);

    /// Lagrange's equations at the point the values hold: writes the free coordinates'
    /// accelerations and the driven coordinates' forces. Where the mass matrix of the free
    /// coordinates is not positive definite (beyond rounding) they are not solved: both are
    /// NaN, and [`Lagrangian::mass_matrix_problem`] says why.
    #[inline]
    fn lagrange<S: Scalar>(values: &mut Self::Values<S>) {
        solve::equations_of_motion::<Self, N, S>(values);
    }

    /// Why the mass matrix of the free coordinates is not positive definite at the point the
    /// values hold, naming the coordinate and the point; `None` when it is.
    fn mass_matrix_problem(values: &Self::Values<f64>) -> Option<String> {
        solve::mass_matrix_problem::<Self, N>(values)
    }
}
