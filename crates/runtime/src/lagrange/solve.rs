//! Lagrange's equations formed and solved at a point.
//!
//! Their terms come from `T` and `V` evaluated on dual numbers, exact to rounding:
//!
//! - on `f64` (a simulation), one evaluation of `L = T - V` on [`Jet`]s gives all three:
//!   `M = ∂²L/∂q̇²`, `C = (∂²L/∂q̇∂q) q̇ + ∂²L/∂q̇∂t` and `∂L/∂q`;
//! - on [`Dual64`] (a directional derivative, the model structure's probe), the same terms
//!   and their derivatives along the dual direction, which are third derivatives of `T`:
//!   one hyper-hyper-dual pass per element of `M`, of `C` and of `∂L/∂q`, with the third
//!   infinitesimal carrying the direction.
//!
//! The equations are then solved by one routine for both: the driven coordinates'
//! accelerations moved to the right-hand side, Cholesky on the free ones, the drives'
//! forces from their rows.

use super::cholesky::solve_positive_definite;
use super::Jet;
use super::{Lagrangian, Resolved};
use crate::model::{Scalar, ValueSet};
use num_dual::{Dual64, HyperHyperDual64};
use std::any::Any;

/// Lagrange's equations at a point, `mass q̈ = rest`: `rest = Q + ∂L/∂q - C`.
struct Terms<S, const N: usize> {
    mass: [[S; N]; N],
    rest: [S; N],
}

/// Writes the free coordinates' accelerations and the drives' forces (NaN where the free
/// coordinates' mass matrix is not positive definite).
#[inline]
pub(super) fn equations_of_motion<L: Lagrangian<N>, const N: usize, S: Scalar>(
    values: &mut L::Values<S>,
) {
    // Where the equations read the coordinates' constant: a mistake in them is reported
    // once, here.
    let resolved = &L::RESOLVED;
    let any = values as &mut dyn Any;
    if let Some(values) = any.downcast_mut::<L::Values<f64>>() {
        let terms = terms_f64::<L, N>(values, resolved);
        let _ = solve::<L, N, f64>(values, &terms, resolved);
    } else if let Some(values) = any.downcast_mut::<L::Values<Dual64>>() {
        let terms = terms_dual::<L, N>(values, resolved);
        let _ = solve::<L, N, Dual64>(values, &terms, resolved);
    } else {
        panic!(
            "{}: Lagrange's equations are formed on f64 and Dual64, not on {}",
            L::NAME,
            std::any::type_name::<S>()
        );
    }
}

/// See [`Lagrangian::mass_matrix_problem`].
pub(super) fn mass_matrix_problem<L: Lagrangian<N>, const N: usize>(
    values: &L::Values<f64>,
) -> Option<String> {
    let resolved = &L::RESOLVED;
    let mut probe = values.clone();
    let terms = terms_f64::<L, N>(&probe, resolved);
    let (row, pivot) = solve::<L, N, f64>(&mut probe, &terms, resolved).err()?;
    let coordinate = L::COORDINATES[row].name;
    let velocity = L::VARIABLES[resolved[row].velocity].name;
    let point = (resolved.iter())
        .flat_map(|r| [r.position, r.velocity])
        .map(|vr| {
            let name = L::VARIABLES[vr].name;
            format!("{name} = {}", values.get(vr).unwrap_or(f64::NAN))
        })
        .collect::<Vec<_>>()
        .join(", ");
    let row_of_mass = &terms.mass[row];
    let why = if !row_of_mass.iter().all(|m| m.is_finite()) || !pivot.is_finite() {
        format!("its row for `{coordinate}` is not a number there (T or V is not, or not differentiable)")
    } else if row_of_mass.iter().all(|&m| m == 0.0) {
        format!("the kinetic energy does not depend on `{velocity}` there")
    } else if row_of_mass[row] == 0.0 {
        format!(
            "∂²T/∂{velocity}² = 0 there: the kinetic energy is not quadratic in `{velocity}` (½ m v² for each body's velocity v)"
        )
    } else {
        format!(
            "its pivot for `{coordinate}` is {pivot:e}: the coordinates are not independent there, or a mass is not positive"
        )
    };
    Some(format!(
        "the mass matrix ∂²T/∂q̇² of the free coordinates is not positive definite at t = {}, {point}: {why}",
        values.time()
    ))
}

/// Solves the equations: the free accelerations and the drives' forces into `values`.
/// `Err((coordinate, pivot))` where the free coordinates' mass matrix is not positive
/// definite; the accelerations and forces are then NaN.
#[inline]
fn solve<L: Lagrangian<N>, const N: usize, S: Scalar>(
    values: &mut L::Values<S>,
    terms: &Terms<S, N>,
    resolved: &[Resolved; N],
) -> Result<(), (usize, S)> {
    let nan = S::from_subset(&f64::NAN);
    if resolved.iter().all(|coordinate| coordinate.force.is_none()) {
        // Every coordinate free, as in most mechanisms: the rows are 0..N, constants over
        // which the compiler unrolls the factorization and writes each acceleration into its
        // field (with the rows gathered below, a third of the equations' cost).
        let rows: [usize; N] = std::array::from_fn(|i| i);
        let mut right = terms.rest;
        let solved = solve_positive_definite(&terms.mass, &rows, &mut right);
        for (coordinate, &acceleration) in resolved.iter().zip(&right) {
            let acceleration = if solved.is_ok() { acceleration } else { nan };
            values.set(coordinate.acceleration, acceleration);
        }
        return solved;
    }
    let (mut free, mut free_count) = ([0; N], 0);
    let mut accelerations = [S::zero(); N];
    for (i, coordinate) in resolved.iter().enumerate() {
        if coordinate.force.is_none() {
            free[free_count] = i;
            free_count += 1;
        } else {
            accelerations[i] = values.get(coordinate.acceleration).unwrap_or(S::zero());
        }
    }
    let free = &free[..free_count];
    // The free rows, with the driven coordinates' known accelerations moved right.
    let mut right = terms.rest;
    for &i in free {
        for (j, coordinate) in resolved.iter().enumerate() {
            if coordinate.force.is_some() {
                right[i] -= terms.mass[i][j] * accelerations[j];
            }
        }
    }
    let solved = solve_positive_definite(&terms.mass, free, &mut right);
    for &i in free {
        accelerations[i] = if solved.is_ok() { right[i] } else { nan };
        values.set(resolved[i].acceleration, accelerations[i]);
    }
    // A drive exerts what its row of the equations lacks: M q̈ - rest.
    for (i, coordinate) in resolved.iter().enumerate() {
        if let Some(force) = coordinate.force {
            let mut exerted = -terms.rest[i];
            for (j, &acceleration) in accelerations.iter().enumerate() {
                exerted += terms.mass[i][j] * acceleration;
            }
            values.set(force, exerted);
        }
    }
    solved.map_err(|(k, pivot)| (free[k], pivot))
}

