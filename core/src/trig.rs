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
//! feature in f32), on the caller's cold path. The host test `trig.rs`
//! bounds the error against a double-double evaluation.

use crate::float::Float;

/// fdlibm `__kernel_sin`: `sin t = t + t z (S1 + S2 z + ... + S6 z^5)`,
/// `z = t^2`, on `|t| <= π/4`, as the bit patterns fdlibm publishes.
pub(crate) const SIN: [f64; 6] = [
    f64::from_bits(0xBFC5_5555_5555_5549), // -1.66666666666666324348e-01
    f64::from_bits(0x3F81_1111_1110_F8A6), //  8.33333333332248946124e-03
    f64::from_bits(0xBF2A_01A0_19C1_61D5), // -1.98412698298579493134e-04
    f64::from_bits(0x3EC7_1DE3_57B1_FE7D), //  2.75573137070700676789e-06
    f64::from_bits(0xBE5A_E5E6_8A2B_9CEB), // -2.50507602534068634195e-08
    f64::from_bits(0x3DE5_D93A_5ACF_D57C), //  1.58969099521155010221e-10
];

/// fdlibm `__kernel_cos`: `cos t = 1 - z/2 + z^2 (C1 + C2 z + ... + C6 z^5)`.
pub(crate) const COS: [f64; 6] = [
    f64::from_bits(0x3FA5_5555_5555_554C), //  4.16666666666666019037e-02
    f64::from_bits(0xBF56_C16C_16C1_5177), // -1.38888888888741095749e-03
    f64::from_bits(0x3EFA_01A0_19CB_1590), //  2.48015872894767294178e-05
    f64::from_bits(0xBE92_7E4F_809C_52AD), // -2.75573143513906633035e-07
    f64::from_bits(0x3E21_EE9E_BDB4_B1C4), //  2.08757232129817482790e-09
    f64::from_bits(0xBDA8_FAE9_BE88_38D4), // -1.13596475577881948265e-11
];

/// `sum_k coef[k] z^k` by Horner's rule (`coef` non-empty).
#[inline(always)]
fn horner<F: Float>(coef: &[F], z: F) -> F {
    let (&last, rest) = coef.split_last().expect("non-empty");
    rest.iter().rev().fold(last, |acc, &c| acc * z + c)
}

/// `sum_k coef[k] z^k` as two Horner halves, `lo(z) + z^m hi(z)` with
/// `m = len/2`: two independent chains, half the latency, for one more
/// multiplication. Only for the f64 length (6): at f32's 4 the gain is nil
/// on vector hardware and the extra product costs a soft-float call on a
/// Cortex-M.
#[inline(always)]
fn split_horner<F: Float>(coef: &[F], z: F) -> F {
    if coef.len() < 6 {
        return horner(coef, z);
    }
    let (lo, hi) = coef.split_at(coef.len() / 2);
    let mut zm = z;
    for _ in 1..lo.len() {
        zm *= z;
    }
    horner(lo, z) + zm * horner(hi, z)
}

/// Lanes of one 128-bit vector of `F` (SSE2, NEON, wasm SIMD128), the unit
/// the compiler vectorises; small, so that padding a short tail wastes
/// little.
pub(crate) const fn lanes<F>() -> usize {
    16 / core::mem::size_of::<F>()
}

/// Whether the target has 256-bit float vectors (AVX): blocks of two
/// [`lanes`] vectors. Results do not depend on it.
pub(crate) const WIDE: bool = cfg!(target_feature = "avx");

/// Whether the target has 128-bit float vectors for blocks of [`lanes`]
/// coordinates; without them (Cortex-M, RISC-V, plain wasm32) a block is one
/// coordinate. Results do not depend on it.
pub(crate) const VECTORS: bool = cfg!(any(
    target_arch = "x86_64",
    target_arch = "aarch64",
    target_feature = "sse2",
    target_feature = "simd128",
    all(target_arch = "arm", target_feature = "neon")
));

/// `(sin(2π x_j), 1 - cos(2π x_j))` for one block of coordinates, on the
/// polynomial path: right where [`all_small`] holds, to be patched by
/// [`patch_large`] where it does not.
#[inline(always)]
pub(crate) fn block<F: Float, const L: usize>(x: &[F; L]) -> ([F; L], [F; L]) {
    let magic = F::ROUND_MAGIC;
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
        let sin_t = t + (t * z) * split_horner(F::SIN_COEFFICIENTS, z);
        let cos_t = F::ONE - (F::HALF * z - (z * z) * split_horner(F::COS_COEFFICIENTS, z));
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
    x.abs() < F::TRIG_FAST_LIMIT
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
