// The carts of the coordinate tests, included by `right.rs` and `mistakes.rs` (each a program
// of its own, compiled by trybuild).

/// A module `$module` with a cart `Cart` of mass `m` at `x` on a line (`x` and its velocity
/// `x_dot` states, its acceleration `x_ddot` declared as `$acceleration`), declared from its
/// energies with `$n` generalized coordinates, and its `compile()`: the call that compiles the
/// equations for `f64`, where the coordinates are resolved (a mistake in them is a compile
/// error there).
macro_rules! cart {
    ($module:ident, x_ddot: $acceleration:expr, $n:literal coordinates: [$($coordinate:expr),+]) => {
        mod $module {
            use mechfmu::lagrange::{Coordinate, Lagrangian};
            use mechfmu::model::{lit, Experiment, Mechanism, Scalar, Variable};

            mechfmu::mechanism! {
                /// A cart on a line.
                pub struct Cart / CartValues {
                    /// Mass
                    m: Variable::parameter("kg", 1.0).positive(),
                    /// Position
                    x: Variable::state("m", 0.1, "x_dot"),
                    /// Velocity
                    x_dot: Variable::state("m/s", 0.0, "x_ddot"),
                    /// Acceleration
                    x_ddot: $acceleration,
                }
            }

            impl Lagrangian<$n> for Cart {
                const COORDINATES: [Coordinate; $n] = [$($coordinate),+];
                fn kinetic_energy<S: Scalar>(v: &CartValues<S>) -> S {
                    lit::<S>(0.5) * v.m * v.x_dot * v.x_dot
                }
                fn potential_energy<S: Scalar>(_: &CartValues<S>) -> S {
                    S::zero()
                }
            }

            impl Mechanism for Cart {
                const EXPERIMENT: Experiment = Experiment::until(1.0).step(0.1);
                fn evaluate<S: Scalar>(v: &mut CartValues<S>) {
                    Self::lagrange(v);
                }
            }

            pub fn compile() {
                let mut v = CartValues::<f64>::default();
                Cart::evaluate(&mut v);
            }
        }
    };
}
