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
//! It is what a general hyper-dual vector would give with the second derivatives the
//! equations do not use never computed, in plain arrays, each part marked zero or not, so
//! that a right-hand side costs one to two and a half times the hand-written equations'
//! rather than ten (`mechfmu bench --instructions`).

mod functions;
mod traits;

use std::ops::{
    Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Rem, RemAssign, Sub, SubAssign,
};

/// Which parts of a jet may be nonzero: bits of [`Jet::parts`]. A part whose bit is clear is
/// all zeros, and the arithmetic skips it. The bits are integers, so where `T` is inlined into
/// the solver the compiler knows them and drops the skipped work altogether (it cannot drop
/// a product by a zero derivative: `x * 0.0` is not `0.0` when `x` is infinite or NaN).
mod part {
    pub const V: u8 = 1;
    pub const Q: u8 = 2;
    pub const P: u8 = 4;
    pub const VV: u8 = 8;
    pub const VP: u8 = 16;
}

/// A value with its derivatives for Lagrange's equations in `N` coordinates (see the module).
#[derive(Clone, Copy, Debug)]
pub struct Jet<const N: usize> {
    pub(crate) re: f64,
    /// `∂/∂q̇_i`
    pub(crate) v: [f64; N],
    /// `∂/∂q_i`
    pub(crate) q: [f64; N],
    /// Along the path: `Σ q̇_j ∂/∂q_j + ∂/∂t`.
    pub(crate) p: f64,
    /// `∂²/∂q̇_i∂q̇_j`, for `i ≤ j` (the upper triangle; the rest is not kept).
    pub(crate) vv: [[f64; N]; N],
    /// `∂/∂q̇_i` of the derivative along the path.
    pub(crate) vp: [f64; N],
    /// Which parts may be nonzero (bits of `part`); the others are zeros.
    parts: u8,
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
            parts: 0,
        }
    }

    /// Velocity `i` at `q_dot`: the direction `ε_v_i`.
    #[inline(always)]
    pub fn velocity(i: usize, q_dot: f64) -> Self {
        let mut jet = Self::constant(q_dot);
        jet.v[i] = 1.0;
        jet.parts = part::V;
        jet
    }

    /// Coordinate `i` at `q`, moving along the path at `q_dot`.
    #[inline(always)]
    pub fn coordinate(i: usize, q: f64, q_dot: f64) -> Self {
        let mut jet = Self::constant(q);
        jet.q[i] = 1.0;
        jet.p = q_dot;
        jet.parts = part::Q | part::P;
        jet
    }

    /// The time, moving along the path at 1.
    #[inline(always)]
    pub fn time(t: f64) -> Self {
        let mut jet = Self::constant(t);
        jet.p = 1.0;
        jet.parts = part::P;
        jet
    }

    #[inline(always)]
    fn has(&self, bits: u8) -> bool {
        self.parts & bits != 0
    }

    /// `f(self)` by the chain rule, from `f`, `f'` and `f''` at the value.
    #[inline(always)]
    pub(crate) fn chain(self, f0: f64, f1: f64, f2: f64) -> Self {
        let mut out = Self::constant(f0);
        out.parts = self.parts;
        if self.has(part::V) {
            out.v = self.v.map(|d| f1 * d);
            out.parts |= part::VV;
            for i in 0..N {
                for j in i..N {
                    out.vv[i][j] = f1 * self.vv[i][j] + f2 * self.v[i] * self.v[j];
                }
            }
        } else if self.has(part::VV) {
            out.vv = self.vv.map(|row| row.map(|d| f1 * d));
        }
        if self.has(part::Q) {
            out.q = self.q.map(|d| f1 * d);
        }
        if self.has(part::P) {
            out.p = f1 * self.p;
        }
        if self.has(part::V) && self.has(part::P) {
            out.parts |= part::VP;
            for i in 0..N {
                out.vp[i] = f1 * self.vp[i] + f2 * self.v[i] * self.p;
            }
        } else if self.has(part::VP) {
            out.vp = self.vp.map(|d| f1 * d);
        }
        out
    }

    /// `self` times the constant `c`.
    #[inline(always)]
    fn scaled(self, c: f64) -> Self {
        let mut out = Self::constant(self.re * c);
        out.parts = self.parts;
        if self.has(part::V) {
            out.v = self.v.map(|d| c * d);
        }
        if self.has(part::Q) {
            out.q = self.q.map(|d| c * d);
        }
        if self.has(part::P) {
            out.p = c * self.p;
        }
        if self.has(part::VV) {
            out.vv = self.vv.map(|row| row.map(|d| c * d));
        }
        if self.has(part::VP) {
            out.vp = self.vp.map(|d| c * d);
        }
        out
    }
}

