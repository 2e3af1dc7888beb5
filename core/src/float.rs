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
    /// The Ziggurat's wedge test decides by bounds of the density, without
    /// `exp`, only when they clear the point by this much (an absolute
    /// margin on densities `<= 1`): far above the rounding errors of either
    /// side, so the decision is always that of `exp`. Infinite (never
    /// decide without `exp`) for micromath's approximate `f32` exponential.
    const WEDGE_MARGIN: Self;
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
        let y = f_tab[i + 1] + (f_tab[i] - f_tab[i + 1]) * uniform(rng);
        if under_density(x, y, x_tab[i + 1], x_tab[i], f_tab[i + 1], f_tab[i]) {
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

/// Whether the wedge point `(x, y)` of the layer between the edges `x0 < x1`
/// (with densities `f0 = f(x0) > f1 = f(x1)`) lies under the density
/// `f(x) = exp(-x^2/2)`: the test `y < f(x)`, with `exp` only where cheap
/// bounds of `f` leave it open.
///
/// Outside the inflection at `|x| = 1` a layer's curve is convex (`|x| >= 1`:
/// below its chord, above its tangents at both edges) or concave (`|x| <= 1`:
/// the reverse). The bounds decide only with [`Float::WEDGE_MARGIN`] to
/// spare, which exceeds every rounding error of the tables, the bounds and
/// `exp`, so the answer is always the `exp` comparison's: same stream, same
/// bits, and `exp` for about 1% of wedge points in f64, 5% in f32, instead
/// of all (the unit test below counts them).
#[inline(always)]
fn under_density<F: Float>(x: F, y: F, x0: F, x1: F, f0: F, f1: F) -> bool {
    // Only on targets with float vectors (hosts, wasm SIMD): on a Cortex-M3
    // the bounds saved 0.3% of the instructions for 340 bytes of flash.
    let verdict = if trig::VECTORS {
        squeeze(x, y, x0, x1, f0, f1)
    } else {
        None
    };
    verdict.unwrap_or_else(|| y < (-x * x * F::HALF).fast_exp())
}

/// The bounds' verdict on `y < f(x)` in [`under_density`], `None` when they
/// leave it open.
#[inline(always)]
fn squeeze<F: Float>(x: F, y: F, x0: F, x1: F, f0: F, f1: F) -> Option<bool> {
    let a = x.abs();
    let chord = f0 + (f1 - f0) * ((a - x0) / (x1 - x0));
    let tangent0 = f0 * (F::ONE - x0 * (a - x0));
    let tangent1 = f1 * (F::ONE - x1 * (a - x1));
    let (lower, upper) = if x0 >= F::ONE {
        let t = if tangent0 > tangent1 {
            tangent0
        } else {
            tangent1
        };
        (t, chord)
    } else if x1 <= F::ONE {
        let t = if tangent0 < tangent1 {
            tangent0
        } else {
            tangent1
        };
        (chord, t)
    } else {
        return None;
    };
    if y < lower - F::WEDGE_MARGIN {
        Some(true)
    } else if y > upper + F::WEDGE_MARGIN {
        Some(false)
    } else {
        None
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
    const WEDGE_MARGIN: Self = 9.094947017729282e-13; // 2^-40
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
    #[cfg(not(feature = "micromath"))]
    const WEDGE_MARGIN: Self = 6.1035156e-5; // 2^-14
    #[cfg(feature = "micromath")]
    const WEDGE_MARGIN: Self = f32::INFINITY;
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

#[cfg(test)]
mod tests {
    use super::*;
    use rand_xoshiro::Xoshiro256PlusPlus;
    use rand_xoshiro::rand_core::SeedableRng;

    /// The wedge squeeze never contradicts the `exp` test, on uniform wedge
    /// points and on points within a few ulps of the curve (where only a
    /// margin too small would show), and it settles most uniform points.
    fn squeeze_agrees<F: Float>(x_tab: &[F; 257], f_tab: &[F; 257], ulp: f64) {
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(11);
        let unit =
            |rng: &mut Xoshiro256PlusPlus| (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64;
        let (mut uniform, mut settled) = (0u32, 0u32);
        for i in 1..256 {
            let (x0, x1, f0, f1) = (x_tab[i + 1], x_tab[i], f_tab[i + 1], f_tab[i]);
            for k in 0..2000 {
                // A wedge abscissa, either sign.
                let t = F::from_f64(unit(&mut rng));
                let x = (x0 + (x1 - x0) * t) * if k % 2 == 0 { F::ONE } else { -F::ONE };
                if !(x.abs() >= x0 && x.abs() <= x1) {
                    continue;
                }
                let f = (-x * x * F::HALF).fast_exp();
                let near = f * F::from_f64(1.0 + ulp * (unit(&mut rng) * 16.0 - 8.0));
                let y_uniform = f0 + (f1 - f0) * F::from_f64(unit(&mut rng));
                for y in [near, y_uniform] {
                    if let Some(verdict) = squeeze(x, y, x0, x1, f0, f1) {
                        assert_eq!(verdict, y < f, "layer {i}, x = {x}, y = {y}");
                    }
                }
                uniform += 1;
                settled += u32::from(squeeze(x, y_uniform, x0, x1, f0, f1).is_some());
            }
        }
        // Measured: 99.2% in f64, 95.3% in f32; a squeeze that settled
        // little would only add work.
        assert!(
            settled as f64 > 0.9 * uniform as f64,
            "{settled} of {uniform}"
        );
    }

    #[test]
    fn wedge_squeeze_agrees_with_exp() {
        squeeze_agrees::<f64>(&zig::X, &zig::F, f64::EPSILON);
        #[cfg(not(feature = "micromath"))]
        squeeze_agrees::<f32>(&X32, &F32, f32::EPSILON as f64);
    }
}
