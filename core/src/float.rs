//! The float types the kernel runs on, and the only maths it calls.
//!
//! Every transcendental function goes through [`Float`], which forwards to the
//! `libm` crate (never to the platform's maths library), so a seeded run gives
//! bit-identical results on x86_64, wasm32 and Cortex-M. With the `micromath`
//! feature, [`Float::fast_sin_cos`] of `f32` (the sine and cosine of Levy and
//! of Rastrigin's fallback for huge arguments) is micromath's approximation
//! instead.

use core::fmt::{Debug, Display};
use core::ops::{Add, AddAssign, Div, Mul, MulAssign, Neg, Sub, SubAssign};

use crate::normal::StandardNormal;

mod private {
    pub trait Sealed {}
    impl Sealed for f32 {}
    impl Sealed for f64 {}
}

/// A floating-point type the kernel can run on: `f32` or `f64` (sealed).
///
/// Arithmetic, conversions and `libm`'s functions; the normal sampler is
/// the supertrait [`StandardNormal`].
pub trait Float:
    private::Sealed
    + StandardNormal
    + Copy
    + Default
    + Debug
    + Display
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
    + Send
    + Sync
    + 'static
{
    /// 0.
    const ZERO: Self;
    /// 1.
    const ONE: Self;
    /// 2.
    const TWO: Self;
    /// 1/2.
    const HALF: Self;
    /// π.
    const PI: Self;
    /// Positive infinity.
    const INFINITY: Self;
    /// The largest finite value.
    const MAX: Self;
    /// Significant bits, the implicit one included (53 for `f64`, 24 for
    /// `f32`), as `f64::MANTISSA_DIGITS`.
    const MANTISSA_DIGITS: u32;

    /// Rounds an `f64` to this type (round to nearest, as `as` does).
    fn from_f64(v: f64) -> Self;
    /// Converts an integer (rounded to nearest where it is not exact).
    fn from_u64(v: u64) -> Self;
    /// Widens to `f64` (exact).
    fn to_f64(self) -> f64;
    /// The IEEE bit pattern, widened to 64 bits: for bit-exact comparisons.
    fn to_bits_u64(self) -> u64;

    /// `true` unless NaN or infinite.
    fn is_finite(self) -> bool;
    /// Absolute value.
    fn abs(self) -> Self;
    /// Correctly rounded square root.
    fn sqrt(self) -> Self;
    /// `e^x` (libm).
    fn exp(self) -> Self;
    /// `e^x - 1`, accurate near 0 (libm).
    fn expm1(self) -> Self;
    /// Natural logarithm (libm).
    fn ln(self) -> Self;
    /// Hyperbolic sine (libm).
    fn sinh(self) -> Self;
    /// Hyperbolic cosine (libm).
    fn cosh(self) -> Self;
    /// Hyperbolic tangent (libm).
    fn tanh(self) -> Self;
    /// `(sin x, cos x)`: libm, or micromath for `f32` with the `micromath`
    /// feature.
    fn fast_sin_cos(self) -> (Self, Self);
}

impl Float for f64 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    const TWO: Self = 2.0;
    const HALF: Self = 0.5;
    const PI: Self = core::f64::consts::PI;
    const INFINITY: Self = f64::INFINITY;
    const MAX: Self = f64::MAX;
    const MANTISSA_DIGITS: u32 = f64::MANTISSA_DIGITS;

    #[inline]
    fn from_f64(v: f64) -> Self {
        v
    }
    #[inline]
    fn from_u64(v: u64) -> Self {
        v as f64
    }
    #[inline]
    fn to_f64(self) -> f64 {
        self
    }
    #[inline]
    fn to_bits_u64(self) -> u64 {
        self.to_bits()
    }
    #[inline]
    fn is_finite(self) -> bool {
        f64::is_finite(self)
    }
    #[inline]
    fn abs(self) -> Self {
        libm::fabs(self)
    }
    #[inline]
    fn sqrt(self) -> Self {
        libm::sqrt(self)
    }
    #[inline]
    fn exp(self) -> Self {
        libm::exp(self)
    }
    #[inline]
    fn expm1(self) -> Self {
        libm::expm1(self)
    }
    #[inline]
    fn ln(self) -> Self {
        libm::log(self)
    }
    #[inline]
    fn sinh(self) -> Self {
        libm::sinh(self)
    }
    #[inline]
    fn cosh(self) -> Self {
        libm::cosh(self)
    }
    #[inline]
    fn tanh(self) -> Self {
        libm::tanh(self)
    }
    #[inline]
    fn fast_sin_cos(self) -> (Self, Self) {
        libm::sincos(self)
    }
}

impl Float for f32 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    const TWO: Self = 2.0;
    const HALF: Self = 0.5;
    const PI: Self = core::f32::consts::PI;
    const INFINITY: Self = f32::INFINITY;
    const MAX: Self = f32::MAX;
    const MANTISSA_DIGITS: u32 = f32::MANTISSA_DIGITS;

    #[inline]
    fn from_f64(v: f64) -> Self {
        v as f32
    }
    #[inline]
    fn from_u64(v: u64) -> Self {
        v as f32
    }
    #[inline]
    fn to_f64(self) -> f64 {
        self as f64
    }
    #[inline]
    fn to_bits_u64(self) -> u64 {
        self.to_bits() as u64
    }
    #[inline]
    fn is_finite(self) -> bool {
        f32::is_finite(self)
    }
    #[inline]
    fn abs(self) -> Self {
        libm::fabsf(self)
    }
    #[inline]
    fn sqrt(self) -> Self {
        libm::sqrtf(self)
    }
    #[inline]
    fn exp(self) -> Self {
        libm::expf(self)
    }
    #[inline]
    fn expm1(self) -> Self {
        libm::expm1f(self)
    }
    #[inline]
    fn ln(self) -> Self {
        libm::logf(self)
    }
    #[inline]
    fn sinh(self) -> Self {
        libm::sinhf(self)
    }
    #[inline]
    fn cosh(self) -> Self {
        libm::coshf(self)
    }
    #[inline]
    fn tanh(self) -> Self {
        libm::tanhf(self)
    }
    #[cfg(not(feature = "micromath"))]
    #[inline]
    fn fast_sin_cos(self) -> (Self, Self) {
        libm::sincosf(self)
    }
    #[cfg(feature = "micromath")]
    #[inline]
    fn fast_sin_cos(self) -> (Self, Self) {
        micromath::F32Ext::sin_cos(self)
    }
}
