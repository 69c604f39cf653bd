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
//! equations do not use never computed, in plain arrays, each entry of each part marked
//! zero or not, so that a step costs 1.2 to 1.9 times the hand-written equations' rather
//! than ten (`mechfmu bench --instructions`).

mod functions;
mod traits;

use std::ops::{
    Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Rem, RemAssign, Sub, SubAssign,
};

/// Which entries of a jet's parts may be nonzero: one bit per index (bit `i` for `v[i]`,
/// `q[i]`, `vp[i]`; for `vv`, bit `i` when row and column `i` may hold nonzeros, so `vv[i][j]`
/// may be nonzero only where both bits are set). An entry whose bit is clear is zero, and the
/// arithmetic skips it. The masks are integers, so where `T` is inlined into the solver the
/// compiler knows them and drops the skipped work altogether: a jet of one coordinate
/// multiplies one entry of each part, not `N` (it cannot drop a product by a zero
/// derivative: `x * 0.0` is not `0.0` when `x` is infinite or NaN). With more than 64
/// coordinates every bit stands for every index: the parts are skipped whole or not at all.
type Mask = u64;

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
    /// Where `v`, `q`, `vv` and `vp` may be nonzero (see [`Mask`]), and whether `p` may be.
    v_mask: Mask,
    q_mask: Mask,
    vv_mask: Mask,
    vp_mask: Mask,
    has_p: bool,
}

/// Whether index `i` may be nonzero in a part with mask `mask`.
#[inline(always)]
fn may<const N: usize>(mask: Mask, i: usize) -> bool {
    if N > Mask::BITS as usize {
        mask != 0
    } else {
        (mask >> i) & 1 == 1
    }
}

/// The mask of index `i` alone.
#[inline(always)]
fn only<const N: usize>(i: usize) -> Mask {
    if N > Mask::BITS as usize {
        Mask::MAX
    } else {
        1 << i
    }
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
            v_mask: 0,
            q_mask: 0,
            vv_mask: 0,
            vp_mask: 0,
            has_p: false,
        }
    }

    /// Velocity `i` at `q_dot`: the direction `ε_v_i`.
    #[inline(always)]
    pub fn velocity(i: usize, q_dot: f64) -> Self {
        let mut jet = Self::constant(q_dot);
        jet.v[i] = 1.0;
        jet.v_mask = only::<N>(i);
        jet
    }

    /// Coordinate `i` at `q`, moving along the path at `q_dot`.
    #[inline(always)]
    pub fn coordinate(i: usize, q: f64, q_dot: f64) -> Self {
        let mut jet = Self::constant(q);
        jet.q[i] = 1.0;
        jet.q_mask = only::<N>(i);
        jet.p = q_dot;
        jet.has_p = true;
        jet
    }

    /// The time, moving along the path at 1.
    #[inline(always)]
    pub fn time(t: f64) -> Self {
        let mut jet = Self::constant(t);
        jet.p = 1.0;
        jet.has_p = true;
        jet
    }

    /// Whether every derivative is zero.
    #[inline(always)]
    pub(crate) fn is_constant(&self) -> bool {
        (self.v_mask | self.q_mask | self.vv_mask | self.vp_mask) == 0 && !self.has_p
    }

    /// `f(self)` by the chain rule, from `f`, `f'` and `f''` at the value.
    #[inline(always)]
    pub(crate) fn chain(self, f0: f64, f1: f64, f2: f64) -> Self {
        let mut out = self.scaled(f1);
        out.re = f0;
        // The second-order terms f'' a' a' the first derivatives add.
        if self.v_mask != 0 {
            out.vv_mask |= self.v_mask;
            for i in 0..N {
                for j in i..N {
                    if may::<N>(self.v_mask, i) && may::<N>(self.v_mask, j) {
                        let square = f2 * self.v[i] * self.v[j];
                        out.vv[i][j] = if may::<N>(self.vv_mask, i) && may::<N>(self.vv_mask, j) {
                            out.vv[i][j] + square
                        } else {
                            square
                        };
                    }
                }
            }
            if self.has_p {
                out.vp_mask |= self.v_mask;
                for i in 0..N {
                    if may::<N>(self.v_mask, i) {
                        let cross = f2 * self.v[i] * self.p;
                        out.vp[i] = if may::<N>(self.vp_mask, i) {
                            out.vp[i] + cross
                        } else {
                            cross
                        };
                    }
                }
            }
        }
        out
    }

    /// `self` times the constant `c`.
    #[inline(always)]
    fn scaled(self, c: f64) -> Self {
        let mut out = self;
        out.re = self.re * c;
        for i in 0..N {
            if may::<N>(self.v_mask, i) {
                out.v[i] = c * self.v[i];
            }
            if may::<N>(self.q_mask, i) {
                out.q[i] = c * self.q[i];
            }
            if may::<N>(self.vp_mask, i) {
                out.vp[i] = c * self.vp[i];
            }
            for j in i..N {
                if may::<N>(self.vv_mask, i) && may::<N>(self.vv_mask, j) {
                    out.vv[i][j] = c * self.vv[i][j];
                }
            }
        }
        if self.has_p {
            out.p = c * self.p;
        }
        out
    }
}

