//! `sin(2πx)` and `1 - cos(2πx)` for a block of coordinates at once: the
//! trigonometry of Rastrigin, fused and branch-free so that the compiler
//! vectorises it.
//!
//! Reduction: `n = round(2x)` and `r = x - n/2` (exact: `n/2` is the nearest
//! half-integer to `x`, and `|r| <= 1/4`), so `πx = nπ/2 + πr` with
//! `t = πr` in `[-π/4, π/4]`. There `s = sin t` and `c = cos t` are fdlibm's
//! minimax polynomials (`__kernel_sin`, `__kernel_cos`: error below
//! `2^-58`), and the double-angle formulas need no quadrant table:
//!
//! - `n` even: `sin(2πx) = 2sc`, `1 - cos(2πx) = 2s^2`;
//! - `n` odd: `sin(2πx) = -2sc`, `1 - cos(2πx) = 2c^2`.
//!
//! `1 - cos` is a square, so it keeps full relative accuracy near the
//! integers (where Rastrigin's value is small) without any cancellation.
//! Only IEEE additions and multiplications are used, so the result is
//! bit-identical on every target. Arguments too large for the rounding trick
//! (`|x| >= 2^49` in f64, `2^20` in f32) or not finite take
//! [`Float::fast_sin_cos`] of the rounded `2πx` (libm, or micromath with that
//! feature in f32), on the caller's cold path.
//!
//! The constants are this module's own, in each float type: the
//! coefficients are rounded from the `f64` ones by `Float::from_f64` inside
//! fully unrolled polynomials, so that even an unoptimised loop never
//! converts them at run time (on a soft-float Cortex-M such a conversion is
//! a library call). The host test `trig.rs`
//! bounds the error against a double-double evaluation.

use crate::float::Float;

/// fdlibm `__kernel_sin`: `sin t = t + t z (S1 + S2 z + ... + S6 z^5)`,
/// `z = t^2`, on `|t| <= π/4`, as the bit patterns fdlibm publishes.
const SIN: [f64; 6] = [
    f64::from_bits(0xBFC5_5555_5555_5549), // -1.66666666666666324348e-01
    f64::from_bits(0x3F81_1111_1110_F8A6), //  8.33333333332248946124e-03
    f64::from_bits(0xBF2A_01A0_19C1_61D5), // -1.98412698298579493134e-04
    f64::from_bits(0x3EC7_1DE3_57B1_FE7D), //  2.75573137070700676789e-06
    f64::from_bits(0xBE5A_E5E6_8A2B_9CEB), // -2.50507602534068634195e-08
    f64::from_bits(0x3DE5_D93A_5ACF_D57C), //  1.58969099521155010221e-10
];

/// fdlibm `__kernel_cos`: `cos t = 1 - z/2 + z^2 (C1 + C2 z + ... + C6 z^5)`.
const COS: [f64; 6] = [
    f64::from_bits(0x3FA5_5555_5555_554C), //  4.16666666666666019037e-02
    f64::from_bits(0xBF56_C16C_16C1_5177), // -1.38888888888741095749e-03
    f64::from_bits(0x3EFA_01A0_19CB_1590), //  2.48015872894767294178e-05
    f64::from_bits(0xBE92_7E4F_809C_52AD), // -2.75573143513906633035e-07
    f64::from_bits(0x3E21_EE9E_BDB4_B1C4), //  2.08757232129817482790e-09
    f64::from_bits(0xBDA8_FAE9_BE88_38D4), // -1.13596475577881948265e-11
];

/// `1.5 * 2^(mantissa bits)`: `(v + M) - M` rounds `v` to the nearest
/// integer (ties to even) for `|v| < M/3`.
#[inline(always)]
fn round_magic<F: Float>() -> F {
    F::from_f64(1.5 * (1u64 << (F::MANTISSA_DIGITS - 1)) as f64)
}

/// Below this `|x|` (`2^49` in f64, `2^20` in f32) the polynomial path is
/// exact in its reduction: `2x` stays far below a third of the magic number.
#[inline(always)]
fn fast_limit<F: Float>() -> F {
    F::from_f64((1u64 << (F::MANTISSA_DIGITS - 4)) as f64)
}

