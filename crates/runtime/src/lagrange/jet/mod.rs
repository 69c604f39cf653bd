//! [`Jet`]: the one number whose arithmetic gives every term of Lagrange's equations on
//! `f64` in a single evaluation of `T`, and of `V`.
//!
//! A jet is a value with the derivatives Lagrange's equations need, along `N` velocity
//! directions `ε_v` (one per coordinate's velocity), `N` coordinate directions `ε_q` and one
//! path direction `ε_p` (the motion at fixed velocities: `q` moves at `q̇`, the time at 1):
//!
//! - first order along all `2N + 1`: `∂T/∂q` for `∂L/∂q`;
//! - second order along `ε_v ε_v` (`M = ∂²T/∂q̇²`) and `ε_v ε_p`
//!   (`C = (∂²T/∂q̇∂q) q̇ + ∂²T/∂q̇∂t`), and no other product: the other products are dropped
//!   (taken as zero), which is exact for the kept parts, since no kept part is ever computed
//!   from a dropped one.
//!
//! It is what a general hyper-dual vector would give with the unused half of its second
//! derivatives never computed, in plain arrays (no optional parts), so that a right-hand side
//! costs a few times the hand-written equations rather than ten (`mechfmu bench`).

mod functions;
mod traits;

use std::ops::{
    Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Rem, RemAssign, Sub, SubAssign,
};

/// A value with its derivatives for Lagrange's equations in `N` coordinates (see the module).
#[derive(Clone, Copy, Debug)]
pub struct Jet<const N: usize> {
    pub re: f64,
    /// `∂/∂q̇_i`
    pub v: [f64; N],
    /// `∂/∂q_i`
    pub q: [f64; N],
    /// Along the path: `Σ q̇_j ∂/∂q_j + ∂/∂t`.
    pub p: f64,
    /// `∂²/∂q̇_i∂q̇_j`, for `i ≤ j` (the upper triangle; the rest is not kept).
    pub vv: [[f64; N]; N],
    /// `∂/∂q̇_i` of the derivative along the path.
    pub vp: [f64; N],
}

impl<const N: usize> Jet<N> {
    /// A constant: no derivatives.
    #[inline(always)]
    pub fn constant(re: f64) -> Self {
        Jet {
            re,
            v: [0.0; N],
            q: [0.0; N],
            p: 0.0,
            vv: [[0.0; N]; N],
            vp: [0.0; N],
        }
    }

    /// Velocity `i` at `q_dot`: the direction `ε_v_i`.
    #[inline(always)]
    pub fn velocity(i: usize, q_dot: f64) -> Self {
        let mut jet = Self::constant(q_dot);
        jet.v[i] = 1.0;
        jet
    }

    /// Coordinate `i` at `q`, moving along the path at `q_dot`.
    #[inline(always)]
    pub fn coordinate(i: usize, q: f64, q_dot: f64) -> Self {
        let mut jet = Self::constant(q);
        jet.q[i] = 1.0;
        jet.p = q_dot;
        jet
    }

    /// The time, moving along the path at 1.
    #[inline(always)]
    pub fn time(t: f64) -> Self {
        let mut jet = Self::constant(t);
        jet.p = 1.0;
        jet
    }

    /// `f(self)` by the chain rule, from `f`, `f'` and `f''` at the value.
    #[inline(always)]
    pub(crate) fn chain(self, f0: f64, f1: f64, f2: f64) -> Self {
        let mut out = Jet {
            re: f0,
            v: self.v.map(|d| f1 * d),
            q: self.q.map(|d| f1 * d),
            p: f1 * self.p,
            vv: self.vv,
            vp: self.vp,
        };
        for i in 0..N {
            for j in i..N {
                out.vv[i][j] = f1 * self.vv[i][j] + f2 * self.v[i] * self.v[j];
            }
            out.vp[i] = f1 * self.vp[i] + f2 * self.v[i] * self.p;
        }
        out
    }
}

impl<const N: usize> Add for Jet<N> {
    type Output = Self;
    #[inline(always)]
    fn add(self, b: Self) -> Self {
        let mut out = self;
        for i in 0..N {
            out.v[i] += b.v[i];
            out.q[i] += b.q[i];
            out.vp[i] += b.vp[i];
            for j in i..N {
                out.vv[i][j] += b.vv[i][j];
            }
        }
        out.re += b.re;
        out.p += b.p;
        out
    }
}

impl<const N: usize> Neg for Jet<N> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        Jet {
            re: -self.re,
            v: self.v.map(|d| -d),
            q: self.q.map(|d| -d),
            p: -self.p,
            vv: self.vv.map(|row| row.map(|d| -d)),
            vp: self.vp.map(|d| -d),
        }
    }
}

impl<const N: usize> Sub for Jet<N> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, b: Self) -> Self {
        self + (-b)
    }
}

impl<const N: usize> Mul for Jet<N> {
    type Output = Self;
    /// The product rule, to the parts kept.
    #[inline(always)]
    fn mul(self, b: Self) -> Self {
        let a = self;
        let mut out = Jet {
            re: a.re * b.re,
            v: [0.0; N],
            q: [0.0; N],
            p: a.re * b.p + a.p * b.re,
            vv: [[0.0; N]; N],
            vp: [0.0; N],
        };
        for i in 0..N {
            out.v[i] = a.re * b.v[i] + a.v[i] * b.re;
            out.q[i] = a.re * b.q[i] + a.q[i] * b.re;
            for j in i..N {
                out.vv[i][j] =
                    a.re * b.vv[i][j] + a.vv[i][j] * b.re + (a.v[i] * b.v[j] + a.v[j] * b.v[i]);
            }
            out.vp[i] = a.re * b.vp[i] + a.vp[i] * b.re + (a.v[i] * b.p + a.p * b.v[i]);
        }
        out
    }
}

impl<const N: usize> Div for Jet<N> {
    type Output = Self;
    /// `a (1/b)`: the reciprocal by the chain rule.
    #[allow(clippy::suspicious_arithmetic_impl)]
    #[inline(always)]
    fn div(self, b: Self) -> Self {
        self * b.recip_jet()
    }
}

impl<const N: usize> Rem for Jet<N> {
    type Output = Self;
    /// `a - n b` with `n` the truncated quotient of the values (a constant where it is
    /// differentiable).
    #[inline]
    fn rem(self, b: Self) -> Self {
        self - b * Self::constant((self.re / b.re).trunc())
    }
}

macro_rules! assign {
    ($($trait:ident $method:ident $op:tt),*) => {$(
        impl<const N: usize> $trait for Jet<N> {
            #[inline(always)]
            fn $method(&mut self, b: Self) {
                *self = *self $op b;
            }
        }
    )*};
}
assign!(AddAssign add_assign +, SubAssign sub_assign -, MulAssign mul_assign *,
    DivAssign div_assign /, RemAssign rem_assign %);

impl<const N: usize> PartialEq for Jet<N> {
    /// By value, as `f64`.
    #[inline(always)]
    fn eq(&self, other: &Self) -> bool {
        self.re == other.re
    }
}

impl<const N: usize> PartialOrd for Jet<N> {
    /// By value, as `f64` (the equations take the same branches as on `f64`).
    #[inline(always)]
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        self.re.partial_cmp(&other.re)
    }
}

impl<const N: usize> std::fmt::Display for Jet<N> {
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        write!(f, "{} + jet", self.re)
    }
}
