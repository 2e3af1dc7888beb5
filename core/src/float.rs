//! The float types the kernel runs on, and the only maths it calls.
//!
//! Every transcendental function goes through [`Float`], which forwards to the
//! `libm` crate (never to the platform's maths library), so a seeded run gives
//! bit-identical results on x86_64, wasm32 and Cortex-M. With the `micromath`
//! feature, the `fast_*` functions of `f32` (the exponential and logarithm
//! of the normal sampler's rare branches, the sine and cosine of Levy and of
//! Rastrigin's fallback for huge arguments) use `micromath`'s approximations
//! instead; the step coefficients and Rastrigin's fused polynomial sine are
//! the same in every build.

use core::fmt::{Debug, Display};
use core::ops::{Add, AddAssign, Div, Mul, MulAssign, Neg, Sub, SubAssign};

use rand_core::Rng;

use crate::trig;

use crate::ziggurat_tables as zig;

mod private {
    pub trait Sealed {}
    impl Sealed for f32 {}
    impl Sealed for f64 {}
}

/// A floating-point type the kernel can run on: `f32` or `f64` (sealed).
pub trait Float:
    private::Sealed
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
    /// `1.5 * 2^(mantissa bits)`: `(v + M) - M` rounds `v` to the nearest
    /// integer (ties to even) for `|v| < M/3`.
    const ROUND_MAGIC: Self;
    /// Below this `|x|` the fused `sin(2πx)` takes its polynomial path.
    const TRIG_FAST_LIMIT: Self;
    /// fdlibm's minimax coefficients of `sin t` on `|t| <= π/4`, in this
    /// type, as many as its precision needs (the dropped terms are below a
    /// tenth of an ulp); Rastrigin's polynomial.
    const SIN_COEFFICIENTS: &'static [Self];
    /// The same for `cos t`.
    const COS_COEFFICIENTS: &'static [Self];

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
    /// `(sin x, cos x)` for the hot path: libm, or micromath for `f32` with
    /// the `micromath` feature.
    fn fast_sin_cos(self) -> (Self, Self);
    /// `e^x` for the hot path (see [`Float::fast_sin_cos`]).
    fn fast_exp(self) -> Self;
    /// `ln x` for the hot path (see [`Float::fast_sin_cos`]).
    fn fast_ln(self) -> Self;

    /// One exact standard normal draw (256-layer Ziggurat, ZIGNOR variant).
    ///
    /// `f64` consumes one `next_u64` per attempt (99% of draws take one);
    /// `f32` consumes `next_u32` only, so 32-bit cores never touch 64-bit
    /// arithmetic. Rare rejections and the tail draw more words.
    fn standard_normal<R: Rng + ?Sized>(rng: &mut R) -> Self;

    /// Two independent exact standard normals (the same Ziggurat), for one
    /// coordinate of a step.
    ///
    /// `f64`: two [`Float::standard_normal`] draws. `f32`: one `next_u64`,
    /// whose low then high 32 bits are the two draws' first words (a 64-bit
    /// generator's `next_u32` would throw half of its output away; a 32-bit
    /// generator's `next_u64` is two `next_u32`, low first, so the stream is
    /// the same as two draws there). Rejections draw more words as usual,
    /// the first normal's before the second's.
    fn standard_normal_pair<R: Rng + ?Sized>(rng: &mut R) -> (Self, Self);
}

/// The ZIGNOR method, shared by both float widths: `first` is the first
/// word's layer index and uniform on [-1, 1), `draw` returns further such
/// pairs, `uniform` a uniform on [0, 1) and `open01` one on (0, 1).
///
/// The fast path (about 99% of draws: one random word, a multiply and a
/// compare) is inlined into the caller; the rest lives in a cold function.
#[inline(always)]
fn ziggurat<F: Float, R: Rng + ?Sized>(
    rng: &mut R,
    x_tab: &[F; 257],
    f_tab: &[F; 257],
    first: (usize, F),
    draw: impl Fn(&mut R) -> (usize, F),
    uniform: impl Fn(&mut R) -> F,
    open01: impl Fn(&mut R) -> F,
) -> F {
    let (i, u) = first;
    let x = u * x_tab[i];
    // Inside the layer's rectangle below the next edge: accept at once.
    if x.abs() < x_tab[i + 1] {
        return x;
    }
    ziggurat_slow(rng, x_tab, f_tab, (i, u, x), draw, uniform, open01)
}

/// The base layer's tail, the wedges, and the redraws after a rejection.
#[cold]
#[inline(never)]
fn ziggurat_slow<F: Float, R: Rng + ?Sized>(
    rng: &mut R,
    x_tab: &[F; 257],
    f_tab: &[F; 257],
    first: (usize, F, F),
    draw: impl Fn(&mut R) -> (usize, F),
    uniform: impl Fn(&mut R) -> F,
    open01: impl Fn(&mut R) -> F,
) -> F {
    let r = F::from_f64(zig::R);
    let (mut i, mut u, mut x) = first;
    loop {
        if i == 0 {
            // Base layer beyond R: Marsaglia's exact tail method.
            loop {
                let t = open01(rng).fast_ln() / r;
                let s = open01(rng).fast_ln();
                if -(s + s) >= t * t {
                    return if u < F::ZERO { t - r } else { r - t };
                }
            }
        }
        // Wedge between the rectangle and the density.
        if f_tab[i + 1] + (f_tab[i] - f_tab[i + 1]) * uniform(rng) < (-x * x * F::HALF).fast_exp() {
            return x;
        }
        // Rejected: a fresh draw, with its own fast path.
        (i, u) = draw(rng);
        x = u * x_tab[i];
        if x.abs() < x_tab[i + 1] {
            return x;
        }
    }
}