/// `sum_k c[k] z^k` for fdlibm's coefficients `c`, in `F`: all six terms
/// in f64, as two Horner halves `lo(z) + z^3 hi(z)` (two independent
/// chains, half the latency); the first four in f32, where the dropped
/// terms are below a tenth of an ulp, by plain Horner (the split gains
/// nothing at that length and costs a soft-float product on a Cortex-M).
#[inline(always)]
fn polynomial<F: Float>(c: &[f64; 6], z: F) -> F {
    let k = |i: usize| F::from_f64(c[i]);
    if F::MANTISSA_DIGITS > 24 {
        let lo = (k(2) * z + k(1)) * z + k(0);
        let hi = (k(5) * z + k(4)) * z + k(3);
        let z3 = z * z * z;
        lo + z3 * hi
    } else {
        ((k(3) * z + k(2)) * z + k(1)) * z + k(0)
    }
}

/// `(sin(2π x_j), 1 - cos(2π x_j))` for one block of coordinates, on the
/// polynomial path: right where [`all_small`] holds, to be patched by
/// [`patch_large`] where it does not.
#[inline(always)]
pub(crate) fn block<F: Float, const L: usize>(x: &[F; L]) -> ([F; L], [F; L]) {
    let magic = round_magic::<F>();
    let mut s = [F::ZERO; L];
    let mut omc = [F::ZERO; L];
    for ((&xi, si), oi) in x.iter().zip(s.iter_mut()).zip(omc.iter_mut()) {
        // Round to nearest by the magic-number trick: exact for |2x| below
        // a third of the magic number, beyond the fast-path limit.
        let n = (F::TWO * xi + magic) - magic;
        let r = xi - F::HALF * n;
        // n - 2 round(n/2): 0 for even n, ±1 for odd.
        let odd = n - F::TWO * ((F::HALF * n + magic) - magic);
        let t = F::PI * r;
        let z = t * t;
        let sin_t = t + (t * z) * polynomial(&SIN, z);
        let cos_t = F::ONE - (F::HALF * z - (z * z) * polynomial(&COS, z));
        let two_sc = (sin_t + sin_t) * cos_t;
        let (sin, w) = if odd == F::ZERO {
            (two_sc, sin_t)
        } else {
            (-two_sc, cos_t)
        };
        *si = sin;
        *oi = (w + w) * w;
    }
    (s, omc)
}

/// A block from up to `L` coordinates, padded with zeros (whose sine and
/// `1 - cos` are exactly 0).
#[inline(always)]
pub(crate) fn pad<F: Float, const L: usize>(x: &[F]) -> [F; L] {
    core::array::from_fn(|k| x.get(k).copied().unwrap_or(F::ZERO))
}

/// `true` if every coordinate of the block takes the polynomial path
/// (finite and below the limit).
#[inline(always)]
pub(crate) fn all_small<F: Float, const L: usize>(x: &[F; L]) -> bool {
    x.iter().all(|&v| is_small(v))
}

#[inline(always)]
fn is_small<F: Float>(x: F) -> bool {
    x.abs() < fast_limit::<F>()
}

/// Replaces the polynomial's values of [`block`] by libm's (micromath's)
/// for the coordinates at or beyond the fast-path limit, or not finite.
/// For the callers' cold paths: no run of the paper's kind reaches it.
pub(crate) fn patch_large<F: Float, const L: usize>(x: &[F; L], s: &mut [F; L], omc: &mut [F; L]) {
    for ((&xj, sj), oj) in x.iter().zip(s.iter_mut()).zip(omc.iter_mut()) {
        if !is_small(xj) {
            let (sv, cv) = (F::from_f64(core::f64::consts::TAU) * xj).fast_sin_cos();
            *sj = sv;
            *oj = one_minus_cos(sv, cv);
        }
    }
}

/// `1 - cos t` from `(sin t, cos t)` without cancellation near `cos t = 1`.
#[inline(always)]
fn one_minus_cos<F: Float>(s: F, c: F) -> F {
    if c > F::ZERO {
        s * s / (F::ONE + c)
    } else {
        F::ONE - c
    }
}