/// `a + b`, part by part, adding only where both have the part.
#[inline(always)]
fn sum<const K: usize>(a: [f64; K], a_has: bool, b: [f64; K], b_has: bool) -> [f64; K] {
    match (a_has, b_has) {
        (true, true) => std::array::from_fn(|i| a[i] + b[i]),
        (true, false) => a,
        _ => b,
    }
}

impl<const N: usize> Add for Jet<N> {
    type Output = Self;
    #[inline(always)]
    fn add(self, b: Self) -> Self {
        let a = self;
        let both = |bits| (a.has(bits), b.has(bits));
        let (av, bv) = both(part::V);
        let (aq, bq) = both(part::Q);
        let (ap, bp) = both(part::P);
        let (avv, bvv) = both(part::VV);
        let (avp, bvp) = both(part::VP);
        let mut out = Self::constant(a.re + b.re);
        out.parts = a.parts | b.parts;
        out.v = sum(a.v, av, b.v, bv);
        out.q = sum(a.q, aq, b.q, bq);
        out.p = sum([a.p], ap, [b.p], bp)[0];
        out.vp = sum(a.vp, avp, b.vp, bvp);
        out.vv = match (avv, bvv) {
            (true, true) => std::array::from_fn(|i| sum(a.vv[i], true, b.vv[i], true)),
            (true, false) => a.vv,
            _ => b.vv,
        };
        out
    }
}

impl<const N: usize> Neg for Jet<N> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        self.scaled(-1.0)
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
    /// The product rule, to the parts kept, on the parts either factor has.
    #[inline(always)]
    fn mul(self, b: Self) -> Self {
        let a = self;
        if a.parts == 0 {
            return b.scaled(a.re);
        }
        if b.parts == 0 {
            return a.scaled(b.re);
        }
        // (a0 + a') (b0 + b') = a0 b0 + a0 b' + b0 a' + a' b': the first-order parts of the
        // last term are the only second-order products kept (v v and v p).
        let mut out = a.scaled(b.re) + b.scaled(a.re);
        out.re = a.re * b.re;
        if a.has(part::V) && b.has(part::V) {
            out.parts |= part::VV;
            for i in 0..N {
                for j in i..N {
                    out.vv[i][j] += a.v[i] * b.v[j] + a.v[j] * b.v[i];
                }
            }
        }
        let (avbp, apbv) = (
            a.has(part::V) && b.has(part::P),
            a.has(part::P) && b.has(part::V),
        );
        if avbp || apbv {
            out.parts |= part::VP;
            for i in 0..N {
                let cross = match (avbp, apbv) {
                    (true, true) => a.v[i] * b.p + a.p * b.v[i],
                    (true, false) => a.v[i] * b.p,
                    _ => a.p * b.v[i],
                };
                out.vp[i] += cross;
            }
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
        let mut out = if b.parts == 0 {
            self.scaled(1.0 / b.re)
        } else {
            self * b.recip_jet()
        };
        // The value itself divided, as on f64.
        out.re = self.re / b.re;
        out
    }
}

impl<const N: usize> Rem for Jet<N> {
    type Output = Self;
    /// `a - n b` with `n` the truncated quotient of the values (a constant where it is
    /// differentiable).
    #[inline]
    fn rem(self, b: Self) -> Self {
        self - b.scaled(libm::trunc(self.re / b.re))
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
