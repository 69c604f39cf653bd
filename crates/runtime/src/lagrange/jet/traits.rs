//! What makes a jet a [`Scalar`]: nalgebra's `RealField` and the traits
//! it requires (simba's, num-traits', approx's), each on the value where it compares and
//! through the chain rule where it computes. A function without a derivative (`floor`,
//! `round`) is constant where it is differentiable.

use super::Jet;
use crate::model::Scalar;
use approx::{AbsDiffEq, RelativeEq, UlpsEq};
use nalgebra::{ComplexField, Field, RealField, SimdValue};
use num_traits::{FromPrimitive, Num, One, Signed, Zero};
use simba::scalar::{SubsetOf, SupersetOf};

impl<const N: usize> crate::model::scalar::sealed::Sealed for Jet<N> {}

impl<const N: usize> Scalar for Jet<N> {
    #[inline(always)]
    fn portable_sin_cos(self) -> (Self, Self) {
        self.sin_cos_jet()
    }
}

impl<const N: usize> Zero for Jet<N> {
    #[inline(always)]
    fn zero() -> Self {
        Self::constant(0.0)
    }
    #[inline(always)]
    fn is_zero(&self) -> bool {
        self.re == 0.0
    }
}

impl<const N: usize> One for Jet<N> {
    #[inline(always)]
    fn one() -> Self {
        Self::constant(1.0)
    }
}

impl<const N: usize> Num for Jet<N> {
    type FromStrRadixErr = <f64 as Num>::FromStrRadixErr;
    fn from_str_radix(text: &str, radix: u32) -> Result<Self, Self::FromStrRadixErr> {
        f64::from_str_radix(text, radix).map(Self::constant)
    }
}

impl<const N: usize> Signed for Jet<N> {
    #[inline]
    fn abs(&self) -> Self {
        self.abs_jet()
    }
    #[inline]
    fn abs_sub(&self, other: &Self) -> Self {
        if self.re > other.re {
            *self - *other
        } else {
            Self::zero()
        }
    }
    #[inline]
    fn signum(&self) -> Self {
        Self::constant(self.re.signum())
    }
    #[inline]
    fn is_positive(&self) -> bool {
        self.re > 0.0
    }
    #[inline]
    fn is_negative(&self) -> bool {
        self.re < 0.0
    }
}

impl<const N: usize> FromPrimitive for Jet<N> {
    fn from_i64(n: i64) -> Option<Self> {
        Some(Self::constant(n as f64))
    }
    fn from_u64(n: u64) -> Option<Self> {
        Some(Self::constant(n as f64))
    }
    fn from_f64(x: f64) -> Option<Self> {
        Some(Self::constant(x))
    }
}

impl<const N: usize> AbsDiffEq for Jet<N> {
    type Epsilon = Self;
    fn default_epsilon() -> Self {
        Self::constant(f64::default_epsilon())
    }
    fn abs_diff_eq(&self, other: &Self, epsilon: Self) -> bool {
        self.re.abs_diff_eq(&other.re, epsilon.re)
    }
}

impl<const N: usize> RelativeEq for Jet<N> {
    fn default_max_relative() -> Self {
        Self::constant(f64::default_max_relative())
    }
    fn relative_eq(&self, other: &Self, epsilon: Self, max_relative: Self) -> bool {
        self.re.relative_eq(&other.re, epsilon.re, max_relative.re)
    }
}

impl<const N: usize> UlpsEq for Jet<N> {
    fn default_max_ulps() -> u32 {
        f64::default_max_ulps()
    }
    fn ulps_eq(&self, other: &Self, epsilon: Self, max_ulps: u32) -> bool {
        self.re.ulps_eq(&other.re, epsilon.re, max_ulps)
    }
}

impl<const N: usize> SimdValue for Jet<N> {
    const LANES: usize = 1;
    type Element = Self;
    type SimdBool = bool;
    #[inline(always)]
    fn splat(value: Self) -> Self {
        value
    }
    #[inline(always)]
    fn extract(&self, _: usize) -> Self {
        *self
    }
    #[inline(always)]
    unsafe fn extract_unchecked(&self, _: usize) -> Self {
        *self
    }
    #[inline(always)]
    fn replace(&mut self, _: usize, value: Self) {
        *self = value;
    }
    #[inline(always)]
    unsafe fn replace_unchecked(&mut self, _: usize, value: Self) {
        *self = value;
    }
    #[inline(always)]
    fn select(self, condition: bool, other: Self) -> Self {
        if condition {
            self
        } else {
            other
        }
    }
}

impl<const N: usize> SubsetOf<Jet<N>> for Jet<N> {
    #[inline(always)]
    fn to_superset(&self) -> Self {
        *self
    }
    #[inline(always)]
    fn from_superset_unchecked(element: &Self) -> Self {
        *element
    }
    #[inline(always)]
    fn is_in_subset(_: &Self) -> bool {
        true
    }
}

impl<const N: usize> SupersetOf<f64> for Jet<N> {
    #[inline(always)]
    fn is_in_subset(&self) -> bool {
        true
    }
    #[inline(always)]
    fn to_subset_unchecked(&self) -> f64 {
        self.re
    }
    #[inline(always)]
    fn from_subset(element: &f64) -> Self {
        Self::constant(*element)
    }
}

impl<const N: usize> SupersetOf<f32> for Jet<N> {
    #[inline(always)]
    fn is_in_subset(&self) -> bool {
        true
    }
    #[inline(always)]
    fn to_subset_unchecked(&self) -> f32 {
        self.re as f32
    }
    #[inline(always)]
    fn from_subset(element: &f32) -> Self {
        Self::constant(f64::from(*element))
    }
}

impl<const N: usize> Field for Jet<N> {}