/// `a + b` where `a` and `b` may be nonzero as their masks say: added where both may be.
#[inline(always)]
fn sum(a: f64, a_may: bool, b: f64, b_may: bool) -> f64 {
    match (a_may, b_may) {
        (true, true) => a + b,
        (true, false) => a,
        _ => b,
    }
}

impl<const N: usize> Add for Jet<N> {
    type Output = Self;
    #[inline(always)]
    fn add(self, b: Self) -> Self {
        let a = self;
        let mut out = Self::constant(a.re + b.re);
        for i in 0..N {
            out.v[i] = sum(a.v[i], may::<N>(a.v_mask, i), b.v[i], may::<N>(b.v_mask, i));
            out.q[i] = sum(a.q[i], may::<N>(a.q_mask, i), b.q[i], may::<N>(b.q_mask, i));
            out.vp[i] = sum(
                a.vp[i],
                may::<N>(a.vp_mask, i),
                b.vp[i],
                may::<N>(b.vp_mask, i),
            );
            for j in i..N {
                let a_may = may::<N>(a.vv_mask, i) && may::<N>(a.vv_mask, j);
                let b_may = may::<N>(b.vv_mask, i) && may::<N>(b.vv_mask, j);
                out.vv[i][j] = sum(a.vv[i][j], a_may, b.vv[i][j], b_may);
            }
        }
        out.p = sum(a.p, a.has_p, b.p, b.has_p);
        out.v_mask = a.v_mask | b.v_mask;
        out.q_mask = a.q_mask | b.q_mask;
        out.vv_mask = a.vv_mask | b.vv_mask;
        out.vp_mask = a.vp_mask | b.vp_mask;
        out.has_p = a.has_p | b.has_p;
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
    /// The product rule, to the parts kept, on the entries either factor may have.
    #[inline(always)]
    fn mul(self, b: Self) -> Self {
        let a = self;
        if a.is_constant() {
            return b.scaled(a.re);
        }
        if b.is_constant() {
            return a.scaled(b.re);
        }
        // (a0 + a') (b0 + b') = a0 b0 + a0 b' + b0 a' + a' b': the first-order parts of the
        // last term are the only second-order products kept (v v and v p).
        let mut out = a.scaled(b.re) + b.scaled(a.re);
        out.re = a.re * b.re;
        if a.v_mask != 0 && b.v_mask != 0 {
            let before = out.vv_mask;
            out.vv_mask |= a.v_mask | b.v_mask;
            for i in 0..N {
                for j in i..N {
                    // a_i b_j + a_j b_i, from the terms that may be nonzero.
                    let ab = may::<N>(a.v_mask, i) && may::<N>(b.v_mask, j);
                    let ba = may::<N>(a.v_mask, j) && may::<N>(b.v_mask, i);
                    let cross = match (ab, ba) {
                        (true, true) => a.v[i] * b.v[j] + a.v[j] * b.v[i],
                        (true, false) => a.v[i] * b.v[j],
                        (false, true) => a.v[j] * b.v[i],
                        (false, false) => continue,
                    };
                    out.vv[i][j] = if may::<N>(before, i) && may::<N>(before, j) {
                        out.vv[i][j] + cross
                    } else {
                        cross
                    };
                }
            }
        }
        let (avbp, apbv) = (a.v_mask != 0 && b.has_p, a.has_p && b.v_mask != 0);
        if avbp || apbv {
            let before = out.vp_mask;
            out.vp_mask |= (if avbp { a.v_mask } else { 0 }) | (if apbv { b.v_mask } else { 0 });
            for i in 0..N {
                let ap = avbp && may::<N>(a.v_mask, i);
                let pa = apbv && may::<N>(b.v_mask, i);
                let cross = match (ap, pa) {
                    (true, true) => a.v[i] * b.p + a.p * b.v[i],
                    (true, false) => a.v[i] * b.p,
                    (false, true) => a.p * b.v[i],
                    (false, false) => continue,
                };
                out.vp[i] = if may::<N>(before, i) {
                    out.vp[i] + cross
                } else {
                    cross
                };
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
        let mut out = if b.is_constant() {
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