/// A Ziggurat word of `f64`: the low 8 bits pick the layer, the top 52 a
/// mantissa in [2, 4), shifted to a uniform on [-1, 1).
#[inline(always)]
fn split64(bits: u64) -> (usize, f64) {
    let u = f64::from_bits((bits >> 12) | 0x4000_0000_0000_0000) - 3.0;
    ((bits & 0xff) as usize, u)
}

/// A Ziggurat word of `f32`: the low 8 bits pick the layer, the top 23 a
/// mantissa in [2, 4), shifted to a uniform on [-1, 1).
#[inline(always)]
fn split32(bits: u32) -> (usize, f32) {
    let u = f32::from_bits((bits >> 9) | 0x4000_0000) - 3.0;
    ((bits & 0xff) as usize, u)
}

/// An `f32` normal from its first word; any further words by `next_u32`.
#[inline(always)]
fn normal32<R: Rng + ?Sized>(rng: &mut R, first: (usize, f32)) -> f32 {
    ziggurat(
        rng,
        &X32,
        &F32,
        first,
        |rng| split32(rng.next_u32()),
        |rng| (rng.next_u32() >> 8) as f32 * (1.0 / (1u32 << 24) as f32),
        |rng| ((rng.next_u32() >> 9) as f32 + 0.5) * (1.0 / (1u32 << 23) as f32),
    )
}

/// The first four coefficients, rounded to f32 once, at compile time.
const fn narrow4(t: &[f64; 6]) -> [f32; 4] {
    [t[0] as f32, t[1] as f32, t[2] as f32, t[3] as f32]
}

const fn narrow(t: &[f64; 257]) -> [f32; 257] {
    let mut out = [0.0f32; 257];
    let mut i = 0;
    while i < 257 {
        out[i] = t[i] as f32;
        i += 1;
    }
    out
}

static X32: [f32; 257] = narrow(&zig::X);
static F32: [f32; 257] = narrow(&zig::F);

impl Float for f64 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    const TWO: Self = 2.0;
    const HALF: Self = 0.5;
    const PI: Self = core::f64::consts::PI;
    const INFINITY: Self = f64::INFINITY;
    const ROUND_MAGIC: Self = 6755399441055744.0;
    const TRIG_FAST_LIMIT: Self = 562949953421312.0; // 2^49
    const SIN_COEFFICIENTS: &'static [Self] = &trig::SIN;
    const COS_COEFFICIENTS: &'static [Self] = &trig::COS;

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
    #[inline]
    fn fast_exp(self) -> Self {
        libm::exp(self)
    }
    #[inline]
    fn fast_ln(self) -> Self {
        libm::log(self)
    }

    #[inline(always)]
    fn standard_normal<R: Rng + ?Sized>(rng: &mut R) -> Self {
        let first = split64(rng.next_u64());
        ziggurat(
            rng,
            &zig::X,
            &zig::F,
            first,
            |rng| split64(rng.next_u64()),
            |rng| (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64),
            |rng| ((rng.next_u64() >> 11) as f64 + 0.5) * (1.0 / (1u64 << 53) as f64),
        )
    }

    #[inline(always)]
    fn standard_normal_pair<R: Rng + ?Sized>(rng: &mut R) -> (Self, Self) {
        let z1 = Self::standard_normal(rng);
        (z1, Self::standard_normal(rng))
    }
}

impl Float for f32 {
    const ZERO: Self = 0.0;
    const ONE: Self = 1.0;
    const TWO: Self = 2.0;
    const HALF: Self = 0.5;
    const PI: Self = core::f32::consts::PI;
    const INFINITY: Self = f32::INFINITY;
    const ROUND_MAGIC: Self = 12582912.0;
    const TRIG_FAST_LIMIT: Self = 1048576.0; // 2^20
    const SIN_COEFFICIENTS: &'static [Self] = &narrow4(&trig::SIN);
    const COS_COEFFICIENTS: &'static [Self] = &narrow4(&trig::COS);

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
    #[cfg(not(feature = "micromath"))]
    #[inline]
    fn fast_exp(self) -> Self {
        libm::expf(self)
    }
    #[cfg(not(feature = "micromath"))]
    #[inline]
    fn fast_ln(self) -> Self {
        libm::logf(self)
    }
    #[cfg(feature = "micromath")]
    #[inline]
    fn fast_sin_cos(self) -> (Self, Self) {
        micromath::F32Ext::sin_cos(self)
    }
    #[cfg(feature = "micromath")]
    #[inline]
    fn fast_exp(self) -> Self {
        micromath::F32Ext::exp(self)
    }
    #[cfg(feature = "micromath")]
    #[inline]
    fn fast_ln(self) -> Self {
        micromath::F32Ext::ln(self)
    }

    #[inline(always)]
    fn standard_normal<R: Rng + ?Sized>(rng: &mut R) -> Self {
        let first = split32(rng.next_u32());
        normal32(rng, first)
    }

    #[inline(always)]
    fn standard_normal_pair<R: Rng + ?Sized>(rng: &mut R) -> (Self, Self) {
        let bits = rng.next_u64();
        let z1 = normal32(rng, split32(bits as u32));
        (z1, normal32(rng, split32((bits >> 32) as u32)))
    }
}