/// A function with no derivative where it is differentiable: its value, as a constant.
/// The value is `libm`'s: `f64::floor` and its kin are calls of the C library on x86-64.
macro_rules! constant_of {
    ($($name:ident),*) => {$(
        #[inline]
        fn $name(self) -> Self {
            Self::constant(libm::$name(self.re))
        }
    )*};
}

impl<const N: usize> ComplexField for Jet<N> {
    type RealField = Self;
    fn from_real(re: Self) -> Self {
        re
    }
    fn real(self) -> Self {
        self
    }
    fn imaginary(self) -> Self {
        Self::zero()
    }
    fn modulus(self) -> Self {
        self.abs_jet()
    }
    fn modulus_squared(self) -> Self {
        self * self
    }
    fn argument(self) -> Self {
        if self.re < 0.0 {
            Self::constant(std::f64::consts::PI)
        } else {
            Self::zero()
        }
    }
    fn norm1(self) -> Self {
        self.abs_jet()
    }
    fn scale(self, factor: Self) -> Self {
        self * factor
    }
    fn unscale(self, factor: Self) -> Self {
        self / factor
    }
    constant_of!(floor, ceil, round, trunc);
    fn fract(self) -> Self {
        self - Self::constant(libm::trunc(self.re))
    }
    fn mul_add(self, a: Self, b: Self) -> Self {
        self * a + b
    }
    fn abs(self) -> Self {
        self.abs_jet()
    }
    fn hypot(self, other: Self) -> Self {
        (self * self + other * other).sqrt_jet()
    }
    #[inline(always)]
    fn recip(self) -> Self {
        self.recip_jet()
    }
    fn conjugate(self) -> Self {
        self
    }
    #[inline(always)]
    fn sin(self) -> Self {
        self.sin_cos_jet().0
    }
    #[inline(always)]
    fn cos(self) -> Self {
        self.sin_cos_jet().1
    }
    #[inline(always)]
    fn sin_cos(self) -> (Self, Self) {
        self.sin_cos_jet()
    }
    fn tan(self) -> Self {
        self.tan_jet()
    }
    fn asin(self) -> Self {
        self.asin_jet()
    }
    fn acos(self) -> Self {
        self.acos_jet()
    }
    fn atan(self) -> Self {
        self.atan_jet()
    }
    fn sinh(self) -> Self {
        self.sinh_jet()
    }
    fn cosh(self) -> Self {
        self.cosh_jet()
    }
    fn tanh(self) -> Self {
        self.tanh_jet()
    }
    fn asinh(self) -> Self {
        self.asinh_jet()
    }
    fn acosh(self) -> Self {
        self.acosh_jet()
    }
    fn atanh(self) -> Self {
        self.atanh_jet()
    }
    fn log(self, base: Self) -> Self {
        self.ln_jet() / base.ln_jet()
    }
    fn log2(self) -> Self {
        self.ln_jet() * Self::constant(std::f64::consts::LOG2_E)
    }
    fn log10(self) -> Self {
        self.ln_jet() * Self::constant(std::f64::consts::LOG10_E)
    }
    fn ln(self) -> Self {
        self.ln_jet()
    }
    fn ln_1p(self) -> Self {
        self.ln_1p_jet()
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        self.sqrt_jet()
    }
    fn exp(self) -> Self {
        self.exp_jet()
    }
    fn exp2(self) -> Self {
        self.exp2_jet()
    }
    fn exp_m1(self) -> Self {
        self.exp_m1_jet()
    }
    fn powi(self, n: i32) -> Self {
        self.powi_jet(n)
    }
    fn powf(self, n: Self) -> Self {
        if n.is_constant() {
            self.powf_constant(n.re)
        } else {
            (self.ln_jet() * n).exp_jet()
        }
    }
    fn powc(self, n: Self) -> Self {
        self.powf(n)
    }
    fn cbrt(self) -> Self {
        self.cbrt_jet()
    }
    fn is_finite(&self) -> bool {
        self.re.is_finite()
    }
    fn try_sqrt(self) -> Option<Self> {
        (self.re >= 0.0).then(|| self.sqrt_jet())
    }
}

/// A constant of `f64`, as a jet.
macro_rules! constants {
    ($($name:ident),*) => {$(
        fn $name() -> Self {
            Self::constant(f64::$name())
        }
    )*};
}

impl<const N: usize> RealField for Jet<N> {
    fn is_sign_positive(&self) -> bool {
        self.re.is_sign_positive()
    }
    fn is_sign_negative(&self) -> bool {
        self.re.is_sign_negative()
    }
    fn copysign(self, sign: Self) -> Self {
        if sign.re.is_sign_positive() == self.re.is_sign_positive() {
            self
        } else {
            -self
        }
    }
    fn max(self, other: Self) -> Self {
        if other.re > self.re {
            other
        } else {
            self
        }
    }
    fn min(self, other: Self) -> Self {
        if other.re < self.re {
            other
        } else {
            self
        }
    }
    fn clamp(self, min: Self, max: Self) -> Self {
        RealField::min(RealField::max(self, min), max)
    }
    fn atan2(self, other: Self) -> Self {
        self.atan2_jet(other)
    }
    fn min_value() -> Option<Self> {
        Some(Self::constant(f64::MIN))
    }
    fn max_value() -> Option<Self> {
        Some(Self::constant(f64::MAX))
    }
    constants!(
        pi,
        two_pi,
        frac_pi_2,
        frac_pi_3,
        frac_pi_4,
        frac_pi_6,
        frac_pi_8,
        frac_1_pi,
        frac_2_pi,
        frac_2_sqrt_pi,
        e,
        log2_e,
        log10_e,
        ln_2,
        ln_10
    );
}