/// The value of `vr` (always a variable: the coordinates are resolved at compile time).
#[inline(always)]
fn value<S: Scalar, V: ValueSet<S>>(values: &V, vr: usize) -> S {
    values.get(vr).unwrap_or(S::zero())
}

/// The terms on `f64`, from one evaluation of `L = T - V` on [`Jet`]s.
#[inline]
fn terms_f64<L: Lagrangian<N>, const N: usize>(
    values: &L::Values<f64>,
    resolved: &[Resolved; N],
) -> Terms<f64, N> {
    let mut x = L::map_values(values, Jet::<N>::constant);
    for (i, coordinate) in resolved.iter().enumerate() {
        let q_dot = value(values, coordinate.velocity);
        x.set(coordinate.velocity, Jet::velocity(i, q_dot));
        let q = value(values, coordinate.position);
        x.set(coordinate.position, Jet::coordinate(i, q, q_dot));
    }
    x.set_time(Jet::time(values.time()));
    let lagrangian = lagrangian::<L, N, _>(&x);
    let forces = L::generalized_forces(values);
    Terms {
        mass: std::array::from_fn(|i| std::array::from_fn(|j| lagrangian.vv[i.min(j)][i.max(j)])),
        rest: std::array::from_fn(|i| forces[i] + lagrangian.q[i] - lagrangian.vp[i]),
    }
}

/// The terms on [`Dual64`]: each with its derivative along the direction the values carry,
/// from hyper-hyper-dual passes whose third infinitesimal is that direction.
fn terms_dual<L: Lagrangian<N>, const N: usize>(
    values: &L::Values<Dual64>,
    resolved: &[Resolved; N],
) -> Terms<Dual64, N> {
    type Third = HyperHyperDual64;
    // Every value with its direction as ε3.
    let base = L::map_values(values, |x: Dual64| {
        Third::new(x.re, 0.0, 0.0, x.eps, 0.0, 0.0, 0.0, 0.0)
    });
    let add = |x: Third, e1: f64, e2: f64, e2e3: f64| {
        let mut y = x;
        y.eps1 += e1;
        y.eps2 += e2;
        y.eps2eps3 += e2e3;
        y
    };
    // ε1 ε2 and ε1 ε2 ε3 parts as a dual number.
    let second = |t: Third| Dual64::new(t.eps1eps2, t.eps1eps2eps3);

    let mut mass = [[Dual64::from_re(0.0); N]; N];
    for i in 0..N {
        for j in i..N {
            let mut x = base.clone();
            let vi = resolved[i].velocity;
            x.set(vi, add(value(&x, vi), 1.0, 0.0, 0.0));
            let vj = resolved[j].velocity;
            x.set(vj, add(value(&x, vj), 0.0, 1.0, 0.0));
            mass[i][j] = second(lagrangian::<L, N, _>(&x));
            mass[j][i] = mass[i][j];
        }
    }

    let mut rest = L::generalized_forces(values);
    for i in 0..N {
        // C_i: ε1 on velocity i, ε2 along (q̇, 1) in (q, t); the direction (q̇) itself moves
        // along ε3 by the velocities' derivatives, the ε2ε3 part.
        let mut x = base.clone();
        let vi = resolved[i].velocity;
        x.set(vi, add(value(&x, vi), 1.0, 0.0, 0.0));
        for coordinate in resolved {
            let q_dot = value(values, coordinate.velocity);
            let q = value(&x, coordinate.position);
            x.set(coordinate.position, add(q, 0.0, q_dot.re, q_dot.eps));
        }
        x.set_time(add(x.time(), 0.0, 1.0, 0.0));
        let c = second(lagrangian::<L, N, _>(&x));

        // ∂L/∂q_i: ε1 on coordinate i; the ε1 and ε1ε3 parts.
        let mut x = base.clone();
        let pi = resolved[i].position;
        x.set(pi, add(value(&x, pi), 1.0, 0.0, 0.0));
        let l = lagrangian::<L, N, _>(&x);
        rest[i] += Dual64::new(l.eps1, l.eps1eps3) - c;
    }
    Terms { mass, rest }
}

/// `L = T - V`.
#[inline(always)]
fn lagrangian<L: Lagrangian<N>, const N: usize, S: Scalar>(values: &L::Values<S>) -> S {
    L::kinetic_energy(values) - L::potential_energy(values)
}
