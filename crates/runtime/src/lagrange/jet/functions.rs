//! The elementary functions on jets: the value and the chain rule with the first two
//! derivatives, from `libm` and the runtime's `sin_cos` (the same bits on every platform).

use super::Jet;
use crate::model::trig;

impl<const N: usize> Jet<N> {
    #[inline(always)]
    pub(crate) fn recip_jet(self) -> Self {
        let r = 1.0 / self.re;
        self.chain(r, -r * r, 2.0 * r * r * r)
    }

    #[inline(always)]
    pub(crate) fn sin_cos_jet(self) -> (Self, Self) {
        let (s, c) = trig::sin_cos(self.re);
        (self.chain(s, c, -s), self.chain(c, -s, -c))
    }

    #[inline]
    pub(crate) fn sqrt_jet(self) -> Self {
        let r = libm::sqrt(self.re);
        let d = 0.5 / r;
        self.chain(r, d, -0.5 * d / self.re)
    }

    #[inline]
    pub(crate) fn exp_jet(self) -> Self {
        let e = libm::exp(self.re);
        self.chain(e, e, e)
    }

    #[inline]
    pub(crate) fn ln_jet(self) -> Self {
        let r = 1.0 / self.re;
        self.chain(libm::log(self.re), r, -r * r)
    }

    #[inline]
    pub(crate) fn powi_jet(self, n: i32) -> Self {
        match n {
            0 => Self::constant(1.0),
            1 => self,
            2 => self * self,
            _ => {
                let x = self.re;
                let n = n as f64;
                self.chain(
                    libm::pow(x, n),
                    n * libm::pow(x, n - 1.0),
                    n * (n - 1.0) * libm::pow(x, n - 2.0),
                )
            }
        }
    }

    #[inline]
    pub(crate) fn tan_jet(self) -> Self {
        let t = libm::tan(self.re);
        let d = 1.0 + t * t;
        self.chain(t, d, 2.0 * t * d)
    }

    #[inline]
    pub(crate) fn asin_jet(self) -> Self {
        let x = self.re;
        let d = 1.0 / libm::sqrt(1.0 - x * x);
        self.chain(libm::asin(x), d, x * d * d * d)
    }

    #[inline]
    pub(crate) fn acos_jet(self) -> Self {
        let x = self.re;
        let d = 1.0 / libm::sqrt(1.0 - x * x);
        self.chain(libm::acos(x), -d, -x * d * d * d)
    }

    #[inline]
    pub(crate) fn atan_jet(self) -> Self {
        let x = self.re;
        let d = 1.0 / (1.0 + x * x);
        self.chain(libm::atan(x), d, -2.0 * x * d * d)
    }

    /// `atan2(self, x)`: the derivatives of `atan(y/x)` (or of `-atan(x/y)` where `|y| > |x|`,
    /// which differs by a constant), the value `libm`'s `atan2`.
    #[inline]
    pub(crate) fn atan2_jet(self, x: Self) -> Self {
        let y = self;
        let mut angle = if x.re.abs() >= y.re.abs() {
            (y / x).atan_jet()
        } else {
            -(x / y).atan_jet()
        };
        angle.re = libm::atan2(y.re, x.re);
        angle
    }

    #[inline]
    pub(crate) fn sinh_jet(self) -> Self {
        let (s, c) = (libm::sinh(self.re), libm::cosh(self.re));
        self.chain(s, c, s)
    }

    #[inline]
    pub(crate) fn cosh_jet(self) -> Self {
        let (s, c) = (libm::sinh(self.re), libm::cosh(self.re));
        self.chain(c, s, c)
    }

    #[inline]
    pub(crate) fn tanh_jet(self) -> Self {
        let t = libm::tanh(self.re);
        let d = 1.0 - t * t;
        self.chain(t, d, -2.0 * t * d)
    }

    #[inline]
    pub(crate) fn asinh_jet(self) -> Self {
        let x = self.re;
        let d = 1.0 / libm::sqrt(x * x + 1.0);
        self.chain(libm::asinh(x), d, -x * d * d * d)
    }

    #[inline]
    pub(crate) fn acosh_jet(self) -> Self {
        let x = self.re;
        let d = 1.0 / libm::sqrt(x * x - 1.0);
        self.chain(libm::acosh(x), d, -x * d * d * d)
    }

    #[inline]
    pub(crate) fn atanh_jet(self) -> Self {
        let x = self.re;
        let d = 1.0 / (1.0 - x * x);
        self.chain(libm::atanh(x), d, 2.0 * x * d * d)
    }

    #[inline]
    pub(crate) fn ln_1p_jet(self) -> Self {
        let d = 1.0 / (1.0 + self.re);
        self.chain(libm::log1p(self.re), d, -d * d)
    }

    #[inline]
    pub(crate) fn exp2_jet(self) -> Self {
        let e = libm::exp2(self.re);
        let ln2 = std::f64::consts::LN_2;
        self.chain(e, ln2 * e, ln2 * ln2 * e)
    }

    #[inline]
    pub(crate) fn exp_m1_jet(self) -> Self {
        let e = libm::exp(self.re);
        self.chain(libm::expm1(self.re), e, e)
    }

    #[inline]
    pub(crate) fn cbrt_jet(self) -> Self {
        let c = libm::cbrt(self.re);
        // 1/(3 c²) rather than c/(3x): infinite at 0, as the derivative is, not NaN.
        let d = 1.0 / (3.0 * c * c);
        self.chain(c, d, -2.0 * d / (3.0 * self.re))
    }

    /// `self^n` for a constant `n`: defined for a negative base where `n` is an integer, as
    /// on `f64` (`exp(n ln x)` is not).
    #[inline]
    pub(crate) fn powf_constant(self, n: f64) -> Self {
        let x = self.re;
        self.chain(
            libm::pow(x, n),
            n * libm::pow(x, n - 1.0),
            n * (n - 1.0) * libm::pow(x, n - 2.0),
        )
    }

    #[inline]
    pub(crate) fn abs_jet(self) -> Self {
        if self.re < 0.0 {
            -self
        } else {
            self
        }
    }
}
